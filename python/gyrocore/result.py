"""The pipeline's per-sample result (:class:`HeadingResult`) and the outputs it may hold."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Union

import numpy as np

from ._arrays import FloatArray, array_fields
from ._checks import require_choice
from .rests import Rest

if TYPE_CHECKING:
    from .fixes import FusionResult


#: The per-sample outputs of the pipeline, in the order of :class:`HeadingResult`.
OUTPUTS = ("heading", "rate", "drift")
#: The fix stage's per-sample outputs, with heading fixes: :attr:`HeadingResult.heading_sigma`, and the
#: bias and scale error of :class:`gyrocore.fixes.FusionResult` (``fusion.bias``, ``fusion.scale``).
FIX_OUTPUTS = ("heading_sigma", "fusion_bias", "fusion_scale")
#: Every output: the default of ``outputs=`` (the fix stage's only with fixes).
ALL_OUTPUTS = OUTPUTS + FIX_OUTPUTS


def output_flags(outputs: tuple[str, ...] | list[str]) -> tuple[bool, bool]:
    """Whether ``outputs`` asks for the rate and the drift (the heading is always computed);
    a name not in :data:`ALL_OUTPUTS`, or no heading, is a ``ValueError``; no sequence of names
    (``None``, a number) a ``TypeError``."""
    give = f"give a tuple of names from {', '.join(ALL_OUTPUTS)}, with heading (the heading is always computed)"
    if not isinstance(outputs, (tuple, list, set, frozenset)):  # None was a bare "'NoneType' object is not iterable"
        raise (ValueError if isinstance(outputs, str) else TypeError)(f"outputs={outputs!r}: {give}")
    if any(o not in ALL_OUTPUTS for o in outputs) or "heading" not in outputs:
        raise ValueError(f"outputs={outputs!r}: {give}")
    return "rate" in outputs, "drift" in outputs


#: What ``out=`` takes: one float64 array per pipeline output (heading, rate, drift) asked for, in
#: the order of ``outputs``, or the array itself when the heading alone is asked for (the fix
#: stage's columns are always fresh arrays).
OutArrays = Union[FloatArray, Sequence[FloatArray]]
#: The caller's arrays for (heading, rate, drift), None where there is none.
Filled = tuple[Union[FloatArray, None], Union[FloatArray, None], Union[FloatArray, None]]


def out_arrays(
    out: OutArrays | None, outputs: tuple[str, ...], n: int, inputs: Mapping[str, Sequence[object]]
) -> Filled | None:
    """The caller's arrays of ``out=`` as (heading, rate, drift), each checked: a float64 numpy
    array of ``n`` elements, C-contiguous and writeable, sharing no memory with an input (the
    values of ``inputs``, by name: the caller's arrays and what the core reads) or with another
    output. None without ``out``. A ``TypeError`` or ``ValueError`` names the array and says what
    to give instead."""
    output_flags(outputs)
    if out is None:
        return None
    names = tuple(o for o in outputs if o in OUTPUTS)
    if len(set(names)) != len(names):
        raise ValueError(f"outputs={names!r} names an output twice: with out=, name each output once")
    arrays: tuple[object, ...]
    if isinstance(out, np.ndarray):
        arrays, labels = (out,), ["out"]
    elif isinstance(out, (tuple, list)):
        arrays, labels = tuple(out), [f"out[{i}]" for i in range(len(out))]
    else:
        raise TypeError(f"out must be a float64 array, or a tuple of one per output in outputs={names!r}; "
                        f"got {type(out).__name__}")
    if len(arrays) != len(names):
        raise ValueError(f"out gives {len(arrays)} array(s) for the {len(names)} output(s) {names!r}: give one "
                         "float64 array per output, in the order of outputs")
    taken: list[tuple[str, FloatArray]] = []
    for label, name, a in zip(labels, names, arrays):
        what = f"{label} ({name})"
        if not isinstance(a, np.ndarray):
            raise TypeError(f"{what} must be a numpy float64 array, got {type(a).__name__}")
        if a.dtype != np.float64:
            raise TypeError(f"{what} holds {a.dtype}, not float64: give numpy.empty(len(t)) (float64)")
        if a.shape != (n,):
            raise ValueError(f"{what} has shape {a.shape}, but t has {n} samples: give a 1-D array of one "
                             "element per sample")
        if not a.flags.c_contiguous:
            raise ValueError(f"{what} is not C-contiguous (a strided view cannot be filled in place): give a "
                             "contiguous array, e.g. numpy.empty(len(t))")
        if not a.flags.writeable:
            raise ValueError(f"{what} is read-only: give a writeable array")
        for source, values in inputs.items():
            if any(isinstance(v, np.ndarray) and np.shares_memory(a, v) for v in values):
                raise ValueError(f"{what} shares memory with the input {source}, which filling it would "
                                 "overwrite: give an array of its own")
        for other, b in taken:
            if np.shares_memory(a, b):
                raise ValueError(f"{what} shares memory with {other}: give each output an array of its own")
        taken.append((what, a))
    given = dict(zip(names, (a for _, a in taken)))
    return given.get("heading"), given.get("rate"), given.get("drift")


def filled(result: HeadingResult, arrays: Filled | None) -> HeadingResult:
    """``result`` with its outputs copied into the caller's ``arrays`` (from :func:`out_arrays`),
    which it then holds; for results computed elsewhere than in the arrays (the fix stage's
    smoother)."""
    if arrays is None:
        return result
    for name, a in zip(OUTPUTS, arrays):
        if a is not None:
            np.copyto(a, result.output(name))
    heading, rate, drift = arrays
    return replace(result, heading=result.heading if heading is None else heading,
                   rate=result.rate if rate is None else rate, drift=result.drift if drift is None else drift)


def fix_output_flags(outputs: tuple[str, ...] | list[str]) -> tuple[bool, bool, bool]:
    """Whether ``outputs`` (checked by :func:`output_flags`) asks for each of :data:`FIX_OUTPUTS`."""
    heading_sigma, bias, scale = (name in outputs for name in FIX_OUTPUTS)
    return heading_sigma, bias, scale


@dataclass(frozen=True, repr=False, eq=False)
class HeadingResult:
    """Per-sample output of the pipeline (all arrays float64, one entry per input sample).

    ``rate`` and ``drift`` are None when not asked for (``outputs=`` of :func:`process` and
    :meth:`Pipeline.process`): they were never computed or stored. :meth:`columns` gives those
    computed by name, for a table (``pandas.DataFrame(result.columns())``) or a file.

    Attributes:
        t: timestamps [s], as given.
        heading: continuous (unwrapped) heading [rad], counter-clockwise positive.
        rate: corrected rate that was integrated [rad/s].
        drift: HDR's drift estimate ``-I`` applied to each sample [rad/s] (0 without HDR).
        rests: the rests whose bias was used in whole mode (:class:`gyrocore.rests.Rest`).
        tracked_rests: with ``track_rests=True``, every rest the core's tracker found in these
            samples, in order (each one's span, the bias it measured, its standard error and the
            filtered bias after it; :class:`gyrocore.rests.Rest`).
        bias_source: where the static bias came from (set by :func:`process` and
            :meth:`gyrocore.Log.process`; empty from a streaming :class:`Pipeline`).
        heading_sigma: with heading fixes, the filter's heading standard deviation [rad] (unless
            ``outputs=`` left it out), else None.
        fusion: with heading fixes, the fix stage's :class:`gyrocore.fixes.FusionResult` (bias and
            scale error of the corrected rate, fix counts), else None.
        report: what the input policy did, as :attr:`gyrocore.Pipeline.report` gives it (``held``,
            ``skipped``, ``gaps``, ``longest_gap`` [s]; a stream's totals since its first block);
            None where no pipeline made the result.
    """

    t: FloatArray
    heading: FloatArray
    rate: FloatArray | None = None
    drift: FloatArray | None = None
    bias_source: str = ""
    rests: tuple[Rest, ...] = ()
    tracked_rests: tuple[Rest, ...] = ()
    heading_sigma: FloatArray | None = None
    fusion: FusionResult | None = None
    report: Mapping[str, float] | None = None

    def output(self, name: str) -> FloatArray:
        """The output ``name`` (one of :data:`OUTPUTS`, or ``heading_sigma``); a ``ValueError`` if it
        was not asked for (or, for ``heading_sigma``, there were no fixes), or is no output's name."""
        if name not in (*OUTPUTS, "heading_sigma"):  # "'foo' output was not computed: ask for it" misled
            require_choice("output", name, (*OUTPUTS, "heading_sigma"))
        value: FloatArray | None = getattr(self, name)
        if value is None and name == "heading_sigma" and self.fusion is None:
            raise ValueError("the 'heading_sigma' output comes with heading fixes, and there were none")
        if value is None:
            raise ValueError(f"the {name!r} output was not computed: ask for it in outputs=")
        return value

    def columns(self) -> dict[str, FloatArray]:
        """The per-sample arrays by name, each one value per sample: ``t`` [s], ``heading`` [rad],
        then of ``rate``, ``drift`` [rad/s], ``heading_sigma`` [rad], ``fusion_bias`` [rad/s] and
        ``fusion_scale`` [1] those that were computed (as :data:`ALL_OUTPUTS` names them). The
        arrays themselves, not copies: ``pandas.DataFrame(result.columns())`` is a table, and
        ``numpy.savez(path, **result.columns())`` saves them by name."""
        fused = {} if self.fusion is None else self.fusion.columns()
        return {**array_fields(self), **{f"fusion_{k}": fused[k] for k in ("bias", "scale") if k in fused}}

    @property
    def heading_deg(self) -> FloatArray:
        """Heading in degrees."""
        return np.degrees(self.heading)

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        if len(self.t) == 0:
            return "HeadingResult(empty)"
        parts = [f"n={len(self.t)}", f"duration={self.t[-1] - self.t[0]:.3f} s"]
        first, last = math.degrees(self.heading[0]), math.degrees(self.heading[-1])
        parts.append(f"heading {first:.3f} -> {last:.3f} deg")
        if self.drift is not None:
            parts.append(f"final drift estimate {math.degrees(self.drift[-1]):.4f} deg/s")
        return f"HeadingResult({', '.join(parts)})"

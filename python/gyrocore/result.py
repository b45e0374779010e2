"""The pipeline's per-sample result (:class:`HeadingResult`) and the outputs it may hold."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ._arrays import FloatArray
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
    a name not in :data:`ALL_OUTPUTS`, or no heading, is a ``ValueError``."""
    if isinstance(outputs, str) or any(o not in ALL_OUTPUTS for o in outputs) or "heading" not in outputs:
        raise ValueError(
            f"outputs={outputs!r}: give a tuple of names from {', '.join(ALL_OUTPUTS)}, with heading "
            "(the heading is always computed)"
        )
    return "rate" in outputs, "drift" in outputs


def fix_output_flags(outputs: tuple[str, ...] | list[str]) -> tuple[bool, bool, bool]:
    """Whether ``outputs`` (checked by :func:`output_flags`) asks for each of :data:`FIX_OUTPUTS`."""
    heading_sigma, bias, scale = (name in outputs for name in FIX_OUTPUTS)
    return heading_sigma, bias, scale


@dataclass(frozen=True, repr=False)
class HeadingResult:
    """Per-sample output of the pipeline (all arrays float64, one entry per input sample).

    ``rate`` and ``drift`` are None when not asked for (``outputs=`` of :func:`process` and
    :meth:`Pipeline.process`): they were never computed or stored.

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

    def output(self, name: str) -> FloatArray:
        """The output ``name`` (one of :data:`OUTPUTS`, or ``heading_sigma``); a ``ValueError`` if it
        was not asked for (or, for ``heading_sigma``, there were no fixes)."""
        value: FloatArray | None = getattr(self, name) if name in (*OUTPUTS, "heading_sigma") else None
        if value is None and name == "heading_sigma" and self.fusion is None:
            raise ValueError("the 'heading_sigma' output comes with heading fixes, and there were none")
        if value is None:
            raise ValueError(f"the {name!r} output was not computed: ask for it in outputs=")
        return value

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

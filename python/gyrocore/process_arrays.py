"""The heading of a whole log given as arrays: :func:`process` (re-exported by
:mod:`gyrocore.pipeline` and the package), whole or causal, with fixes where given; the work is
:func:`gyrocore.wholelog.process_log`'s."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from numpy.typing import ArrayLike

from ._arrays import READ_AND_PROCESS, no_path_for_arrays
from .result import ALL_OUTPUTS, HeadingResult, OutArrays

if TYPE_CHECKING:
    from .fixes import FixesLike


@no_path_for_arrays("gyrocore.process", READ_AND_PROCESS)
def process(
    t: ArrayLike,
    rate: ArrayLike,
    preset: str = "recommended",
    *,
    temperature: ArrayLike | None = None,
    outputs: tuple[str, ...] = ALL_OUTPUTS,
    mode: str = "whole",
    speed: ArrayLike | None = None,
    speed_t: ArrayLike | None = None,
    fixes: FixesLike | None = None,
    fusion: dict[str, float] | None = None,
    out: OutArrays | None = None,
    **overrides: Any,
) -> HeadingResult:
    """Heading of a whole log, ``t`` [s] and ``rate`` [rad/s, counter-clockwise positive; deg/s:
    ``numpy.radians(rate)``], with ``preset`` (default ``recommended``, as everywhere: ``gyrocore
    presets`` lists them); ``outputs`` chooses which of ``heading``, ``rate`` and ``drift`` (and
    with fixes ``heading_sigma``, ``fusion_bias``, ``fusion_scale``) are computed, and ``out`` gives
    arrays to fill with the first three (see :meth:`Pipeline.process`).

    ``fixes`` (see :meth:`Pipeline.process`) add the fix stage with the settings ``fusion``: in
    whole mode the Rauch-Tung-Striebel smoother, in causal mode the filter.

    ``mode="whole"`` (default): the static bias is known before the first sample, from the given
    ``bias_window`` / ``bias_duration`` wherever it lies (its mean applies from the first sample)
    or, when none is given, from every rest found in the log (from the rate, and from ``speed``
    [m/s] where given: one per sample, or at its own times ``speed_t``), smoothed between rests
    (see :mod:`gyrocore.wholelog`). ``mode="causal"``: what a streaming
    ``Pipeline(preset, **overrides)`` gives, sample after sample (a rest corrects only what
    follows it; ``speed`` then feeds the core's rest tracker, ``track_rests=True``). The result's
    ``bias_source`` and ``rests`` say where the bias came from.

    Example:
        >>> import numpy as np, gyrocore
        >>> t = np.arange(0, 60, 0.01)
        >>> r = gyrocore.process(t, np.full_like(t, 0.002), "static_bias", bias_duration=20.0)
        >>> bool(abs(r.heading[-1]) < 1e-9)
        True
    """
    from .wholelog import process_log  # it builds on this module

    return process_log(
        t, rate, preset, mode=mode, temperature=temperature, speed=speed, speed_t=speed_t, outputs=outputs,
        fixes=fixes, fusion=fusion, out=out, **overrides,
    )

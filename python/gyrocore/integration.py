"""Heading from rate and block means: the core's integrator (HDR eq 3, or the trapezoid rule)
and the HDR paper's down-sampling, for arrays in memory."""

from __future__ import annotations

from numpy.typing import ArrayLike

from . import _gyrocore
from ._arrays import FloatArray, as_float_array


def integrate(
    t: ArrayLike, rate: ArrayLike, method: str = "trapezoid", *, initial_heading: float = 0.0
) -> FloatArray:
    """Continuous heading [rad] from rate [rad/s]: ``trapezoid`` or ``rectangle`` (HDR eq 3)."""
    heading: FloatArray = _gyrocore.integrate(
        as_float_array("t", t), as_float_array("rate", rate), method, initial_heading
    )
    return heading


def downsample(t: ArrayLike, rate: ArrayLike, interval: float = 1.0) -> tuple[FloatArray, FloatArray]:
    """Block means over ``interval`` seconds (the HDR paper's down-sampling, its second eq 14).

    Returns the end time of each complete block and its time-weighted mean rate.
    """
    tb, rb = _gyrocore.downsample(as_float_array("t", t), as_float_array("rate", rate), interval)
    return tb, rb

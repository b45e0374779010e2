"""Heading from rate and block means: the core's integrator (HDR eq 3, or the trapezoid rule)
and the HDR paper's down-sampling, for arrays in memory."""

from __future__ import annotations

from numpy.typing import ArrayLike

from . import _gyrocore
from ._arrays import READ_THE_LOG, FloatArray, as_float_array, no_path_for_arrays
from ._checks import check_number, public_dir, warn_units
from ._time_steps import time_steps_named

__all__ = ["angle_of", "downsample", "integrate"]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


@no_path_for_arrays("gyrocore.integrate", READ_THE_LOG)
def integrate(
    t: ArrayLike, rate: ArrayLike, method: str = "trapezoid", *, initial_heading: float = 0.0
) -> FloatArray:
    """Continuous heading [rad] from rate [rad/s]: ``trapezoid`` or ``rectangle`` (HDR eq 3).

    Warns:
        InputWarning: rates that look like deg/s or times like ms, as :func:`gyrocore.process` warns
            (a log in ms integrated to a heading 1000 times too large without a word).

    Raises:
        SampleError: (a ValueError) a time or reading the core refuses, naming the first.
        ValueError: lengths apart, an unknown ``method``, an ``initial_heading`` that is not finite.
        TypeError: non-numeric arrays, a ``method`` that is no name, an ``initial_heading`` that is
            no number (the core's "must be real number, not str" named neither; True was 1 rad).
    """
    ta, ra = as_float_array("t", t), as_float_array("rate", rate, unit="rad/s")
    heading = angle_of(ta, ra, method, initial_heading)
    warn_units(ta, ra)  # after the core's checks: a time it refuses is the error to give first
    return heading


def angle_of(t: FloatArray, rate: FloatArray, method: str = "trapezoid", initial_heading: float = 0.0) -> FloatArray:
    """:func:`integrate` without its unit warning, for the package's own callers that warned of the
    whole log already (a calibration integrating a part of it would warn a second time)."""
    if not isinstance(method, str):
        raise TypeError(f"method must be 'trapezoid' or 'rectangle', got {method!r}")
    start = check_number("initial_heading", initial_heading, low=None, unit=" [rad]")
    with time_steps_named(t):  # a counter's wrap, float32 times: not mended by sorting
        heading: FloatArray = _gyrocore.integrate(t, rate, method, start)
    return heading


@no_path_for_arrays("gyrocore.downsample", READ_THE_LOG)
def downsample(t: ArrayLike, rate: ArrayLike, interval: float = 1.0) -> tuple[FloatArray, FloatArray]:
    """Block means over ``interval`` seconds (the HDR paper's down-sampling, its second eq 14).

    Returns the end time of each complete block and its time-weighted mean rate.

    Warns:
        InputWarning: rates that look like deg/s or times like ms, as :func:`integrate` warns.

    Raises:
        TypeError: an ``interval`` that is no number (text was the core's unnamed "must be real
            number", True an interval of 1 s).
        ValueError: an ``interval`` that is not finite and > 0, samples the core refuses.
    """
    ta, ra = as_float_array("t", t), as_float_array("rate", rate, unit="rad/s")
    step = check_number("interval", interval, unit=" [s]")
    with time_steps_named(ta):
        tb, rb = _gyrocore.downsample(ta, ra, step)
    warn_units(ta, ra)
    return tb, rb

"""Checks of the samples every calibration takes: errors name the array and the index."""

from __future__ import annotations

from numpy.typing import ArrayLike

from .._arrays import FloatArray, as_float_array
from .._checks import require_readings, require_series, warn_units


def check_series(
    t: ArrayLike, rate: ArrayLike, *, t_name: str = "t", rate_name: str = "rate", readings: bool = True,
    minimum: int = 0,
) -> tuple[FloatArray, FloatArray]:
    """Equal lengths, finite values, strictly increasing times, at least ``minimum`` samples (an
    empty log was a bare IndexError of a fit); ValueError naming the index. With
    ``readings`` (a gyro's rates, not a reference heading) each within the pipeline's +-2^20 rad/s
    too (a :class:`~gyrocore.SampleError`): 1e300 overflowed the fits' squares into nonsense; and
    an :class:`~gyrocore.InputWarning` where they look like deg/s or the times like ms, as the
    pipeline says (a static bias of 641 "rad/s" came without a word)."""
    ta, ra = as_float_array(t_name, t), as_float_array(rate_name, rate, unit="rad/s" if readings else "rad")
    require_series(t_name, ta, rate_name, ra)
    if len(ta) < minimum:
        raise ValueError(f"need at least {minimum} sample(s) of {rate_name}, got {len(ta)}")
    if readings:
        require_readings("rate", ra)
        warn_units(ta, ra)
    return ta, ra


def check_temperature(temperature: ArrayLike, n: int) -> FloatArray:
    """The temperature record [degC], checked: as long as the timestamps, every value finite and
    within the pipeline's +-2^20 degC (a :class:`~gyrocore.SampleError` naming the first that is not)."""
    temp = as_float_array("temperature", temperature, unit="degC")
    if len(temp) != n:
        raise ValueError(f"temperature has {len(temp)} samples but t has {n}")
    require_readings("temperature", temp)
    return temp

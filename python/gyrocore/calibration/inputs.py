"""Checks of the samples every calibration takes: errors name the array and the index."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .._arrays import FloatArray, as_float_array


def check_series(
    t: ArrayLike, rate: ArrayLike, *, t_name: str = "t", rate_name: str = "rate"
) -> tuple[FloatArray, FloatArray]:
    """Equal lengths, finite values, strictly increasing times; ValueError naming the index."""
    ta, ra = as_float_array(t_name, t), as_float_array(rate_name, rate)
    if len(ta) != len(ra):
        raise ValueError(f"{rate_name} has {len(ra)} samples but {t_name} has {len(ta)}")
    for name, a in ((t_name, ta), (rate_name, ra)):
        bad = np.flatnonzero(~np.isfinite(a))
        if len(bad):
            raise ValueError(f"{name}[{bad[0]}] is {a[bad[0]]}: samples must be finite (drop or fill them first)")
    steps = np.flatnonzero(np.diff(ta) <= 0)
    if len(steps):
        i = int(steps[0]) + 1
        raise ValueError(f"{t_name} must strictly increase: {t_name}[{i}] = {ta[i]} follows {ta[i - 1]}")
    return ta, ra


def check_temperature(temperature: ArrayLike, n: int) -> FloatArray:
    """The temperature record [degC], checked: as long as the timestamps, every value finite."""
    temp = as_float_array("temperature", temperature)
    if len(temp) != n:
        raise ValueError(f"temperature has {len(temp)} samples but t has {n}")
    bad = np.flatnonzero(~np.isfinite(temp))
    if len(bad):
        raise ValueError(f"temperature[{bad[0]}] is {temp[bad[0]]}: samples must be finite")
    return temp

"""A rate, heading, speed or fix sigma given as durations or dates (numpy's timedelta64 or
datetime64, a pandas timedelta column) is refused naming the argument and what to give: a
timedelta64 rate was read as seconds, as a time is, and processed as so many rad/s."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd
import pytest

import gyrocore
import gyrocore.allan as allan
from gyrocore import calibration, integration
from gyrocore.fixes import Fixes, fuse
from gyrocore.io import Log

pytestmark = pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")

T = np.arange(0.0, 60.0, 0.01)
RATE = 0.01 * np.sin(T)
ZERO = np.zeros(len(T))


def durations(a: np.ndarray) -> np.ndarray:
    """``a`` as timedelta64 nanoseconds: what a rate column of a table cut from a time column is."""
    return (a * 1e9).astype("timedelta64[ns]")


def dates(a: np.ndarray) -> np.ndarray:
    return durations(a) + np.datetime64("2024-01-01T00:00:00", "ns")


def pandas_durations(a: np.ndarray) -> pd.Series:
    return pd.Series(pd.to_timedelta(a, unit="s"))


def refused(name: str, unit: str, call: Callable[[], Any], what: str = "durations") -> None:
    with pytest.raises(TypeError, match=rf"^{re.escape(name)} holds {what} \(.*\), not values in {re.escape(unit)}: "
                                        rf"give {re.escape(name)} as floats in {re.escape(unit)}$"):
        call()


#: Every entry point that takes a rate, with the rate to give it.
RATE_CALLS: dict[str, Callable[[Any], Any]] = {
    "process": lambda r: gyrocore.process(T, r, "raw"),
    "process whole": lambda r: gyrocore.process(T, r, "hong_park", mode="whole", bias_duration=5.0),
    "Pipeline.process": lambda r: gyrocore.Pipeline("raw").process(T, r),
    "integrate": lambda r: integration.integrate(T, r),
    "downsample": lambda r: integration.downsample(T, r),
    "allan.deviation": lambda r: allan.deviation(r, 0.01),
    "allan.deviation_from_timestamps": lambda r: allan.deviation_from_timestamps(T, r),
    "fuse": lambda r: fuse(T, r, Fixes.of([1.0, 2.0], [0.0, 0.0], 0.1)),
    "static_bias": lambda r: calibration.static_bias(T, r, window=(0.0, 10.0)),
    "rotary_table": lambda r: calibration.rotary_table(T, r),
    "detect_rest": lambda r: calibration.detect_rest(T, r),
    "Log": lambda r: Log("drive", T, r),
}


@pytest.mark.parametrize("make", [durations, pandas_durations], ids=["timedelta64", "pandas"])
@pytest.mark.parametrize("entry", RATE_CALLS)
def test_a_rate_given_as_durations_is_refused_at_every_entry(entry: str, make: Callable[[np.ndarray], Any]) -> None:
    refused("rate", "rad/s", lambda: RATE_CALLS[entry](make(RATE)))


@pytest.mark.parametrize("entry", ["process", "Pipeline.process", "integrate", "allan.deviation", "Log"])
def test_a_rate_given_as_dates_is_refused(entry: str) -> None:
    refused("rate", "rad/s", lambda: RATE_CALLS[entry](dates(RATE)), "dates")


def test_python_durations_as_a_rate_are_refused() -> None:
    """A list of ``datetime.timedelta`` becomes seconds as a time: as a rate it is refused too."""
    rate = list(pd.to_timedelta(RATE, unit="s").to_pytimedelta())
    refused("rate", "rad/s", lambda: gyrocore.process(T, rate, "raw"))


def test_calibration_rates_name_their_argument() -> None:
    turn = np.where(T < 30, 0.0, 0.5)
    refused("rate_measured", "rad/s", lambda: calibration.rate_reference(durations(turn), turn))
    refused("rate_reference", "rad/s", lambda: calibration.rate_reference(turn, durations(turn)))
    refused("rate_measured", "rad/s", lambda: calibration.heading_reference(T, durations(turn), T, ZERO))
    refused("heading_ref", "rad", lambda: calibration.heading_reference(T, turn, T, durations(ZERO)))


def test_headings_speeds_and_fix_sigmas_given_as_times_are_refused() -> None:
    refused("speed", "m/s", lambda: gyrocore.process(T, RATE, "hong_park", mode="causal", track_rests=True, speed=durations(ZERO)))
    refused("speed", "m/s", lambda: gyrocore.process(T, RATE, "hong_park", mode="whole", speed=durations(ZERO)))
    refused("fix heading", "rad", lambda: Fixes.of([1.0, 2.0], durations(np.zeros(2)), 0.1))
    refused("fix heading", "rad", lambda: Fixes(np.array([1.0, 2.0]), dates(np.zeros(2)), np.full(2, 0.1)), "dates")
    refused("fix sigma", "rad", lambda: Fixes.of([1.0, 2.0], [0.0, 0.0], np.timedelta64(1, "s")))
    refused("fix sigma", "rad", lambda: Fixes.of([1.0, 2.0], [0.0, 0.0], pandas_durations(np.full(2, 0.1))))
    refused("heading_ref", "rad", lambda: Log("drive", T, RATE, t_ref=T, heading_ref=durations(ZERO)))
    refused("speed", "m/s", lambda: Log("drive", T, RATE, t_odometry=T, speed=pandas_durations(ZERO)))
    refused("heading", "rad", lambda: gyrocore.evaluate.heading_errors(T, durations(ZERO), T, ZERO))


def test_times_as_durations_are_still_seconds() -> None:
    """The check is of quantities: durations as the times themselves stay seconds in their unit."""
    t = durations(T)
    given = gyrocore.process(t, RATE, "raw")
    assert np.array_equal(given.heading, gyrocore.process(t / np.timedelta64(1, "s"), RATE, "raw").heading)


@pytest.mark.parametrize(("key", "unit"), [("bias", "rad/s"), ("bias_dps", "deg/s"), ("initial_heading", "rad")])
def test_a_parameter_given_as_a_duration_is_told_its_own_unit(key: str, unit: str) -> None:
    """A bias given as a duration was told to give seconds, which a rate never is."""
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = .*: a duration or date is no value in "
                                        rf"{re.escape(unit)}: give {key} as a float in {re.escape(unit)}$"):
        gyrocore.process(T, RATE, "raw", **{key: np.timedelta64(1, "s")})

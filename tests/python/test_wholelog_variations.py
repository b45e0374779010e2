"""Whole-log mode on variations of a log (slower, cut, shifted): the rests it uses and the bias
it takes from them stay what the log shows."""

from __future__ import annotations

import numpy as np
import pytest

import gyrocore

from .test_wholelog import NOISE, drive, stop_speed


def test_a_stop_of_one_reading_is_refused_not_taken_as_exact() -> None:
    # a slow log (every 50th reading of a 100 Hz drive: 2 Hz) whose second stop, less its edges,
    # holds one reading: its spread is unknown ("+- 0"), and it outweighed the long stop
    t, rate, _ = drive(120.0, [(20.0, 40.0), (80.0, 81.0)], bias=0.01)
    t, rate = t[::50], rate[::50]
    speed = stop_speed(t, [(20.0, 40.0), (80.0, 81.0)])
    result = gyrocore.process(t, rate, "static_bias", speed=speed)
    short = [r for r in result.rests if r.samples < 3]
    assert len(short) == 1 and short[0].refused is not None and "reading" in short[0].refused
    assert [r.samples for r in result.rests if r.accepted] == [39]
    long_only = gyrocore.process(t, rate, "static_bias", speed=stop_speed(t, [(20.0, 40.0)]))
    np.testing.assert_array_equal(result.heading, long_only.heading)


def test_a_rest_with_a_gap_reads_the_error_of_its_time_weighted_mean() -> None:
    # the readings of most of a stop skipped (NaN): the core's time-weighted mean takes the one
    # reading after the gap for 17 of the rest's 19 s, and its error is nearly one reading's noise
    # (it read the error of all 160 readings left, 0.1 of it)
    t, rate, _ = drive(60.0, [(20.0, 40.0)], bias=0.01)
    rate[(t > t[0] + 20.6) & (t < t[0] + 38.0)] = np.nan
    with pytest.warns(gyrocore.InputWarning):  # the readings skipped, and the gap they leave
        result = gyrocore.process(t, rate, "static_bias", speed=stop_speed(t, [(20.0, 40.0)]), nonfinite="skip")
    (rest,) = result.rests
    inside = t[(t >= rest.start) & (t <= rest.end) & np.isfinite(rate)]
    weights = np.diff(inside)
    assert rest.bias_std_error >= rest.noise * np.sqrt(np.sum(weights**2)) / np.sum(weights) > 0.8 * NOISE


def test_a_stop_of_a_large_mean_rate_is_listed_refused_not_left_unsaid() -> None:
    # a gyro whose bias exceeds 0.05 rad/s (2.9 deg/s; comma_seg40's reads 0.068): its stop reads
    # as a turn on the spot and is not used, but the speed shows it, and the report said "no rest
    # was found in the log"
    t, rate, _ = drive(60.0, [(20.0, 40.0)], bias=0.08)
    with pytest.warns(gyrocore.InputWarning, match="1 rest.s. found, none used .its mean rate 4.5"):
        result = gyrocore.process(t, rate, "static_bias", speed=stop_speed(t, [(20.0, 40.0)]))
    (rest,) = result.rests
    assert rest.found_by == "speed" and "turn on the spot" in (rest.refused or "")
    assert abs(rest.bias - 0.08) < 0.001 and result.bias_source.startswith("none: 1 rest(s) found, none used")

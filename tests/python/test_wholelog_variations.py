"""Whole-log mode on variations of a log (slower, cut, shifted): the rests it uses and the bias
it takes from them stay what the log shows."""

from __future__ import annotations

import numpy as np

import gyrocore

from .test_wholelog import drive, stop_speed


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

"""A :class:`gyrocore.Log` built in memory: a speed is used however it is given, and series that
belong together, or a rest window, that cannot be are refused when the log is made, by name."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import gyrocore
from gyrocore import datasets


def test_a_speed_without_its_own_times_is_one_per_gyro_sample() -> None:
    """``Log(..., speed=per_sample)`` was processed as if no speed were given (bit for bit): its
    stops went unused, E_psi 213.7 deg against 2.05 with the speed's times given."""
    drive = datasets.sample_drive()
    speed = np.interp(drive.t, drive.t_odometry, drive.speed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        bare = gyrocore.Log("bare", drive.t, drive.rate, speed=speed).process("static_bias")
        timed = gyrocore.Log("timed", drive.t, drive.rate, t_odometry=drive.t, speed=speed).process("static_bias")
        none = gyrocore.Log("none", drive.t, drive.rate).process("static_bias")
    np.testing.assert_array_equal(bare.heading, timed.heading)
    assert "speed" in {r.found_by for r in bare.rests}
    assert not np.array_equal(bare.heading, none.heading)


@pytest.mark.parametrize(
    ("fields", "said"),
    [({"rate": np.zeros(9)}, "log x: rate has 9 samples but t has 10: give one per time"),
     ({"speed": np.zeros(7)}, "log x: speed given without t_odometry: give its times as t_odometry (or one per gyro "
                              "sample, as long as t)"),
     ({"t_odometry": np.arange(3.0), "speed": np.zeros(2)}, "log x: speed has 2 samples but t_odometry has 3"),
     ({"t_odometry": np.arange(3.0)}, "log x: t_odometry given without speed"),
     ({"heading_ref": np.zeros(3)}, "log x: heading_ref given without t_ref"),
     ({"t_ref": np.arange(3.0), "heading_ref": np.zeros(3), "x_ref": np.zeros(2)},
      "log x: x_ref has 2 samples but t_ref has 3"),
     ({"stationary": (10.0, 5.0)}, "log x: stationary = (10.0, 5.0): give the rest window as (start, end) [s]"),
     ({"stationary": (0.0, float("nan"))}, "log x: stationary = (0.0, nan): give the rest window"),
     ({"stationary": 4.0}, "log x: stationary = 4.0: give the rest window")],
    ids=["rate", "speed alone", "speed short", "odometry times alone", "reference alone", "track short",
         "window backwards", "window nan", "window number"],
)
def test_series_that_do_not_match_are_refused_when_the_log_is_made(fields: dict[str, object], said: str) -> None:
    """They were accepted, and a backward window was later refused as ``bias_window``, a name the
    caller never gave."""
    series = {"t": np.arange(10.0), "rate": np.zeros(10), **fields}
    with pytest.raises(ValueError, match=f"^{re.escape(said)}"):
        gyrocore.Log("x", **series)  # type: ignore[arg-type]

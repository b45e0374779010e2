"""An Allan deviation of a gyro in motion is the motion's, not the sensor's: such a record is
warned about, and one at rest is not."""

from __future__ import annotations

import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan, sim
from gyrocore._motion import MOTION_SHARE, moving_share

from .conftest import gyrocore_cli, real_log_path

MOVING = "the gyro seems to move"


@pytest.mark.parametrize("name", ["f110_ds1", "kitti_2011_10_03_0042_mems", "comma_seg40"])
def test_a_drive_is_warned_about_as_moving(name: str) -> None:
    log = gyrocore.read_log(real_log_path(name))
    with pytest.warns(gyrocore.InputWarning, match=MOVING + r": \d+% of its 0.5 s means differ"):
        allan.deviation_from_timestamps(log.t, log.rate)


@pytest.mark.parametrize("name, rest_end", [("broad_10", 36.0), ("broad_11", 32.0)])
def test_a_real_rest_is_not(name: str, rest_end: float) -> None:
    log = gyrocore.read_log(real_log_path(name))
    inside = log.t < rest_end
    share = moving_share(log.rate[inside], float(np.mean(np.diff(log.t[inside]))))
    assert share is not None and share < MOTION_SHARE / 5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        allan.deviation_from_timestamps(log.t[inside], log.rate[inside])


#: The largest share docs/calibration.md gives for each simulated gyro at rest.
AT_REST = {"crs03": 0.0, "fog": 0.021, "xv3500": 0.002}


@pytest.mark.parametrize("sensor", ["crs03", "fog", "xv3500"])
def test_simulated_gyros_at_rest_for_an_hour_are_not(sensor: str) -> None:
    # their bias instability and rate random walk move the means too, but far less than motion
    spec = sim.sensor(sensor)
    t = sim.sample_times(spec, 0.0, 3600.0, seed=1)
    rate = sim.measure(spec, t, np.zeros(len(t)), seed=2).rate
    share = moving_share(rate[1:], float(np.mean(np.diff(t))))
    assert share is not None and share <= AT_REST[sensor], share  # the page said 0 for the XV-3500
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        allan.deviation(rate[1:], float(np.mean(np.diff(t))))


def test_records_too_short_or_quantised_to_judge_are_not() -> None:
    assert moving_share(np.random.default_rng(0).standard_normal(40), 0.1) is None  # 8 half-seconds
    steps = np.repeat([0.0, 1.0, 0.0, 1.0], 500)  # a gyro that reads in whole steps and moves
    assert moving_share(steps, 0.01) is None


def test_the_command_names_the_log() -> None:
    proc = gyrocore_cli("allan", real_log_path("f110_ds1"), code=0)
    assert f"gyrocore: warning: {real_log_path('f110_ds1')}: {MOVING}" in proc.stderr
    assert MOVING not in gyrocore_cli("allan", real_log_path("broad_10"), "--window", "0", "36", code=0).stderr


TURNING = r"the rest window \[1650775094.7543092, 1650775099.7543092\] s does not look like a rest: its readings spread 5.86 times their sample-to-sample noise, 33.6 deg/s beyond it"


def test_a_rest_window_in_which_the_gyro_turns_is_warned_about() -> None:
    # f110_ds1 drives from its first sample: its first 5 s as the rest gave a bias of 40.7 deg/s
    log = gyrocore.read_log(real_log_path("f110_ds1"))
    window = (float(log.t[0]), float(log.t[0]) + 5.0)
    with pytest.warns(gyrocore.InputWarning, match=TURNING + r".*its bias, 40.683 deg/s, holds the turn"):
        gyrocore.calibration.static_bias(log.t, log.rate, window)
    with pytest.warns(gyrocore.InputWarning, match=TURNING):
        gyrocore.process(log.t, log.rate, "static_bias", bias_window=window)


@pytest.mark.parametrize("name", ["broad_10", "f110_ds3", "kitti_2011_09_30_0018_mems", "kitti_2011_09_30_0027"])
def test_the_real_logs_rests_are_not(name: str) -> None:
    # their meta.json windows, and the rests whole mode finds by the speed, given as windows
    log = gyrocore.read_log(real_log_path(name))
    windows = {(r.start, r.end) for r in log.process("static_bias").rests or []}
    assert windows
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for window in windows:
            gyrocore.calibration.static_bias(log.t, log.rate, window, min_duration=0.1)
            gyrocore.process(log.t, log.rate, "static_bias", bias_window=window)


def test_a_causal_rest_window_with_a_turn_in_it_is_warned_about_once_however_it_is_chunked() -> None:
    log = gyrocore.read_log(real_log_path("f110_ds1"))
    window = (float(log.t[0]), float(log.t[0]) + 5.0)
    for step in (len(log.t), 7):
        p = gyrocore.Pipeline("static_bias", bias_window=window)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            for i in range(0, len(log.t), step):
                p.process(log.t[i:i + step], log.rate[i:i + step])
        said = [str(w.message) for w in caught if "does not look like a rest" in str(w.message)]
        assert len(said) == 1 and said[0].startswith("the rest window [1650775094.7543092, 1650775099.7543092] s")
    # a pipeline pickled inside the window keeps what it has seen of it
    p = gyrocore.Pipeline("static_bias", bias_duration=5.0)
    p.process(log.t[:50], log.rate[:50])
    again = pickle.loads(pickle.dumps(p))
    with pytest.warns(gyrocore.InputWarning, match=TURNING):
        again.process(log.t[50:], log.rate[50:])


def test_the_command_warns_once_for_a_causal_run_of_a_file(tmp_path: Path) -> None:
    proc = gyrocore_cli("process", real_log_path("f110_ds1"), "--causal", "--bias-duration", "5", "--chunk-rows", "7",
                        "--out", tmp_path / "h.csv", code=0)
    assert proc.stderr.count("does not look like a rest") == 1
    assert f"gyrocore: warning: {real_log_path('f110_ds1')}: the rest window [" in proc.stderr

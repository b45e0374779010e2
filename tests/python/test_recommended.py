"""The ``tracked`` preset (``tuned`` with the rest tracker): its tracker gives way to whole mode's
bias, a log's odometry feeds the tracker in causal mode; and what the README claims for the
recommended preset on the real logs."""

from __future__ import annotations

import numpy as np
import pytest

import gyrocore

from .conftest import real_log_path
from .test_rest_tracking import drive


def test_tracked_is_tuned_with_the_rest_tracker() -> None:
    tracked, tuned = gyrocore.preset_params("tracked"), gyrocore.preset_params("tuned")
    assert tracked.pop("track_rests") is True and tuned.pop("track_rests") is False
    assert {k: v for k, v in tracked.items() if not k.startswith("rest_")} == {
        k: v for k, v in tuned.items() if not k.startswith("rest_")}


def test_whole_mode_sets_the_presets_tracker_aside() -> None:
    # Whole mode already takes the bias from every rest of the log: the preset's tracker, which
    # would measure the rests again on the corrected rate, is off, and its result says none.
    t, r, speed, _ = drive()
    whole = gyrocore.process(t, r, "tracked", speed=speed)
    without = gyrocore.process(t, r, "tracked", speed=speed, track_rests=False)
    assert whole.heading.tobytes() == without.heading.tobytes()
    assert not whole.tracked_rests and len(whole.rests) == 2
    causal = gyrocore.process(t, r, "tracked", mode="causal", bias=0.0, speed=speed)
    assert len(causal.tracked_rests) == 2 and causal.heading.tobytes() != whole.heading.tobytes()
    with pytest.raises(ValueError, match="whole mode already takes it from every rest"):
        gyrocore.process(t, r, "tracked", speed=speed, track_rests=True)


def test_a_causal_log_feeds_its_odometry_to_the_tracker() -> None:
    log = gyrocore.read_log(real_log_path("kitti_2011_09_30_0027_mems"))
    assert log.speed is not None and log.t_odometry is not None
    with pytest.warns(gyrocore.InputWarning, match="the bias is taken as 0 until the rest tracker measures one"):
        result = log.process("tracked", mode="causal")
    with pytest.warns(gyrocore.InputWarning, match="the bias is taken as 0 until the rest tracker measures one"):
        expected = gyrocore.process(log.t, log.rate, "tracked", mode="causal", speed=log.speed,
                                    speed_t=log.t_odometry)
    assert result.heading.tobytes() == expected.heading.tobytes()
    assert result.tracked_rests


def test_the_arrays_and_the_stream_default_to_the_recommended_preset_as_the_command_line_does() -> None:
    # gyrocore.process(t, rate) and Pipeline() ran Table III's hdr, while Log.process, process_file
    # and `gyrocore process` ran the recommended preset
    t = np.arange(0.0, 120.0, 0.01)
    rate = 0.01 + np.where((t > 40) & (t < 60), 0.0, 0.2 * np.sin(t / 5))
    assert np.array_equal(gyrocore.process(t, rate).heading, gyrocore.process(t, rate, "recommended").heading)
    assert not np.array_equal(gyrocore.process(t, rate).heading, gyrocore.process(t, rate, "hdr").heading)
    assert gyrocore.Pipeline(bias=0.01).params == gyrocore.Pipeline("recommended", bias=0.01).params

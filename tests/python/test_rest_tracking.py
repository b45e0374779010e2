"""Rest tracking (track_rests=True): rests found from speed and from the rate, the bias filter,
chunk invariance and pickling, and named errors for bad speed input and bad settings."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import gyrocore
from gyrocore import rests, sim

#: Random-walk intensity [rad^2/s^3] that makes the drive's bias step (0.01 rad/s within a
#: minute) about one standard deviation of the filter's model.
WALK = 1e-6
STOPS = ((30.0, 45.0), (90.0, 110.0))


def drive(stops: tuple[tuple[float, float], ...] = STOPS) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A 150 s drive at 100 Hz through the Epson XV3500 model with its bias moved by 0.01 rad/s
    at 60 s: turning at 5 m/s except at ``stops``. Returns t, reading, speed and the true bias."""
    t = np.arange(0.0, 150.0, 0.01)
    stopped = np.zeros(len(t), dtype=bool)
    for a, b in stops:
        stopped |= (t >= a) & (t <= b)
    truth = np.where(stopped, 0.0, 0.2 * np.sin(0.3 * t))
    reading = sim.measure(sim.sensor("xv3500", scale_error=0.0), t, truth, seed=3)
    step = np.where(t >= 60.0, 0.01, 0.0)
    return t, reading.rate + step, np.where(stopped, 0.0, 5.0), reading.bias + step


def tracked(**more: object) -> dict[str, object]:
    return {"bias": 0.0, "track_rests": True, "rest_bias_walk": WALK, **more}


def assert_inside_stops(found: tuple[rests.Rest, ...] | list[rests.Rest], stops: tuple[tuple[float, float], ...]) -> None:
    """One rest per stop, inside it and covering most of it (its first and last blocks, and
    blocks whose mean still changes, are left out)."""
    assert len(found) == len(stops), found
    for rest, (a, b) in zip(found, stops):
        assert a <= rest.start < rest.end <= b and rest.end - rest.start > 0.6 * (b - a), (rest, a, b)


def test_a_bias_step_is_caught_at_a_mid_drive_stop() -> None:
    t, r, speed, bias = drive()
    result = gyrocore.process(t, r, "static_bias", mode="causal", speed=speed, **tracked())
    assert_inside_stops(result.tracked_rests, STOPS)
    for rest in result.tracked_rests:
        inside = (t >= rest.start) & (t <= rest.end)
        assert rest.accepted
        assert abs(rest.bias - bias[inside].mean()) < 4 * rest.std_error
    # After the second stop the integrated rate has no bias left beyond the filter's error.
    after = t > 110
    truth = 0.2 * np.sin(0.3 * t)
    assert result.rate is not None
    assert abs(np.mean(result.rate[after] - truth[after])) < 1e-3
    # Static-bias removal with the (unknown) start's bias of 0 keeps the whole error.
    plain = gyrocore.process(t, r, "static_bias", bias=0.0)
    assert plain.rate is not None
    assert abs(np.mean(plain.rate[after] - truth[after])) > 5e-3


def test_chunks_and_pickle_give_the_same_heading_and_rests() -> None:
    t, r, speed, _ = drive()
    t = t + 1.65e9  # Unix time: the rests are reported in the log's own clock
    whole = gyrocore.process(t, r, "recommended", mode="causal", speed=speed, **tracked())
    p = gyrocore.Pipeline("recommended", **tracked())
    parts = []
    for a, b in ((0, 1234), (1234, 5000), (5000, 9001)):
        parts.append(p.process(t[a:b], r[a:b], speed=speed[a:b], index_offset=a))
    p = pickle.loads(pickle.dumps(p))
    parts.append(p.process(t[9001:], r[9001:], speed=speed[9001:], index_offset=9001))
    heading = np.concatenate([x.heading for x in parts])
    assert heading.tobytes() == whole.heading.tobytes()
    assert p.rests == list(whole.tracked_rests)
    assert [x for part in parts for x in part.tracked_rests] == list(whole.tracked_rests)
    for rest, (a, b) in zip(whole.tracked_rests, STOPS):
        assert 1.65e9 + a <= rest.start < rest.end <= 1.65e9 + b


def test_a_speed_series_at_its_own_times_is_interpolated_onto_the_gyros() -> None:
    t, r, speed, _ = drive()
    t_odo = np.arange(0.05, 149.0, 0.1)  # 10 Hz odometry, ending before the gyro
    s_odo = np.interp(t_odo, t, speed)
    result = gyrocore.process(t, r, "static_bias", mode="causal", speed=s_odo, speed_t=t_odo, **tracked())
    assert_inside_stops(result.tracked_rests, STOPS)
    at = rests.speed_at(t, s_odo, t_odo)
    assert np.isnan(at[t < 0.05]).all() and np.isnan(at[t > t_odo[-1]]).all()
    assert (at[(t >= 1) & (t <= 2)] == 5.0).all()


def test_without_speed_rests_are_found_from_the_rate_after_a_rest_window() -> None:
    t, r, _, _ = drive(((0.0, 10.0), *STOPS))
    result = gyrocore.process(t, r, "static_bias", mode="causal", **{**tracked(), "bias": None}, bias_window=(0.0, 10.0))
    assert_inside_stops(result.tracked_rests, STOPS)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"speed": [0.0] * 5}, "speed has 5 samples but t has 15000"),
        ({"speed": np.where(np.arange(15000) == 7, np.nan, 1.0)}, r"speed\[7\] is nan"),
        ({"speed": [1.0, 2.0], "speed_t": [0.0, 1.0, 2.0]}, "speed: 3 times but 2 speeds"),
        ({"speed": [1.0, 2.0, 3.0], "speed_t": [0.0, 2.0, 1.0]}, r"speed: times must strictly increase, but index 2 \(1.0\) follows 2.0"),
        ({"speed": [1.0, 2.0], "speed_t": [0.0, np.inf]}, r"speed: time at index 1 is inf"),
    ],
)
def test_bad_speed_is_named_and_nothing_is_processed(kwargs: dict[str, object], message: str) -> None:
    t, r, _, _ = drive()
    p = gyrocore.Pipeline("static_bias", **tracked())
    with pytest.raises(ValueError, match=message):
        p.process(t, r, **kwargs)  # type: ignore[arg-type]
    assert p._inner.last_time() is None


def test_speed_without_tracking_is_refused() -> None:
    t, r, speed, _ = drive()
    with pytest.raises(ValueError, match="rest tracking is off: pass track_rests=True"):
        gyrocore.process(t, r, "static_bias", mode="causal", bias=0.0, speed=speed)


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("rest_block", 0.0, "rest_block"),
        ("rest_min_duration", 0.9, "at least two blocks"),
        ("rest_noise_ratio", 0.5, "rest_noise_ratio"),
        ("rest_speed_threshold", -0.1, "rest_speed_threshold"),
        ("rest_bias_walk", float("nan"), "rest_bias_walk"),
        ("rest_gate_sigmas", 0.0, "rest_gate_sigmas"),
    ],
)
def test_the_rules_name_the_parameter(name: str, value: float, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        gyrocore.Pipeline("static_bias", **tracked(**{name: value}))


def test_a_rest_setting_without_tracking_says_how_to_turn_it_on() -> None:
    with pytest.raises(ValueError, match="rest_block is set but rest tracking is off; pass track_rests=True"):
        gyrocore.Pipeline("static_bias", bias=0.0, rest_block=0.5)


def test_params_round_trip_and_tracked_bias() -> None:
    p = gyrocore.Pipeline("static_bias", **tracked(rest_noise=0.001))
    params = p.params
    assert params["track_rests"] and params["rest_bias_walk"] == WALK and params["rest_noise"] == 0.001
    assert gyrocore.Pipeline("static_bias", **params).params == params
    assert p.tracked_bias == (0.0, None)
    assert gyrocore.Pipeline("static_bias", bias=0.0).tracked_bias is None


def test_bias_walk_from_allan_parameters() -> None:
    assert rests.bias_walk(rate_random_walk=1e-4, bias_instability=0.0) == pytest.approx(1e-8)
    with_b = rests.bias_walk(rate_random_walk=0.0, bias_instability=1e-4, horizon=100.0)
    assert with_b == pytest.approx((0.664 * 1e-4) ** 2 / 100.0, rel=1e-3)
    with pytest.raises(ValueError, match="horizon must be finite and > 0"):
        rests.bias_walk(rate_random_walk=0.0, bias_instability=0.0, horizon=0.0)

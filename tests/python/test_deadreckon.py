"""Gyro-aided odometry (FOG section 4.2) against closed forms and the real logs' reference tracks."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gyrocore
from gyrocore import deadreckon

from .conftest import real_log_path


def irregular_times(duration: float, mean_dt: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    steps = rng.uniform(0.3, 1.7, int(duration / mean_dt) + 10) * mean_dt
    t = np.concatenate(([0.0], np.cumsum(steps)))
    return t[t <= duration]


def test_constant_speed_on_a_circle_matches_the_closed_form() -> None:
    # v = 2 m/s, w = 0.3 rad/s: x = v/w sin(wt), y = v/w (1 - cos(wt)) from the origin heading +x.
    v, w = 2.0, 0.3
    t_odo = irregular_times(40.0, 0.05, seed=1)
    t_gyro = irregular_times(41.0, 0.01, seed=2)
    track = deadreckon.dead_reckon(t_odo, np.full_like(t_odo, v), t_gyro, w * t_gyro)
    t = track.t
    np.testing.assert_allclose(track.x, v / w * np.sin(w * t), atol=1e-9)
    np.testing.assert_allclose(track.y, v / w * (1 - np.cos(w * t)), atol=1e-9)
    assert track.distance == pytest.approx(v * (t[-1] - t[0]), rel=1e-3)  # chords of the circle


def test_start_position_and_heading_offset_move_the_track_rigidly() -> None:
    v, w = 1.5, -0.2
    t = irregular_times(20.0, 0.1, seed=3)
    base = deadreckon.dead_reckon(t, np.full_like(t, v), t, w * t)
    moved = deadreckon.dead_reckon(t, np.full_like(t, v), t, w * t, position=(5.0, -2.0), heading_offset=math.pi / 2)
    # Rotating by +90 degrees maps (x, y) to (-y, x).
    np.testing.assert_allclose(moved.x, 5.0 - base.y, atol=1e-9)
    np.testing.assert_allclose(moved.y, -2.0 + base.x, atol=1e-9)


def square_lap(side: float, speed: float, scale: float, dt: float = 0.05) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """FOG's square path: four sides at ``speed``, turning 90 degrees on the spot (speed 0) after
    each; the gyro reads each turn ``(1 + scale)`` times too large. Speed ramps up and down within
    one step at each end of a side, so each side is ``speed * (T - dt)`` long on the grid."""
    t_side = side / speed + dt
    t_turn = 3.0
    times, speeds, headings = [], [], []
    now, heading = 0.0, 0.0
    for _ in range(4):
        n = int(round(t_side / dt))
        ts = now + dt * np.arange(n + 1)
        sp = np.full(n + 1, speed)
        sp[0] = sp[-1] = 0.0
        times.append(ts[:-1])
        speeds.append(sp[:-1])
        headings.append(np.full(n, heading))
        now = ts[-1]
        m = int(round(t_turn / dt))
        tt = now + dt * np.arange(m)
        times.append(tt)
        speeds.append(np.zeros(m))
        headings.append(heading + (math.pi / 2) * (1 + scale) * np.arange(m) / m)
        now += t_turn
        heading += (math.pi / 2) * (1 + scale)
    times.append(np.array([now]))
    speeds.append(np.array([0.0]))
    headings.append(np.array([heading]))
    return np.concatenate(times), np.concatenate(speeds), np.concatenate(headings)


def test_square_path_returns_to_its_start_with_a_perfect_gyro() -> None:
    t, v, psi = square_lap(4.0, 0.4, scale=0.0)
    track = deadreckon.dead_reckon(t, v, t, psi)
    assert deadreckon.return_position_error(track) == pytest.approx(0.0, abs=1e-9)
    assert track.distance == pytest.approx(16.0, rel=1e-9)


@pytest.mark.parametrize("scale", [0.01, -0.02])
def test_square_path_return_position_error_of_a_scale_error(scale: float) -> None:
    # Side k points along k * theta, theta = 90 deg (1 + s): error = L |sum_k exp(i k theta)|.
    t, v, psi = square_lap(4.0, 0.4, scale=scale)
    track = deadreckon.dead_reckon(t, v, t, psi)
    theta = (math.pi / 2) * (1 + scale)
    expected = 4.0 * abs(sum(complex(math.cos(k * theta), math.sin(k * theta)) for k in range(4)))
    assert deadreckon.return_position_error(track) == pytest.approx(expected, rel=1e-9)
    assert expected > 0.05  # the case is not trivially zero


def test_return_position_error_subtracts_the_true_displacement() -> None:
    t = np.linspace(0.0, 10.0, 101)
    track = deadreckon.dead_reckon(t, np.full_like(t, 1.0), t, np.zeros_like(t))
    assert deadreckon.return_position_error(track) == pytest.approx(10.0)
    assert deadreckon.return_position_error(track, displacement=(10.0, 0.0)) == pytest.approx(0.0, abs=1e-12)


def test_position_errors_against_a_shifted_reference() -> None:
    t = np.linspace(0.0, 10.0, 101)
    track = deadreckon.dead_reckon(t, np.full_like(t, 1.0), t, np.zeros_like(t))
    errors = deadreckon.position_errors(track, t, t, np.full_like(t, 0.5))  # reference 0.5 m to the left
    assert errors.mean_error_m == pytest.approx(0.5)
    assert errors.final_error_m == pytest.approx(0.5)
    assert errors.distance_m == pytest.approx(10.0)
    assert errors.final_error_percent == pytest.approx(5.0)


def test_bad_input_names_what_and_where() -> None:
    t = np.array([0.0, 1.0, 1.0, 2.0])
    with pytest.raises(ValueError, match=r"t_speed must strictly increase: t_speed\[2\] = 1.0 follows 1.0"):
        deadreckon.dead_reckon(t, np.ones(4), np.arange(4.0), np.zeros(4))
    with pytest.raises(ValueError, match=r"speed\[1\] is nan: samples must be finite"):
        deadreckon.dead_reckon(np.arange(3.0), [1.0, math.nan, 1.0], np.arange(3.0), np.zeros(3))
    with pytest.raises(ValueError, match="the odometry has fewer than two samples inside the heading.s time span"):
        deadreckon.dead_reckon(np.arange(3.0) + 10, np.ones(3), np.arange(3.0), np.zeros(3))


@pytest.mark.parametrize("name", ["f110_ds3", "comma_seg40"])
def test_real_odometry_tracks_the_reference_and_a_better_heading_helps(name: str) -> None:
    log = gyrocore.read_log(real_log_path(name))
    # The reference's own heading: what odometry alone can do (typical dead reckoning: ~2 % of distance).
    own = gyrocore.HeadingResult(log.t_ref, np.unwrap(log.heading_ref), log.t_ref * 0, log.t_ref * 0)
    track = deadreckon.dead_reckon_log(log, own)
    best = deadreckon.position_errors(track, log.t_ref, log.x_ref, log.y_ref)
    assert best.final_error_percent < 2.0
    assert track.distance == pytest.approx(best.distance_m, rel=0.07)  # odometry is in m/s
    bias = {} if log.stationary is not None else {"bias_duration": 10.0}
    errors = {}
    for preset, extra in (("raw", {}), ("static_bias", bias)):
        tr = deadreckon.dead_reckon_log(log, log.process(preset, **extra))
        errors[preset] = deadreckon.position_errors(tr, log.t_ref, log.x_ref, log.y_ref).final_error_m
    assert errors["static_bias"] < errors["raw"] / 5

"""Rest tracking (track_rests=True): rests found from speed and from the rate, the bias filter,
chunk invariance and pickling, and named errors for bad speed input and bad settings."""

from __future__ import annotations

import math
import pickle
import warnings

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
        assert abs(rest.bias - bias[inside].mean()) < 4 * rest.bias_std_error
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
        ({"speed": [1.0, 2.0], "speed_t": [0.0, 1.0, 2.0]}, "speed: speed has 2 samples but t has 3"),
        ({"speed": [1.0, 2.0, 3.0], "speed_t": [0.0, 2.0, 1.0]}, r"speed: t must strictly increase: t\[2\] = 1.0 follows 2.0"),
        ({"speed": [1.0, 2.0], "speed_t": [0.0, np.inf]}, r"speed: t\[1\] is inf"),
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


def stop_and_go(cycles: int, stop: float, go: float, turn: float) -> gyrocore.motion.Motion:
    """A drive that stops ``cycles`` times: each cycle stands ``stop`` seconds, then drives ``go``
    seconds at 5 m/s turning at ``turn`` rad/s (1 s ramps in and out)."""
    knots, rate, speed = [0.0], [0.0], [0.0]
    for _ in range(cycles):
        for dt, r, v in ((stop, 0.0, 0.0), (1.0, turn, 5.0), (go - 2.0, turn, 5.0), (1.0, 0.0, 0.0)):
            knots.append(knots[-1] + dt)
            rate.append(r)
            speed.append(v)
    return gyrocore.motion.Motion("stop and go", np.array(knots), np.array(rate), np.array(speed))


def test_every_stop_of_a_long_drive_is_reported_however_it_is_chunked() -> None:
    # 100 stops with a bias that wanders (the XV3500 with a strong rate random walk): the core hands
    # over every rest as it ends, so none is lost, in one call or many, across a pickle. White
    # noise (no sensor bandwidth): the change test judges block means by white noise, and the
    # 20 Hz bandwidth's correlated noise makes it split a stop now and then (docs/rest_tracking.md).
    route = stop_and_go(100, 6.0, 14.0, 0.1)
    spec = sim.sensor("xv3500", scale_error=0.0, bandwidth_hz=math.inf, rrw_deg_per_h_per_sqrt_h=400.0)
    drive = sim.simulate(route, spec, seed=5)
    t, r, speed = drive.t, drive.rate_measured, drive.speed
    whole = gyrocore.process(t, r, "static_bias", mode="causal", speed=speed, **tracked())
    stops = [(20.0 * k, 20.0 * k + 6.0) for k in range(100)]
    assert len(whole.tracked_rests) == 100
    for rest, (a, b) in zip(whole.tracked_rests, stops):
        assert a <= rest.start < rest.end <= b, (rest, a, b)
        assert rest.found_by == "speed" and rest.filtered is not None
    # The filtered bias follows the wandering bias within its standard errors.
    z = [
        (rest.bias - drive.bias - drive.drift[(t >= rest.start) & (t <= rest.end)].mean()) / rest.bias_std_error
        for rest in whole.tracked_rests
    ]
    assert np.mean(np.abs(z) < 4) > 0.95, z
    p = gyrocore.Pipeline("static_bias", **tracked())
    cuts = [0, 7, 5000, 5001, 77777, 123456, len(t)]
    found = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        found += p.process(t[a:b], r[a:b], speed=speed[a:b], index_offset=a).tracked_rests
        p = pickle.loads(pickle.dumps(p))
    assert found == list(whole.tracked_rests) == p.rests


def test_the_dead_band_widens_with_the_bias_uncertainty_between_two_stops() -> None:
    # Stops at 0-10 s and 150-165 s; between them and after, a steady turn of 0.04 rad/s. The bias
    # wanders (a strong rate random walk), and the filter's walk is the gyro's: its standard error
    # grows from the first stop to the second, and the dead band (3 standard deviations of the
    # noise and that error together) with it, until the second stop measures the bias again.
    delta = 0.04
    knots = np.array([0.0, 10.0, 11.0, 149.0, 150.0, 165.0, 166.0, 200.0])
    rate = np.array([0.0, 0.0, delta, delta, 0.0, 0.0, delta, delta])
    speed = np.array([0.0, 0.0, 5.0, 5.0, 0.0, 0.0, 5.0, 5.0])
    route = gyrocore.motion.Motion("two stops", knots, rate, speed)
    spec = sim.sensor("xv3500", scale_error=0.0, rrw_deg_per_h_per_sqrt_h=20000.0)
    drive = sim.simulate(route, spec, seed=2)
    k = math.radians(spec.rrw_deg_per_h_per_sqrt_h / 3600.0) / 60.0  # rad/s/sqrt(s)
    walk = rests.bias_walk(rate_random_walk=k, bias_instability=math.radians(spec.bias_instability_deg_per_h / 3600.0))
    p = gyrocore.Pipeline("static_bias", bias=0.0, track_rests=True, rest_bias_walk=walk, threshold_sigmas=3.0)
    t, r, v = drive.t, drive.rate_measured, drive.speed
    sigma, bands_ok = {}, []
    for second in range(200):
        inside = (t >= second) & (t < second + 1)
        before = p.tracked_bias
        out = p.process(t[inside], r[inside], speed=v[inside])
        after = p.tracked_bias
        assert after is not None or second < 10
        if after is None or before is None or before[1] is None or p.rests[-1].end > second - 2:
            continue  # no band yet, or a rest just ended (the bias changed within the second)
        sigma[second] = after[1]
        noise = p.rests[0].noise
        low, high = (3 * math.hypot(noise, s) for s in (before[1], after[1]))  # type: ignore[arg-type]
        corrected = r[inside] - after[0]
        assert out.rate is not None
        cut = out.rate == 0.0
        # Cut where the reading is inside the band, passed where it is outside.
        bands_ok.append(bool((np.abs(corrected[cut]) < high).all() and (np.abs(corrected[~cut]) >= low).all()))
    assert all(bands_ok) and len(bands_ok) > 150
    assert sigma[148] > 3 * sigma[15], (sigma[15], sigma[148])
    assert sigma[170] < sigma[148] / 2, (sigma[148], sigma[170])


@pytest.mark.filterwarnings("ignore:preset 'static_bias' removes a static bias")  # where no rest is found: not the subject
@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize(("shift", "scale", "covered", "inside"), [(1.7e9, 1.0, "0", 0), (0.0, 1e9, "100", 1), (45.0, 1.0, "25", 150)])
def test_a_speed_in_another_time_base_or_unit_warns(mode: str, shift: float, scale: float, covered: str, inside: int) -> None:
    t = np.arange(0.0, 60.0, 0.01)
    speed = np.where((t > 20) & (t < 30), 0.0, 5.0)
    rate = 0.003 + np.where(speed > 0, 0.1 * np.sin(t), 0.0)
    causal = {"track_rests": True, "bias": 0.0} if mode == "causal" else {}
    speed_t = t[::10] * scale + shift
    with pytest.warns(gyrocore.InputWarning, match=rf"speed: its times \(\[.*\] s\) cover {covered} % of the gyro's \[0, 59.99\] s, "
                      rf"with {inside} speed sample\(s\) inside it: .*in the gyro's clock, in seconds"):
        gyrocore.process(t, rate, "static_bias", mode=mode, speed=speed[::10], speed_t=speed_t, **causal)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_speed_times_without_a_speed_are_refused(mode: str) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    causal = {"track_rests": True, "bias": 0.0} if mode == "causal" else {}
    with pytest.raises(ValueError, match="speed_t is given without speed: give the speed"):
        gyrocore.process(t, np.zeros_like(t), "static_bias", mode=mode, speed_t=t, **causal)


def test_a_stream_given_its_odometry_as_it_comes_is_told_to_hold_the_gyro_back() -> None:
    """Odometry at its own times, given with each chunk as it comes, leaves the chunk's last gyro
    samples past its last speed: judged by the rate alone, they broke the rest, and the stream
    found none where one call found one, without a word. Held back (docs/python.md), the stream is
    one call, bit for bit."""
    d = sim.car_drive(duration=60.0, rate_hz=50.0, seed=4)
    t, rate = d.t, d.rate_measured
    st, sp = t[::5] + 0.013, d.speed[::5]  # odometry at 10 Hz on its own clock ticks
    with pytest.warns(gyrocore.InputWarning, match="removes a static bias"):
        whole = gyrocore.Pipeline("tracked").process(t, rate, speed=sp, speed_t=st)
    assert len(whole.tracked_rests) == 1
    naive, held, parts = gyrocore.Pipeline("tracked"), gyrocore.Pipeline("tracked"), []
    start, said = 0, []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for a in range(0, len(t), 25):
            b = min(a + 25, len(t))
            k = int(np.searchsorted(st, t[b - 1], side="right"))  # the odometry received by then
            naive.process(t[a:b], rate[a:b], speed=sp[:k], speed_t=st[:k])
            end = len(t) if b == len(t) else int(np.searchsorted(t, st[k - 1], side="right"))
            j = max(int(np.searchsorted(st, t[start], side="right")) - 1, 0) if start < len(t) else 0
            parts.append(held.process(t[start:end], rate[start:end], speed=sp[j:k], speed_t=st[j:k]))
            start = end
            said.append(sum("lie outside the times of the speed" in str(w.message) for w in caught))
    assert not naive.rests
    assert said[1] == 1 and said[-2] == 1  # the naive stream's second chunk says it, once
    assert np.concatenate([p.heading for p in parts]).tobytes() == whole.heading.tobytes()
    assert len(held.rests) == 1


def test_a_stream_too_slow_for_the_trackers_blocks_is_told_so() -> None:
    # the drive at 3.3 Hz: a block of 0.5 s holds one reading, no block is still, and the
    # tracker found no rest without a word; blocks of two sample intervals find rests in both stops
    t, reading, speed, _ = drive()
    t, reading, speed = t[::30], reading[::30], speed[::30]
    with pytest.warns(gyrocore.InputWarning, match=r"blocks of rest_block = 0.5 s hold fewer than two readings at "
                      r"this stream's rate \(3.33 Hz\).*rest_block of at least two sample intervals \(0.6 s\)"):
        result = gyrocore.process(t, reading, mode="causal", speed=speed, **tracked())
    assert result.tracked_rests == ()
    with warnings.catch_warnings():
        warnings.simplefilter("error", gyrocore.InputWarning)
        fitting = gyrocore.process(t, reading, mode="causal", speed=speed, **tracked(rest_block=0.6, rest_min_duration=1.2))
    stop_of = [[i for i, (a, b) in enumerate(STOPS) if a <= r.start < r.end <= b] for r in fitting.tracked_rests]
    assert {i for inside in stop_of for i in inside} == {0, 1} and all(stop_of)  # each stop, nothing outside

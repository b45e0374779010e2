"""Whole-log mode: the bias from every rest in the log, known from the first sample."""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pa_csv
import pytest

import gyrocore
from gyrocore import calibration
from gyrocore.batch import process_file
from gyrocore._smoother import smooth

from .conftest import gyrocore_cli as run_cli, real_log_path

RATE_HZ = 100.0
NOISE = 0.01  # rad/s, one reading


def drive(
    duration: float,
    rests: list[tuple[float, float]],
    bias: float | Callable[[np.ndarray], np.ndarray] = 0.01,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(t, measured rate, true rate)``: turning all the time except in ``rests``; ``bias`` is a
    number or a function of t [rad/s]."""
    rng = np.random.default_rng(seed)
    t = 1000.0 + np.arange(0.0, duration, 1.0 / RATE_HZ)
    true = 0.3 * np.sin(2 * math.pi * (t - t[0]) / 17.0) + 0.1
    for a, b in rests:
        true[(t >= t[0] + a) & (t <= t[0] + b)] = 0.0
    b_t = bias(t) if callable(bias) else np.full_like(t, bias)
    return t, true + b_t + rng.normal(0.0, NOISE, len(t)), true


def stop_speed(t: np.ndarray, stops: list[tuple[float, float]]) -> np.ndarray:
    """A speed [m/s] of 4 that is 0 in ``stops`` (seconds from the first sample), as odometry reads it."""
    speed = np.full_like(t, 4.0)
    for a, b in stops:
        speed[(t >= t[0] + a) & (t <= t[0] + b)] = 0.0
    return speed


def window(t: np.ndarray, a: float, b: float) -> tuple[float, float]:
    return float(t[0] + a), float(t[0] + b)


def heading_gap(a: gyrocore.HeadingResult, b: gyrocore.HeadingResult) -> float:
    return float(np.max(np.abs(a.heading - b.heading)))


def test_a_rest_in_the_middle_gives_its_bias_from_the_first_sample() -> None:
    t, rate, _ = drive(120.0, [(50.0, 62.0)])
    whole = gyrocore.process(t, rate, "static_bias")
    assert len(whole.rests) == 1 and whole.rests[0].found_by == "rate"
    rest = whole.rests[0]
    assert t[0] + 50.0 <= rest.start <= t[0] + 51.0 and rest.end >= t[0] + 61.0
    given = calibration.static_bias(t, rate, window=(rest.start, rest.end)).bias
    assert given == pytest.approx(0.01, abs=3 * NOISE / math.sqrt(1000))
    expected = gyrocore.process(t, rate, "static_bias", bias=given)
    assert heading_gap(whole, expected) < 1e-9
    # The same from the window given, and unlike the causal pipeline, which corrects only after it.
    w = window(t, 50.0, 62.0)
    by_window = gyrocore.process(t, rate, "static_bias", bias_window=w)
    bias_w = calibration.static_bias(t, rate, window=w).bias
    assert heading_gap(by_window, gyrocore.process(t, rate, "static_bias", bias=bias_w)) < 1e-9
    assert by_window.rests[0].found_by == "given" and "applied from the first sample" in by_window.bias_source
    causal = gyrocore.process(t, rate, "static_bias", bias_window=w, mode="causal")
    assert heading_gap(causal, by_window) > 0.4  # 50 s of a 0.01 rad/s bias
    assert "(causal)" in causal.bias_source and causal.rests == ()


def test_a_rest_at_the_end_serves_the_start() -> None:
    t, rate, true = drive(90.0, [(80.0, 90.0)])
    whole = gyrocore.process(t, rate, "static_bias")
    (rest,) = whole.rests
    assert rest.end == t[-1]
    expected = gyrocore.process(t, rate, "static_bias", bias=calibration.static_bias(t, rate, window=(rest.start, rest.end)).bias)
    assert heading_gap(whole, expected) < 1e-9
    truth = gyrocore.integrate(t, true)
    assert np.max(np.abs(whole.heading - truth)) < 0.05  # raw integration drifts 0.9 rad
    assert np.max(np.abs(gyrocore.process(t, rate, "raw").heading - truth)) > 0.8


def applied_bias(result: gyrocore.HeadingResult, rate: np.ndarray) -> np.ndarray:
    """The bias whole mode subtracted (static_bias: the corrected rate is the rate minus it)."""
    return rate - result.output("rate")


@pytest.mark.parametrize("walk", [0.0, 2e-5, 1.0])
def test_two_rests_with_a_drift_between_them_are_smoothed(walk: float) -> None:
    # The bias drifts 0.024 rad/s over the drive; the stops sit at 10-25 s and 120-135 s, shown by
    # the speed (two rests the rate alone found that disagree this much are refused: see below)
    stops = [(10.0, 25.0), (120.0, 135.0)]
    t, rate, _ = drive(150.0, stops, bias=lambda t: 0.004 + 0.0002 * (t - t[0]))
    whole = gyrocore.process(t, rate, "static_bias", bias_walk=walk, speed=stop_speed(t, stops))
    first, second = whole.rests
    for r, mid in zip(whole.rests, (17.5, 127.5)):  # each rest's own mean, within 3 standard errors of 15 s of noise
        assert r.bias == pytest.approx(calibration.static_bias(t, rate, window=(r.start, r.end)).bias, abs=1e-12)
        assert r.bias == pytest.approx(0.004 + 0.0002 * mid, abs=3 * NOISE / math.sqrt(1500))
        assert r.refused is None
    # Two measurements of a random walk: each rest's smoothed bias is the inverse-variance mean of
    # its own reading and the other's, whose variance grows by walk^2 per second between them.
    q_dt = walk**2 * (second.middle - first.middle)
    r0, r1 = first.bias_std_error**2, second.bias_std_error**2
    m0 = (first.bias / r0 + second.bias / (r1 + q_dt)) / (1 / r0 + 1 / (r1 + q_dt))
    m1 = (second.bias / r1 + first.bias / (r0 + q_dt)) / (1 / r1 + 1 / (r0 + q_dt))
    applied = applied_bias(whole, rate)
    np.testing.assert_allclose(applied, np.interp(t, [first.middle, second.middle], [m0, m1]), rtol=0, atol=1e-12)
    if walk == 0.0:  # no walk: one bias, the rests' weighted mean
        assert m0 == pytest.approx(m1, abs=1e-15)
    if walk == 1.0:  # a free walk: each rest's own bias, interpolated between them
        assert applied[0] == pytest.approx(first.bias, abs=1e-9) and applied[-1] == pytest.approx(second.bias, abs=1e-9)
    if walk == 2e-5:  # a walk about as uncertain as the rests: each pulled toward the other, in order
        assert first.bias < m0 < m1 < second.bias
        assert m0 - first.bias == pytest.approx((second.bias - first.bias) * r0 / (r0 + r1 + q_dt), rel=1e-9)
    if walk == 1.0:  # the smoothed bias follows the drift: within 10 % of it everywhere between the rests
        true = 0.004 + 0.0002 * (t - t[0])
        between = (t >= first.middle) & (t <= second.middle)
        assert np.max(np.abs(applied - true)[between]) < 0.1 * 0.0002 * 110
    assert "2 rests, bias smoothed between them" in whole.bias_source


def test_a_short_noisy_false_rest_gets_little_weight() -> None:
    # Two long stops read the bias 0.01 rad/s; a 1.5 s stop at 70 s reads 0.016 with 1.5 times
    # the noise (engine running, the car creeping): a reading of the bias, but a poor one. The
    # speed shows the stops (the rate alone does not take so short and noisy a stretch for rest).
    stops = [(5.0, 25.0), (69.0, 70.5), (115.0, 135.0)]
    t, rate, _ = drive(140.0, stops, seed=2)
    stop = (t >= t[0] + 69.0) & (t <= t[0] + 70.5)
    rng = np.random.default_rng(7)
    rate[stop] += 0.006 + rng.normal(0.0, 0.5 * NOISE * math.sqrt(5), np.count_nonzero(stop))
    speed = stop_speed(t, stops)
    whole = gyrocore.process(t, rate, "static_bias", bias_walk=2e-5, speed=speed)
    false = next(r for r in whole.rests if r.start > t[0] + 60.0)
    assert false.refused is None and false.bias == pytest.approx(0.016, abs=3 * false.bias_std_error)
    assert false.bias_std_error > 4 * max(r.bias_std_error for r in whole.rests if r is not false)
    applied = applied_bias(whole, rate)
    at_stop = applied[np.argmin(np.abs(t - false.middle))]
    assert abs(at_stop - 0.01) < 0.1 * abs(false.bias - 0.01)  # pulled a tenth of the way at most
    # The same stop with 3 times the noise of the rests is no rest at all: the rate does not show
    # one, and where the speed does, its noise refuses it.
    rate[stop] += rng.normal(0.0, 3 * NOISE, np.count_nonzero(stop))
    assert len(gyrocore.process(t, rate, "static_bias", bias_walk=2e-5).rests) == 2
    noisy = gyrocore.process(t, rate, "static_bias", bias_walk=2e-5, speed=speed)
    refused = [r for r in noisy.rests if r.refused is not None]
    assert len(refused) == 1 and "noise" in str(refused[0]) and "1 refused" in noisy.bias_source


def test_a_rest_that_reads_no_significant_bias_leaves_the_bias_at_0() -> None:
    # A gyro that is already calibrated: its rest reads 0 within its standard error, so whole mode
    # subtracts nothing (a stop's reading is not the bias while driving to better than that).
    t, rate, _ = drive(120.0, [(50.0, 55.0)], bias=0.0, seed=4)
    whole = gyrocore.process(t, rate, "static_bias")
    (rest,) = whole.rests
    assert abs(rest.bias) < 5 * rest.bias_std_error and "standard errors of 0: bias 0" in whole.bias_source
    np.testing.assert_array_equal(whole.heading, gyrocore.process(t, rate, "raw").heading)
    # asked to subtract any bias it reads, whole mode takes the rest's
    always = gyrocore.process(t, rate, "static_bias", bias_sigmas=0.0)
    assert heading_gap(always, gyrocore.process(t, rate, "static_bias", bias=rest.bias)) < 1e-9
    with pytest.raises(ValueError, match="invalid parameter bias_sigmas = -1.0: must be a finite number >= 0"):
        gyrocore.process(t, rate, "static_bias", bias_sigmas=-1.0)
    with pytest.raises(ValueError, match="used by mode='whole' only"):
        gyrocore.process(t, rate, "static_bias", bias_walk=1e-5, mode="causal")


def test_no_rest_at_all_warns_and_is_the_causal_result() -> None:
    t, rate, _ = drive(60.0, [])
    for preset in ("static_bias", "recommended"):
        with pytest.warns(gyrocore.InputWarning, match="no rest was found"):
            whole = gyrocore.process(t, rate, preset)
        with pytest.warns(gyrocore.InputWarning, match="no bias"):
            causal = gyrocore.process(t, rate, preset, mode="causal")
        assert whole.rests == () and "no rest found" in whole.bias_source
        np.testing.assert_array_equal(whole.heading, causal.heading)


def test_noise_scaled_preset_gets_the_bound_of_its_rest() -> None:
    # tuned bounds HDR by hdr_bound_sigmas standard errors of the rest: whole mode passes that
    # bound explicitly, as the causal pipeline would set it at the end of the rest. Here the gyro
    # drives straight with a bias 0.002 rad/s above the rest's, so HDR's correction runs into a
    # bound of 0.5 standard errors (about 1.4e-4 rad/s).
    t, rate, _ = drive(120.0, [(0.0, 120.0)], bias=lambda t: 0.012 - 0.002 * (np.abs(t - t[0] - 56.0) < 6.0), seed=3)
    w = window(t, 50.0, 62.0)
    p = gyrocore.Pipeline("tuned", bias_window=w, hdr_bound_sigmas=0.5)
    p.process(t, rate)
    stats = p.rest_statistics
    assert stats is not None
    bound = 0.5 * stats["bias_std_error"]
    expected = gyrocore.process(t, rate, "tuned", bias=p.bias, hdr_max_correction=bound)
    whole = gyrocore.process(t, rate, "tuned", bias_window=w, hdr_bound_sigmas=0.5)
    assert whole.rests[0].bias_std_error == stats["bias_std_error"] and whole.rests[0].noise == stats["noise"]
    assert heading_gap(whole, expected) < 1e-9
    assert np.max(np.abs(whole.drift)) == pytest.approx(bound, rel=1e-9)  # the bound is reached
    # a bound 1 % wider gives another heading
    wider = gyrocore.process(t, rate, "tuned", bias=p.bias, hdr_max_correction=1.01 * bound)
    assert heading_gap(whole, wider) > 1e-6


@pytest.mark.filterwarnings("ignore:preset 'static_bias' removes a static bias")  # before a refused causal call
def test_speed_finds_stops_and_drops_steady_driving() -> None:
    t, rate, _ = drive(120.0, [(30.0, 40.0), (70.0, 80.0)])
    speed = np.full_like(t, 8.0)
    stopped = (t >= t[0] + 30.0) & (t <= t[0] + 40.0)
    speed[stopped] = 0.0  # 70-80 s: the rate is steady, but the car drives straight
    assert len(gyrocore.process(t, rate, "static_bias").rests) == 2
    with_speed = gyrocore.process(t, rate, "static_bias", speed=speed)
    (rest,) = with_speed.rests
    assert rest.found_by == "speed"  # the stop, less half a second at each end
    assert rest.start == pytest.approx(t[stopped][0] + 0.5) and rest.end == pytest.approx(t[stopped][-1] - 0.5)
    with pytest.raises(ValueError, match="one speed per gyro sample"):
        gyrocore.process(t, rate, "static_bias", speed=speed[:-1])
    # in causal mode a speed is for the core's rest tracker only
    with pytest.raises(ValueError, match="speed is given but rest tracking is off: pass track_rests=True"):
        gyrocore.process(t, rate, "static_bias", speed=speed, mode="causal")
    with pytest.raises(ValueError, match="whole mode already takes it from every rest of the log"):
        gyrocore.process(t, rate, "static_bias", speed=speed, track_rests=True)
    with pytest.raises(ValueError, match="unknown mode .*; choose one of whole, causal"):
        gyrocore.process(t, rate, "static_bias", mode="smooth")


def test_a_speed_series_must_increase() -> None:
    t = np.arange(0.0, 10.0, 0.1)
    with pytest.raises(ValueError, match=r"odometry: t must strictly increase: t\[2\] = 1.0 follows 2.0"):
        gyrocore.wholelog.speed_on(t, [0.0, 2.0, 1.0], [0.0, 0.0, 0.0], where="odometry")
    with pytest.raises(ValueError, match=r"odometry: speed\[1\] is nan: samples must be finite"):
        gyrocore.wholelog.speed_on(t, [0.0, 2.0], [0.0, np.nan], where="odometry")
    # outside the series the speed is unknown, not held (and a series covering a tenth says so)
    with pytest.warns(gyrocore.InputWarning, match=r"speed: its times \(\[1, 2\] s\) cover 10.1 %"):
        assert np.isnan(gyrocore.wholelog.speed_on(t, [1.0, 2.0], [0.0, 0.0])[[0, -1]]).all()


def test_log_process_on_a_real_log_without_a_rest_at_the_start() -> None:
    # f110_ds1 moves at its first sample; it stops later, which the rate and the odometry show.
    log = gyrocore.read_log(real_log_path("f110_ds1"))
    assert log.stationary is None and log.speed is not None

    def e_psi(r: gyrocore.HeadingResult) -> float:
        return gyrocore.heading_errors(r.t, r.heading, *log.reference()).e_psi_deg

    whole = log.process("static_bias")
    assert len(whole.rests) >= 1 and "speed" in whole.rests[0].found_by
    with pytest.warns(gyrocore.InputWarning, match="no bias"):
        causal = log.process("static_bias", mode="causal")
    assert e_psi(whole) < 0.7 * e_psi(causal)  # the causal pipeline has no bias: raw integration
    assert all(r.found_by == "rate" for r in log.process("static_bias", use_speed=False).rests)


def test_file_streamed_in_chunks_measures_a_given_window_as_in_memory(tmp_path: Path) -> None:
    t, rate, _ = drive(60.0, [(20.0, 30.0), (50.0, 60.0)])
    src = tmp_path / "in.csv"
    pa_csv.write_csv(pa.table({"t": t, "gyro_z": rate}), src)
    read = pa_csv.read_csv(src)
    t_read, r_read = read["t"].to_numpy(), read["gyro_z"].to_numpy()
    for kwargs in ({"bias_window": window(t, 20.0, 30.0)}, {"bias_window": window(t, 50.0, 59.5)}, {}):
        report = process_file(src, tmp_path / "h.csv", preset="recommended", chunk_rows=700, **kwargs)
        out = pa_csv.read_csv(tmp_path / "h.csv")["heading"].to_numpy()
        expected = gyrocore.process(t_read, r_read, "recommended", **kwargs)
        np.testing.assert_allclose(out, expected.heading, rtol=0, atol=1e-12)
        assert report.rests == expected.rests and report.bias_source == expected.bias_source


def test_cli_process_whole_by_default_and_causal_on_request(tmp_path: Path) -> None:
    path = real_log_path("f110_ds1")
    whole = run_cli("process", str(path), "--out", str(tmp_path / "w.csv"), "--preset", "static_bias")
    causal = run_cli("process", str(path), "--out", str(tmp_path / "c.csv"), "--preset", "static_bias", "--causal")
    assert whole.returncode == causal.returncode == 0, whole.stderr + causal.stderr
    assert "bias: rest [" in whole.stdout and "applied from the first sample" in whole.stdout
    assert "(causal)" in causal.stdout and "was given: the bias is taken as 0 (on the command line" in causal.stderr
    log = gyrocore.read_log(path)
    written = {k: pa_csv.read_csv(tmp_path / f"{k}.csv")["heading"].to_numpy() for k in "wc"}
    np.testing.assert_allclose(written["w"], log.process("static_bias").heading, rtol=0, atol=1e-12)
    np.testing.assert_allclose(written["c"], gyrocore.integrate(log.t, log.rate), rtol=0, atol=1e-12)


def test_cli_evaluate_prints_the_bias_source_and_rests_of_each_method() -> None:
    path = str(real_log_path("f110_ds1"))
    whole = run_cli("evaluate", path, "--preset", "static_bias", "--preset", "recommended")
    assert whole.returncode == 0, whole.stderr
    assert "bias source:" in whole.stdout and "static_bias, recommended: rest [" in whole.stdout
    assert "(speed)" in whole.stdout
    no_speed = run_cli("evaluate", path, "--preset", "static_bias", "--no-speed", "--json")
    rows = json.loads(no_speed.stdout)
    assert [r["found_by"] for r in rows[0]["rests"]] == ["rate"]
    causal = run_cli("evaluate", path, "--preset", "static_bias", "--causal", "--json")
    (row,) = json.loads(causal.stdout)
    assert row["rests"] == [] and "(causal)" in row["bias_source"]
    assert row["e_psi_deg"] > json.loads(run_cli("evaluate", path, "--preset", "static_bias", "--json").stdout)[0]["e_psi_deg"]


def test_cli_evaluate_says_once_that_a_log_has_no_rest() -> None:
    proc = run_cli("evaluate", str(real_log_path("comma_seg40")), "--preset", "static_bias", "--preset", "hdr")
    assert proc.returncode == 0, proc.stderr
    # besides the note that its gnss.csv is not used (tests/python/test_inputs_named.py)
    lines = [line for line in proc.stderr.splitlines() if not line.startswith("gyrocore: note:")]
    # the two presets' same warning once, naming both (each printed it: six lines for all presets)
    warned = f"gyrocore: warning: {real_log_path('comma_seg40')}: presets 'static_bias' and 'hdr' remove a static bias"
    assert len(lines) == 1 and lines[0].startswith(warned)
    assert "no rest was found" in lines[0] and "static_bias, hdr: none: no rest found in the log; bias 0" in proc.stdout


@pytest.mark.parametrize("name", ["f110_ds1", "f110_ds5"])
def test_f110_logs_without_a_rest_at_the_start_beat_raw_integration(name: str) -> None:
    # Issue 17's bar: the stop later in the drive serves the whole log.
    log = gyrocore.read_log(real_log_path(name))
    assert log.stationary is None
    raw = log.process("raw")
    for preset in ("static_bias", "recommended"):
        r = log.process(preset)
        assert r.rests and gyrocore.heading_errors(r.t, r.heading, *log.reference()).e_psi_deg < 0.7 * (
            gyrocore.heading_errors(raw.t, raw.heading, *log.reference()).e_psi_deg
        )


def test_batch_is_whole_by_default_and_causal_on_request(tmp_path: Path) -> None:
    from gyrocore.batch import process_many

    logs = [real_log_path("f110_ds1"), real_log_path("broad_10")]
    whole = process_many(logs, preset="static_bias", out_dir=tmp_path / "w", jobs=1)
    with pytest.warns(gyrocore.InputWarning, match="removes a static bias, but no bias, bias_window or bias_duration was given"):
        causal = process_many(logs, preset="static_bias", out_dir=tmp_path / "c", jobs=1, mode="causal")
    assert [len(r.rests) for r in whole.files] == [1, 1] and [len(r.rests) for r in causal.files] == [0, 0]
    assert whole.files[1].rests[0].found_by == "given" and all("(causal)" in (r.bias_source or "") for r in causal.files)
    with pytest.raises(ValueError, match="unknown mode .*; choose one of whole, causal"):
        process_many(logs, preset="static_bias", out_dir=tmp_path / "x", mode="offline")
    with pytest.raises(ValueError, match="invalid parameter min_rest = -1"):
        process_many(logs, preset="static_bias", out_dir=tmp_path / "x", min_rest=-1)
    with pytest.raises(ValueError, match="bias_walk: used by mode='whole' only"):
        process_many(logs, preset="static_bias", out_dir=tmp_path / "x", mode="causal", bias_walk=1e-4)
    strict = process_many(logs[:1], preset="static_bias", out_dir=tmp_path / "s", jobs=1, bias_sigmas=100.0)
    assert "standard errors of 0: bias 0" in (strict.files[0].bias_source or "")
    assert not (tmp_path / "x").exists()  # refused before any work


@pytest.mark.parametrize("name", ["2011_09_30_0018", "2011_09_30_0020", "2011_09_30_0027", "2011_09_30_0033",
                                  "2011_09_30_0034", "2011_10_03_0042"])
@pytest.mark.parametrize("use_speed", [True, False])
def test_whole_mode_does_not_harm_the_kitti_true_rate_drives(name: str, use_speed: bool) -> None:
    # Issue 17's bar: the OXTS rate is already bias-corrected; its stops read a few hundredths of
    # a deg/s (the car rocking), which whole mode must not take for a bias. From the rate alone
    # (a log without odometry) slow driving passes for rest too: on 0034 three rate rests within
    # 8 s read 0.20, 0.07 and 0.02 deg/s, and a bias walk of 1e-3 rad/s/sqrt(s) let the smoother
    # follow them (12.3 deg against raw 0.40); at the default 1e-4 the first is refused and the
    # other two read 4.6 standard errors, within bias_sigmas (5) of 0 (test below).
    log = gyrocore.read_log(real_log_path(f"kitti_{name}"))

    def e_psi(r: gyrocore.HeadingResult) -> float:
        return gyrocore.heading_errors(r.t, r.heading, *log.reference()).e_psi_deg

    raw = e_psi(log.process("raw"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # three of them never stop: no rest, bias 0
        for preset in ("static_bias", "recommended"):
            assert e_psi(log.process(preset, use_speed=use_speed)) <= raw + 0.5


def test_kitti_0034_from_the_rate_alone_keeps_a_bias_of_0_as_docs_whole_log_says() -> None:
    # its three rate rests (slow driving, 10 Hz) span 3-5 blocks of 4 readings and read 10-18 % of
    # the drive's noise (the OXTS rate is smooth throughout): none is used, and the bias stays 0
    log = gyrocore.read_log(real_log_path("kitti_2011_09_30_0034"))
    r = log.process("static_bias", use_speed=False)
    assert [x.samples for x in r.rests] == [12, 15, 19]
    assert all(x.refused is not None and "too short and not quiet enough" in x.refused for x in r.rests)
    assert r.bias_source == "none: 3 rest(s) found, none used; bias 0"
    np.testing.assert_array_equal(r.heading, log.process("raw").heading)


def test_a_wandering_bias_is_followed_within_its_standard_error() -> None:
    # Six stops of 8 s in 260 s; the bias walks with K = 2e-4 rad/s/sqrt(s) (about 3e-3 rad/s
    # over the drive, ten standard errors of a stop), and whole mode is told that K.
    k, rng = 2e-4, np.random.default_rng(11)
    grid = np.arange(0.0, 261.0, 0.01)
    walk = 0.01 + np.concatenate(([0.0], np.cumsum(rng.normal(0.0, k * math.sqrt(0.01), len(grid) - 1))))
    stops = [(s, s + 8.0) for s in (5.0, 50.0, 100.0, 150.0, 200.0, 245.0)]
    t, rate, true = drive(260.0, stops, bias=lambda t: np.interp(t - t[0], grid, walk), seed=5)
    bias_true = np.interp(t - t[0], grid, walk)
    whole = gyrocore.process(t, rate, "static_bias", bias_walk=k)
    assert len(whole.rests) == 6 and all(r.refused is None for r in whole.rests)
    plan = gyrocore.wholelog.plan_arrays("static_bias", {}, t, rate, None, gyrocore.wholelog.Options(bias_walk=k))
    assert plan.smoothed is not None
    mean, sd = plan.smoothed.at(t)
    np.testing.assert_allclose(applied_bias(whole, rate), mean, rtol=0, atol=1e-12)
    z = (mean - bias_true) / sd
    assert np.max(np.abs(z)) < 4.0 and np.sqrt(np.mean(z**2)) < 2.0  # its standard error is honest
    # and it beats one constant bias from the same rests (walk 0) on the heading
    constant = gyrocore.process(t, rate, "static_bias", bias_walk=0.0)
    truth = gyrocore.integrate(t, true)
    assert np.mean(np.abs(whole.heading - truth)) < 0.5 * np.mean(np.abs(constant.heading - truth))


def test_found_rests_give_a_noise_scaled_preset_its_bound_and_dead_band() -> None:
    stops = [(10.0, 25.0), (120.0, 135.0)]
    t, rate, _ = drive(150.0, stops, bias=lambda t: 0.004 + 0.0002 * (t - t[0]))
    speed = stop_speed(t, stops)
    overrides = {"hdr_bound_sigmas": 2.0, "threshold_sigmas": 3.0}
    options = gyrocore.wholelog.Options(bias_walk=1e-5, hdr_bound_walk=1e-3)
    plan = gyrocore.wholelog.plan_arrays("tuned", overrides, t, rate, speed, options)
    assert plan.smoothed is not None and len(plan.used) == 2
    # the bias is smoothed with bias_walk; the bound grows away from the rests with hdr_bound_walk
    middles, biases, errors = ([getattr(r, k) for r in plan.used] for k in ("middle", "bias", "bias_std_error"))
    np.testing.assert_array_equal(plan.smoothed.at(t)[0], smooth(middles, biases, errors, 1e-5).at(t)[0])
    sd = smooth(middles, biases, errors, 1e-3).at(t)[1]
    assert plan.overrides["hdr_max_correction"] == pytest.approx(2.0 * math.sqrt(float(np.mean(sd**2))), rel=1e-12)
    narrow = smooth(middles, biases, errors, 1e-5).at(t)[1]
    assert np.sqrt(np.mean(narrow**2)) < 0.5 * np.sqrt(np.mean(sd**2))  # the two walks differ here
    noise = math.sqrt(sum(r.noise**2 * r.samples for r in plan.used) / sum(r.samples for r in plan.used))
    assert plan.overrides["threshold"] == pytest.approx(3.0 * noise, rel=1e-12)
    whole = gyrocore.process(t, rate, "tuned", bias_walk=1e-5, hdr_bound_walk=1e-3, speed=speed, **overrides)
    expected = gyrocore.process(t, rate - plan.bias(t), "tuned", **plan.overrides)
    np.testing.assert_array_equal(whole.heading, expected.heading)


def test_bias_free_gyros_are_not_harmed() -> None:
    # A perfect gyro and a noisy bias-free one stopping three times (found by the rate and by
    # the speed): their stops read no bias, so whole mode integrates them as raw integration does.
    stops = [(10.0, 20.0), (60.0, 63.0), (100.0, 112.0)]
    t, noisy, perfect = drive(120.0, stops, bias=0.0, seed=9)
    speed = stop_speed(t, stops)
    for rate in (perfect, noisy):
        for kwargs in ({}, {"speed": speed}):
            whole = gyrocore.process(t, rate, "static_bias", **kwargs)
            assert len(whole.rests) == 3 and "standard errors of 0: bias 0" in whole.bias_source
            np.testing.assert_array_equal(whole.heading, gyrocore.process(t, rate, "raw").heading)


def test_a_bad_sample_is_named_where_it_is_in_the_log(tmp_path: Path) -> None:
    # Nanoseconds read as seconds: the core refuses them. Whole mode measures its rests on slices
    # of the log first; the error must still name the log's first sample and its row.
    t = 1.7e18 + np.arange(0.0, 60.0, 0.01) * 1e9
    rate = np.where((t > t[0] + 20e9) & (t < t[0] + 30e9), 0.01, 0.3)
    with pytest.raises(gyrocore.SampleError, match=r"^t\[0\] = 1.7e\+?18 s is beyond") as e:
        with pytest.warns(gyrocore.InputWarning, match="timestamps look like ms, us or ns"):
            gyrocore.process(t, rate, "static_bias")
    assert e.value.index == 0
    src = tmp_path / "ns.csv"
    pa_csv.write_csv(pa.table({"t": t, "gyro_z": rate}), src)
    proc = run_cli("process", str(src), "--out", str(tmp_path / "h.csv"), "--preset", "static_bias")
    assert proc.returncode != 0 and "line 2" in proc.stderr and not (tmp_path / "h.csv").exists()


@pytest.mark.parametrize("options", [{"bias_duration": 10.0}, {}, {"bias_window": (1050.0, 1060.0)}])
def test_one_bias_for_the_log_is_the_cores_bias_with_no_copy_of_the_rate(
    options: dict[str, object], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A bias constant over the log (a given rest window, or the one rest found) is subtracted by
    the core, bit for bit as ``bias=`` that mean: the rate reaches the pipeline as the caller's
    array, not as a copy with the bias taken off."""
    t, rate, _ = drive(120.0, [(0.0, 12.0), (50.0, 60.0)] if "bias_window" in options else [(0.0, 12.0)])
    seen: list[np.ndarray] = []
    process = gyrocore.Pipeline.process

    def spy(self: gyrocore.Pipeline, t: np.ndarray, rate: np.ndarray, **kwargs: object) -> gyrocore.HeadingResult:
        seen.append(rate)
        return process(self, t, rate, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(gyrocore.Pipeline, "process", spy)
    whole = gyrocore.process(t, rate, "combined", **options)  # type: ignore[arg-type]
    (used,) = [r for r in whole.rests if r.refused is None]
    assert seen[-1] is rate and "applied from the first sample" in whole.bias_source
    exact = gyrocore.process(t, rate, "combined", bias=used.bias)
    for name in ("heading", "rate", "drift"):
        np.testing.assert_array_equal(whole.output(name).view(np.uint64), exact.output(name).view(np.uint64))

"""Whole-log mode on variations of a log (slower, cut, shifted): the rests it uses and the bias
it takes from them stay what the log shows."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import gyrocore
from gyrocore._rests import measure_rest

from .conftest import real_log_path
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


def ar1(rng: np.random.Generator, n: int, rho: float) -> np.ndarray:
    """``n`` readings of unit variance whose neighbours correlate by ``rho`` (first-order
    autoregressive, started in its stationary state)."""
    x = np.empty(n)
    x[0] = rng.normal()
    for i in range(1, n):
        x[i] = rho * x[i - 1] + np.sqrt(1.0 - rho * rho) * rng.normal()
    return x


@pytest.mark.parametrize("rho", [0.0, 0.8])
def test_a_rate_rest_of_correlated_readings_reads_the_error_of_their_mean(rho: float) -> None:
    # a rest the rate alone found, 40 readings whose neighbours correlate (a filtered rate): the
    # standard deviation of their mean is the textbook sum over lags, sqrt((1 + 2 sum_j (1 - j/n)
    # rho^j) / n); at rho 0.8 the white-noise error and batch means of 5 readings read 0.55 of it
    # (median of 300). A stop the speed shows keeps them (next test).
    n, rng = 40, np.random.default_rng(7)
    lags = np.arange(1, n)
    exact = NOISE * np.sqrt((1.0 + 2.0 * np.sum((1.0 - lags / n) * rho**lags)) / n)
    t = 1000.0 + np.arange(n) * 0.1
    errors = [measure_rest([(t, NOISE * ar1(rng, n, rho))], (t[0], t[-1]), "rate").bias_std_error for _ in range(300)]
    assert 0.8 < np.median(errors) / exact < 1.3


def test_a_stop_the_speed_shows_keeps_its_bias_when_the_log_is_interpolated() -> None:
    # f110_ds1 interpolated to twice and five times its rate, gyro and speed alike: counted as
    # correlated, its 0.76 s stop read +- 0.12 and 0.15 deg/s, its -0.40 deg/s bias within
    # bias_sigmas of 0, and the heading was raw integration's 6.69 deg against 3.62 as logged
    log = gyrocore.read_log(real_log_path("f110_ds1"))
    assert log.speed is not None and log.t_odometry is not None
    speed = np.interp(log.t, log.t_odometry, log.speed)
    for k in (2, 5):
        t = np.linspace(log.t[0], log.t[-1], (len(log.t) - 1) * k + 1)
        result = gyrocore.process(t, np.interp(t, log.t, log.rate), "static_bias", speed=np.interp(t, log.t, speed))
        (stop,) = [r for r in result.rests if r.accepted]
        assert stop.found_by == "speed" and abs(stop.bias) > 5 * stop.bias_std_error
        assert gyrocore.heading_errors(result.t, result.heading, *log.reference()).e_psi_deg < 3.62 + 0.5


@pytest.mark.parametrize("step", [2, 3])
def test_a_smooth_rate_taken_slower_keeps_slow_driving_from_passing_for_a_rest(step: int) -> None:
    # kitti_2011_09_30_0034 (the OXTS's filtered, bias-free rate) taken at 5 and 3.3 Hz, without
    # its speed: eight readings of slow driving pass the rate's rest test, and as white noise their
    # mean read 5.5 and 8.0 standard errors from 0, past bias_sigmas: 6.2 and 10.8 deg against raw
    # integration's 0.49 and 1.20. Their neighbours correlate (rho 0.55-0.61): counted, 2.2 and 2.9.
    log = gyrocore.read_log(real_log_path("kitti_2011_09_30_0034"))
    t, rate = log.t[::step], log.rate[::step]

    def e_psi(preset: str, mode: str) -> float:
        result = gyrocore.process(t, rate, preset, mode=mode)
        return gyrocore.heading_errors(result.t, result.heading, *log.reference()).e_psi_deg

    raw = e_psi("raw", "causal")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # the rests refused are reported
        assert e_psi("static_bias", "whole") <= raw + 0.5
        assert e_psi("recommended", "whole") <= raw + 0.5


def test_a_stop_a_noisy_speed_does_not_show_is_named_as_such() -> None:
    # f110_ds1's speed with 0.05 m/s of noise (a receiver's speed at rest): no run of 1 s stays under
    # 0.05 m/s, so no stop is found, and the warning said the steadiest stretch (its 1.5 s stop,
    # reading -0.4 deg/s) was "beyond 0.05 rad/s" and asked whether the rate was in deg/s
    log = gyrocore.read_log(real_log_path("f110_ds1"))
    noisy = np.asarray(log.speed) + np.random.default_rng(0).normal(0.0, 0.05, len(np.asarray(log.speed)))
    with pytest.warns(gyrocore.InputWarning) as caught:
        result = gyrocore.process(log.t, log.rate, "static_bias", speed=noisy, speed_t=log.t_odometry)
    (said,) = [str(w.message) for w in caught if "no rest was found" in str(w.message)]
    assert "beyond 0.05 rad/s" not in said and "rad/s read as" not in said
    assert ("the speed shows no stop (below 0.05 m/s for 1 s), but the rate is as steady as a rest 41.7647 .. 43.2407 s "
            "after the first sample, reading -0.3993 deg/s, where the speed reads -0.0721 .. 0.102 m/s") in said
    assert "use_speed=False, --no-speed" in said and result.rests == ()
    rate_only = log.process("static_bias", use_speed=False)  # what the hint offers: its stop from the rate
    assert gyrocore.heading_errors(rate_only.t, rate_only.heading, *log.reference()).e_psi_deg == pytest.approx(3.75, abs=0.005)

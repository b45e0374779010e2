"""Rests whole mode finds from the rate alone (no speed, no window): a steady turn reads as steady
as a rest, so such rests are used only when they agree with one another and are no chance run
of quiet readings (``gyrocore._rests.accept``)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import gyrocore
from gyrocore import tune
from gyrocore._rests import MIN_RATE_BLOCKS, QUIET_RATIO, accept
from gyrocore.rests import Rest

from .conftest import real_log_path

WALK = 1e-4


def rest(start: float, bias: float, found_by: str = "rate", seconds: float = 10.0, noise: float = 1e-3) -> Rest:
    """A rest at 100 Hz: ``seconds`` long, as many readings as that."""
    return Rest(start, start + seconds, bias, 1e-5, noise, int(100 * seconds) + 1, found_by)


@pytest.mark.parametrize(("mix", "seed", "noisy"), [("highway", 2002, False), ("highway", 2003, False),
                                                     ("highway", 2002, True), ("suburbs", 2004, True)])
def test_a_bias_free_gyro_on_gentle_curves_is_integrated_as_raw_integration(mix: str, seed: int, noisy: bool) -> None:
    # 20 minutes at 10 Hz without a rest window or a speed: steady curves passed for rests reading
    # 0.9-1.4 deg/s (a perfect gyro: 674 and 703 deg of error against raw integration's 0) or 1 s
    # runs of chance-quiet readings on a curve (a noisy one: 190 and 100 deg against 1.75 and 0.61)
    (case,) = tune.harm_cases(mixes=[mix], per_mix=1, first_seed=seed, noisy=noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # no rest used: the bias is taken as 0
        whole = gyrocore.process(case.t, case.rate, "static_bias")
    assert whole.bias_source.startswith("none: ") and all(r.refused is not None for r in whole.rests)
    np.testing.assert_array_equal(whole.heading, gyrocore.process(case.t, case.rate, "raw").heading)


def test_rests_from_the_rate_that_disagree_are_none_of_them_used() -> None:
    # two rests 100 s apart reading 0 and 0.02 rad/s: 0.02 is 20 sigma of a walk of 1e-4 over 100 s
    apart = accept([rest(0.0, 0.0), rest(100.0, 0.02)], WALK)
    assert all(r.refused is not None and "the rests found from the rate disagree" in r.refused for r in apart)
    # three that agree and one that does not: the one is refused as an outlier, and then the rest
    # with it, as the rate has shown it takes motion for rest
    four = accept([rest(0.0, 0.0), rest(100.0, 1e-4), rest(200.0, -1e-4), rest(300.0, 0.03)], WALK)
    assert "sigma from what the other rests give" in str(four[3].refused)
    assert all("the rests found from the rate disagree" in str(r.refused) for r in four[:3])
    together = accept([rest(0.0, 0.0), rest(100.0, 1e-4), rest(200.0, -1e-4)], WALK)
    assert all(r.refused is None for r in together)


def test_a_stop_the_speed_shows_is_kept_against_a_rest_of_the_rate() -> None:
    speed, rate = accept([rest(0.0, 0.0, "speed"), rest(100.0, 0.02)], WALK)
    assert speed.refused is None and rate.refused is not None and "disagree" in rate.refused
    both = accept([rest(0.0, 0.0, "speed"), rest(100.0, 0.02, "speed")], WALK)  # stops, whatever they read
    assert all(r.refused is None for r in both)


def test_a_short_rest_from_the_rate_must_be_far_quieter_than_the_motion() -> None:
    motion = 0.01
    short = 0.25 * MIN_RATE_BLOCKS - 0.1  # seconds: blocks of 0.25 s at 100 Hz
    loud, quiet, long = accept([rest(0.0, 0.0, seconds=short, noise=0.2 * motion),
                                rest(100.0, 0.0, seconds=short, noise=0.5 * QUIET_RATIO * motion),
                                rest(200.0, 0.0, seconds=0.25 * MIN_RATE_BLOCKS, noise=0.2 * motion)], WALK, motion)
    assert loud.refused is not None and "too short and not quiet enough" in loud.refused
    assert quiet.refused is None and long.refused is None
    # at 10 Hz a block holds 4 readings: 2 s hold 5 blocks
    (slow,) = accept([Rest(0.0, 2.0, 0.0, 1e-5, 0.2 * motion, 21, "rate")], WALK, motion)
    assert slow.refused is not None and "21 readings (5 blocks" in slow.refused
    # a log all at rest has no motion to compare with (NaN): its rests are kept
    assert accept([rest(0.0, 0.0, seconds=short)], WALK)[0].refused is None


def test_a_real_gyro_rests_far_quieter_than_it_drives() -> None:
    # f110_ds5 from the rate alone: its one stop lasts 1.2 s (under 8 blocks), and reads 1 % of
    # the motor-shaken drive's noise, so it is kept (26.94 deg raw, 3.13 with it)
    log = gyrocore.read_log(real_log_path("f110_ds5"))
    r = log.process("static_bias", use_speed=False)
    (used,) = r.rests
    assert used.refused is None and used.end - used.start < 0.25 * MIN_RATE_BLOCKS
    e_psi = gyrocore.heading_errors(r.t, r.heading, *log.reference()).e_psi_deg
    assert e_psi == pytest.approx(3.13, abs=0.005)


def test_two_rests_from_the_rate_whose_bias_walks_faster_than_the_walk_allows_are_refused() -> None:
    # Two 15 s rests 110 s apart reading 0.0075 and 0.0295 rad/s (a bias drifting 2e-4 rad/s per
    # second): 21 standard deviations of the default walk (1e-4 rad/s/sqrt(s)) apart. From the rate
    # alone they may be a rest and a steady curve, so neither is used and the warning says so; a
    # caller who knows the gyro drifts so gives its walk, and then both are smoothed.
    from .test_wholelog import drive, stop_speed

    stops = [(10.0, 25.0), (120.0, 135.0)]
    t, rate, _ = drive(150.0, stops, bias=lambda t: 0.004 + 0.0002 * (t - t[0]))
    with pytest.warns(gyrocore.InputWarning, match=r"2 rest\(s\) found, none used \(the rests found from the rate "
                      r"disagree .*\): the bias is taken as 0"):
        refused = gyrocore.process(t, rate, "static_bias")
    assert refused.bias_source == "none: 2 rest(s) found, none used; bias 0"
    drifting = gyrocore.process(t, rate, "static_bias", bias_walk=3e-3)
    assert [r.refused for r in drifting.rests] == [None, None]
    assert "2 rests, bias smoothed between them" in drifting.bias_source
    stopped = gyrocore.process(t, rate, "static_bias", speed=stop_speed(t, stops))  # stops the speed shows
    assert [r.refused for r in stopped.rests] == [None, None]


def test_a_stop_refused_against_the_rates_rests_is_judged_again_without_them() -> None:
    # A stop reading 0.01 rad/s, five rate rests reading 0 and one reading 0.006: the stop lay 10
    # sigma from the rate's rests and was refused, then the rate's rests were found to disagree and
    # dropped too, and nothing was used; the stop alone gives the bias
    rests = [rest(0.0, 0.01, "speed")] + [rest(100.0 * k, 0.0) for k in range(1, 6)] + [rest(600.0, 0.006)]
    stop, *rated = accept(rests, WALK)
    assert stop.refused is None
    assert all(r.refused is not None for r in rated)
    assert "disagree" in str(rated[0].refused) and "sigma from what the other rests give" in str(rated[-1].refused)


def test_a_few_quiet_readings_cannot_show_a_rest_twenty_times_quieter_than_the_motion() -> None:
    # 4 readings whose noise reads 0.036 of the motion's: over 3 successive differences the noise is
    # known only within a factor of 4.2 (95 %), so they do not show a rest 20 x quieter; 200 do
    motion = 0.01
    few, many = accept([Rest(0.0, 1.5, 0.0, 1e-5, 0.036 * motion, 4, "rate"),
                        Rest(100.0, 101.5, 0.0, 1e-5, 0.036 * motion, 200, "rate")], WALK, motion)
    assert few.refused is not None and "its noise 0.021 deg/s (at most 0.087 at 95 % confidence)" in few.refused
    assert many.refused is None


def test_a_steady_curve_of_a_bias_free_rate_averaged_to_2_hz_is_no_rest() -> None:
    # kitti_2011_10_03_0042 (OXTS rate, no bias, no stop) averaged over blocks of 5 readings, from
    # the rate alone: 4 readings of a steady curve read a twenty-eighth of the drive's noise and
    # were used as a rest, 0.58 deg/s removed from the whole drive (E_psi 35.72 deg, raw 0.82)
    log = gyrocore.read_log(real_log_path("kitti_2011_10_03_0042"))
    n = len(log.t) // 5 * 5
    t, rate = (x[:n].reshape(-1, 5).mean(axis=1) for x in (log.t, log.rate))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # no rest used: the bias is taken as 0
        whole = gyrocore.process(t, rate, "static_bias")
    raw = gyrocore.process(t, rate, "raw")
    assert all(r.refused is not None for r in whole.rests)
    errors = [gyrocore.heading_errors(r.t, r.heading, *log.reference()).e_psi_deg for r in (whole, raw)]
    assert errors[0] == pytest.approx(errors[1], abs=1e-9)

"""Numbers a hostile user gives the API's functions (calibration, Allan deviation, simulation,
whole mode's options): text, bools, NaN, infinities and huge values, each refused with the
argument's name, never a bare Python or numpy error, an overflow or a silently odd result."""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable

import numpy as np
import pytest

import gyrocore
from gyrocore import allan, calibration, deadband, motion, rests, sim

T = np.arange(0.0, 60.0, 0.01)
RATE = 0.002 + np.random.default_rng(0).normal(0.0, 0.001, len(T))


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: calibration.static_bias(T, RATE, min_duration="1"), TypeError, "min_duration must be a number, got '1'"),
        (lambda: calibration.rest_windows(T, RATE, min_duration=True), TypeError, "min_duration must be a number, got True"),
        (lambda: calibration.rest_windows(T, RATE, consistency="a"), TypeError, "consistency must be a number, got 'a'"),
        (lambda: calibration.rotary_table(T, RATE, turn_angle=0), ValueError, "turn_angle must be finite and > 0, got 0"),
        (lambda: calibration.rotary_table(T, RATE, tolerance=np.nan), ValueError, "tolerance must be finite and > 0"),
        (lambda: calibration.rotary_table(T, RATE, min_rest=np.nan), ValueError, "min_rest must be finite and > 0"),
        (lambda: calibration.rotary_table(T, RATE, min_pause=-1), ValueError, "min_pause must be finite and > 0, got -1"),
        (lambda: calibration.bias_temperature_table(T, RATE, 20 + T / 10, min_samples=0), ValueError,
         "min_samples must be a whole number >= 1, got 0"),
        (lambda: calibration.bias_temperature_table(T, RATE, 20 + T / 10, min_samples=2.5), ValueError,
         "min_samples must be a whole number >= 1, got 2.5"),
        (lambda: calibration.bias_temperature_table(T, RATE, 20 + T / 10, bin_width=True), TypeError,
         "bin_width must be a number [degC], got True"),
        (lambda: allan.deviation(RATE, "0.01"), TypeError, "dt must be a number [s], got '0.01'"),
        (lambda: allan.deviation(RATE, True), TypeError, "dt must be a number [s], got True"),
        (lambda: allan.deviation(RATE, 0.01, overlapping="no"), TypeError, "overlapping must be True or False, got 'no'"),
        (lambda: allan.deviation(RATE, 0.01, confidence="0.5"), TypeError, "confidence must be a number, got '0.5'"),
        (lambda: allan.deviation_from_timestamps(T, RATE, dt="x"), TypeError, "dt must be a number [s], got 'x'"),
        (lambda: allan.settings_from_noise(arw="1e-3", bias_instability=1e-5, dt=0.01), TypeError,
         "arw must be a number [rad/sqrt(s)], got '1e-3'"),
        (lambda: allan.settings_from_noise(arw=1e6, bias_instability=1e-11, dt=0.01), ValueError,
         "arw = 1e+06 and bias_instability = 1e-11 give T_bias = (N / 0.664 B)^2 = inf s, beyond the pipeline's 2^40 s"),
        # a bare OverflowError of N^2; settings of 0 the pipeline refused by their names; a dt of 1e300 s taken
        (lambda: allan.settings_from_noise(arw=1e300, bias_instability=1e300, dt=0.01), ValueError,
         "arw must be finite and > 1e-12 and at most 1.04858e+06 [rad/sqrt(s)], got 1e+300"),
        (lambda: allan.settings_from_noise(arw=1e-3, bias_instability=1e-300, dt=0.01), ValueError,
         "bias_instability must be finite and > 1e-12 and at most 1.04858e+06 [rad/s], got 1e-300"),
        (lambda: allan.settings_from_noise(arw=1e-3, bias_instability=1e-5, dt=1e300), ValueError,
         "dt must be finite and >= 1e-12 and at most 1.09951e+12 [s], got 1e+300"),
        (lambda: allan.noise_parameters(allan.deviation(RATE, 0.01), slope_tolerance=np.nan), ValueError,
         "slope_tolerance must be finite and > 0, got nan"),
        (lambda: allan.confidence_interval([1.0, 2.0], [3.0]), ValueError, "dev has 2 values but edf has 1"),
        (lambda: allan.confidence_interval([1.0], [0.0]), ValueError, "edf[0] = 0.0: must be finite and > 0"),
        (lambda: allan.confidence_interval([1.0], [np.nan]), ValueError, "edf[0] = nan: must be finite and > 0"),
        (lambda: allan.confidence_interval([1.0], [3.0], 1.0), ValueError, "confidence must lie in (0, 1), got 1.0"),
        (lambda: rests.bias_walk(rate_random_walk="1", bias_instability=1e-5), TypeError,
         "rate_random_walk must be a number, got '1'"),
        (lambda: rests.bias_walk(rate_random_walk=1e300, bias_instability=1e-5), ValueError,
         "rate_random_walk must be finite and >= 0 and at most 1.04858e+06, got 1e+300"),
        (lambda: deadband.expected_output([0.1], "a", 0.02), TypeError, "noise_rms must be a number, got 'a'"),
        (lambda: deadband.bias_leak(True, 0.02), TypeError, "noise_rms must be a number, got True"),
        (lambda: sim.car_drive(duration="30"), TypeError, "duration must be a number [s], got '30'"),
        (lambda: sim.car_drive(duration=30, rate_hz=True), TypeError, "rate_hz must be a number [Hz], got True"),
        (lambda: sim.car_drive(duration=30, rest=-1), ValueError, "rest must be finite and >= 0 [s], got -1"),
        (lambda: sim.car_drive(duration=30, rest="1"), TypeError, "rest must be a number [s], got '1'"),
        (lambda: sim.car_drive(duration=30, seed=-1), ValueError, "seed must be an integer in [0, 2**64), got -1"),
        (lambda: sim.car_drive(duration=30, bias_dps="x"), TypeError, "sensor field bias_dps must be a number, got 'x'"),
        (lambda: sim.car_drive(duration=30, bias_dps=True), TypeError, "sensor field bias_dps must be a number, got True"),
        (lambda: sim.sensor("crs03", temperature_c=20), TypeError, "sensor field temperature_c must be two numbers, got 20"),
        (lambda: sim.sensor("crs03", foo=1), TypeError, "unknown sensor field(s) foo; the fields are name, rate_hz"),
        # a spec built directly was not checked: a gyro at 1 Hz, a ZeroDivisionError, 0.05 deg/s of noise at -1 Hz
        (lambda: sim.GyroSpec(rate_hz=True), TypeError, "sensor field rate_hz must be a number, got True"),
        (lambda: sim.GyroSpec(rate_hz=0).noise_rms_dps, ValueError,
         "gyro model: invalid parameter rate_hz = 0: must be in [1e-6, 1e9] Hz"),
        (lambda: sim.sensor("crs03", rate_hz=-1).noise_rms_dps, ValueError, "gyro model: invalid parameter rate_hz = -1"),
        (lambda: sim.sensor("crs03", arw_deg_per_sqrt_h=-1), ValueError,
         "sensor field arw_deg_per_sqrt_h = -1: gyro model: invalid parameter arw = -0.00029"),
        (lambda: sim.simulate(None, "crs03", seed=0), TypeError,  # type: ignore[arg-type]
         "trajectory must be a gyrocore.motion.Motion (e.g. gyrocore.motion.car(600)), got NoneType"),
        (lambda: motion.rotary_table(runs=2, rate_dps=0), ValueError, "rate_dps must be finite and > 0, got 0"),
        (lambda: motion.rotary_table(runs=2, pause=-1), ValueError, "pause must be finite and >= 0 [s], got -1"),
        (lambda: motion.rotary_table(runs=1.5), ValueError, "runs must be a whole number >= 1, got 1.5"),
        (lambda: motion.square_path(speed=0), ValueError, "speed must be finite and > 0, got 0"),
        (lambda: motion.square_path(accel=np.nan), ValueError, "accel must be finite and > 0, got nan"),
        (lambda: motion.hdr_figure3(speed=np.nan), ValueError, "speed must be finite and > 0, got nan"),
        (lambda: motion.hdr_figure3(curve_dps=np.nan), ValueError, "curve_dps must be finite [deg/s], got nan"),
        (lambda: motion.robot_run(max_speed=np.nan), ValueError, "max_speed must be finite and > 0, got nan"),
        (lambda: motion.car(60, swerve_dps="a"), TypeError, "swerve_dps must be a number [deg/s], got 'a'"),
        (lambda: motion.car(60, swerve_dps=np.nan), ValueError, "swerve_dps must be finite [deg/s], got nan"),
        (lambda: motion.car(60, seed=-1), ValueError, "seed must be an integer in [0, 2**64), got -1"),
        (lambda: gyrocore.integrate(T, RATE, initial_heading="0"), TypeError, "initial_heading must be a number [rad], got '0'"),
        (lambda: gyrocore.integrate(T, RATE, initial_heading=True), TypeError, "initial_heading must be a number [rad], got True"),
        (lambda: gyrocore.integrate(T, RATE, None), TypeError, "method must be 'trapezoid' or 'rectangle', got None"),
        (lambda: gyrocore.downsample(T, RATE, "1"), TypeError, "interval must be a number [s], got '1'"),
        (lambda: gyrocore.downsample(T, RATE, True), TypeError, "interval must be a number [s], got True"),
        (lambda: calibration.bias_temperature_table(T, RATE * 1e300, 20 + T / 10), gyrocore.SampleError, "rate[0] = 2"),
        (lambda: calibration.static_bias(T, RATE, (False, True)), ValueError,
         "the rest window must be (start, end) in seconds, got (False, True)"),
    ],
)
def test_a_number_argument_that_is_no_number_or_out_of_range_is_named(
    call: Callable[[], object], error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match="^" + re.escape(message)):
        call()


def test_numbers_of_every_real_type_are_taken_as_they_are() -> None:
    """numpy scalars and 0-d arrays are numbers (whole mode refused a float32 as none)."""
    assert calibration.rest_windows(T, RATE, min_duration=np.float32(1.0)) == calibration.rest_windows(T, RATE)
    assert allan.deviation(RATE, np.float64(0.01)).dt == allan.deviation(RATE, np.array(0.01)).dt == 0.01
    low, high = allan.confidence_interval(1.0, 3.0)
    assert np.ndim(low) == np.ndim(high) == 0 and 0 < low < 1 < high  # one deviation in, one out
    single = gyrocore.process(T, RATE, "recommended", bias_walk=np.float32(1e-4))
    double = gyrocore.process(T, RATE, "recommended", bias_walk=float(np.float32(1e-4)))
    assert np.array_equal(single.heading, double.heading)


@pytest.mark.parametrize("name", ["bias_walk", "hdr_bound_walk"])
def test_a_walk_beyond_a_readings_limit_is_refused_not_overflowed(name: str) -> None:
    t = np.arange(0.0, 120.0, 0.01)
    rate = np.where((t > 40) & (t < 80), 0.3, 0.002) + np.random.default_rng(1).normal(0.0, 1e-3, len(t))
    with pytest.raises(ValueError, match=rf"^invalid parameter {name} = 1e\+300: must be a finite number >= 0 and at "
                                         r"most 2\^20 = 1048576"):
        gyrocore.process(t, rate, "recommended", **{name: 1e300})
    with pytest.raises(ValueError, match=rf"^invalid parameter {name} = True: must be a finite number"):
        gyrocore.process(t, rate, "recommended", **{name: True})
    assert np.isfinite(gyrocore.process(t, rate, "recommended", **{name: 2.0**20}).heading).all()  # the limit itself


def test_a_reading_beyond_the_limit_is_named_not_overflowed_in_a_fit() -> None:
    """1e300 overflowed the squares of rate_reference's fit (a numpy warning, then "the gyro's
    readings are constant") and gave bias_temperature_table's bins nonsense."""
    with pytest.raises(ValueError, match=r"^rate_measured\[0\] = .* rad/s is beyond \+-2\^20 rad/s"):
        calibration.rate_reference(RATE * 1e300, RATE)
    with pytest.raises(ValueError, match=r"^rate_reference\[0\] = .* rad/s is beyond \+-2\^20 rad/s"):
        calibration.rate_reference(RATE, RATE * 1e300)
    good = calibration.rate_reference(1.01 * RATE + 0.003, RATE)  # the limits take every plausible reading
    assert good.bias == pytest.approx(0.003, rel=1e-9)


@pytest.mark.parametrize("dtype", [np.float16, np.float32])
def test_times_too_coarse_for_their_samples_say_why_they_repeat(dtype: type) -> None:
    """float16 times step by 1/32 s near a minute: samples at 100 Hz repeat, and the error
    ("t[1602] = 16.015625 follows 16.015625") said nothing of the type."""
    t = (T + (1.7e9 if dtype == np.float32 else 0.0)).astype(dtype)
    with pytest.warns(gyrocore.InputWarning, match=rf"^the times are {np.dtype(dtype)}, which at their size resolve only"):
        with pytest.raises(gyrocore.SampleError, match="must strictly increase"):
            gyrocore.process(t, RATE, "raw")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # float16 times that resolve their samples are taken without a word
        assert len(gyrocore.process(np.arange(0.0, 1.0, 0.01).astype(np.float16), RATE[:100], "raw")) == 100


@pytest.mark.parametrize(
    ("build", "what"),
    [(lambda: motion.rotary_table(runs=10**9), "the rotary table of 1000000000 runs would last 4.8e+10 s"),
     (lambda: motion.square_path(runs=10**9), "the square path of 1000000000 runs would last 1.69e+11 s"),
     (lambda: motion.car(1e9), "the drive would last 1e+09 s"),
     (lambda: motion.hdr_figure3(duration=1e9), "the drive would last 1e+09 s"),
     (lambda: motion.robot_run(duration=1e9), "the robot run would last 1e+09 s")],
)
def test_a_motion_too_long_to_build_is_refused_before_it_is_built(build: Callable[[], object], what: str) -> None:
    """A billion runs, or a drive of a billion seconds, were built manoeuvre by manoeuvre until the
    memory ran out (a car drive of 1e6 s took over a minute)."""
    with pytest.raises(ValueError, match="^" + re.escape(what) + r", more than the 131072 s a motion may last"):
        build()
    assert motion.rotary_table(runs=2730).knots[-1] <= motion.MAX_DURATION  # up to the limit they are built


def test_a_calibration_of_rates_in_degrees_says_so_as_the_pipeline_does() -> None:
    """A static bias of 641 "rad/s" (a log in deg/s) came without a word."""
    rate_dps = np.degrees(RATE) * 100.0
    with pytest.warns(gyrocore.InputWarning, match=r"^rates look like deg/s, not rad/s"):
        calibration.static_bias(T, rate_dps, (0.0, 10.0))
    with pytest.warns(gyrocore.InputWarning, match=r"^timestamps look like ms, us or ns, not seconds"):
        calibration.static_bias(T * 1000.0, RATE, (0.0, 10000.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # rad/s and seconds: no word
        calibration.static_bias(T, RATE, (0.0, 10.0))


def test_masked_values_are_refused_where_any_shape_is_taken() -> None:
    """numpy.asarray dropped the mask: the hidden values were computed with as data."""
    rate = np.ma.masked_array([[0.1, 0.2], [0.3, 0.4]], mask=[[False, False], [True, False]])
    with pytest.raises(ValueError, match=r"^rate is a masked array with 1 masked value\(s\), the first at index \(1, 0\)"):
        deadband.expected_output(rate, 0.01, 0.02)
    table = calibration.bias_temperature_table(T, RATE, 20 + T / 10)
    with pytest.raises(ValueError, match=r"^temperature is a masked array with 1 masked value\(s\), the first at index 2"):
        table(np.ma.masked_array([20.0, 21.0, 22.0], mask=[False, False, True]))
    unmasked = np.ma.masked_array([20.0, 21.0, 22.0])
    assert np.array_equal(table(unmasked), table(unmasked.data))  # nothing masked: the values
    assert np.array_equal(deadband.expected_output(rate.data, 0.01, 0.02),
                          deadband.expected_output(np.ma.masked_array(rate.data), 0.01, 0.02))


def test_the_masked_values_hint_names_what_the_function_offers() -> None:
    # the hint named nonfinite='hold' or 'skip' for every function, also the Allan deviation and
    # integrate, which have no such parameter
    t = np.arange(0.0, 60.0, 0.01)
    rate = np.ma.masked_array(np.full_like(t, 0.002), mask=t >= 30.0)
    phase = np.ma.masked_array(np.cumsum(rate.data) * 0.01, mask=rate.mask)
    head = r"^{} is a masked array with 3000 masked value\(s\), the first at index 3000: "
    allan_hint = (r"an Allan deviation takes no missing reading: give the others with their times to "
                  r"allan\.deviation_from_timestamps \(it integrates over the intervals between them; a gap beyond "
                  r"10 median intervals is refused\), or analyse each unmasked stretch on its own$")
    for call, name in ((lambda: allan.deviation(rate, 0.01), "rate"),
                       (lambda: allan.phase_deviation(phase, 0.01), "phase"),
                       (lambda: allan.deviation_from_timestamps(t, rate), "rate"),
                       (lambda: allan.deviation_from_timestamps(np.ma.masked_array(t, mask=rate.mask), rate.data), "t")):
        with pytest.raises(ValueError, match=head.format(name) + allan_hint):
            call()
    with pytest.raises(ValueError, match=head.format("rate") + r"leave those samples out \(rate\.compressed\(\), "
                       r"and the others' times\), or fill them with values of your own \(rate\.filled\(value\)\)$"):
        gyrocore.integrate(t, rate)
    nonfinite = head.format("rate") + r"give rate\.filled\(numpy\.nan\) \(with nonfinite='hold' or 'skip'\)"
    for mode in ("whole", "causal"):  # these take nonfinite=
        with pytest.raises(ValueError, match=nonfinite):
            gyrocore.process(t, rate, "hdr", mode=mode)
        with pytest.warns(gyrocore.InputWarning, match="replaced by the last usable reading"):
            held = gyrocore.process(t, rate.filled(np.nan), "hdr", mode=mode, nonfinite="hold", bias=0.0)
        assert held.heading.shape == t.shape


def test_readings_beyond_the_limit_are_no_sign_of_degrees() -> None:
    """Glitches of 1e7 rad/s in 2 % of the samples, held by the input policy, made the unit check
    say the rates were deg/s and advise numpy.radians, which would have made the log 57 times too
    small; a reading of 1e308 added numpy's overflow warning before the core's error."""
    rate = RATE.copy()
    rate[::50] = 1e7
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        result = gyrocore.process(T, rate, "raw", nonfinite="hold")
    assert result.report["held"] + result.report["skipped"] == len(rate[::50])
    messages = [str(w.message) for w in said]
    assert not [m for m in messages if "deg/s" in m], messages
    assert any("replaced by the last usable reading" in m for m in messages), messages
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        with pytest.raises(ValueError, match=r"^rate\[1\] = 1e\+?308 rad/s is beyond \+-1048576 rad/s"):
            gyrocore.process(np.array([0.0, 1.0]), np.array([0.0, 1e308]), "raw")
    assert not said, [str(w.message) for w in said]
    with pytest.warns(gyrocore.InputWarning, match=r"^rates look like deg/s, not rad/s"):
        gyrocore.process(T, np.degrees(0.5 * np.sin(T)), "raw")  # deg/s within the limit still say so

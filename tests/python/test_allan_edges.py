"""gyrocore.allan at the edges of its inputs: records with no noise, long lists of averaging
times, and curves whose shape is not one of the three noise slopes."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan, sim

from .conftest import gyrocore_cli
from .test_allan import synthetic_gyro


def constant_csv(path: Path, n: int = 3000, value: float = 0.0123) -> Path:
    path.write_text("t,gyro_z\n" + "".join(f"{0.01 * i:.2f},{value}\n" for i in range(n)))
    return path


@pytest.mark.parametrize("value", [0.0123, 0.01, -0.7, 1e-5])
def test_a_constant_record_has_a_deviation_of_zero_and_no_noise_to_read(value: float) -> None:
    """A gyro that reads one value (stuck, saturated, or quantised coarser than its noise) has an
    Allan deviation of exactly 0. Its float rounding (7.9e-31 rad/s from a rate of 0.01, 2.4e-15
    from the timestamps' route) was read as N, B and K."""
    rate = np.full(3000, value)
    t = np.arange(3000) * 0.01
    for result in (allan.deviation(rate, 0.01), allan.deviation_from_timestamps(t, rate),
                   allan.deviation(rate, 0.01, kind="hadamard"), allan.deviation(rate, 0.01, kind="modified")):
        assert np.all(result.adev == 0.0), result.adev
        assert np.all(result.adev_low == 0.0) and np.all(result.adev_high == 0.0)
    with pytest.raises(ValueError, match=r"^the Allan deviation is 0 at every tau: the readings are constant"):
        allan.noise_parameters(allan.deviation_from_timestamps(t, rate))


def test_the_first_reading_of_a_log_stands_for_no_interval() -> None:
    """The timestamps' route leaves the first reading out (it has no interval): a log constant
    after it is constant."""
    rate = np.full(3000, 0.0123)
    rate[0] = 5.0
    result = allan.deviation_from_timestamps(np.arange(3000) * 0.01, rate)
    assert np.all(result.adev == 0.0)


def test_the_command_line_says_a_constant_record_has_no_noise(tmp_path: Path) -> None:
    path = constant_csv(tmp_path / "stuck.csv")
    for window in ((), ("--window", "+0", "+20")):  # no advice of a longer window: it is no matter of length
        proc = gyrocore_cli("allan", path, *window, code=2)
        assert proc.stderr.startswith(f"gyrocore: error: {path}: the Allan deviation is 0 at every tau: the readings "
                                      "are constant"), proc.stderr
        assert "longer --window" not in proc.stderr


def test_a_long_list_of_averaging_times_is_refused_as_every_one_is() -> None:
    """``taus="all"`` is refused above 1e10 terms to sum, and the same averaging times given as a
    list were summed: 60,000 taus over 200,000 samples took 9 s here, a day at 100 Hz hours."""
    rate = np.random.default_rng(0).normal(0.0, 0.01, 200_000)
    with pytest.raises(ValueError, match=r"^taus: 60000 averaging times over 200000 intervals ask for 1\.2e\+10 terms "
                                         r"to sum \(more than 1e\+10: minutes to hours of work\); give fewer"):
        allan.deviation(rate, 0.01, taus=np.arange(1, 60_001) * 0.01)
    assert len(allan.deviation(rate[:4000], 0.01, taus=np.arange(1, 1001) * 0.01).taus) == 1000  # a short record


@pytest.mark.parametrize("tolerance", [0.25, 0.5, 5.0])
def test_a_slope_tolerance_that_lets_a_point_count_for_two_noise_types_is_refused(tolerance: float) -> None:
    """The slopes -1/2, 0 and +1/2 lie 1/2 apart: from a tolerance of 1/4 a point of slope -1/4
    counted for both N and B. At 5, white noise of N = 1e-3 read as a flat floor over the whole
    curve, B = 0.0107 rad/s, 80 times its lowest point."""
    result = allan.deviation(np.random.default_rng(0).normal(0.0, 0.01, 10_000), 0.01)
    with pytest.raises(ValueError, match=r"^slope_tolerance must be below 0\.25 \(half the step between the slopes"):
        allan.noise_parameters(result, slope_tolerance=tolerance)
    assert allan.noise_parameters(result, slope_tolerance=0.24).arw is not None


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("taus", ["octave", "log"])
def test_a_rate_ramp_is_named_and_what_is_read_beside_it_is_an_upper_bound(seed: int, taus: str) -> None:
    """White noise (N = 1e-3) and a rate drifting by R = 1e-5 rad/s^2 (IEEE 952's rate ramp, slope
    +1): the bend between them was read as K = 9.3e-5 rad/s^2/sqrt(Hz) and a floor B, as measured,
    where the record has neither, and the ramp went without a word."""
    rng = np.random.default_rng(seed)
    t = np.arange(400_000) * 0.01
    p = allan.noise_parameters(allan.deviation(rng.normal(0.0, 0.01, len(t)) + 1e-5 * t, 0.01, taus=taus))
    ramp = [note for note in p.notes if "rate ramp" in note]
    assert len(ramp) == 1, p.notes
    r = float(ramp[0].split("R = ")[1].split(" ")[0])
    assert r == pytest.approx(1e-5, rel=0.2)
    assert p.arw is not None and p.arw.value == pytest.approx(1e-3, rel=0.03)
    assert p.bias_instability is not None and "upper bound" in p.bias_instability.method
    assert p.rrw is None or "upper bound" in p.rrw.method


def test_rate_random_walk_alone_is_no_ramp() -> None:
    rng = np.random.default_rng(0)
    rate = rng.normal(0.0, 0.01, 400_000) + np.cumsum(rng.normal(0.0, 2e-5, 400_000))  # K = 2e-4
    for taus in ("octave", "log"):
        p = allan.noise_parameters(allan.deviation(rate, 0.01, taus=taus))
        assert not [note for note in p.notes if "ramp" in note], p.notes
        assert p.rrw is not None and "upper bound" not in p.rrw.method
        assert p.rrw.value == pytest.approx(2e-4, rel=0.2)


def test_white_noise_alone_shows_no_floor_of_bias_instability() -> None:
    """The last points of white noise scatter (a few terms each): a flat stretch among them was
    read as a floor, B as measured, in 10 of these 60 records of white noise alone (N = 1e-3,
    1000 s). A floor, or a minimum, that lies on the -1/2 line within its interval bounds B only."""
    measured = []
    for seed in range(100, 160):
        rate = np.random.default_rng(seed).normal(0.0, 0.01, 100_000)
        p = allan.noise_parameters(allan.deviation(rate, 0.01))
        assert p.bias_instability is not None
        if "upper bound" not in p.bias_instability.method:
            measured.append(seed)
    assert len(measured) <= 4, measured  # a one-sigma interval: a few remain


def test_a_floor_beside_white_noise_is_still_read() -> None:
    n_true, b_true, dt = 1e-3, 2e-4, 0.05
    for seed in (2, 3):
        p = allan.noise_parameters(allan.deviation(synthetic_gyro(400_000, dt, n_true, 0.0, b_true, seed), dt))
        assert p.bias_instability is not None and "upper bound" not in p.bias_instability.method
        assert p.bias_instability.value == pytest.approx(b_true, rel=0.25)
        assert p.arw is not None and p.arw.value == pytest.approx(n_true, rel=0.05)


def test_a_curve_of_zeros_is_not_drawn_on_log_axes(tmp_path: Path) -> None:
    """The Hadamard deviation of a constant record, now exactly 0, was drawn as an empty figure
    (matplotlib: "Data has no positive values, and therefore cannot be log-scaled")."""
    pytest.importorskip("matplotlib")
    with pytest.raises(ValueError, match=r"^the deviation is 0 at every tau \(constant readings\): a log-log plot has "
                                         r"nothing to draw"):
        allan.plot(allan.deviation(np.full(3000, 0.0123), 0.01, kind="hadamard"))
    path = constant_csv(tmp_path / "stuck.csv")
    proc = gyrocore_cli("allan", path, "--kind", "hadamard", "--plot", tmp_path / "h.png", code=2)
    assert "nothing to draw" in proc.stderr and "log-scaled" not in proc.stderr
    assert not (tmp_path / "h.png").exists()


def test_a_sinusoid_rising_with_slope_one_and_falling_again_is_no_ramp() -> None:
    """IEEE 952's sinusoidal term rises with slope +1 below its period and falls after it: white
    noise and a 400 s sinusoid were noted as a rate ramp, R = 4.5e-5 rad/s^2."""
    rng = np.random.default_rng(0)
    t = np.arange(400_000) * 0.01
    p = allan.noise_parameters(allan.deviation(rng.normal(0.0, 0.01, len(t)) + 0.004 * np.sin(2 * np.pi * t / 400), 0.01))
    assert not [note for note in p.notes if "ramp" in note], p.notes


@pytest.mark.parametrize(("arw", "bias_instability"), [(2.9e-5, 4.8e-4), (1e-6, 1e-3)])
def test_settings_from_noise_give_a_bias_duration_the_pipeline_takes(arw: float, bias_instability: float) -> None:
    """A gyro whose bias instability outweighs its white noise (N = 0.1 deg/sqrt(h), B = 100 deg/h)
    has its knee (N / 0.664 B)^2 below one sample at 100 Hz (0.008 s; 2.3 us for N = 1e-6,
    B = 1e-3): the settings' bias_duration was refused by the pipeline they were made for."""
    settings = allan.settings_from_noise(arw=arw, bias_instability=bias_instability, dt=0.01)
    assert settings.bias_duration == pytest.approx(0.03)  # the pipeline's 3 readings, one interval to spare
    floor = allan.FLICKER_FLOOR * bias_instability
    assert settings.bias_error == pytest.approx(np.hypot(arw / np.sqrt(0.03), floor))
    t = np.arange(3000) * 0.01
    rate = np.random.default_rng(0).normal(0.001, 1e-4, len(t))
    result = gyrocore.process(t, rate, "combined", **settings.overrides())
    assert np.all(np.isfinite(result.heading))


def test_a_grid_finer_than_the_log_is_warned_about() -> None:
    """``deviation_from_timestamps(dt=...)`` finer than the log's interval interpolates between
    readings: for white noise at 100 Hz on a grid of 2.5 ms the deviation at 0.01 s read 27 %
    low (0.00729 for 0.0100) and N 8 % low, without a word."""
    rng = np.random.default_rng(0)
    t = np.arange(100_000) * 0.01
    rate = rng.normal(0.0, 0.01, len(t))
    with pytest.warns(gyrocore.InputWarning, match=r"^dt = 0\.0025 s is finer than the log's interval "
                                                   r"\(0\.01 s\): the grid interpolates between readings"):
        fine = allan.deviation_from_timestamps(t, rate, dt=0.0025)
    assert fine.adev[fine.taus == 0.01][0] < 0.8 * 0.01  # what the warning is about
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for dt in (None, 0.01, 0.02):
            allan.deviation_from_timestamps(t, rate, dt=dt)
        jittered = t + rng.uniform(-0.002, 0.002, len(t))  # the mean interval as its grid: no warning
        allan.deviation_from_timestamps(jittered, rate)
        # times rounded to 1 ms at 285.7 Hz step by 3 and 4 ms (median 4): the true interval is no finer
        rounded = np.round(1.7e9 + np.arange(20_001) / 285.7, 3)
        allan.deviation_from_timestamps(rounded, rate[: len(rounded)], dt=1 / 285.7)


def test_settings_for_an_hdr_step_run_the_pipeline_with_that_step() -> None:
    """``settings_from_noise(hdr_interval=0.5)`` set the turn threshold for 0.5 s steps, but its
    overrides left the pipeline's HDR at 1 s steps: a threshold for another step length."""
    settings = allan.settings_from_noise(arw=1e-4, bias_instability=5e-5, dt=0.01, hdr_interval=0.5)
    assert settings.hdr_interval == 0.5
    assert gyrocore.Pipeline("combined", **settings.overrides()).params["hdr_interval"] == 0.5
    default = allan.settings_from_noise(arw=1e-4, bias_instability=5e-5, dt=0.01)
    assert gyrocore.Pipeline("combined", **default.overrides()).params["hdr_interval"] == 1.0


@pytest.mark.parametrize("taus", ["octave", "log"])
def test_a_sensors_bandwidth_does_not_pull_the_angle_random_walk_down(taus: str) -> None:
    """The simulated XV3500 (N = 2.5 deg/sqrt(h), a 20 Hz bandwidth at 100 Hz) bends the shortest
    taus to a slope of about -0.4, within the default tolerance of -1/2: those points, known most
    closely, weighed most in N's line and read N 7.6-8.6 % low (2.29-2.31 deg/sqrt(h))."""
    spec = sim.SENSORS["xv3500"]
    t = np.arange(int(3600 * spec.rate_hz)) / spec.rate_hz
    for seed in (1, 2, 3):
        rate = sim.measure(spec, t, np.zeros(len(t)), seed=seed).rate
        p = allan.noise_parameters(allan.deviation(rate, 1.0 / spec.rate_hz, taus=taus))
        assert p.arw is not None and p.arw.value_deg == pytest.approx(spec.arw_deg_per_sqrt_h, rel=0.04)


@pytest.mark.parametrize("function", ["deviation", "phase_deviation", "deviation_from_timestamps"])
def test_taus_out_of_order_or_twice_are_refused_naming_the_first(function: str) -> None:
    # taus given in their own order were sorted (and one given twice merged) without a word: the
    # i-th point of the result was not taus[i]
    rate = np.random.default_rng(0).normal(size=2000)
    call = {
        "deviation": lambda taus: allan.deviation(rate, 0.01, taus=taus),
        "phase_deviation": lambda taus: allan.phase_deviation(np.cumsum(rate) * 0.01, 0.01, taus=taus),
        "deviation_from_timestamps": lambda taus: allan.deviation_from_timestamps(np.arange(2000) * 0.01, rate,
                                                                                  taus=taus),
    }[function]
    with pytest.raises(ValueError, match=r"^taus must strictly increase: taus\[2\] = 0\.02 follows 0\.04 "):
        call([0.01, 0.04, 0.02])
    with pytest.raises(ValueError, match=r"^taus must strictly increase: taus\[2\] = 0\.04 follows 0\.04 "):
        call([0.01, 0.04, 0.04])
    with pytest.raises(ValueError, match=r"^as whole multiples of dt: taus must strictly increase: taus\[1\]"):
        call([0.04, 0.04 * (1 + 1e-7)])  # one averaging time, 4 dt
    assert call([0.01, 0.02, 0.04]).taus == pytest.approx([0.01, 0.02, 0.04])

"""gyrocore.allan against Stable32 (PHASE.DAT), closed forms of simulated noise, and bad input."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan

from .conftest import DATA, gyrocore_cli

PHASE_DAT = DATA / "allan" / "phase_dat"


def stable32(name: str) -> np.ndarray:
    """Rows of AF, Tau, #, Alpha, MinSigma, Sigma, MaxSigma."""
    path = PHASE_DAT / name
    if not path.is_file():
        pytest.skip(f"shared data not found at {path}")
    return np.loadtxt(path, comments="#")


@pytest.fixture(scope="module")
def phase() -> np.ndarray:
    return stable32("PHASE.DAT")


@pytest.mark.parametrize(
    ("name", "kind", "overlapping"),
    [
        ("phase_dat_adev.txt", "allan", False),
        ("phase_dat_adev_octave.txt", "allan", False),
        ("phase_dat_oadev.txt", "allan", True),
        ("phase_dat_oadev_octave.txt", "allan", True),
        ("phase_dat_mdev.txt", "modified", True),
        ("phase_dat_hdev.txt", "hadamard", False),
        ("phase_dat_ohdev.txt", "hadamard", True),
    ],
)
def test_sigma_and_terms_match_stable32(phase: np.ndarray, name: str, kind: str, overlapping: bool) -> None:
    rows = stable32(name)
    r = allan.phase_deviation(phase, 1.0, taus=rows[:, 1], overlapping=overlapping, kind=kind)  # type: ignore[arg-type]
    np.testing.assert_array_equal(r.taus, rows[:, 1])
    np.testing.assert_array_equal(r.n, rows[:, 2])
    # Stable32 prints 5 significant digits: 1e-4 relative is within its rounding.
    np.testing.assert_allclose(r.adev, rows[:, 5], rtol=1e-4)


def test_time_deviation_from_mdev_matches_stable32(phase: np.ndarray) -> None:
    # docs/calibration.md: tdev is tau * mdev / sqrt(3); there is no function of its own.
    rows = stable32("phase_dat_tdev.txt")
    r = allan.phase_deviation(phase, 1.0, taus=rows[:, 1], overlapping=True, kind="modified")
    np.testing.assert_array_equal(r.n, rows[:, 2])
    np.testing.assert_allclose(r.adev * r.taus / math.sqrt(3.0), rows[:, 5], rtol=1e-4)


@pytest.mark.parametrize(
    ("name", "overlapping"), [("phase_dat_adev_octave.txt", False), ("phase_dat_oadev_octave.txt", True)]
)
def test_confidence_interval_matches_stable32(phase: np.ndarray, name: str, overlapping: bool) -> None:
    # Stable32 used white FM (Alpha 0 = white rate noise) and 0.683 confidence for these files.
    rows = stable32(name)
    assert np.all(rows[:, 3] == 0)
    r = allan.phase_deviation(phase, 1.0, taus="octave", overlapping=overlapping)
    np.testing.assert_array_equal(r.taus, rows[:, 1])  # the octave set stops where Stable32's does
    # Greenhall-Riley EDF and chi-squared quantiles give Stable32's bounds to 3.3e-4 (measured);
    # its 5 printed digits alone allow 1e-4.
    np.testing.assert_allclose(r.adev_low, rows[:, 4], rtol=5e-4)
    np.testing.assert_allclose(r.adev_high, rows[:, 6], rtol=5e-4)


def white_noise(n: int, dt: float, density: float, seed: int) -> np.ndarray:
    """White rate noise of density ``density`` [rad/s/sqrt(Hz)]: sigma = density / sqrt(dt)."""
    return np.random.default_rng(seed).normal(0.0, density / math.sqrt(dt), n)


def test_white_rate_noise_gives_q_over_sqrt_tau_inside_the_interval() -> None:
    q, dt = 3e-3, 0.005
    r = allan.deviation(0.02 + white_noise(400_000, dt, q, 1), dt)
    expected = q / np.sqrt(r.taus)
    # The estimate's relative spread is about 1 / sqrt(2 edf): 4 of those.
    assert np.all(np.abs(r.adev / expected - 1) < 4.0 / np.sqrt(2 * r.edf))
    # A one-sigma interval holds the truth about 68 % of the time; the 16 points are correlated.
    inside = (r.adev_low <= expected) & (expected <= r.adev_high)
    assert inside.mean() >= 0.4


def test_rate_input_equals_phase_input_and_timestamp_route() -> None:
    dt = 0.01
    rate = 0.1 + white_noise(20_000, dt, 1e-3, 2)
    a = allan.deviation(rate, dt, taus="decade")
    b = allan.phase_deviation(np.concatenate(([0.0], np.cumsum(rate) * dt)), dt, taus="decade")
    np.testing.assert_allclose(a.adev, b.adev, rtol=1e-9)
    np.testing.assert_array_equal(a.n, b.n)
    # Timestamps (here regular, from an epoch): the first reading has no interval.
    t = 1.6e9 + np.arange(len(rate)) * dt
    c = allan.deviation_from_timestamps(t, rate, taus="decade")
    d = allan.deviation(rate[1:], dt, taus="decade")
    np.testing.assert_allclose(c.adev, d.adev, rtol=1e-5)


def test_irregular_timestamps_keep_the_white_noise_level() -> None:
    # 23 Hz with jitter like the f110 logger: the curve still falls as q / sqrt(tau).
    rng = np.random.default_rng(3)
    dt = rng.uniform(0.03, 0.057, 50_000)
    t = np.cumsum(dt)
    q = 2e-3
    rate = rng.normal(0.0, 1.0, len(t)) * q / np.sqrt(dt)  # each reading averages its own interval
    r = allan.deviation_from_timestamps(t, rate)
    long = r.taus >= 1.0
    expected = q / np.sqrt(r.taus[long])
    assert np.all(np.abs(r.adev[long] / expected - 1) < 0.05 + 4.0 / np.sqrt(2 * r.edf[long]))


@pytest.mark.parametrize(
    ("spec", "expected"),
    [
        ("octave", [1, 2, 4, 8, 16, 32, 64, 128, 256]),
        ("decade", [1, 2, 4, 10, 20, 40, 100, 200]),
        ("all", list(range(1, 257))),
    ],
)
def test_named_tau_sets_stop_at_a_quarter_of_the_record(spec: str, expected: list[int]) -> None:
    r = allan.deviation(white_noise(1027, 0.5, 1.0, 4), 0.5, taus=spec)  # type: ignore[arg-type]
    np.testing.assert_array_equal(r.taus, np.array(expected) * 0.5)


def test_log_spaced_taus_are_about_ten_per_decade() -> None:
    r = allan.deviation(white_noise(100_001, 1.0, 1.0, 5), 1.0, taus="log")
    per_decade = len(r.taus) / math.log10(r.taus[-1])
    assert 8 <= per_decade <= 11
    assert np.all(np.diff(r.taus) > 0)


def test_bad_input_is_rejected_with_where_and_what() -> None:
    rate = white_noise(1000, 0.1, 1.0, 6)
    bad = rate.copy()
    bad[17] = np.nan
    with pytest.raises(ValueError, match=r"rate\[17\] is NaN"):
        allan.deviation(bad, 0.1)
    with pytest.raises(ValueError, match=r"taus\[1\] = 0.25 s is not a whole multiple"):
        allan.deviation(rate, 0.1, taus=[0.2, 0.25])
    with pytest.raises(ValueError, match="too long: the record allows at most 50"):
        allan.deviation(rate, 0.1, taus=[60.0])
    with pytest.raises(ValueError, match="too few samples"):
        allan.deviation(rate[:1], 0.1)
    with pytest.raises(ValueError, match="dt must be"):
        allan.deviation(rate, 0.0)
    with pytest.raises(ValueError, match="unknown kind"):
        allan.deviation(rate, 0.1, kind="total")  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        allan.deviation(np.array(["a", "b", "c"]), 0.1)


def synthetic_gyro(n: int, dt: float, arw: float, rrw: float, bias_instability: float, seed: int) -> np.ndarray:
    """White rate noise (N), rate random walk (K) and flicker rate noise (B), with the two-sided
    rate PSDs of IEEE 952 Annex C: N^2, K^2 / (2 pi f)^2 and B^2 / (2 pi f)."""
    rng = np.random.default_rng(seed)
    rate = rng.normal(0.0, arw / math.sqrt(dt), n)
    rate += np.cumsum(rng.normal(0.0, rrw * math.sqrt(dt), n))
    if bias_instability > 0:
        spectrum = np.fft.rfft(rng.normal(0.0, 1.0, n))
        f = np.fft.rfftfreq(n, dt)
        gain = np.zeros_like(f)
        gain[1:] = np.sqrt(bias_instability**2 / (2 * math.pi * f[1:]) / dt)  # unit white has PSD dt
        rate += np.fft.irfft(spectrum * gain, n)
    return rate


def test_noise_parameters_recover_arw_and_rrw() -> None:
    n_true, k_true, dt = 1e-3, 1e-5, 0.1
    r = allan.deviation(synthetic_gyro(1_000_000, dt, n_true, k_true, 0.0, 7), dt)
    p = allan.noise_parameters(r)
    assert p.arw is not None and p.rrw is not None and p.bias_instability is not None
    assert p.arw.value == pytest.approx(n_true, rel=0.03)
    assert p.arw.tau_range[0] == pytest.approx(0.1) and p.arw.tau_range[1] < 100
    assert p.rrw.value == pytest.approx(k_true, rel=0.25)
    assert p.rrw.tau_range[0] > 300
    assert p.arw.unit == "rad/s/sqrt(Hz)" and p.rrw.unit == "rad/s^2/sqrt(Hz)"
    assert p.arw.value_deg == pytest.approx(math.degrees(p.arw.value) * 60)
    # White plus random walk: the minimum is sqrt(2) N / sqrt(tau_c) with tau_c = sqrt(3) N / K.
    tau_c = math.sqrt(3) * n_true / k_true
    assert p.bias_instability.value * allan.FLICKER_FLOOR == pytest.approx(
        math.sqrt(2) * n_true / math.sqrt(tau_c), rel=0.1
    )


def test_bias_instability_of_flicker_noise() -> None:
    # Pure flicker rate noise: the flat floor is 0.664 B (IEEE 952 C.1).
    b_true, dt = 2e-4, 0.05
    r = allan.deviation(synthetic_gyro(400_000, dt, 1e-6, 0.0, b_true, 8), dt)
    mid = (r.taus >= 1) & (r.taus <= 200)
    np.testing.assert_allclose(r.adev[mid], allan.FLICKER_FLOOR * b_true, rtol=0.15)
    p = allan.noise_parameters(r)
    assert p.bias_instability is not None
    assert p.bias_instability.value == pytest.approx(b_true, rel=0.2)
    assert p.bias_instability.unit == "rad/s" and p.bias_instability.unit_deg == "deg/h"


def test_a_falling_curve_reports_bias_instability_as_an_upper_bound() -> None:
    r = allan.deviation(white_noise(10_000, 0.01, 1e-3, 9), 0.01)
    p = allan.noise_parameters(r)
    assert p.rrw is None
    assert p.bias_instability is not None and "upper bound" in p.bias_instability.method
    assert any("upper bound" in note for note in p.notes)
    with pytest.raises(ValueError, match="rate random walk was not found"):
        p.kalibr_yaml()


@pytest.mark.parametrize("given", [[1, 2], np.arange(5.0), None])
def test_noise_parameters_of_anything_but_an_allan_result_names_what_to_give(given: object) -> None:
    # a list failed as "'list' object has no attribute 'kind'"
    with pytest.raises(TypeError, match=r"^give the AllanResult of gyrocore.allan.deviation \(or "
                                        rf"deviation_from_timestamps\), not {type(given).__name__}$"):
        allan.noise_parameters(given)  # type: ignore[arg-type]


def test_a_filter_plateau_at_the_shortest_taus_is_not_bias_instability() -> None:
    # A 10 s rest of a sensor with an internal filter (ADIS16448-like at 200 Hz): the curve is flat
    # from 0.005 to 0.02 s, then falls as white noise. That plateau is the filter, not the floor.
    rng = np.random.default_rng(3)
    t = np.arange(2000) * 0.005
    white = allan.deviation_from_timestamps(t, rng.normal(0.002, 0.01, len(t)))
    lift = np.where(white.taus <= 0.02, white.adev[white.taus == 0.02][0] / white.adev, 1.0)
    curve = replace(white, adev=white.adev * lift, adev_low=white.adev_low * lift, adev_high=white.adev_high * lift)
    b = allan.noise_parameters(curve).bias_instability
    assert b is not None
    assert b.tau_range[0] > 0.02
    assert allan.FLICKER_FLOOR * b.value <= curve.adev_high.min()  # the B line is not above the curve
    assert "upper bound" in b.method


def test_a_minimum_at_the_shortest_tau_is_only_an_upper_bound() -> None:
    rng = np.random.default_rng(4)
    t = np.arange(2000) * 0.005
    white = allan.deviation_from_timestamps(t, rng.normal(0.002, 0.01, len(t)))
    rising = replace(white, adev=white.adev[0] * np.sqrt(white.taus / white.taus[0]))  # lowest at 0.005 s
    p = allan.noise_parameters(rising)
    assert p.bias_instability is not None and "upper bound" in p.bias_instability.method
    assert any("shortest taus" in note and "upper bound" in note for note in p.notes)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        # a line break wrote a YAML key of its own; True was a rate random walk of 1
        ({"rostopic": "/imu0\nupdate_rate: 1"}, "rostopic must be a ROS topic name (e.g. /imu0): text without spaces "
                                                 "or line breaks, got '/imu0\\nupdate_rate: 1'"),
        ({"rostopic": ""}, "rostopic must be a ROS topic name"),
        ({"rrw": True}, "rrw (--rrw) = True: give the rate random walk K, a finite number > 0"),
    ],
)
def test_kalibr_yaml_refuses_a_topic_or_rate_random_walk_it_cannot_write(options: dict[str, object], message: str) -> None:
    rate = np.random.default_rng(3).normal(0.0, 1e-3, 100_000)
    p = allan.noise_parameters(allan.deviation(rate, 0.01))
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        p.kalibr_yaml(**options)  # type: ignore[arg-type]


def test_kalibr_yaml_states_units_and_values() -> None:
    dt = 0.1
    r = allan.deviation(synthetic_gyro(1_000_000, dt, 1e-3, 1e-5, 0.0, 10), dt)
    p = allan.noise_parameters(r)
    text = p.kalibr_yaml(rostopic="/imu/data")
    values = dict(re.findall(r"^(\w+):\s*([^\s#]+)", text, flags=re.M))
    assert p.arw is not None and p.rrw is not None
    assert float(values["gyroscope_noise_density"]) == pytest.approx(p.arw.value, rel=1e-6)
    assert float(values["gyroscope_random_walk"]) == pytest.approx(p.rrw.value, rel=1e-6)
    assert float(values["update_rate"]) == pytest.approx(10.0)
    assert values["rostopic"] == "/imu/data"
    assert "IEEE Std 952" in text and "rad / s / sqrt(Hz)" in text and "rad / s^2 / sqrt(Hz)" in text


def test_settings_from_noise_reproduce_hong_threshold_and_follow_the_stated_rules() -> None:
    # Hong & Park's XV3500: ARW 2.5 deg/sqrt(h), bias instability 18 deg/h, gyro at 100 Hz; they
    # used a threshold of 0.3 deg/s (section 3.2).
    n = math.radians(2.5) / 60.0
    b = math.radians(18.0) / 3600.0
    s = allan.settings_from_noise(arw=n, bias_instability=b, dt=0.01)
    assert math.degrees(s.threshold) == pytest.approx(0.3, rel=0.01)
    floor = allan.FLICKER_FLOOR * b
    assert s.bias_duration == pytest.approx((n / floor) ** 2)
    assert s.bias_error == pytest.approx(math.sqrt(2) * floor)
    assert s.hdr_increment == pytest.approx(s.bias_error)
    assert s.hdr_turn_threshold == pytest.approx(3 * math.sqrt(n**2 + s.bias_error**2))
    p = gyrocore.Pipeline("combined", **s.overrides())  # the pipeline accepts every value
    assert p.params["threshold"] == pytest.approx(s.threshold)
    with pytest.raises(ValueError, match="arw must be finite"):
        allan.settings_from_noise(arw=0.0, bias_instability=b, dt=0.01)


def test_t_bias_from_noise_is_where_longer_averaging_stops_paying() -> None:
    # Simulated rests: the spread of the T-second mean follows sqrt(N^2/T + (0.664 B)^2); at the
    # derived T_bias the white part equals the floor.
    n, b, dt = 2e-3, 1e-3, 0.05
    s = allan.settings_from_noise(arw=n, bias_instability=b, dt=dt)
    rate = synthetic_gyro(2_000_000, dt, n, 0.0, b, 11)
    r = allan.deviation(rate, dt, taus=np.array([1.0, 2.0, 4.0]) * round(s.bias_duration / dt) * dt)
    # ADEV(T_bias) is the spread of adjacent T_bias means: about sqrt(N^2/T + floor^2).
    assert r.adev[0] == pytest.approx(s.bias_error, rel=0.15)
    assert r.adev[2] > 0.6 * r.adev[0]  # four times longer gains little


def test_plot_writes_a_log_log_figure(tmp_path: Path) -> None:
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    r = allan.deviation(synthetic_gyro(200_000, 0.1, 1e-3, 1e-5, 0.0, 12), 0.1)
    ax = allan.plot(r, parameters=allan.noise_parameters(r))
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    out = tmp_path / "allan.png"
    ax.figure.savefig(out)
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_result_prints_and_serialises() -> None:
    r = allan.deviation(white_noise(5000, 0.01, 1e-3, 13), 0.01)
    assert "overlapping allan" in repr(r) and "5000 samples" in repr(r)
    d = r.as_dict()
    assert d["taus"] == r.taus.tolist() and d["n"] == r.n.tolist()


@pytest.mark.parametrize(
    ("rate", "index", "shown"),
    [
        (np.full(1000, 1e300), 0, "1e300"),
        (np.where(np.arange(1000) % 2, 1e300, -1e300), 0, "-1e300"),
        (np.random.default_rng(0).normal(0.0, 1e200, 1000), 0, "1.2573022109339328e199"),
        (np.r_[np.zeros(9), 2.0**20, np.zeros(990)], 9, "1048576"),
    ],
)
def test_a_rate_beyond_the_limit_is_named_as_integrate_names_it(rate: np.ndarray, index: int, shown: str) -> None:
    with pytest.raises(gyrocore.SampleError, match=rf"rate\[{index}\] = {shown} rad/s is beyond \+-1048576") as info:
        allan.deviation(rate, 0.01)
    assert (info.value.index, info.value.what) == (index, "rate")
    with pytest.raises(gyrocore.SampleError, match=rf"rate\[{index}\] = {shown} rad/s is beyond"):
        allan.deviation_from_timestamps(np.arange(len(rate)) * 0.01, rate)


def test_unsorted_timestamps_are_shown_as_given() -> None:
    t = 100.0 + np.arange(0.0, 50.0, 0.01)[::-1]
    with pytest.raises(gyrocore.SampleError, match=r"t\[1\] = 149.98\d* follows 149.99 "):
        allan.deviation_from_timestamps(t, np.zeros(len(t)))


def test_a_non_overlapping_modified_deviation_is_refused_not_computed_overlapping() -> None:
    rate = np.random.default_rng(0).normal(0.0, 1e-3, 4000)
    with pytest.raises(ValueError, match=r"^overlapping=False: the modified Allan deviation is always overlapping"):
        allan.deviation(rate, 0.01, kind="modified", overlapping=False)
    assert allan.deviation(rate, 0.01, kind="modified").overlapping


def test_the_command_line_says_a_unit_problem_of_its_record_once(tmp_path: Path) -> None:
    """The reader said it, and the Allan deviation, which now warns of units for a Python caller,
    said it again."""
    rng = np.random.default_rng(1)
    t = np.arange(4000) * 0.01
    path = tmp_path / "dps.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{a},{b}\n" for a, b in zip(t, 30.0 + rng.normal(0, 0.5, len(t)))))
    proc = gyrocore_cli("allan", path, code=0)
    assert proc.stderr.count("look like deg/s") == 1, proc.stderr

"""gyrocore.calibration: each equation against known truth, the real logs, and the failure cases."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import calibration as cal
from gyrocore.cli import main

from .conftest import real_log_path

ROOT = Path(__file__).resolve().parents[2]

# --- Hong & Park section 3.1: s = -10 %, b = 0.1 rad/s ------------------------------------------

S_TRUE, B_TRUE = -0.10, 0.10


def motion_profile(t: np.ndarray) -> np.ndarray:
    """A true yaw rate that changes (turns of different rates and directions) [rad/s]."""
    return 0.8 * np.sin(0.7 * t) + 0.3 * np.sign(np.sin(0.13 * t)) + 0.1 * t / t[-1]


def gyro(rate_true: np.ndarray) -> np.ndarray:
    """Hong eq 2: r_m = (1 + s) r + b."""
    return (1.0 + S_TRUE) * rate_true + B_TRUE


def test_rate_reference_recovers_hong_simulation_exactly() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    r = motion_profile(t)
    c = cal.rate_reference(gyro(r), r)
    # Hong: s_bar = 1/(1+s) = 1.111, b_bar = -b/(1+s) = -0.111, "0 % error".
    assert c.s_bar == pytest.approx(1.0 / 0.9, abs=1e-12)
    assert c.b_bar == pytest.approx(-0.1 / 0.9, abs=1e-12)
    assert c.scale_error == pytest.approx(S_TRUE, abs=1e-12)
    assert c.bias == pytest.approx(B_TRUE, abs=1e-12)
    assert c.residual_rms is not None and c.residual_rms < 1e-12
    assert c.condition_number is not None and c.condition_number < 10


def test_hong_eq_8_as_printed_has_its_columns_swapped() -> None:
    # Eq 8 prints [[sum r_m, sum r_m^2], [n, sum r_m]] q = [sum r r_m, sum r]; solved by Cramer's
    # rule as printed it does not return (1.111, -0.111). The normal equations of the fit do, and
    # rate_reference solves those.
    t = np.arange(0.0, 20.0, 0.01)
    r = motion_profile(t)
    rm = gyro(r)
    z = np.array([np.sum(r * rm), np.sum(r)])
    printed = np.array([[rm.sum(), np.sum(rm**2)], [len(rm), rm.sum()]])
    normal = np.array([[np.sum(rm**2), rm.sum()], [rm.sum(), len(rm)]])
    assert not np.allclose(np.linalg.solve(printed, z), [1 / 0.9, -0.1 / 0.9], atol=1e-3)
    np.testing.assert_allclose(np.linalg.solve(normal, z), [1 / 0.9, -0.1 / 0.9], atol=1e-10)
    c = cal.rate_reference(rm, r)
    np.testing.assert_allclose([c.s_bar, c.b_bar], np.linalg.solve(normal, z), atol=1e-12)


def test_heading_reference_recovers_truth_with_a_slower_reference() -> None:
    # Gyro at 100 Hz, reference heading at 20 Hz (Hong section 4.1), at every fifth gyro time: the
    # heading is the exact integral of a rate that is linear between gyro samples.
    t = np.arange(0.0, 20.0 + 1e-9, 0.01)
    r = motion_profile(t)
    heading = np.concatenate(([0.0], np.cumsum(0.5 * (r[1:] + r[:-1]) * np.diff(t))))
    c = cal.heading_reference(t, gyro(r), t[::5], np.angle(np.exp(1j * heading[::5])))  # wrapped
    assert c.scale_error == pytest.approx(S_TRUE, abs=1e-9)
    assert c.bias == pytest.approx(B_TRUE, abs=1e-9)
    assert c.s_bar == pytest.approx(1.0 / 0.9, abs=1e-9)
    assert c.samples == len(t[::5])


def test_heading_reference_at_other_instants_and_rate() -> None:
    # Reference at 20 Hz offset by 13 ms from the gyro's 100 Hz, heading from the closed-form
    # integral of a smooth rate: the fit is limited only by interpolating the gyro's integral.
    t = np.arange(0.0, 30.0, 0.01)
    rate = lambda x: 0.6 * np.sin(0.5 * x) + 0.2 * np.cos(1.3 * x)  # noqa: E731
    heading = lambda x: -1.2 * np.cos(0.5 * x) + 1.2 + 0.2 / 1.3 * np.sin(1.3 * x)  # noqa: E731
    t_ref = np.arange(0.013, 29.9, 0.05)
    c = cal.heading_reference(t, gyro(rate(t)), t_ref, heading(t_ref))
    assert c.scale_error == pytest.approx(S_TRUE, abs=1e-4)
    assert c.bias == pytest.approx(B_TRUE, abs=1e-4)


def test_heading_reference_with_noise_is_within_its_stated_uncertainty() -> None:
    rng = np.random.default_rng(1)
    t = np.arange(0.0, 60.0, 0.01)
    r = motion_profile(t)
    rm = gyro(r) + rng.normal(0.0, 0.01, len(t))
    c = cal.rate_reference(rm, r)
    assert c.bias_stderr is not None and c.scale_error_stderr is not None
    assert abs(c.bias - B_TRUE) < 4 * c.bias_stderr
    assert abs(c.scale_error - S_TRUE) < 4 * c.scale_error_stderr
    assert c.residual_rms == pytest.approx(0.01 / 0.9, rel=0.05)  # the noise in true-rate units


@pytest.mark.parametrize("rate", [0.0, 0.4])
def test_no_excitation_is_a_clear_error(rate: float) -> None:
    t = np.arange(0.0, 20.0, 0.01)
    r = np.full_like(t, rate)  # at rest, or turning at one constant rate
    rm = gyro(r) + np.random.default_rng(2).normal(0.0, 0.001, len(t))
    with pytest.raises(ValueError, match="the rate must change during calibration"):
        cal.rate_reference(rm, r)
    with pytest.raises(ValueError, match="the rate must change during calibration"):
        cal.heading_reference(t, rm, t[::5], r[::5] * t[::5])


def test_least_squares_reject_bad_input() -> None:
    t = np.arange(0.0, 10.0, 0.01)
    r = motion_profile(t)
    bad = gyro(r)
    bad[42] = np.nan
    with pytest.raises(ValueError, match=r"rate_measured\[42\] is nan"):
        cal.rate_reference(bad, r)
    with pytest.raises(ValueError, match=r"rate_measured\[42\] is nan"):
        cal.heading_reference(t, bad, t, r)
    with pytest.raises(ValueError, match="has 999 samples but"):
        cal.rate_reference(gyro(r)[:-1], r)
    with pytest.raises(ValueError, match="reference sample"):
        cal.heading_reference(t, gyro(r), t + 100.0, r)  # other time base


# --- static bias ------------------------------------------------------------------------------


def test_static_bias_of_white_noise_with_its_standard_error() -> None:
    rng = np.random.default_rng(3)
    t = 1.65e9 + np.arange(0.0, 30.0, 0.01)  # epoch timestamps
    rate = 0.012 + rng.normal(0.0, 0.005, len(t))
    c = cal.static_bias(t, rate, (t[0], t[-1]))
    assert c.bias_stderr is not None
    assert c.bias_stderr == pytest.approx(0.005 / math.sqrt(len(t)), rel=0.5)  # batch means, 10 batches
    assert abs(c.bias - 0.012) < 4 * 0.005 / math.sqrt(len(t))
    assert c.residual_rms == pytest.approx(0.005, rel=0.05)
    assert c.window == (t[0], t[-1]) and c.samples == len(t)


def test_static_bias_equals_the_pipelines_rest_window_bias() -> None:
    rng = np.random.default_rng(4)
    t = np.cumsum(rng.uniform(0.02, 0.06, 3000))  # irregular, like the f110 logger
    rate = 0.01 + rng.normal(0.0, 0.003, len(t))
    window = (float(t[100]) - 0.001, float(t[900]))
    c = cal.static_bias(t, rate, window)
    p = gyrocore.Pipeline("static_bias", bias_window=window)
    p.process(t, rate)
    assert c.bias == pytest.approx(p.bias, rel=1e-12)
    # After the window (inside it the pipeline uses its running mean) the headings advance alike.
    a = gyrocore.process(t, rate, "static_bias", **c.overrides())
    b = gyrocore.process(t, rate, "static_bias", bias_window=window)
    assert a.heading[-1] - a.heading[901] == pytest.approx(b.heading[-1] - b.heading[901], rel=1e-9)


def test_batch_means_widen_the_standard_error_of_a_wandering_bias() -> None:
    rng = np.random.default_rng(5)
    t = np.arange(0.0, 60.0, 0.01)
    rate = rng.normal(0.0, 0.002, len(t)) + np.cumsum(rng.normal(0.0, 2e-4, len(t)))
    c = cal.static_bias(t, rate, (0.0, t[-1]))
    naive = float(np.std(rate) / math.sqrt(len(t)))
    assert c.bias_stderr is not None and c.bias_stderr > 3 * naive


def test_rest_detection_finds_the_real_logs_rest_windows() -> None:
    for name in ("f110_ds3", "broad_10"):
        log = gyrocore.read_log(real_log_path(name))
        assert log.stationary is not None
        c = cal.static_bias(log.t, log.rate)
        assert c.window is not None
        (d0, d1), (m0, m1) = c.window, log.stationary
        overlap = min(d1, m1) - max(d0, m0)
        assert overlap >= 0.9 * (m1 - m0), (name, c.window, log.stationary)
        assert d0 >= m0 - 0.3 and d1 <= m1 + 0.3, (name, c.window, log.stationary)
        reference = cal.static_bias(log.t, log.rate, log.stationary)
        assert reference.bias_stderr is not None
        assert abs(c.bias - reference.bias) < 4 * reference.bias_stderr


def test_no_rest_found_on_the_log_without_one() -> None:
    log = gyrocore.read_log(real_log_path("comma_seg40"))  # meta.json: stationary null
    with pytest.raises(ValueError, match="no rest found"):
        cal.static_bias(log.t, log.rate)


def test_static_bias_failure_cases() -> None:
    t = np.arange(0.0, 10.0, 0.01)
    rest = np.random.default_rng(6).normal(0.0, 0.001, len(t))
    with pytest.raises(ValueError, match="shorter than min_duration"):
        cal.static_bias(t, rest, (1.0, 1.5))
    with pytest.raises(ValueError, match="reaches past the end of the log"):
        cal.static_bias(t, rest, (1.65e9, 1.65e9 + 5))
    turning = 0.5 + 0.2 * np.sin(t) + rest
    with pytest.raises(ValueError, match="no rest found"):
        cal.static_bias(t, turning)
    bad = rest.copy()
    bad[7] = np.inf
    with pytest.raises(ValueError, match=r"rate\[7\] is inf"):
        cal.static_bias(t, bad)
    # the options of the search for a rest, with a window that skips the search (they went unused)
    with pytest.raises(TypeError, match="max_rate: options of the search for a rest"):
        cal.static_bias(t, rest, (1.0, 5.0), max_rate=0.5)


def test_cli_calibrate_refuses_search_options_with_a_window(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    np.savetxt(tmp_path / "gyro.csv", np.column_stack([t, np.full(len(t), 0.01)]), delimiter=",",
               header="t,gyro_z", comments="")
    args = ["calibrate", str(tmp_path), "--window", "0", "5", "--max-rate-dps", "9", "--block", "1"]
    assert main(args) == 2
    assert "--max-rate-dps and --block: how a rest is found, and --window gives the rest" in capsys.readouterr().err
    assert main(args[:-4]) == 0  # the window alone


# --- real logs: fitted scale and bias --------------------------------------------------------

#: ../shared/data/README.md, "constant scale+bias fitted to the reference" (E_psi, deg, 1 decimal).
README_FLOOR = {"f110_ds3": 1.5, "broad_10": 1.1, "comma_seg40": 0.1}
#: docs/calibration.md's "Measured" table: the same fits, E_psi to two decimals.
CALIBRATION_PAGE = {"f110_ds3": 1.46, "broad_10": 1.13, "comma_seg40": 0.12}


@pytest.mark.parametrize("name", sorted(README_FLOOR))
def test_heading_fit_on_real_logs_reaches_the_data_readme_floor(name: str) -> None:
    log = gyrocore.read_log(real_log_path(name))
    assert log.t_ref is not None and log.heading_ref is not None
    if name == "comma_seg40":  # its reference turns by 0.02 rad: the scale cannot be told, the bias is fitted
        with pytest.warns(gyrocore.InputWarning, match="too little to determine the scale"):
            c = cal.heading_reference(log.t, log.rate, log.t_ref, log.heading_ref)
    else:
        c = cal.heading_reference(log.t, log.rate, log.t_ref, log.heading_ref)
    result = gyrocore.process(log.t, log.rate, "raw", **c.overrides())
    e_psi = gyrocore.heading_errors(result.t, result.heading, log.t_ref, log.heading_ref).e_psi_deg
    assert abs(e_psi - README_FLOOR[name]) <= 0.1, e_psi
    assert round(e_psi, 2) == CALIBRATION_PAGE[name], e_psi  # the page showed 0.105 for comma_seg40
    assert f"{name} {CALIBRATION_PAGE[name]:.2f}" in (ROOT / "docs" / "calibration.md").read_text(encoding="utf-8")


# --- rotary table (FOG eq 1-6) ----------------------------------------------------------------

OMEGA = math.radians(30.0)  # FOG: turns at 30 deg/s
ALPHA = math.radians(60.0)  # acceleration [rad/s^2]: 0.5 s ramps


def e_t_deg(temp: float) -> float:
    """FOG eq 5: E_T = -0.52 T + 19.23 [deg]."""
    return -0.52 * temp + 19.23


def turn_profile(dt: float, sign: float) -> np.ndarray:
    """True rate of one 360-degree turn with trapezoidal speed (breakpoints on samples)."""
    ramp = OMEGA / ALPHA
    end = 2 * math.pi / OMEGA + ramp  # the trapezoid's area is 2 pi
    t = np.arange(round(end / dt) + 1) * dt
    return sign * OMEGA * np.clip(np.minimum(t / ramp, (end - t) / ramp), 0.0, 1.0)


def rotary_log(
    temps: list[float], *, dt: float = 0.01, asym: tuple[float, float] = (1.0, 1.0), bias: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Runs as in FOG section 3: a 20 s static bias test, a cw turn, a 2 s pause, a ccw turn."""
    rng = np.random.default_rng(7)
    rates, temperature, biases = [], [], []
    for k, temp in enumerate(temps):
        b = (0.002 + 0.0005 * k) if bias is None else bias
        for piece, direction in ((np.zeros(2000), 0), (turn_profile(dt, -1.0), -1), (np.zeros(200), 0),
                                 (turn_profile(dt, 1.0), 1), (np.zeros(200), 0)):
            gain = (1 + e_t_deg(temp) / 360.0) * (asym[0] if direction < 0 else asym[1])
            rates.append(piece * gain)
            temperature.append(np.full(len(piece), temp))
            biases.append(np.full(len(piece), b))
    r = np.concatenate(rates) + np.concatenate(biases) + rng.normal(0.0, 1e-4, sum(map(len, rates)))
    return np.arange(len(r)) * dt, r, np.concatenate(temperature)


def test_rotary_table_turn_errors_and_temperature_fit_are_fog_eq_1_to_6() -> None:
    temps = [20.0, 25.0, 30.0, 35.0, 40.0]
    t, rate, temperature = rotary_log(temps)
    table = cal.rotary_table(t, rate, temperature=temperature)
    assert [x.direction for x in table.turns] == ["cw", "ccw"] * len(temps)
    for x in table.turns:
        assert x.temperature is not None
        assert x.error_deg == pytest.approx(e_t_deg(x.temperature), abs=0.01)  # eq 1
        # eq 2; noise and bias error are about 0.003 deg per turn, 1e-5 of C
        assert x.factor == pytest.approx(360.0 / (360.0 + e_t_deg(x.temperature)), abs=3e-5)
    assert table.temperature_fit is not None
    slope, offset, _ = table.temperature_fit
    assert math.degrees(slope) == pytest.approx(-0.52, abs=1e-3)  # eq 5
    assert math.degrees(offset) == pytest.approx(19.23, abs=0.02)
    c = table.calibration
    assert c.temp_slope == pytest.approx(-0.52 / 360.0, abs=1e-5)
    assert c.temp_offset == pytest.approx(19.23 / 360.0, abs=1e-4)
    assert c.c_cw == pytest.approx(1.0, abs=1e-5) and c.c_ccw == pytest.approx(1.0, abs=1e-5)
    assert set(c.overrides()) == {"c_cw", "c_ccw", "temp_slope", "temp_offset"}

    # The pipeline with these factors (eq 6) measures each turn as 360 deg.
    t2, rate2, temp2 = rotary_log([22.0, 38.0], bias=0.003)
    out = gyrocore.process(t2, rate2, "static_bias", temperature=temp2, bias=0.003, **c.overrides())
    quiet = np.abs(rate2 - 0.003) < 1e-3
    plateaus = np.degrees(out.heading[quiet])
    assert {round(v / 360.0) for v in plateaus} == {0, -1}
    np.testing.assert_allclose(plateaus, np.round(plateaus / 360.0) * 360.0, atol=0.02)


def test_rotary_table_direction_factors_without_temperature() -> None:
    t, rate, _ = rotary_log([20.0, 20.0, 20.0], asym=(1.01, 0.98))
    table = cal.rotary_table(t, rate)
    gain = 1 + e_t_deg(20.0) / 360.0
    assert math.degrees(table.e_cw) == pytest.approx(360.0 * (gain * 1.01 - 1), abs=0.01)
    assert math.degrees(table.e_ccw) == pytest.approx(360.0 * (gain * 0.98 - 1), abs=0.01)
    assert table.calibration.c_cw == pytest.approx(1 / (gain * 1.01), abs=1e-5)
    assert table.calibration.c_ccw == pytest.approx(1 / (gain * 0.98), abs=1e-5)
    assert table.calibration.temp_slope is None
    assert [x.bias for x in table.turns][::2] == pytest.approx([0.002, 0.0025, 0.003], abs=1e-5)


def test_rotary_table_failure_cases() -> None:
    t, rate, temperature = rotary_log([20.0, 30.0])
    with pytest.raises(ValueError, match="not 90 deg"):
        cal.rotary_table(t, rate, turn_angle=math.pi / 2)
    with pytest.raises(ValueError, match="two or more temperatures"):
        cal.rotary_table(t, rate, temperature=np.full(len(t), 25.0))
    with pytest.raises(ValueError, match="no rest of at least 5"):
        cal.rotary_table(t[2000:4000], rate[2000:4000])


# --- bias versus temperature -------------------------------------------------------------------


def test_bias_temperature_table_interpolates_and_holds_its_ends() -> None:
    rng = np.random.default_rng(8)
    t = np.arange(0.0, 3600.0, 0.05)
    temperature = 15.0 + 30.0 * (1 - np.exp(-t / 900.0))  # warm-up after power-on
    truth = lambda T: 0.01 + 2e-4 * (T - 20.0) + 1e-5 * (T - 20.0) ** 2  # noqa: E731
    table = cal.bias_temperature_table(t, truth(temperature) + rng.normal(0.0, 0.002, len(t)), temperature)
    temps, biases, err = map(np.array, (table.temperatures, table.biases, table.stderr))
    assert np.all(np.diff(temps) > 0) and len(temps) >= 25
    # Each bin averages the curvature over 1 degC (1e-5 * 0.5^2 / 3 at most) plus noise.
    assert np.all(np.abs(biases - truth(temps)) < 4 * err + 1e-6)
    mid = 0.5 * (temps[3] + temps[4])
    assert table(mid) == pytest.approx(truth(mid), abs=4 * err[3] + 1e-5)
    assert table(-40.0) == table.biases[0] and table(90.0) == table.biases[-1]
    corrected = table.correct([0.02, 0.02], [temps[0], temps[-1]])
    np.testing.assert_allclose(corrected, 0.02 - biases[[0, -1]])
    with pytest.raises(ValueError, match="temperature spans only"):
        cal.bias_temperature_table(t, t * 0, np.full(len(t), 20.0))


# --- calibration objects -------------------------------------------------------------------------


def test_overrides_plug_into_the_pipeline_and_reproduce_hong_eq_3() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    r = motion_profile(t)
    c = cal.rate_reference(gyro(r), r)
    assert set(c.overrides()) == {"bias", "scale", "offset"}
    out = gyrocore.process(t, gyro(r), "hong_park", threshold=0.0, **c.overrides())
    np.testing.assert_allclose(out.rate, r, atol=1e-12)  # s_bar (r_m - b) = s_bar r_m + b_bar
    assert "bias" not in c.overrides(include_bias=False)


def test_json_round_trip_with_units_and_version(tmp_path: Path) -> None:
    table = cal.BiasTable((10.0, 20.0), (0.001, 0.002), (1e-5, 1e-5), (100, 100))
    c = cal.Calibration(
        method="rotary_table", bias=0.002, c_cw=1.01, c_ccw=0.99, temp_slope=-1e-3, temp_offset=0.05,
        window=(1.0, 2.0), samples=10, bias_table=table, notes=("two turns",),
    )
    path = tmp_path / "cal.json"
    c.save(path)
    data = json.loads(path.read_text())
    assert data["format"] == "gyrocore-calibration" and data["version"] == 1
    assert data["units"]["bias"].startswith("rad/s") and "degC" in data["units"]["temp_slope"]
    assert cal.Calibration.load(path) == c
    data["version"] = 2
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="calibration file version 2, written by a newer gyrocore; this one reads version 1"):
        cal.Calibration.load(path)
    path.write_text("{")
    with pytest.raises(ValueError, match="line 1 column 2"):
        cal.Calibration.load(path)


def test_repr_is_readable() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    r = motion_profile(t)
    text = repr(cal.rate_reference(gyro(r), r))
    assert text.startswith("Calibration(rate_reference, bias = 0.1 ")
    assert "scale error = -10 +-" in text and "s_bar = 1.11111" in text and "condition number" in text


# --- command line ------------------------------------------------------------------------------


def test_cli_calibrate_saves_a_loadable_calibration(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "f110.json"
    assert main(["calibrate", str(real_log_path("f110_ds3")), "--json", "--save", str(out)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["static_bias"]["window"][0] == pytest.approx(report["meta_stationary"][0])
    assert report["saved"]["method"] == "heading_reference"
    assert cal.Calibration.load(out).method == "heading_reference"


def test_cli_calibrate_says_how_a_run_takes_what_it_found(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # it printed the bias in rad/s and left the option that takes it (in deg/s) to be found
    t = np.arange(0.0, 60.0, 0.01)
    rate = 0.01 + np.where((t > 20) & (t < 40), 0.0, 0.2 * np.sin(t / 5))
    rate += np.random.default_rng(2).normal(0, 0.002, len(t))
    (tmp_path / "log").mkdir()
    np.savetxt(tmp_path / "log" / "gyro.csv", np.column_stack([t, rate]), delimiter=",", header="t,gyro_z",
               comments="")
    assert main(["calibrate", str(tmp_path / "log")]) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert line.startswith("  to use it: gyrocore process ... --bias-dps ") and "--calibration FILE" in line
    bias = cal.static_bias(t, rate).bias
    assert float(line.split("--bias-dps ")[1].split(",")[0]) == pytest.approx(math.degrees(bias), rel=1e-5)
    assert main(["calibrate", str(tmp_path / "log"), "--save", str(tmp_path / "c.json")]) == 0
    assert f"use it with gyrocore process ... --calibration {tmp_path / 'c.json'}" in capsys.readouterr().out


def test_cli_calibrate_reports_no_rest_and_still_fits(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["calibrate", str(real_log_path("comma_seg40"))]) == 0
    text = capsys.readouterr().out
    assert "no rest found" in text and "reference fit: Calibration(heading_reference" in text


def test_cli_calibrate_without_rest_or_reference_exits_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    np.savetxt(tmp_path / "gyro.csv", np.column_stack([t, 0.5 + 0.3 * np.sin(t)]), delimiter=",",
               header="t,gyro_z", comments="")
    assert main(["calibrate", str(tmp_path)]) == 2
    assert "nothing to calibrate from: no rest found" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("rate", "temperature", "message"),
    [
        ([0.1, 0.2, 0.3], [15.0, math.nan, 20.0], r"temperature\[1\] is NaN: samples must be finite"),
        ([0.1, math.inf, 0.3], [15.0, 16.0, 20.0], r"rate\[1\] is inf: samples must be finite"),
        ([0.1, 0.2, 0.3], [15.0, 16.0, 1e300], r"temperature\[2\] = 1e\+?300 degC is beyond"),
        ([0.1, 0.2, 0.3], [15.0, 16.0], "rate has 3 samples but temperature has 2"),
    ],
)
def test_a_bias_table_names_a_reading_it_cannot_correct(rate: list[float], temperature: list[float],
                                                        message: str) -> None:
    # a NaN temperature (or rate) came back as a NaN corrected rate
    table = cal.BiasTable((10.0, 20.0), (0.001, 0.002), (1e-5, 1e-5), (100, 100))
    with pytest.raises(ValueError, match=message):
        table.correct(rate, temperature)


@pytest.mark.parametrize("temperature, message", [
    (float("nan"), r"^temperature is nan: samples must be finite"),
    ([15.0, float("inf")], r"^temperature\[1\] is inf: samples must be finite"),
])
def test_a_bias_table_names_a_temperature_it_cannot_look_up(temperature: object, message: str) -> None:
    # the table called with a NaN temperature gave a NaN bias
    table = cal.BiasTable((10.0, 20.0), (0.001, 0.002), (1e-5, 1e-5), (100, 100))
    with pytest.raises(ValueError, match=message):
        table(temperature)
    assert table([15.0, 25.0]) == pytest.approx([0.0015, 0.002])

"""gyrocore.calibration where the data limit it: a reference that turns too little to tell the
scale (bias alone, with a warning), and rests in a gyro whose noise is correlated over a few
samples (found whole, not cut into pieces)."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrocore
from gyrocore import calibration as cal
from gyrocore import datasets, motion, sim
from gyrocore.cli import main

from .conftest import gyrocore_cli, real_log_path


def straight(seed: int) -> sim.Drive:
    """Five minutes of driving straight at 5 m/s, read by the CRS03 (bias about 0.024 rad/s)."""
    route = motion.Motion("straight", np.array([0.0, 300.0]), np.zeros(2), np.full(2, 5.0))
    return sim.simulate(route, "crs03", seed=seed)


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5, 6])
def test_a_straight_drive_gets_the_bias_alone_and_a_warning(seed: int) -> None:
    drive = straight(seed)
    rng = np.random.default_rng(seed)
    t_ref = drive.t[::10]
    heading_ref = drive.heading_true[::10] + rng.normal(0.0, 0.002, len(t_ref))  # a 10 Hz reference
    with pytest.warns(gyrocore.InputWarning, match="too little to determine the scale"):
        c = cal.heading_reference(drive.t, drive.rate_measured, t_ref, heading_ref)
    assert c.scale_error == 0.0 and c.scale_error_stderr is None
    assert c.notes and "the bias alone was fitted" in c.notes[0] and "note:" in repr(c)
    # The bias is still the gyro's (its mean over the drive).
    assert c.bias_stderr is not None
    truth = drive.bias + float(np.mean(drive.drift))
    assert abs(c.bias - truth) < 1e-3, (c.bias, truth)
    assert c.overrides() == {"bias": c.bias, "scale": 1.0, "offset": 0.0}


def test_a_drive_with_turns_gets_its_scale_without_a_warning() -> None:
    log = datasets.sample_drive()  # a 2.5 % scale error, 11 rad of turns
    assert log.t_ref is not None and log.heading_ref is not None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = cal.heading_reference(log.t, log.rate, log.t_ref, log.heading_ref)
    assert c.scale_error_stderr is not None and c.scale_error_stderr <= cal.MAX_SCALE_STDERR
    assert c.scale_error == pytest.approx(0.025, abs=0.005) and not c.notes


def correlated_rest(seed: int, rho: float) -> tuple[np.ndarray, np.ndarray]:
    """60 s at rest (bias 0.02 rad/s, AR(1) noise of lag-one correlation ``rho``), then 60 s of
    turning, at 100 Hz."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 120.0, 0.01)
    w = np.empty(len(t))
    w[0] = 0.0
    e = rng.normal(0.0, 0.005 * np.sqrt(1 - rho**2), len(t))
    for i in range(1, len(t)):
        w[i] = rho * w[i - 1] + e[i]
    return t, 0.02 + w + np.where(t < 60.0, 0.0, 0.3 * np.sin(0.5 * (t - 60.0)))


@pytest.mark.parametrize("rho", [0.0, 0.3, 0.55])
def test_a_rest_with_correlated_noise_is_found_whole(rho: float) -> None:
    # A first-order sensor bandwidth of 10 Hz sampled at 100 Hz (the CRS03 of the sample log)
    # correlates successive readings by exp(-2 pi 10 / 100) = 0.53: a block's mean then scatters
    # about twice as much as white noise of the same size would make it, and a level test that
    # assumed white noise cut the rest into pieces (at 0.55: after 7-57 s on these seeds).
    for seed in range(8):
        t, r = correlated_rest(seed, rho)
        windows = cal.rest_windows(t, r)
        assert windows[0][0] == 0.0 and 59.9 <= windows[0][1] <= 60.5, (rho, seed, windows[:3])


def test_gyrocore_calibrate_finds_the_sample_logs_whole_rest(tmp_path: Path) -> None:
    folder = datasets.write_sample(tmp_path / "sample")
    proc = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "calibrate", str(folder), "--json"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    report = json.loads(proc.stdout)
    start, end = report["static_bias"]["window"]
    # The rest is 0-60 s; the straight road after it reads the same to a gyro (no speed is read).
    assert start == 0.0 and end >= 59.9, (start, end)
    log = datasets.sample_drive()
    drive = sim.car_drive(**datasets.SAMPLE)
    inside = (drive.t >= start) & (drive.t <= end)
    truth = drive.bias + float(np.mean(drive.drift[inside]))
    assert abs(report["static_bias"]["bias"] - truth) < 4 * report["static_bias"]["bias_stderr"] + 1e-4
    assert len(log.t) == len(drive.t)


def rest_then_turning(start: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """20 s at rest (bias 0.01 rad/s, noise 0.001) then 40 s of turning, at 100 Hz from ``start``."""
    t = start + np.arange(6000) * 0.01
    rate = 0.01 + rng.normal(0.0, 0.001, len(t)) + np.where(t - start > 20.0, 0.3 * np.sin(t - start), 0.0)
    return t, rate


@pytest.mark.parametrize("jump", [1e3, 1e9])
def test_a_clock_jump_costs_no_memory_and_ends_a_rest(jump: float) -> None:
    # A log whose clock jumps (boot time, then epoch time) is searched in memory that follows its
    # samples, not its time span: one bin per 0.25 s of a 1e9 s span would be 32 GB. Each part's
    # rest is found where it is, and none spans the jump.
    rng = np.random.default_rng(1)
    (t1, r1), (t2, r2) = rest_then_turning(0.0, rng), rest_then_turning(jump, rng)
    windows = cal.rest_windows(np.r_[t1, t2], np.r_[r1, r2])
    assert len(windows) == 2
    for (start, end), part in zip(windows, (t1, t2)):
        assert part[0] <= start < part[0] + 0.5 and part[0] + 19.5 < end <= part[0] + 20.0


def test_a_gap_between_two_quiet_stretches_ends_the_rest() -> None:
    # Two rests at the same level, 10 s apart with no sample between them: two windows, as a
    # block with no sample is no evidence of rest.
    rng = np.random.default_rng(2)
    t = np.r_[np.arange(0.0, 5.0, 0.01), np.arange(15.0, 20.0, 0.01)]
    windows = cal.rest_windows(t, 0.01 + rng.normal(0.0, 0.001, len(t)))
    assert [(round(a, 2), round(b, 2)) for a, b in windows] == [(0.0, 4.99), (15.0, 19.99)]


@pytest.mark.parametrize("bad", [-1e12, -1e8, 2.0**20])
def test_a_temperature_beyond_the_limit_is_named_not_binned(bad: float) -> None:
    t = np.arange(0.0, 120.0, 0.01)
    temperature = 20.0 + t / 10
    temperature[5] = bad
    with pytest.raises(gyrocore.SampleError, match=r"temperature\[5\] = .* degC is beyond \+-1048576 degC") as info:
        cal.bias_temperature_table(t, np.full_like(t, 0.01), temperature)
    assert (info.value.index, info.value.what) == (5, "temperature")


def test_the_temperature_bins_follow_the_readings_not_the_span() -> None:
    t = np.arange(0.0, 120.0, 0.01)
    temperature = np.where(t < 60.0, 20.0, 1e6)  # two clusters 10^6 bins of 0.001 degC apart
    table = cal.bias_temperature_table(t, np.where(t < 60.0, 0.01, 0.02), temperature, bin_width=1e-3)
    assert table.temperatures == pytest.approx((20.0, 1e6)) and table.biases == pytest.approx((0.01, 0.02))


def _wrapped_degrees(heading: np.ndarray) -> np.ndarray:
    return np.degrees(np.angle(np.exp(1j * heading)))


@pytest.mark.parametrize(("to_degrees", "message"), [
    (np.degrees, r"the reference changes 5\d.\d+ times as much as the gyro \(s_bar\).*heading_ref looks like degrees"),
    (_wrapped_degrees, r"heading_ref looks like degrees, not radians: it jumps by -3\d\d"),
])
def test_a_reference_heading_in_degrees_is_refused(to_degrees: Any, message: str) -> None:
    log = datasets.sample_drive()
    assert log.t_ref is not None and log.heading_ref is not None
    with pytest.raises(ValueError, match=message + ".*convert it to rad"):
        cal.heading_reference(log.t, log.rate, log.t_ref, to_degrees(log.heading_ref))


def test_a_scale_error_no_gyro_has_warns_that_a_unit_looks_wrong() -> None:
    log = datasets.sample_drive()
    assert log.t_ref is not None and log.heading_ref is not None
    with pytest.warns(gyrocore.InputWarning, match=r"scale error is -6\d.\d %, beyond \+-50 %.*units .* look wrong"):
        cal.heading_reference(log.t, log.rate / 3.0, log.t_ref, log.heading_ref)
    truth = np.sin(np.linspace(0.0, 20.0, 500))
    with pytest.warns(gyrocore.InputWarning, match=r"rate_reference: the fitted scale error is \+200 %.*\(rad/s\) look wrong"):
        cal.rate_reference(3.0 * truth, truth)


def test_a_reference_in_degrees_that_is_not_refused_is_warned_about() -> None:
    # docs/calibration.md: f110_ds3's reference in degrees, unwrapped, neither wraps by 360 nor
    # fits an s_bar near 180/pi; the scale error of -87.8 % says that a unit looks wrong
    log = gyrocore.read_log(real_log_path("f110_ds3"))
    t_ref, heading_ref = log.reference()
    with pytest.warns(gyrocore.InputWarning, match=r"scale error is -87.8 %, beyond \+-50 %.*look wrong"):
        cal.heading_reference(log.t, log.rate, t_ref, np.degrees(np.unwrap(heading_ref)))


def _sample_with_reference_in_degrees(folder: Path) -> Path:
    datasets.write_sample(folder)
    reference = folder / "reference.csv"
    lines = reference.read_text().splitlines()
    column = lines[0].split(",").index("heading")
    rows = [line.split(",") for line in lines[1:]]
    for row in rows:
        row[column] = repr(float(_wrapped_degrees(np.array([float(row[column])]))[0]))
    reference.write_text("\n".join([lines[0], *(",".join(row) for row in rows)]) + "\n")
    return folder


def test_the_command_line_refuses_a_reference_in_degrees(tmp_path: Path) -> None:
    folder = _sample_with_reference_in_degrees(tmp_path / "deg")
    saved = tmp_path / "c.json"
    proc = gyrocore_cli("calibrate", folder, "--save", saved, code=2)
    assert "looks like degrees, not radians" in proc.stderr and "convert it to radians" in proc.stderr
    assert not saved.exists()
    proc = gyrocore_cli("evaluate", folder, code=2)
    assert "the reference heading looks like degrees, not radians" in proc.stderr


def test_a_calibration_file_with_a_scale_error_of_minus_one_is_named_on_the_command_line(tmp_path: Path) -> None:
    # s_bar = 1/(1 + s) raised ZeroDivisionError, a traceback, once the file was read
    path = tmp_path / "cal.json"
    data = cal.Calibration("rate_reference", bias=0.01, scale_error=0.01).to_dict()
    data["calibration"]["scale_error"] = -1
    path.write_text(json.dumps(data))
    log = tmp_path / "log.csv"
    log.write_text("t,gyro_z\n" + "".join(f"{i / 100},0.01\n" for i in range(300)))
    proc = gyrocore_cli("process", log, "--calibration", path, "--out", tmp_path / "out.csv", code=2, timeout=60)
    assert proc.stderr.splitlines()[-1] == (
        f"gyrocore: error: {path}: not a valid calibration: scale_error must be > -1 (s_bar = 1/(1 + s) > 0), got -1"
    )


def test_a_bias_table_out_of_order_is_refused_as_it_is_made() -> None:
    # np.interp gave the bias of 30 degC at 20 degC without a word
    with pytest.raises(ValueError, match=r"temperatures\[1\] = 10 degC does not come after 30 degC"):
        cal.BiasTable((30.0, 10.0, 20.0), (0.01, 0.02, 0.03), (0.0, 0.0, 0.0), (5, 5, 5))


@pytest.mark.parametrize(
    ("window", "min_duration", "message"),
    [
        # each was measured without a word: over the part inside the log, or from two readings "+- 0"
        ((5.0, 50.0), 1.0, "the bias window [5.0, 50.0] s reaches past the end of the log"),
        ((-50.0, 5.0), 1.0, "the bias window [-50.0, 5.0] s starts before the first sample (t[0] = 0.0): the bias would "
                            "be measured over [0.0, 5.0] s only"),
        ((0.0, 0.01), 0.0, "the rest window [0.0, 0.01] s of the log (t = 0.000 to 9.990 s) holds 2 reading(s): the "
                           "bias needs at least 3"),
        ((0.0, 5.0), float("nan"), "min_duration must be finite and >= 0, got nan"),
    ],
)
def test_a_static_bias_window_the_pipeline_refuses_is_refused(
    window: tuple[float, float], min_duration: float, message: str
) -> None:
    t = np.arange(1000) * 0.01
    rate = 0.01 + np.random.default_rng(0).normal(0.0, 0.001, len(t))
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        cal.static_bias(t, rate, window, min_duration=min_duration)


def test_calibrate_refuses_a_fit_window_without_a_reference(tmp_path: Path) -> None:
    # the span of a fit that cannot run was ignored without a word
    t = np.arange(0.0, 30.0, 0.01)
    log = tmp_path / "log.csv"
    np.savetxt(log, np.column_stack([t, 0.01 + np.random.default_rng(1).normal(0.0, 1e-3, len(t))]), delimiter=",",
               header="t,gyro_z", comments="")
    proc = gyrocore_cli("calibrate", log, "--fit-window", "5", "10", code=2, timeout=60)
    assert proc.stderr.splitlines()[-1] == (
        f"gyrocore: error: --fit-window is the span of the reference fit, and {log} has no reference heading: give one "
        "(--reference FILE, or reference.csv in a log folder) or leave --fit-window out"
    )


def test_no_rest_found_at_a_low_rate_says_which_block_finds_it() -> None:
    # ten minutes at rest at 10 Hz: blocks of 4 readings scatter too much to show a rest, and the
    # error only said to give the window
    t = np.arange(6000) / 10.0
    rate = 0.01 + np.random.default_rng(0).normal(0.0, 1e-3, len(t))
    with pytest.raises(ValueError, match=r"at this log's 10 Hz a block of 0.25 s holds 4 readings, too few to tell a "
                                         r"rest by its spread: give block=2.4 \(25 readings\) to find it$"):
        cal.detect_rest(t, rate)
    assert cal.detect_rest(t, rate, block=2.4) == pytest.approx((0.0, 599.9))


def test_a_fit_window_outside_the_log_is_named() -> None:
    # it said "only 0 reference sample(s) fall inside the gyro's span 200.0 .. 119.99 s"
    t = np.arange(0.0, 120.0, 0.01)
    heading = np.cumsum(0.3 * np.sin(t / 5)) * 0.01
    with pytest.raises(ValueError, match=r"^the window \[200.0, 300.0\] s lies outside the gyro's log \(0.0 \.\. 119.99"):
        cal.heading_reference(t, 0.3 * np.sin(t / 5), t[::10], heading[::10], window=(200.0, 300.0))


def test_a_fit_window_at_rest_gets_the_bias_alone_not_a_scale_error_no_gyro_has() -> None:
    """``gyrocore calibrate f110_ds3 --fit-window +0 +0.5`` (inside its rest) fitted a scale error of
    -99.2 % "+- 0.25 %" (the first-order error shrinks with the gain), which ``--save`` kept and
    ``process --calibration`` applied: a final heading of 421 rad for 3.37."""
    log = gyrocore.read_log(real_log_path("f110_ds3"))
    t_ref, heading_ref = log.reference()
    start = float(log.t[0])
    with pytest.warns(gyrocore.InputWarning, match=r"too little to determine the scale \(the gyro turns by .* rad "
                                                   r"besides its steady drift, under 0.1 rad, and the reference by "
                                                   r"0.0101 rad\)"):
        fit = cal.heading_reference(log.t, log.rate, t_ref, heading_ref, window=(start, start + 0.5))
    assert fit.scale_error == 0.0 and fit.scale_error_stderr is None
    assert fit.bias_stderr is not None  # the rest's bias, within the fit's error (its static bias: -0.3709 deg/s)
    assert abs(math.degrees(fit.bias) + 0.3709) < 3 * math.degrees(fit.bias_stderr)


def test_a_saved_calibration_with_a_scale_error_no_gyro_has_warns_where_it_is_read(tmp_path: Path) -> None:
    path = tmp_path / "cal.json"
    cal.Calibration("heading_reference", bias=0.01, scale_error=-0.992).save(path)
    with pytest.warns(gyrocore.InputWarning, match=r"cal.json: the scale error -99.2 % is beyond \+-50 % for any gyro: "
                                                   r"applied, it scales every turn by 125"):
        cal.Calibration.load(path)
    with pytest.raises(ValueError, match=r"scale_error must be at most 2\^20, got 1e\+300"):
        cal.Calibration("heading_reference", scale_error=1e300)


def test_calibrate_reports_and_saves_the_gyros_time_offset(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # the OXTS rate is stamped 0.06 s after the yaw it matches (meta.json's checks fit 0.062 s)
    path, out = real_log_path("kitti_2011_09_30_0034"), tmp_path / "kitti.json"
    assert main(["calibrate", str(path), "--json", "--save", str(out)]) == 0
    found = json.loads(capsys.readouterr().out)["time_offset"]
    assert found["offset"] == pytest.approx(-0.0607, abs=5e-5) and 0 < found["offset_stderr"] < 0.001
    saved = cal.Calibration.load(out)
    assert saved.method == "heading_reference"
    assert (saved.time_offset, saved.time_offset_stderr) == (found["offset"], found["offset_stderr"])
    assert main(["calibrate", str(path)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("  time offset: "))
    assert line.startswith("  time offset: TimeOffset(offset = -0.0607 +- 0.00043 s (add to the gyro's times)")
    assert line.endswith("): the gyro's times t - 0.06068 s are on the reference's clock")
    assert main(["calibrate", str(path), "--json", "--fit-window", "+0", "+60"]) == 0  # the reference fit's span
    window = json.loads(capsys.readouterr().out)["time_offset"]["window"]
    assert window[1] - window[0] == pytest.approx(60.0, abs=0.11) and window[0] == found["window"][0]


def test_calibrate_says_why_a_drive_tells_no_time_offset_and_saves_none(tmp_path: Path,
                                                                        capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "comma.json"
    assert main(["calibrate", str(real_log_path("comma_seg40")), "--json", "--save", str(out)]) == 0
    printed = capsys.readouterr()
    assert "too little to determine the scale" in printed.err  # the scale fit's own warning
    error = json.loads(printed.out)["time_offset"]["error"]
    assert error == ("the rate must change during calibration to tell a time offset: the reference turns by 0.0214 rad "
                     "besides a steady turn, under 0.1 rad; fit over a drive with turns that start and end")
    assert "time_offset" not in json.loads(out.read_text())["calibration"]


@pytest.mark.parametrize("command", ["process", "evaluate"])
def test_a_calibrations_time_offset_not_applied_is_said(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                         command: str) -> None:
    # the file's offset was ignored without a word: its scale and bias applied, its times not
    path, saved = real_log_path("kitti_2011_09_30_0034"), tmp_path / "cal.json"
    cal.Calibration("heading_reference", bias=0.0, scale_error=0.001, time_offset=-0.0607).save(saved)
    out = ["--out", str(tmp_path / "h.csv")] if command == "process" else ["--preset", "raw"]
    assert main([command, str(path), "--calibration", str(saved), *out]) == 0
    notes = [x for x in capsys.readouterr().err.splitlines() if x.startswith("gyrocore: note: --calibration")]
    assert notes == [f"gyrocore: note: --calibration {saved}: its time offset (-0.0607 s) is not applied: the heading "
                     "stays at the gyro's times; on the reference's clock they are t - 0.0607 s (in Python: "
                     "gyrocore.process(t + calibration.time_offset, rate, ...))"]
    cal.Calibration("heading_reference", bias=0.0, scale_error=0.001).save(saved)  # no offset: no note
    again = ["--overwrite"] if command == "process" else []
    assert main([command, str(path), "--calibration", str(saved), *out, *again]) == 0
    assert "time offset" not in capsys.readouterr().err

"""Reading any IMU's files from the command line: the shared reading options, units stated by the
header, windows after the first sample, the first bad CSV line, calibrations given to process and
evaluate. Every case runs the real ``gyrocore`` command (exit code, message, no traceback)."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.calibration import Calibration

from .conftest import gyrocore_cli, real_log_path

#: EuRoC's epoch of the first sample [ns].
EPOCH_NS = 1403636579758555392


def one_error(proc: subprocess.CompletedProcess[str]) -> str:
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gyrocore: error: "), proc.stderr
    return lines[0]


@pytest.fixture(scope="module")
def broad() -> gyrocore.Log:
    return gyrocore.read_log(real_log_path("broad_10"))  # 285.7 Hz, from 0 s, a long rest first


def write_csv(path: Path, header: list[str], columns: list[np.ndarray], fmt: str = "%.17g") -> Path:
    np.savetxt(path, np.column_stack(columns), delimiter=",", header=",".join(header), comments="", fmt=fmt)
    return path


def euroc(path: Path, log: gyrocore.Log, time_header: str = "#timestamp [ns]", epoch_ns: int = EPOCH_NS) -> Path:
    """The log as EuRoC writes it: ns since the epoch, three axes in rad/s, units in the header."""
    t_ns = epoch_ns + np.round(log.t * 1e9).astype(np.int64)
    rows = [f"{t},0.001,-0.002,{r!r}" for t, r in zip(t_ns, log.rate.tolist())]
    header = f"{time_header},w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]"
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def read_heading(path: Path) -> np.ndarray:
    return np.loadtxt(path, delimiter=",", skiprows=1)


# --- finding 2: one set of reading options; plain warnings -----------------------------------


@pytest.mark.parametrize("command", ["process", "allan", "calibrate", "evaluate", "tune"])
def test_every_command_that_reads_a_file_takes_the_same_reading_options(command: str) -> None:
    out = gyrocore_cli(command, "--help", code=0).stdout
    for option in ("--time-col", "--rate-col", "--time-unit", "--rate-unit", "--topic", "--delimiter"):
        assert option in out, f"gyrocore {command} lacks {option}"


def test_allan_takes_time_unit_and_warns_in_one_plain_line(tmp_path: Path, broad: gyrocore.Log) -> None:
    ms = write_csv(tmp_path / "ms.csv", ["time", "rate"], [broad.t * 1e3, broad.rate])
    # every interval read as seconds is a gap: stop, naming the option to add
    assert "--time-unit ms" in one_error(gyrocore_cli("allan", ms, "--time-col", "time", "--rate-col", "rate", code=2))
    proc = gyrocore_cli("allan", ms, "--time-col", "time", "--rate-col", "rate", "--time-unit", "ms", "--json", code=0)
    assert json.loads(proc.stdout)["allan"]["dt"] == pytest.approx(1 / 285.7, rel=1e-3)
    # a warning is one line of its own, not Python's "file:line: InputWarning: ..." form
    proc = gyrocore_cli("allan", real_log_path("broad_10"), "--time-unit", "ms", "--json", code=0)
    assert proc.stderr.startswith("gyrocore: warning: ") and "timestamps look like s, not ms" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "InputWarning" not in proc.stderr and ".py:" not in proc.stderr


# --- finding 5: units stated by the header --------------------------------------------------


def test_a_euroc_header_states_ns_and_rad_per_s(tmp_path: Path, broad: gyrocore.Log) -> None:
    src = euroc(tmp_path / "data.csv", broad)
    out = tmp_path / "heading.csv"
    gyrocore_cli("process", src, "--time-col", "timestamp", "--rate-col", "w_RS_S_z", "--out", out,
                 "--preset", "raw", code=0)
    got = read_heading(out)
    assert got.shape == (len(broad.t), 4)
    np.testing.assert_allclose(got[:, 0] - EPOCH_NS / 1e9, broad.t, atol=1e-6)
    expected = gyrocore.process(broad.t, broad.rate, "raw").heading
    np.testing.assert_allclose(got[:, 1], expected, atol=1e-6)


def test_a_missing_column_error_says_a_name_may_leave_out_its_unit(tmp_path: Path, broad: gyrocore.Log) -> None:
    message = one_error(gyrocore_cli("allan", euroc(tmp_path / "data.csv", broad), code=2))
    assert "missing column(s) t, gyro_z; it has #timestamp [ns], w_RS_S_x [rad s^-1]" in message
    assert "a name may leave out its unit, e.g. timestamp" in message
    assert message.endswith("; time_col='timestamp', rate_col='w_RS_S_z' (--time-col timestamp --rate-col w_RS_S_z) "
                            "look like them; where z does not point up, give the three axes and the axis that does: "
                            "gyro_cols='w_RS_S_x,w_RS_S_y,w_RS_S_z', up='x' for x up (--gyro-cols "
                            "'w_RS_S_x,w_RS_S_y,w_RS_S_z' --up x), or accel_cols to measure up)")


@pytest.mark.parametrize("header, python, options, reads", [
    (["timestamp", "gx", "gy", "gz"], "time_col='timestamp', rate_col='gz'", "--time-col timestamp --rate-col gz", True),
    (["time_ns", "yaw_rate_dps"], "time_col='time', rate_col='yaw_rate'", "--time-col time --rate-col yaw_rate", True),
    (["time", "gyro_z"], "time_col='time'", "--time-col time", True),
    (["t", "omega_z [deg/s]"], "rate_col='omega_z'", "--rate-col omega_z", True),
    (["stamp", "wx", "wz", "gz"], "time_col='stamp'", "--time-col stamp", False),  # two yaw rates: no guess
    (["T", "GYRO_Z"], "time_col='T', rate_col='GYRO_Z'", "--time-col T --rate-col GYRO_Z", True),
    (["a", "b"], None, None, False),
])
@pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")  # the samples' units: not the point here
def test_a_missing_default_column_names_the_option_of_the_one_that_looks_like_it(
        tmp_path: Path, header: list[str], python: str | None, options: str | None, reads: bool) -> None:
    src = write_csv(tmp_path / "imu.csv", header, [np.arange(3.0) * 0.01] + [np.full(3, 0.5)] * (len(header) - 1))
    message = one_error(gyrocore_cli("process", src, "--out", tmp_path / "h.csv", code=2))
    if python is None:
        assert "look like" not in message and "looks like" not in message
        return
    # a header with the gyro's x and y too goes on with the three-axis options
    assert f"; {python} ({options}) {'look like them' if ',' in python else 'looks like it'}" in message
    if reads:  # following the hint reads the file, on the command line and in Python
        gyrocore_cli("process", src, *(options or "").split(), "--out", tmp_path / "h.csv", "--preset", "raw", code=0)
        keywords = dict(kv.split("=") for kv in python.split(", "))
        gyrocore.read_log(src, **{k: v.strip("'") for k, v in keywords.items()})


def test_unit_suffixes_t_ms_and_gyro_z_dps_are_read_by_the_default_columns(tmp_path: Path, broad: gyrocore.Log) -> None:
    src = write_csv(tmp_path / "dps.csv", ["t_ms", "gyro_z_dps"], [broad.t * 1e3, np.degrees(broad.rate)])
    out = tmp_path / "heading.csv"
    gyrocore_cli("process", src, "--out", out, "--preset", "raw", code=0)
    got = read_heading(out)
    np.testing.assert_allclose(got[:, 0], broad.t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(got[:, 2], broad.rate, rtol=1e-12, atol=1e-15)


def test_a_header_unit_that_is_not_read_or_contradicts_an_option_stops(tmp_path: Path, broad: gyrocore.Log) -> None:
    src = write_csv(tmp_path / "min.csv", ["t [min]", "gyro_z"], [broad.t / 60, broad.rate])
    message = one_error(gyrocore_cli("process", src, "--out", tmp_path / "o.csv", code=2))
    assert "min.csv: column 't [min]' states the unit 'min'" in message and "--time-unit" in message
    src = euroc(tmp_path / "data.csv", broad)
    message = one_error(gyrocore_cli("allan", src, "--time-col", "timestamp", "--rate-col", "w_RS_S_z",
                                     "--time-unit", "s", code=2))
    assert "states the unit 'ns' but --time-unit s was given" in message
    assert not (tmp_path / "o.csv").exists()


def test_timestamps_that_are_all_gaps_are_an_error_not_a_warning(tmp_path: Path, broad: gyrocore.Log) -> None:
    # ns from the first sample, but the header does not say: every interval read as seconds is a gap
    src = euroc(tmp_path / "data.csv", broad, time_header="#timestamp", epoch_ns=0)
    out = tmp_path / "heading.csv"
    message = one_error(gyrocore_cli("process", src, "--time-col", "timestamp", "--rate-col", "w_RS_S_z",
                                     "--out", out, code=2))
    assert f"each of the {len(broad.t) - 1} intervals is longer than 2 s" in message
    assert "--time-unit ns" in message
    assert not out.exists()


def test_an_epoch_in_ns_read_as_seconds_is_refused_naming_the_option(tmp_path: Path, broad: gyrocore.Log) -> None:
    """Beyond the core's limit of a timestamp (2^40 s): the first chunk is refused, and the error
    says which unit the timestamps look like."""
    src = euroc(tmp_path / "data.csv", broad, time_header="#timestamp")
    out = tmp_path / "heading.csv"
    message = one_error(gyrocore_cli("process", src, "--time-col", "timestamp", "--rate-col", "w_RS_S_z",
                                     "--out", out, code=2))
    first = repr(float(EPOCH_NS)).replace("e+", "e")  # as the core writes an extreme number
    assert f"t[0] = {first} s is beyond +-1099511627776 s" in message and f"{src}, line 2" in message
    assert "timestamps look like ns, not s" in message and "--time-unit ns" in message
    assert not out.exists()


# --- finding 6: windows after the first sample, and the log's range in every empty-window error


def test_windows_after_the_first_sample_everywhere(tmp_path: Path, broad: gyrocore.Log) -> None:
    src = euroc(tmp_path / "data.csv", broad)
    cols = ("--time-col", "timestamp", "--rate-col", "w_RS_S_z")
    t0 = EPOCH_NS / 1e9
    relative, absolute = tmp_path / "relative.csv", tmp_path / "absolute.csv"
    gyrocore_cli("process", src, *cols, "--out", relative, "--preset", "static_bias", "--bias-window", "+0", "+5",
                 code=0)
    gyrocore_cli("process", src, *cols, "--out", absolute, "--preset", "static_bias", "--bias-window",
                 repr(t0), repr(t0 + 5), code=0)
    assert relative.read_bytes() == absolute.read_bytes()
    proc = gyrocore_cli("allan", src, *cols, "--window", "+0", "+5", "--json", code=0)
    assert json.loads(proc.stdout)["allan"]["samples"] == pytest.approx(5 * 285.7, abs=2)
    proc = gyrocore_cli("calibrate", src, *cols, "--window", "+0", "+5", "--json", code=0)
    window = json.loads(proc.stdout)["static_bias"]["window"]
    assert window[0] == pytest.approx(t0, abs=1e-6) and window[1] == pytest.approx(t0 + 5, abs=0.01)


@pytest.mark.parametrize(
    "args",
    [
        ("allan", "--window", "0", "5"),
        ("calibrate", "--window", "0", "5"),
        ("calibrate", "--fit-window", "+500", "+600"),
        ("process", "--bias-window", "+500", "+600", "--out", "OUT"),
        ("process", "--bias-window", "0", "5", "--out", "OUT"),
    ],
)
def test_every_empty_window_error_shows_the_logs_range(tmp_path: Path, broad: gyrocore.Log, args: tuple[str, ...]) -> None:
    src = euroc(tmp_path / "data.csv", broad)
    command, *rest = (str(tmp_path / "o.csv") if a == "OUT" else a for a in args)
    message = one_error(gyrocore_cli(command, src, "--time-col", "timestamp", "--rate-col", "w_RS_S_z", *rest, code=2))
    assert f"{EPOCH_NS / 1e9:.10g}" in message, message  # the first sample in the log's time base
    assert "+T for T seconds after" in message


# --- finding 7: the first bad line of a CSV file --------------------------------------------


def test_the_first_bad_csv_line_is_reported(tmp_path: Path) -> None:
    lines = ["t,gyro_z", *(f"{k * 0.005:.3f},0.001" for k in range(40))]
    lines[21] = ","  # a row of delimiters (line 22), before a line of text in the same block (line 28)
    lines[27] = "Step: 0.005 = 1/200,"
    src = tmp_path / "bad.csv"
    src.write_text("\n".join(lines) + "\n")
    message = one_error(gyrocore_cli("process", src, "--out", tmp_path / "o.csv", code=2))
    assert "bad.csv: line 22, column 1 (t): blank line" in message
    lines[21] = "0.105,"  # an empty rate is a missing reading (NaN); the text line is the first error
    src.write_text("\n".join(lines) + "\n")
    assert "line 28, column 1 (t): 'Step: 0.005 = 1/200' is not a number" in one_error(
        gyrocore_cli("process", src, "--out", tmp_path / "o.csv", code=2)
    )
    lines[27] = ",0.001"
    src.write_text("\n".join(lines) + "\n")
    assert "line 28, column 1 (t): empty timestamp" in one_error(
        gyrocore_cli("allan", src, code=2)
    )


# --- findings 3 and 4: calibrate any file; a saved calibration in process and evaluate -------


def test_calibrate_a_file_with_a_reference_file(tmp_path: Path) -> None:
    folder = real_log_path("f110_ds3")
    log = gyrocore.read_log(folder)
    gyro = write_csv(tmp_path / "imu.csv", ["stamp [ms]", "yaw_rate [deg/s]"], [log.t * 1e3, np.degrees(log.rate)])
    assert log.t_ref is not None and log.heading_ref is not None
    ref = write_csv(tmp_path / "truth.csv", ["t", "heading"], [log.t_ref, log.heading_ref])
    from_file, from_folder = tmp_path / "file.json", tmp_path / "folder.json"
    gyrocore_cli("calibrate", gyro, "--time-col", "stamp", "--rate-col", "yaw_rate", "--reference", ref,
                 "--save", from_file, code=0)
    gyrocore_cli("calibrate", folder, "--save", from_folder, code=0)
    a, b = Calibration.load(from_file), Calibration.load(from_folder)
    assert a.method == b.method == "heading_reference"
    assert a.bias == pytest.approx(b.bias, rel=1e-6) and a.scale_error == pytest.approx(b.scale_error, rel=1e-6)


def test_calibrate_says_what_a_folder_needs(tmp_path: Path) -> None:
    message = one_error(gyrocore_cli("calibrate", tmp_path, code=2))
    assert f"{tmp_path}: not a log folder" in message
    for needed in ("gyro.csv", "reference.csv", "meta.json", "--reference FILE", "--time-col"):
        assert needed in message


def test_process_and_evaluate_take_a_saved_calibration(tmp_path: Path) -> None:
    folder = real_log_path("f110_ds3")
    cal = tmp_path / "cal.json"
    gyrocore_cli("calibrate", folder, "--save", cal, code=0)
    overrides = Calibration.load(cal).overrides()
    assert set(overrides) >= {"scale", "bias"}
    out = tmp_path / "heading.csv"
    gyrocore_cli("process", folder, "--out", out, "--preset", "hdr", "--calibration", cal, code=0)
    log = gyrocore.read_log(folder)
    expected = gyrocore.process(log.t, log.rate, "hdr", **overrides)
    np.testing.assert_allclose(read_heading(out)[:, 1], expected.heading, rtol=0, atol=1e-12)
    rows = json.loads(gyrocore_cli("evaluate", folder, "--preset", "hdr", "--calibration", cal, "--json", code=0).stdout)
    method = gyrocore.evaluate.Method("hdr", "hdr", overrides)
    (score,) = gyrocore.evaluate.compare([log], [method])
    assert rows[0]["e_psi_deg"] == pytest.approx(score.errors.e_psi_deg, rel=1e-12)
    assert rows[0]["bias_source"] == "given by the method"
    message = one_error(gyrocore_cli("process", folder, "--out", out, "--calibration", cal, "--param", "bias=0", code=2))
    assert f"--param bias is also given by --calibration {cal}" in message


def test_evaluate_takes_param_and_bias_dps_like_process(tmp_path: Path) -> None:
    folder = real_log_path("f110_ds3")

    def e_psi(*args: str) -> float:
        proc = gyrocore_cli("evaluate", folder, "--preset", "static_bias", "--json", *args, code=0)
        return float(json.loads(proc.stdout)[0]["e_psi_deg"])

    by_dps = e_psi("--bias-dps", "-0.35")
    assert by_dps == pytest.approx(e_psi("--param", f"bias={math.radians(-0.35)!r}"), rel=1e-12)
    assert by_dps != pytest.approx(e_psi(), rel=1e-3)  # the rest window's bias differs
    # the same helper reads --param in both commands
    for command in ("evaluate", "process"):
        out = ["--out", str(tmp_path / "o.csv")] if command == "process" else []
        proc = gyrocore_cli(command, folder, "--param", "bias", *out, code=2)
        assert "--param 'bias': expected NAME=VALUE" in one_error(proc)


# --- finding 10: what a new user sees -------------------------------------------------------


def test_a_log_prints_as_a_short_summary() -> None:
    log = gyrocore.read_log(real_log_path("f110_ds3"))
    text = repr(log)
    assert text.startswith("Log('f110_ds3': 2736 samples, 126.993 s from t = 1651541251.831 s")
    assert "reference 2736 samples with track" in text and "rest +0 .. +1.83939 s" in text
    assert "array" not in text and len(text) < 200


def test_output_csv_never_holds_negative_zero(tmp_path: Path) -> None:
    src = tmp_path / "rest.csv"
    src.write_text("t,gyro_z\n0,0\n0.01,0\n0.02,0\n")  # at rest: the compass rate is -0.0
    out = tmp_path / "heading.csv"
    gyrocore_cli("process", src, "--out", out, "--preset", "raw", "--heading", "compass", code=0)
    rows = [line.split(",") for line in out.read_text().splitlines()[1:]]
    assert len(rows) == 3 and all(float(r[2]) == 0.0 for r in rows)
    assert not any(value.startswith("-0") and float(value) == 0.0 for r in rows for value in r)


def test_the_demo_says_why_recommended_is_not_the_best_and_titles_its_plot(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    args = ("demo", "--duration", "300", "--drives", "2", "--seed", "0")
    rows = json.loads(gyrocore_cli(*args, "--plot", "", "--json", code=0).stdout)
    best = min((r for r in rows if r["preset"] != "raw"), key=lambda r: r["e_psi_deg"])["preset"]
    out = gyrocore_cli(*args, "--plot", "", code=0).stdout
    recommended = gyrocore.recommended_preset()
    if best == recommended:
        assert f"{recommended} has the lowest E_psi here" in out
    else:
        assert f"{recommended} is not the lowest E_psi here ({best} is): it was chosen to do no harm" in out
    import matplotlib.pyplot as plt

    from gyrocore.cli import main

    figures: list[object] = []
    monkeypatch.setattr(plt, "close", figures.append)  # keep the demo's figure to read its title
    assert main([*args, "--plot", str(tmp_path / "demo.png")]) == 0
    title = figures[0].axes[0].get_title()  # type: ignore[attr-defined]
    assert "simulated car drive" in title and "'mixed' roads" in title
    assert gyrocore.sim.SENSORS["crs03"].name in title


def test_the_allan_plot_keeps_its_labels_inside_the_figure(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import matplotlib.pyplot as plt

    from gyrocore.cli import main

    figures: list[object] = []
    monkeypatch.setattr(plt, "close", figures.append)  # keep the figure to measure its layout
    png = tmp_path / "allan.png"
    # half a second: a curve within one decade, labelled at minor ticks (1.7x10^-3), wider than 10^-3
    assert main(["allan", str(real_log_path("broad_10")), "--window", "+0", "+0.5", "--plot", str(png)]) == 0
    fig = figures[0]
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    ax = fig.axes[0]  # type: ignore[attr-defined]
    box = fig.bbox  # type: ignore[attr-defined]
    low, high = sorted(ax.get_ylim())
    ticks = [*ax.get_yticklabels(), *ax.get_yticklabels(minor=True)]
    drawn = [t for t in ticks if low <= t.get_position()[1] <= high]  # the ticks in view
    texts = [ax.yaxis.label, ax.xaxis.label, ax.title, *drawn]
    assert drawn and ax.yaxis.label.get_text() == "deviation [rad/s]"
    for text in (t for t in texts if t.get_text()):
        extent = text.get_window_extent(renderer)
        assert box.x0 <= extent.x0 and extent.x1 <= box.x1 and box.y0 <= extent.y0 and extent.y1 <= box.y1, text
    assert png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("units", ["s,deg/s", "[s],[deg/s]", "(s),(dps)"])
def test_a_row_of_units_under_the_header_says_how_to_state_them(tmp_path: Path, units: str) -> None:
    # phone apps and spreadsheets write one; it was only "'s' is not a number"
    rows = "".join(f"{k * 0.01:.2f},{5 + 10 * (k % 3)},20\n" for k in range(300))
    path = tmp_path / "phone.csv"
    path.write_text(f"time,wz,temp\n{units},C\n{rows}")
    error = one_error(gyrocore_cli("process", path, "--time-col", "time", "--rate-col", "wz", "--preset", "raw",
                                   "--out", tmp_path / "h.csv", code=2))
    assert error.startswith("gyrocore: error: ")
    assert "phone.csv: line 2, column 1 (time): " in error
    assert "a row of units: delete line 2 and state them in the header, time [s],wz [d" in error
    # what the message says to do reads the file
    path.write_text(f"time [s],wz [deg/s],temp\n{rows}")
    log = gyrocore.read_log(path, time_col="time", rate_col="wz")
    assert log.rate[0] == pytest.approx(np.radians(5))


def test_a_word_that_is_no_unit_gets_no_units_row_hint(tmp_path: Path) -> None:
    path = tmp_path / "x.csv"
    path.write_text("t,gyro_z\nabc,0.1\n0.01,0.1\n")
    with pytest.raises(ValueError, match=r"'abc' is not a number$"):
        gyrocore.read_log(path)


def test_a_unit_option_takes_the_spellings_a_header_takes(tmp_path: Path) -> None:
    # a header's gyro_z_dps and t_msec were read, while --rate-unit dps and --time-unit msec were refused
    path = tmp_path / "d.csv"
    path.write_text("time,wz\n" + "".join(f"{k * 10},{1.5 + k % 4}\n" for k in range(300)))
    spelled = {"time_col": "time", "rate_col": "wz", "time_unit": "msec", "rate_unit": "dps"}
    canonical = {**spelled, "time_unit": "ms", "rate_unit": "deg/s"}
    a, b = gyrocore.read_log(path, **spelled), gyrocore.read_log(path, **canonical)
    assert np.array_equal(a.t, b.t) and np.array_equal(a.rate, b.rate)
    for name, option in (("dps", ("--time-unit", "msec", "--rate-unit", "dps")),
                         ("canonical", ("--time-unit", "ms", "--rate-unit", "deg/s"))):
        gyrocore_cli("process", path, "--time-col", "time", "--rate-col", "wz", *option, "--preset", "raw",
                     "--out", tmp_path / f"{name}.csv", code=0)
    assert (tmp_path / "dps.csv").read_text() == (tmp_path / "canonical.csv").read_text()
    with pytest.raises(ValueError, match="unknown rate_unit 'rpm'"):
        gyrocore.read_log(path, time_col="time", rate_col="wz", rate_unit="rpm")


def test_a_log_folders_gyro_csv_given_alone_names_the_folder(tmp_path: Path) -> None:
    # read as a plain file it lost the folder's rest window and odometry without a word: the sample
    # log's straight roads became 21 "rests" found from the rate
    from gyrocore import datasets

    folder = datasets.write_sample(tmp_path / "drive")
    proc = gyrocore_cli("process", folder / "gyro.csv", "--out", tmp_path / "h.csv", code=0)
    assert (f"gyrocore: warning: {folder / 'gyro.csv'}: the gyro of the log folder {folder}, read as a file alone, "
            f"without the meta.json, odometry.csv, reference.csv beside it; give the folder ({folder})") in proc.stderr
    assert "warning" not in gyrocore_cli("process", folder, "--out", tmp_path / "f.csv", code=0).stderr
    alone = tmp_path / "alone"
    alone.mkdir()
    (alone / "gyro.csv").write_bytes((folder / "gyro.csv").read_bytes())  # nothing beside it: no word
    assert "the gyro of the log folder" not in gyrocore_cli("process", alone / "gyro.csv", "--out",
                                                            tmp_path / "a.csv", code=0).stderr


@pytest.mark.parametrize(("unit", "scale"), [("ms", 1e3), ("us", 1e6), ("ns", 1e9)])
def test_epoch_times_in_a_smaller_unit_get_one_diagnosis(tmp_path: Path, unit: str, scale: float) -> None:
    # the core's "(nanoseconds read as seconds are this large)" and "timestamps look like ms" were
    # both said of the same times: the unit the times fit is the one named
    src = tmp_path / f"{unit}.csv"
    t = 1.65e9 + np.arange(300) * 0.01
    src.write_text("t,gyro_z\n" + "".join(f"{round(x * scale)},0.01\n" for x in t))
    error = one_error(gyrocore_cli("process", src, "--out", tmp_path / "h.csv", code=2))
    assert "nanoseconds" not in error
    assert f"({src}, line 2); timestamps look like {unit}, not s: " in error and f"--time-unit {unit}" in error

"""A user's own files, not the bundled logs: a phone's or a logger's export, a still recording, a
drive with its reference in a file of its own. Each test is a case where gyrocore said too little,
or something wrong, about such a file."""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import sim
from gyrocore.batch import process_file
from gyrocore.rests import LISTED_RESTS

from .conftest import gyrocore_cli


def test_a_header_read_as_one_field_names_the_delimiter_and_no_column(tmp_path: Path) -> None:
    # a semicolon-separated export: the whole header line was offered as the time column,
    # time_col='timestamp [ms];gyro_z [deg/s]' (--time-col 'timestamp [ms];gyro_z [deg/s]') looks like it
    src = tmp_path / "phone.csv"
    src.write_text("timestamp [ms];gyro_z [deg/s]\n0;0.5\n10;0.6\n20;0.7\n")
    with pytest.raises(ValueError) as e:
        gyrocore.read_log(src)
    message = str(e.value)
    assert "give the file's delimiter (delimiter=';', --delimiter ';')" in message, message
    assert "looks like" not in message and "time_col=" not in message, message
    log = gyrocore.read_log(src, delimiter=";", time_col="timestamp")
    assert np.allclose(log.t, [0.0, 0.01, 0.02]) and np.allclose(log.rate, np.radians([0.5, 0.6, 0.7]))


@pytest.mark.parametrize("time", ["2024-05-03T14:00:00.010Z", "2024-05-03 14:00:00.010", "2024-05-03"])
def test_dates_as_csv_times_are_named_with_what_to_do(tmp_path: Path, time: str) -> None:
    # it said only "'2024-05-03T14:00:00.010Z' is not a number", as for any text
    src = tmp_path / "dated.csv"
    src.write_text(f"t,gyro_z\n{time},0.1\n")
    with pytest.raises(ValueError) as e:
        gyrocore.read_log(src)
    assert f"line 2, column 1 (t): {time!r} is not a number (a date and time:" in str(e.value), e.value
    assert "convert the file to Parquet with this column as a timestamp" in str(e.value)
    src.write_text("t,gyro_z\n0.0,abc\n")  # other text is not taken for a date
    with pytest.raises(ValueError, match=r"'abc' is not a number$"):
        gyrocore.read_log(src)


def _still_recording(path: Path, header: str) -> float:
    """Ten minutes of a simulated XV3500 at rest, written in deg/s under ``header``; its bias [deg/s]."""
    spec = sim.sensor("xv3500", rate_hz=50.0)
    t = sim.sample_times(spec, 0.0, 600.0, seed=4)
    reading = sim.measure(spec, t, np.zeros_like(t), seed=4)
    np.savetxt(path, np.column_stack([t, np.degrees(reading.rate)]), delimiter=",", header=header, comments="")
    return float(np.degrees(np.mean(reading.bias)))


def test_a_still_recording_whose_header_states_deg_per_s_is_not_told_it_looks_like_rad_per_s(tmp_path: Path) -> None:
    # calibrate warned "rates look like rad/s ...; use --rate-unit rad/s", which then stopped with
    # "column 'gyro_z_dps' states the unit 'dps' but --rate-unit rad/s was given"
    still = tmp_path / "still.csv"
    bias = _still_recording(still, "t,gyro_z_dps")
    proc = gyrocore_cli("calibrate", still, "--json", code=0)
    assert "look like rad/s" not in proc.stderr, proc.stderr
    assert "states the unit" in gyrocore_cli("calibrate", still, "--rate-unit", "rad/s", code=2).stderr
    measured = json.loads(proc.stdout)["static_bias"]["bias"]
    assert abs(np.degrees(measured) - bias) < 0.05  # read in deg/s, as the header says
    # a unit given as an option is still checked: rad/s readings given as deg/s
    unstated = tmp_path / "unstated.csv"
    unstated.write_text(still.read_text().replace("gyro_z_dps", "gyro_z"))
    with pytest.warns(gyrocore.InputWarning, match="look like rad/s"):
        gyrocore.read_log(unstated, rate_unit="deg/s")


def test_evaluate_scores_a_file_against_a_reference_file_of_its_own(tmp_path: Path) -> None:
    # evaluate took a reference only from a log folder or a heading_true column, while calibrate
    # took --reference FILE: a drive and its reference in two files could not be scored
    drive = sim.car_drive(duration=120.0, rate_hz=50.0, seed=3, sensor_name="xv3500")
    t0 = 1234.5  # seconds since boot, in ms in the file
    gyro, ref = tmp_path / "drive.csv", tmp_path / "truth.csv"
    np.savetxt(gyro, np.column_stack([(t0 + drive.t) * 1e3, np.degrees(drive.rate_measured)]), delimiter=",",
               header="timestamp_ms,gyro_z_dps", comments="")
    np.savetxt(ref, np.column_stack([t0 + drive.t[::5], drive.heading_true[::5]]), delimiter=",",
               header="t,heading", comments="")
    missing = gyrocore_cli("evaluate", gyro, "--time-col", "timestamp", code=2).stderr
    assert "no reference heading to score against" in missing and "--reference FILE" in missing, missing
    proc = gyrocore_cli("evaluate", gyro, "--time-col", "timestamp", "--reference", ref, "--preset", "static_bias",
                        "--bias-duration", "20", "--json", code=0)
    (row,) = json.loads(proc.stdout)
    # what the Python API gives for the same samples and reference
    result = gyrocore.process(drive.t, drive.rate_measured, "static_bias", bias_duration=20.0)
    expected = gyrocore.heading_errors(result.t, result.heading, drive.t[::5], drive.heading_true[::5])
    assert row["e_psi_deg"] == pytest.approx(expected.e_psi_deg, rel=1e-3, abs=1e-3)
    assert row["n"] == len(drive.t[::5])
    # one reference file is one log's
    other = tmp_path / "drive2.csv"  # another log (one given twice is scored once)
    other.write_bytes(gyro.read_bytes())
    two = gyrocore_cli("evaluate", gyro, other, "--time-col", "timestamp", "--reference", ref, code=2).stderr
    assert "--reference" in two and "2 logs were given" in two, two


def test_a_report_lists_a_dozen_rests_and_counts_the_others(tmp_path: Path) -> None:
    # a 10-minute phone drive's report listed 120 rests, a line each, and a day's log thousands
    t = np.arange(0.0, 400.0, 0.01)
    moving = (t // 5) % 2 == 1  # 5 s stops between 5 s turns: 40 rests
    rate = 0.01 + np.where(moving, 0.3, 0.0) + np.random.default_rng(0).normal(0.0, 0.002, len(t))
    src = tmp_path / "stops.csv"
    np.savetxt(src, np.column_stack([t, rate]), delimiter=",", header="t,gyro_z", comments="")
    report = process_file(src, tmp_path / "h.csv", preset="static_bias")
    assert len(report.rests) > LISTED_RESTS + 10
    lines = str(report).splitlines()
    listed = [line for line in lines if line.strip().startswith("rest [")]
    assert len(listed) == LISTED_RESTS - 1 and listed == [f"{' ' * 9}rest {r}" for r in report.rests[: len(listed)]]
    others = report.rests[len(listed):]
    used = sum(r.accepted for r in others)
    assert lines[-1] == (f"{' ' * 9}... and {len(others)} more rests ({used} of them used): the JSON report "
                         "(--json; .rests in Python) lists every one")
    assert len(report.as_dict()["rests"]) == len(report.rests)


@pytest.mark.parametrize("hz", [1000, 500])
def test_whole_ms_timestamps_of_a_fast_gyro_read_as_seconds_warn(tmp_path: Path, hz: int) -> None:
    # a 1 kHz gyro's ms since boot read as s is a 1 Hz gyro, within the intervals judged sound: its
    # two minutes became 33 hours and its heading 1267 deg where the drive turned 25, without a word
    drive = sim.car_drive(duration=60.0, rate_hz=float(hz), seed=2, sensor_name="xv3500")
    ms = np.round(drive.t * 1e3) + 5000.0
    src = tmp_path / "fast.csv"
    np.savetxt(src, np.column_stack([ms, drive.rate_measured]), fmt=["%d", "%.6f"], delimiter=",",
               header="timestamp,gyro_z", comments="")
    step = 1000 // hz
    with pytest.warns(gyrocore.InputWarning, match=rf"timestamps look like ms, not s: whole numbers {step} apart, a "
                      rf"{1 / step:g} Hz gyro in s or a {hz} Hz one in ms; use time_unit='ms' \(--time-unit ms\)"):
        gyrocore.read_log(src, time_col="timestamp")
    read = gyrocore.read_log(src, time_col="timestamp", time_unit="ms")  # as the warning says: no warning
    assert read.t[-1] - read.t[0] == pytest.approx(drive.t[-1] - drive.t[0], abs=1e-3)
    proc = gyrocore_cli("process", src, "--time-col", "timestamp", "--out", tmp_path / "h.csv", code=0)
    assert "--time-unit ms" in proc.stderr, proc.stderr


@pytest.mark.parametrize(("header", "options", "t0"), [
    ("t [s],gyro_z", {}, 0.0),           # the header states seconds
    ("t,gyro_z", {"time_unit": "s"}, 0.0),  # so does the option
    ("t,gyro_z", {}, 1.7e9),             # Unix epoch seconds at 1 Hz
])
def test_whole_seconds_stated_or_on_the_epoch_do_not_warn(
    tmp_path: Path, header: str, options: dict[str, str], t0: float
) -> None:
    src = tmp_path / "slow.csv"
    t = t0 + np.arange(600.0)
    np.savetxt(src, np.column_stack([t, 0.2 * np.sin(t / 30.0)]), fmt=["%d", "%.6f"], delimiter=",",
               header=header, comments="")
    with warnings.catch_warnings():
        warnings.simplefilter("error", gyrocore.InputWarning)
        log = gyrocore.read_log(src, **options)
    assert np.array_equal(log.t, t)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_rest_window_that_reads_a_bias_no_gyro_has_names_deg_per_s(mode: str) -> None:
    # a drive in deg/s read as rad/s, its first 20 s given as the rest: "bias 81.11632 deg/s",
    # and a heading 57 times too large, without a word (its turns stay under the 20 rad/s check)
    drive = sim.car_drive(duration=120.0, rate_hz=50.0, seed=1)
    assert np.percentile(np.abs(np.degrees(drive.rate_measured)), 99) < 20.0
    read_as_rad = np.degrees(drive.rate_measured)
    with pytest.warns(gyrocore.InputWarning, match=r"the rest window \[0\.0, 20\.0\] s reads a bias of [\d.]+ rad/s "
                      r"\([\d.]+ deg/s\), beyond any gyro's at rest .*then convert arrays with numpy.radians, or read the file "
                      r"with rate_unit='deg/s', --rate-unit deg/s") as said:
        gyrocore.process(drive.t, read_as_rad, "static_bias", bias_window=(0.0, 20.0), mode=mode)
    shown = re.search(r"reads a bias of ([\d.]+) rad/s", str(said[0].message))
    assert shown is not None and float(shown[1]) == pytest.approx(np.mean(read_as_rad[drive.t <= 20.0]), rel=1e-2)
    with warnings.catch_warnings():  # the same drive in rad/s: its bias, 1.4 deg/s, is a gyro's
        warnings.simplefilter("error", gyrocore.InputWarning)
        gyrocore.process(drive.t, drive.rate_measured, "static_bias", bias_window=(0.0, 20.0), mode=mode)


def test_a_decimal_comma_in_a_semicolon_file_is_told_how_to_mend_it(tmp_path: Path) -> None:
    # "a decimal comma: write numbers with a decimal point", with no word of how
    src = tmp_path / "euro.csv"
    src.write_text("t [ms];gyro_z [deg/s]\n1000;0,25\n1010;0,5\n1020;0,75\n")
    with pytest.raises(ValueError, match=r"line 2, column 2 \(gyro_z \[deg/s\]\): '0,25' is not a number \(a decimal "
                       r"comma: write numbers with a decimal point, e.g. tr ',' '\.' < old\.csv > new\.csv\)$"):
        gyrocore.read_log(src, delimiter=";")
    mended = tmp_path / "mended.csv"
    mended.write_text(src.read_text().translate(str.maketrans(",", ".")))  # what the command does
    assert np.allclose(np.degrees(gyrocore.read_log(mended, delimiter=";").rate), [0.25, 0.5, 0.75])
    # in a comma-separated file the recipe would split the fields: not offered
    src.write_text('t,gyro_z\n0,"0,25"\n')
    with pytest.raises(ValueError, match=r"'0,25' is not a number \(a decimal comma: write numbers with a decimal "
                       r"point\)$"):
        gyrocore.read_log(src)

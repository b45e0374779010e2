"""Logs in the formats other tools write (EuRoC/ASL, pandas' Parquet, NumPy archives): each is read
right (values, units, axis) with the options docs/reading-logs.md gives, or refused with an error
that names what to give."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import gyrocore_cli
from .test_cli_reading import read_heading, write_csv

DOCS = Path(__file__).resolve().parents[2] / "docs" / "reading-logs.md"

#: 2 s at rest, a 90-degree turn over 2 s, 2 s at rest, at 200 Hz.
RATE_HZ = 200
T = np.arange(6 * RATE_HZ) / RATE_HZ
TURNING = (T >= 2) & (T < 4)
YAW = np.where(TURNING, np.pi / 4 * (1 - np.cos(np.pi * (T - 2))), 0.0)


def euroc_six_axis(path: Path) -> Path:
    """An EuRoC/ASL ``imu0/data.csv``: ns since the epoch, the x axis up (the yaw rate is
    w_RS_S_x, gravity on a_RS_S_x)."""
    t_ns = 1403636579758555392 + np.round(T * 1e9).astype(np.int64)
    header = ("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
              "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]")
    rows = [f"{t},{w!r},0.001,-0.002,9.81,0.02,-0.01" for t, w in zip(t_ns.tolist(), YAW.tolist())]
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def test_the_euroc_command_of_the_docs_reads_a_euroc_file(tmp_path: Path) -> None:
    """The docs' EuRoC line (without --time-col the default t is missing from EuRoC's header)."""
    text = DOCS.read_text()
    line = next(ln for ln in text.splitlines() if ln.rstrip().endswith("# EuRoC"))
    before = text.splitlines()[text.splitlines().index(line) - 1]
    words = shlex.split((before.rstrip(" \\") + " " + line).split("#")[0])
    assert words[:2] == ["gyrocore", "process"], words
    data = euroc_six_axis(tmp_path / "data.csv")
    out = tmp_path / "heading.csv"
    args = [data if w == "data.csv" else out if w == "heading.csv" else w for w in words[2:]]
    args = [re.sub(r"^\+20$", "+1.5", str(a)) for a in args]  # the rest of this short log
    gyrocore_cli("process", *args, code=0)
    # up is off x by 2.3e-3 rad (the accelerometer's y and z): the turn reads cos(2.3e-3) of 90 deg
    assert read_heading(out)[-1, 1] == pytest.approx(np.pi / 2, abs=1e-5)


def pandas_parquet(path: Path) -> Path:
    """What ``df.to_parquet`` writes of a frame indexed by an unnamed tz-aware DatetimeIndex: the
    index as a timestamp column ``__index_level_0__``, described in the ``pandas`` metadata."""
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    ns = 1714557600_000_000_000 + np.round(T * 1e9).astype(np.int64)
    meta = ('{"index_columns": ["__index_level_0__"], "columns": [{"name": "gyro_z", "field_name": "gyro_z", '
            '"pandas_type": "float64"}, {"name": null, "field_name": "__index_level_0__", '
            '"pandas_type": "datetimetz", "metadata": {"timezone": "Europe/Berlin"}}]}')
    table = pa.table({"gyro_z": YAW, "__index_level_0__": pa.array(ns, pa.timestamp("ns", tz="Europe/Berlin"))})
    pq.write_table(table.replace_schema_metadata({b"pandas": meta.encode()}), path)
    return path


def test_a_pandas_frames_unnamed_datetime_index_is_named_as_its_time(tmp_path: Path) -> None:
    path = pandas_parquet(tmp_path / "drive.parquet")
    with pytest.raises(ValueError, match=r"time_col='__index_level_0__' \(--time-col __index_level_0__\) looks like it"):
        gyrocore.read_log(path)
    log = gyrocore.read_log(path, time_col="__index_level_0__")
    assert log.t[0] == 1714557600.0  # UTC epoch seconds, whatever the zone the index was shown in
    assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)


def test_an_npz_of_arrays_saved_without_names_says_which_to_give(tmp_path: Path) -> None:
    """``np.savez(path, t, rate)`` names them arr_0 and arr_1; the error said only that t and
    gyro_z were missing."""
    path = tmp_path / "drive.npz"
    np.savez(path, T, YAW)
    hint = (r"np\.savez\(file, t, rate\) names its arrays arr_0, arr_1, \.\.\.: give time_col='arr_0', "
            r"rate_col='arr_1' \(--time-col arr_0 --rate-col arr_1\)")
    with pytest.raises(ValueError, match=hint):
        gyrocore.read_log(path)
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", "--preset", "raw", code=2)
    assert re.search(hint, proc.stderr) and len(proc.stderr.strip().splitlines()) == 1
    log = gyrocore.read_log(path, time_col="arr_0", rate_col="arr_1")
    assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)


def test_a_three_axis_header_is_told_the_three_axis_options(tmp_path: Path) -> None:
    """EuRoC's yaw rate is w_RS_S_x (x points up): the hint named w_RS_S_z alone, which reads a
    turn about x as no turn at all."""
    path = euroc_six_axis(tmp_path / "data.csv")
    cols = "w_RS_S_x,w_RS_S_y,w_RS_S_z"
    with pytest.raises(ValueError, match=re.escape(f"where z does not point up, give the three axes and the axis "
                                                   f"that does: gyro_cols={cols!r}, up='x' for x up "
                                                   f"(--gyro-cols {cols!r} --up x), or accel_cols to measure up")):
        gyrocore.read_log(path)
    log = gyrocore.read_log(path, time_col="timestamp", gyro_cols=cols, up="x")  # as the hint says
    assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)
    z = gyrocore.read_log(path, time_col="timestamp", rate_col="w_RS_S_z")
    assert abs(np.degrees(np.sum(z.rate[1:] * np.diff(z.t)))) < 1
    with pytest.raises(ValueError, match=r"\) looks like it\)$"):  # one axis only: no three-axis hint
        gyrocore.read_log(write_csv(tmp_path / "one.csv", ["time", "gyro_z_dps"], [T, YAW]))


def test_up_window_takes_bounds_after_the_first_sample_as_the_error_writes_them(tmp_path: Path) -> None:
    """EuRoC's times are epoch ns: a window (0, 1.5) holds nothing and its error says to write
    +T; ("+0", "+1.5") then failed inside numpy (`ufunc 'greater_equal' did not contain a loop`)."""
    path = euroc_six_axis(tmp_path / "data.csv")
    axes = {"time_col": "timestamp", "gyro_cols": "w_RS_S_x,w_RS_S_y,w_RS_S_z", "accel_cols": "a_RS_S_x,a_RS_S_y,a_RS_S_z"}
    with pytest.raises(ValueError, match=r"write a bound as \+T for T seconds after the first sample"):
        gyrocore.read_log(path, up_window=(0, 1.5), **axes)
    log = gyrocore.read_log(path, up_window=("+0", "+1.5"), **axes)
    assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)
    first = 1403636579.758555392
    assert np.array_equal(gyrocore.read_log(path, up_window=np.array([first, first + 1.5]), **axes).rate, log.rate)
    with pytest.raises(TypeError, match=r"^up_window must be two times \[s\], \(t0, t1\), or two bounds as text, "
                                        r"\('\+0', '\+20'\) for the first 20 s, got \(True, 2\)$"):
        gyrocore.read_log(path, up_window=(True, 2), **axes)


def test_a_phone_apps_bare_axis_names_are_named_as_a_gyros(tmp_path: Path) -> None:
    """Sensor Logger's Gyroscope.csv: time [ns since the epoch], seconds_elapsed, z, y, x [rad/s].
    The error named the time alone; the axes x, y, z look like no gyro by their names."""
    header = ["time", "seconds_elapsed", "z", "y", "x"]
    ns = 1700000000123456789 + np.round(T * 1e9).astype(np.int64)
    path = tmp_path / "Gyroscope.csv"
    path.write_text(",".join(header) + "\n" + "".join(
        f"{n},{s!r},{z!r},0.001,-0.001\n" for n, s, z in zip(ns.tolist(), (T + 0.5).tolist(), YAW.tolist())))
    with pytest.raises(ValueError, match=re.escape(
            "; time_col='time' (--time-col time) looks like it; its x, y, z may be a gyro's axes: rate_col='z' "
            "(--rate-col z) for a sensor z up (a phone lying flat), else gyro_cols='x,y,z' and the axis that points "
            "up (--gyro-cols x,y,z --up AXIS))")):
        gyrocore.read_log(path)
    for options in ({"time_col": "time", "time_unit": "ns", "rate_col": "z"},
                    {"time_col": "seconds_elapsed", "gyro_cols": "x,y,z", "up": "z"}):
        log = gyrocore.read_log(path, **options)
        assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)
    with pytest.raises(ValueError, match=r"it has t, x, y \(choose with time_col/rate_col, --time-col/--rate-col\)$"):
        gyrocore.read_log(write_csv(tmp_path / "track.csv", ["t", "x", "y"], [T, T, T]))  # no z: no gyro hint


def test_an_npz_holding_a_table_says_how_to_save_it(tmp_path: Path) -> None:
    """``np.savez(path, data=table)``: no column option reads a 2-D member, and the error named
    only the member."""
    path = tmp_path / "drive.npz"
    np.savez(path, data=np.column_stack([T, YAW]))
    with pytest.raises(ValueError, match=re.escape(
            "it has data (choose with time_col/rate_col, --time-col/--rate-col); its data is a 2-D array of shape "
            "(1200, 2), and an .npz archive is read one 1-D array per column: save the table as an .npy file")):
        gyrocore.read_log(path)
    np.save(tmp_path / "drive.npy", np.load(path)["data"])  # as the error says
    log = gyrocore.read_log(tmp_path / "drive.npy")
    assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)


def test_px4s_array_columns_are_named_and_read_as_a_gyros_axes(tmp_path: Path) -> None:
    """PX4's ulog2csv writes sensor_combined as timestamp [us since boot], gyro_rad[0] to
    gyro_rad[2] [rad/s], ..., accelerometer_timestamp_relative. The element index [2] was read as a
    unit ("states the unit '2'") and the rate column could not be named at all; the hint named no
    time (two names hold "timestamp") and left out the gyro."""
    header = ["timestamp", "gyro_rad[0]", "gyro_rad[1]", "gyro_rad[2]", "gyro_integral_dt",
              "accelerometer_timestamp_relative"]
    us = 20_000_000 + np.round(T * 1e6).astype(np.int64)
    path = tmp_path / "log_sensor_combined_0.csv"
    path.write_text(",".join(header) + "\n" + "".join(
        f"{u},0.001,-0.002,{z!r},5000,0\n" for u, z in zip(us.tolist(), YAW.tolist())))
    with pytest.raises(ValueError, match=re.escape(
            "; time_col='timestamp', rate_col='gyro_rad[2]' (--time-col timestamp --rate-col 'gyro_rad[2]') look "
            "like them; where z does not point up, give the three axes and the axis that does: "
            "gyro_cols='gyro_rad[0],gyro_rad[1],gyro_rad[2]', up='x' for x up (--gyro-cols "
            "'gyro_rad[0],gyro_rad[1],gyro_rad[2]' --up x), or accel_cols to measure up)")):
        gyrocore.read_log(path)
    for options in ({"rate_col": "gyro_rad[2]"}, {"gyro_cols": "gyro_rad[0],gyro_rad[1],gyro_rad[2]", "up": "z"}):
        log = gyrocore.read_log(path, time_col="timestamp", time_unit="us", **options)
        assert log.t[0] == pytest.approx(20.0)
        assert np.degrees(np.sum(log.rate[1:] * np.diff(log.t))) == pytest.approx(90, abs=0.01)
    assert gyrocore.io.units.split_unit("w [deg/s]") == ("w", "deg/s")  # a unit in brackets stays one

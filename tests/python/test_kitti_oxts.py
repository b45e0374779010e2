"""KITTI raw OXTS folders read as logs, checked against the shared KITTI logs: an OXTS folder is
written back from a shared log's CSV files (as KITTI ships it: timestamps.txt, data/*.txt,
dataformat.txt), and reading it must give the shared log again."""

from __future__ import annotations

import json
import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.io import open_source

from .conftest import gyrocore_cli, real_log_path

#: KITTI raw's dataformat.txt fields, in order, as the devkit's readme lists them (written here
#: apart from the reader's own list, that a wrong order there fails these tests).
DEVKIT_FIELDS = ("lat lon alt roll pitch yaw vn ve vf vl vu ax ay az af al au wx wy wz wf wl wu posacc velacc navstat "
                 "numsats posmode velmode orimode").split()
#: The first frame's position (Karlsruhe; the shared logs keep x, y only, relative to it).
LAT0, LON0 = 49.011212804408, 8.4228850417969
R = 6378137.0
KITTI = ("kitti_2011_09_30_0018", "kitti_2011_09_30_0020", "kitti_2011_09_30_0027", "kitti_2011_09_30_0033",
         "kitti_2011_09_30_0034", "kitti_2011_10_03_0042")


def _columns(path: Path) -> tuple[list[str], np.ndarray]:
    """A shared CSV's t column as written (text) and its other columns as floats."""
    lines = path.read_text().splitlines()[1:]
    t = [line.split(",", 1)[0] for line in lines]
    return t, np.array([[float(v) for v in line.split(",")[1:]] for line in lines])


def _stamp(date: str, t: str) -> str:
    """KITTI's timestamp of the shared t (seconds of the first frame's day, 9 decimals) on ``date``."""
    whole, _, fraction = t.partition(".")
    ns = int(whole) * 10**9 + int(fraction.ljust(9, "0"))
    return str(np.datetime64(date, "ns") + np.timedelta64(ns, "ns")).replace("T", " ")


def write_oxts(log: Path, folder: Path, frames: slice = slice(None)) -> Path:
    """The shared KITTI log ``log`` as the OXTS folder ``folder`` (``frames`` of it): the
    timestamps from meta.json's first-frame date and the t column, yaw = heading, wz = gyro_z,
    vf = speed, and lat, lon from x, y inverted about :data:`LAT0`, :data:`LON0` as meta.json's
    equirectangular projection states; the other fields are 0 (flags 4 10 4 4 6)."""
    meta = json.loads((log / "meta.json").read_text())
    assert "equirectangular about the first frame (R = 6378137 m)" in meta["reference"]
    date = re.search(r"\((\d{4}-\d{2}-\d{2}) \d{2}:", meta["time"]).group(1)
    t, gyro = _columns(log / "gyro.csv")
    t_ref, ref = _columns(log / "reference.csv")
    t_odo, odo = _columns(log / "odometry.csv")
    assert t == t_ref == t_odo  # one frame per line in each
    lat = LAT0 + np.degrees(ref[:, 2] / R)
    lon = LON0 + np.degrees(ref[:, 1] / (R * np.cos(np.radians(LAT0))))
    (folder / "data").mkdir(parents=True)
    rows = range(len(t))[frames]
    (folder / "timestamps.txt").write_text("".join(_stamp(date, t[k]) + "\n" for k in rows))
    (folder / "dataformat.txt").write_text("".join(f"{name}: the devkit's description\n" for name in DEVKIT_FIELDS))
    for i, k in enumerate(rows):
        values = dict.fromkeys(DEVKIT_FIELDS, 0.0)
        values.update(lat=lat[k], lon=lon[k], yaw=ref[k, 0], wz=gyro[k, 0], vf=odo[k, 0])
        floats = " ".join(format(float(values[name]), ".17g") for name in DEVKIT_FIELDS[:-5])
        (folder / "data" / f"{i:010d}.txt").write_text(f"{floats} 4 10 4 4 6\n")
    return folder


@pytest.fixture(scope="module")
def drive(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """kitti_2011_09_30_0034 as a KITTI raw drive folder (its oxts/ folder)."""
    folder = tmp_path_factory.mktemp("kitti") / "2011_09_30_drive_0034_sync"
    write_oxts(real_log_path("kitti_2011_09_30_0034"), folder / "oxts")
    return folder


@pytest.fixture
def short(tmp_path: Path) -> Path:
    """The first 12 frames of kitti_2011_09_30_0034 as an OXTS folder, to be spoilt by a test."""
    return write_oxts(real_log_path("kitti_2011_09_30_0034"), tmp_path / "drive" / "oxts", slice(0, 12))


def _same_log(oxts: gyrocore.Log, shared: gyrocore.Log) -> None:
    """``oxts`` read from the folder written back from ``shared`` holds the same log. Times, rates,
    headings and speeds are written with 17 digits and come back as the same floats: t is the
    ns count divided once, as the shared t's 9 decimals are read, so they are equal. x, y went
    through degrees: a degree near 49 is resolved to 7e-15 (0.8 nm on the earth), so a few of
    those steps stay within 10 nm (the shared files write micrometres)."""
    np.testing.assert_array_equal(oxts.t, shared.t)
    np.testing.assert_array_equal(oxts.rate, shared.rate)
    np.testing.assert_array_equal(oxts.t_ref, shared.t_ref)
    np.testing.assert_array_equal(oxts.heading_ref, shared.heading_ref)
    np.testing.assert_allclose(oxts.x_ref, shared.x_ref, rtol=0, atol=1e-8)
    np.testing.assert_allclose(oxts.y_ref, shared.y_ref, rtol=0, atol=1e-8)
    np.testing.assert_array_equal(oxts.t_odometry, shared.t_odometry)
    np.testing.assert_array_equal(oxts.speed, shared.speed)


@pytest.mark.parametrize("name", KITTI)
def test_an_oxts_folder_reads_as_its_shared_log(name: str, tmp_path: Path) -> None:
    shared = real_log_path(name)
    oxts = write_oxts(shared, tmp_path / "oxts")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no unit looks wrong
        _same_log(gyrocore.read_log(oxts), gyrocore.read_log(shared))


def test_the_drive_folder_and_its_oxts_folder_are_one_log(drive: Path) -> None:
    by_drive, by_oxts = gyrocore.read_log(drive), gyrocore.read_log(drive / "oxts")
    assert by_drive.name == by_oxts.name == "2011_09_30_drive_0034_sync"
    _same_log(by_drive, gyrocore.read_log(real_log_path("kitti_2011_09_30_0034")))
    np.testing.assert_array_equal(by_oxts.t, by_drive.t)
    source = open_source(drive)
    assert (source.kind, source.data_path, source.progress_total) == ("kitti oxts", drive / "oxts", 1224)
    assert gyrocore.io.is_input(drive) and gyrocore.io.is_input(drive / "oxts")
    chunks = list(source.chunks(500))  # streamed as gyrocore process reads it
    assert [len(c) for c in chunks] == [500, 500, 224] and chunks[-1].done == 1224
    np.testing.assert_array_equal(np.concatenate([c.rate for c in chunks]), by_drive.rate)


def _scores(proc_stdout: str) -> dict[str, dict[str, object]]:
    """Each method's row of ``gyrocore evaluate --json``, without the log's path and name."""
    return {row["preset"]: {k: v for k, v in row.items() if k not in ("path", "name")} for row in json.loads(proc_stdout)}


def test_evaluate_scores_the_oxts_folder_as_the_shared_log(drive: Path) -> None:
    """The same E_psi (and every heading metric) to the last bit: the times, rates and headings
    are the same floats. Dead reckoning's position errors [m] follow x, y, equal to 10 nm
    (:func:`_same_log`), so within 1e-7 m (or percent) after a few hundred sums."""
    presets = ("--preset", "raw", "--preset", "recommended")
    ours = _scores(gyrocore_cli("evaluate", drive / "oxts", *presets, "--json", code=0).stdout)
    theirs = _scores(gyrocore_cli("evaluate", real_log_path("kitti_2011_09_30_0034"), *presets, "--json", code=0).stdout)
    assert sorted(ours) == sorted(theirs) == ["raw", "recommended"]
    for preset, row in ours.items():
        assert row["e_psi_deg"] == theirs[preset]["e_psi_deg"]
        assert row.keys() == theirs[preset].keys()
        for key, value in row.items():
            if key.startswith("position_"):
                assert value == pytest.approx(theirs[preset][key], rel=0, abs=1e-7), key
            else:
                assert value == theirs[preset][key], key
    assert ours["raw"]["e_psi_deg"] == pytest.approx(0.39998675, abs=1e-8)  # the shared meta's own integration: 0.40


def test_process_finds_the_rests_where_vf_stops(tmp_path: Path) -> None:
    """``gyrocore process`` streams the folder and, in whole mode, takes the stops of its speed vf
    as rests, as of the shared log's odometry.csv (kitti_2011_09_30_0018 stops for 5 s; at 10 Hz
    the rate alone finds no rest): the same rest, report and headings."""
    shared = real_log_path("kitti_2011_09_30_0018")
    drive = tmp_path / "2011_09_30_drive_0018_sync"
    write_oxts(shared, drive / "oxts")
    ours = gyrocore_cli("process", drive, "--out", tmp_path / "ours.csv", code=0)
    theirs = gyrocore_cli("process", shared, "--out", tmp_path / "theirs.csv", code=0)
    assert "no logs" not in ours.stderr
    rests = [line.strip() for line in ours.stdout.splitlines() if line.strip().startswith(("bias:", "rest "))]
    assert rests == [line.strip() for line in theirs.stdout.splitlines() if line.strip().startswith(("bias:", "rest "))]
    assert any(line.endswith("(speed): bias -0.00493 +- 0.0047 deg/s") for line in rests), rests
    assert (tmp_path / "ours.csv").read_bytes() == (tmp_path / "theirs.csv").read_bytes()


def test_a_missing_data_file_is_named(short: Path) -> None:
    (short / "data" / "0000000007.txt").unlink()
    with pytest.raises(ValueError, match=r"data: 11 data files, and .*timestamps.txt has 12 timestamps "
                                         r"\(0000000007.txt is missing\)"):
        gyrocore.read_log(short)


def test_a_data_file_beyond_the_timestamps_is_named(short: Path) -> None:
    (short / "data" / "0000000012.txt").write_text((short / "data" / "0000000011.txt").read_text())
    with pytest.raises(ValueError, match=r"13 data files, and .* has 12 timestamps \(0000000012.txt is not a frame's\)"):
        gyrocore.read_log(short)


def test_a_line_without_30_numbers_is_named(short: Path) -> None:
    path = short / "data" / "0000000004.txt"
    path.write_text(path.read_text().rsplit(" ", 1)[0] + "\n")  # cut short: the last number gone
    with pytest.raises(ValueError, match=r"0000000004.txt: line 1: 29 numbers, and an OXTS data line has 30 \(lat lon"):
        gyrocore.read_log(short)


def edit_lines(path: Path, edit: Callable[[list[str]], None]) -> list[str]:
    """The file ``path`` written again with its lines as ``edit`` leaves them; those lines."""
    lines = path.read_text().splitlines()
    edit(lines)
    path.write_text("\n".join(lines) + "\n")
    return lines


def set_field(path: Path, index: int, value: str) -> list[str]:
    """Field ``index`` of the OXTS data file ``path`` written as ``value``; the fields as they were."""
    fields = path.read_text().split()
    path.write_text(" ".join([*fields[:index], value, *fields[index + 1:]]) + "\n")
    return fields


def test_text_in_a_field_is_named(short: Path) -> None:
    set_field(short / "data" / "0000000003.txt", 19, "abc")
    with pytest.raises(ValueError, match=r"0000000003.txt: line 1, column 20 \(wz\): 'abc' is not a number"):
        gyrocore.read_log(short)


@pytest.mark.parametrize("line, said", [("2011-09-30 13:16:0x.640352090", "'2011-09-30 13:16:0x.640352090' is not a timestamp"),
                                        ("2011-13-30 13:16:06.640352090", "'2011-13-30 13:16:06.640352090' is not a timestamp"),
                                        ("", "blank, where a frame's timestamp belongs")])
def test_a_timestamp_that_does_not_parse_is_named(short: Path, line: str, said: str) -> None:
    def put(lines: list[str]) -> None:
        lines[4] = line

    edit_lines(short / "timestamps.txt", put)
    with pytest.raises(ValueError, match=rf"timestamps.txt: line 5: {re.escape(said)}"):
        gyrocore.read_log(short)


def test_a_repeated_timestamp_is_named(short: Path) -> None:
    def repeat(lines: list[str]) -> None:
        lines[7], lines[10] = lines[6], lines[2]

    lines = edit_lines(short / "timestamps.txt", repeat)
    with pytest.raises(ValueError, match=rf"timestamps.txt: line 8: {lines[6]} repeats {lines[6]} on line 7 \(2 such "
                                         r"lines in all\); timestamps must strictly increase. KITTI raw's extract"):
        gyrocore.read_log(short)


def test_a_dataformat_in_another_order_is_refused(short: Path) -> None:
    def swap(lines: list[str]) -> None:
        lines[19], lines[22] = lines[22], lines[19]  # wz and wu swapped

    edit_lines(short / "dataformat.txt", swap)
    with pytest.raises(ValueError, match=r"dataformat.txt: line 20: field 'wu' where KITTI raw's OXTS format has 'wz'"):
        gyrocore.read_log(short)


def test_the_rate_is_wz_or_wu(short: Path) -> None:
    fields = set_field(short / "data" / "0000000000.txt", 22, "0.5")
    assert gyrocore.read_log(short, rate_col="wu").rate[0] == 0.5
    assert gyrocore.read_log(short).rate[0] == float(fields[19])
    with pytest.raises(ValueError, match=r"rate_col 'wx' \(--rate-col\) is no yaw rate of a KITTI OXTS folder"):
        gyrocore.read_log(short, rate_col="wx")
    with pytest.raises(ValueError, match=r"leave out gyro_cols, accel_cols and up"):
        gyrocore.read_log(short, up="z")
    with pytest.warns(gyrocore.InputWarning, match=r"time_unit 'ms' \(--time-unit\) is not used: a KITTI OXTS"):
        gyrocore.read_log(short, time_unit="ms")


def test_a_camera_folder_is_named_as_such(short: Path) -> None:
    camera = short.parent / "image_00"
    (camera / "data").mkdir(parents=True)
    (camera / "timestamps.txt").write_text((short / "timestamps.txt").read_text())
    with pytest.raises(ValueError, match=r"looks like a KITTI raw sensor folder \(timestamps.txt, data/\), and gyrocore "
                                         r"reads the drive's GPS/IMU: give its oxts folder"):
        gyrocore.read_log(camera)
    proc = gyrocore_cli("process", camera, "--out", short.parent / "heading.csv", code=2)
    assert proc.stderr.strip().endswith(f"log or bag folders); it looks like a KITTI raw sensor folder (timestamps.txt, "
                                        f"data/), and gyrocore reads the drive's GPS/IMU: give its oxts folder ({short}) "
                                        f"or the drive folder ({short.parent})")


def test_a_value_read_that_is_not_finite_is_named(short: Path) -> None:
    set_field(short / "data" / "0000000009.txt", 8, "nan")  # vf, the odometry
    with pytest.raises(ValueError, match=r"0000000009.txt: line 1, column 9 \(vf\): nan is not a finite number"):
        gyrocore.read_log(short)


def test_a_timestamp_that_goes_back_is_named(short: Path) -> None:
    def swap(lines: list[str]) -> None:
        lines[3], lines[4] = lines[4], lines[3]

    lines = edit_lines(short / "timestamps.txt", swap)
    with pytest.raises(ValueError, match=rf"timestamps.txt: line 5: {lines[4]} goes back from {lines[3]} on line 4; "):
        gyrocore.read_log(short)


def test_a_drive_past_midnight_counts_on(short: Path) -> None:
    # seconds of the first frame's day: the frames after midnight are 86400 s and more, not 0
    stamps = [str(np.datetime64("2011-09-30T23:59:59.550000001") + np.timedelta64(k * 100_000_000, "ns")) for k in range(12)]
    (short / "timestamps.txt").write_text("".join(s.replace("T", " ") + "\n" for s in stamps))
    t = gyrocore.read_log(short).t
    assert t[0] == 86399.550000001 and t[5] == 86400.050000001 and t[-1] == 86400.650000001
    assert np.all(np.diff(t) > 0.0999999)


def test_outputs_are_named_after_their_drives(tmp_path: Path) -> None:
    """Two drives' oxts folders processed into one output folder: each output was named after its
    folder, oxts.csv, and the second refused as the first's; each is named after its drive."""
    drives = [tmp_path / f"2011_09_30_drive_00{n}_sync" for n in ("18", "34")]
    for drive, log in zip(drives, ("kitti_2011_09_30_0018", "kitti_2011_09_30_0034")):
        write_oxts(real_log_path(log), drive / "oxts", slice(0, 300))
    out = tmp_path / "headings"
    proc = gyrocore_cli("process", *(drive / "oxts" for drive in drives), "--out", out, code=0)
    assert sorted(p.name for p in out.iterdir()) == [f"{drive.name}.csv" for drive in drives], proc.stderr
    # the drive folder names its output alike, and a drive given both ways is one output, refused
    assert gyrocore.batch.output_paths([drives[0]], out, "csv") == [out / f"{drives[0].name}.csv"]
    with pytest.raises(ValueError, match=r"would both be written to .*2011_09_30_drive_0018_sync\.csv"):
        gyrocore.batch.output_paths([drives[0], drives[0] / "oxts"], out, "csv")

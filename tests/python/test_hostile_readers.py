"""Parquet, NumPy and bag files built to break the readers: each gives its samples, or an error
naming the file and where, never a wrong heading or an error that blames something else."""

from __future__ import annotations

import gzip
import re
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import io

from .conftest import gyrocore_cli
from .test_io import write_bag

N = 2_000
T = np.arange(N) * 0.01


def speed_parquet(path: Path, speed: list[float | None]) -> Path:
    """A Parquet file with a gyro at rest (bias 0.01 rad/s) in its first and last 5 s and turning
    between, and the ``speed`` column given."""
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    rate = 0.01 + np.where((T > 5) & (T < 15), 0.2, 0.0)
    pq.write_table(pa.table({"t": T, "gyro_z": rate, "speed": pa.array(speed, pa.float64())}), path)
    return path


def test_an_empty_speed_value_of_a_file_is_a_speed_unknown_there(tmp_path: Path) -> None:
    # Log.process refused it (`log x: odometry speed: speed[3] is nan`) where gyrocore process took it
    speed: list[float | None] = [0.0 if t < 5 or t > 15 else 3.0 for t in T]
    speed[3] = None
    log = gyrocore.read_log(speed_parquet(tmp_path / "x.parquet", speed))
    given = np.array([np.nan if s is None else s for s in speed])
    expected = gyrocore.process(log.t, log.rate, "static_bias", speed=given)
    result = log.process("static_bias")
    assert any(r.found_by == "speed" for r in result.rests)
    np.testing.assert_array_equal(result.heading, expected.heading)


def test_an_infinite_speed_of_a_file_is_named_where_it_is_read(tmp_path: Path) -> None:
    # it was refused only by Log.process, as `odometry speed: speed[7] is inf`, without the file
    speed: list[float | None] = [0.0] * N
    speed[7] = float("inf")
    path = speed_parquet(tmp_path / "x.parquet", speed)
    with pytest.raises(ValueError, match=r"x\.parquet: row 7, column speed: inf is not a finite speed \[m/s\]"):
        gyrocore.read_log(path)


def test_a_nan_time_of_a_short_file_is_not_taken_for_another_unit(tmp_path: Path) -> None:
    # every interval touched the NaN, and read as a gap: "each of the 2 intervals is longer than
    # 2 s, a gap: give the unit of the time column"
    path = tmp_path / "x.npy"
    np.save(path, np.array([[0.0, 0.1], [np.nan, 0.1], [0.02, 0.1]]))
    assert np.isnan(gyrocore.read_log(path).t[1])
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2)
    assert proc.stderr == f"gyrocore: error: t[1] is NaN: samples must be finite (drop or fill them first) ({path}, row 1)\n"


def npy_bytes(header: dict[str, object], data: bytes = b"") -> bytes:
    """An .npy file of version 1.0 with ``header`` as written, whatever it says."""
    text = repr(header).encode()
    pad = -(10 + len(text) + 1) % 64
    return b"\x93NUMPY\x01\x00" + (len(text) + pad + 1).to_bytes(2, "little") + text + b" " * pad + b"\n" + data


NEGATIVE = {"descr": "<f8", "fortran_order": False, "shape": (-1, 2)}


def test_a_negative_shape_is_no_npy_file(tmp_path: Path) -> None:
    # numpy's header parser takes it, and the reader found "no samples" in a file that holds some
    path = tmp_path / "x.npy"
    path.write_bytes(npy_bytes(NEGATIVE, np.zeros(8).tobytes()))
    with pytest.raises(ValueError, match=r"x\.npy: not a NumPy \.npy file \(its header's shape \(-1, 2\) has a negative size\)"):
        gyrocore.read_log(path)
    archive = tmp_path / "x.npz"
    with zipfile.ZipFile(archive, "w") as z:
        for name in ("t", "gyro_z"):
            z.writestr(f"{name}.npy", npy_bytes({**NEGATIVE, "shape": (-2,)}))
    with pytest.raises(ValueError, match=r"x\.npz: member t: not a NumPy \.npy file \(its header's shape \(-2,\)"):
        gyrocore.read_log(archive)


def test_an_empty_archive_says_it_has_no_arrays(tmp_path: Path) -> None:
    path = tmp_path / "x.npz"
    zipfile.ZipFile(path, "w").close()
    with pytest.raises(ValueError, match=r"x\.npz: missing column\(s\) t, gyro_z; it has none \("):
        gyrocore.read_log(path)


def durations_file(path: Path) -> Path:
    """A log whose time is a timedelta64[ns] (a structured .npy array, or an .npz member)."""
    t = (np.arange(100) * 10_000_000).astype("m8[ns]")
    if path.suffix == ".npz":
        np.savez(path, t=t, gyro_z=np.full(100, 0.1))
    else:
        np.save(path, np.rec.fromarrays([t, np.full(100, 0.1)], names=["t", "gyro_z"]))
    return path


@pytest.mark.parametrize("name", ["x.npy", "x.npz"])
def test_a_time_unit_given_for_numpy_durations_says_it_is_not_used(tmp_path: Path, name: str) -> None:
    # a Parquet duration column warned so; a NumPy one took its own unit without a word
    path = durations_file(tmp_path / name)
    with pytest.warns(gyrocore.InputWarning, match=rf"{name}: column t is a timedelta64\[ns\] with its own unit "
                      r"\(ns\): time_unit 'ms' \(--time-unit\) is not used"):
        log = gyrocore.read_log(path, time_unit="ms")
    assert log.t[-1] == 0.99
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gyrocore.read_log(path, time_unit="ns")


def test_a_plain_array_of_more_than_two_columns_says_which_is_the_rate(tmp_path: Path) -> None:
    # t, gx, gy, gz read gx as the yaw rate without a word
    path = tmp_path / "imu.npy"
    np.save(path, np.column_stack([T, np.full(N, 0.3), np.full(N, -0.2), np.full(N, 0.1)]))
    with pytest.warns(gyrocore.InputWarning, match=r"imu\.npy: a plain array of 4 columns, and the rate is read "
                      r"from column 1, the default: give rate_col \(--rate-col N\)"):
        assert gyrocore.read_log(path).rate[0] == 0.3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert gyrocore.read_log(path, rate_col="3").rate[0] == 0.1


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_a_bag_whose_stamps_were_never_set_says_so(tmp_path: Path, ros1: bool) -> None:
    # it was "timestamps must strictly increase: t[1] = 0 follows 0 (sort the log and drop
    # duplicate timestamps)"; a simulated clock's first stamp of 0 is read
    unset, simulated = (tmp_path / name for name in (("x.bag", "y.bag") if ros1 else ("x", "y")))
    write_bag(unset, [0, 10_000_000, 20_000_000, 0, 40_000_000], [0.1] * 5, ros1=ros1)
    with pytest.raises(ValueError, match=r"x(\.bag)?: message 3 on /imu: header\.stamp is 0, a stamp its driver never set"):
        list(io.open_source(unset).chunks(2))
    write_bag(simulated, [k * 10_000_000 for k in range(5)], [0.1] * 5, ros1=ros1)
    assert gyrocore.read_log(simulated).t.tolist() == [0.0, 0.01, 0.02, 0.03, 0.04]


def test_the_storage_file_of_a_ros2_bag_names_its_folder(tmp_path: Path) -> None:
    # it was "unknown kind of file", without a word that the folder is what is read
    folder = tmp_path / "drive"
    write_bag(folder, [0, 10_000_000], [0.1, 0.1], ros1=False)
    (storage,) = folder.glob("*.db3")
    with pytest.raises(ValueError, match=rf"unknown kind of file .*; {storage.name} is a file of the ROS 2 bag "
                       rf"{folder}: give the bag's folder$"):
        io.open_source(storage)


def test_a_field_named_beyond_latin_1_is_read_by_its_name(tmp_path: Path) -> None:
    # np.save writes such a header as version 3.0 (UTF-8), which was read as Latin-1: "missing
    # column(s) ω_z; it has t, Ï_z"
    path = tmp_path / "x.npy"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # numpy: "Stored array in format 3.0"
        np.save(path, np.rec.fromarrays([T, np.full(N, 0.1)], names=["t", "ω_z"]))
    assert path.read_bytes()[6:8] == b"\x03\x00"
    log = gyrocore.read_log(path, rate_col="ω_z")
    assert np.array_equal(log.t, T) and np.all(log.rate == 0.1)


def samples_as(path: Path, kind: str) -> None:
    """Write a small log to ``path`` as ``kind`` content, whatever its suffix says."""
    t, rate = T[:10], np.full(10, 0.1)
    if kind == "csv":
        path.write_text("t,gyro_z\n" + "".join(f"{a},{b}\n" for a, b in zip(t, rate)))
    elif kind == "parquet":
        pa, pq = pytest.importorskip("pyarrow"), pytest.importorskip("pyarrow.parquet")
        pq.write_table(pa.table({"t": t, "gyro_z": rate}), path)
    elif kind == "gzip":
        path.write_bytes(gzip.compress(b"t,gyro_z\n0,0.1\n"))
    else:
        with open(path, "wb") as f:
            (np.savez if kind == "npz" else np.save)(f, np.column_stack([t, rate]))  # type: ignore[operator]


@pytest.mark.parametrize(("name", "kind", "said"), [
    ("x.parquet", "csv", "its content is text (a CSV file?): name it x.csv"),
    ("x.npy", "npz", "its content is that of a zip archive (a NumPy .npz file?): name it x.npz"),
    ("x.npz", "npy", "its content is that of a NumPy .npy file: name it x.npy"),
    ("x.npy", "parquet", "its content is that of a Parquet file: name it x.parquet"),
    ("x.dat", "npy", "its content is that of a NumPy .npy file: name it x.npy"),
    ("x.npy", "gzip", "it is compressed with gzip: decompress it first"),
])
def test_a_file_whose_suffix_lies_says_what_it_holds(tmp_path: Path, name: str, kind: str, said: str) -> None:
    # the reader's error alone said "Parquet magic bytes not found in footer", "File is not a zip file"
    path = tmp_path / name
    samples_as(path, kind)
    with pytest.raises(ValueError, match=rf"{re.escape(name)}: .*; {re.escape(said)}$"):
        io.open_source(path)


def test_a_file_whose_suffix_is_right_gets_no_word_on_its_content(tmp_path: Path) -> None:
    pa, pq = pytest.importorskip("pyarrow"), pytest.importorskip("pyarrow.parquet")
    path = tmp_path / "x.pq"  # Parquet's other suffix
    pq.write_table(pa.table({"t [ms]": T, "gyro_z": np.zeros(N)}), path)
    with pytest.raises(ValueError, match=r"states the unit 'ms' but --time-unit s was given: leave out --time-unit "
                       r"\(or correct the header\)$"):
        io.open_source(path, time_col="t", time_unit="s")


EPOCH_NS = 1_700_000_000_000_000_000


@pytest.mark.parametrize("kind", ["csv", "npy", "datetime64", "timedelta64"])
def test_nanoseconds_that_float64_seconds_cannot_tell_apart_say_so(tmp_path: Path, kind: str) -> None:
    """Epoch nanoseconds 100 ns apart are one float64 time (it resolves 238-256 ns there): the
    error said only "sort the log and drop duplicate timestamps", of a file with neither. numpy
    times (datetime64, read as epoch seconds, and timedelta64) carry their unit and said nothing."""
    t = EPOCH_NS + np.arange(100, dtype=np.int64) * 100
    path = tmp_path / f"fast.{'csv' if kind == 'csv' else 'npy'}"
    if kind == "csv":
        path.write_text("t,gyro_z\n" + "".join(f"{v},0.0\n" for v in t))
    else:
        times = t if kind == "npy" else t.astype(f"{kind}[ns]")
        np.save(path, np.rec.fromarrays([times, np.zeros(100)], names="t,gyro_z"))
    unit = {"time_unit": "ns"} if kind in ("csv", "npy") else {}
    with pytest.warns(gyrocore.InputWarning, match=r"two times read as one, 1700000000\.000000000 s \(counts of 1/1e\+09 s\), "
                      r"where float64 resolves only 2\.\d+e-07 s: .*subtract 1700000000000000000 from each"):
        with pytest.raises(ValueError, match="must strictly increase"):
            gyrocore.read_log(path, **unit).process("raw")


def test_timedelta64_nanoseconds_given_to_the_api_that_float64_merges_say_so() -> None:
    t = (EPOCH_NS + np.arange(100, dtype=np.int64) * 100).astype("timedelta64[ns]")
    with pytest.warns(gyrocore.InputWarning, match=r"two times read as one, 1700000000\.000000000 s \(counts of "
                      r"1/1e\+09 s\), where float64 resolves only 2\.\d+e-07 s"):
        with pytest.raises(ValueError, match="must strictly increase"):
            gyrocore.process(t, np.zeros(100), "raw")
    with warnings.catch_warnings():  # durations from the first sample are told apart: no word
        warnings.simplefilter("error")
        gyrocore.process(t - t[0], np.zeros(100), "raw")
    # a longer unit's counts are 60 s apart: said as counts of 1/0.0166667 s (it said 1/1 s)
    minutes = (2**54 + np.arange(4)).astype("timedelta64[m]")
    with pytest.warns(gyrocore.InputWarning, match=r"counts of 1/0\.0166667 s\), where float64 resolves only 240 s"):
        with pytest.raises(ValueError, match="is beyond"):
            gyrocore.process(minutes, np.zeros(4), "raw")


def test_a_repeated_time_the_file_holds_is_no_matter_of_resolution(tmp_path: Path) -> None:
    """Nanosecond counts repeated in the file, or seconds repeated, are the file's duplicates."""
    for name, t, unit in (("ns.npy", EPOCH_NS + np.array([0, 10**7, 10**7, 3 * 10**7]), "ns"),
                          ("s.csv", 1.7e9 + np.array([0.0, 0.01, 0.01, 0.03]), "s")):
        path = tmp_path / name
        if name.endswith(".npy"):
            np.save(path, np.rec.fromarrays([t, np.zeros(4)], names="t,gyro_z"))
        else:
            path.write_text("t,gyro_z\n" + "".join(f"{v:.2f},0.0\n" for v in t))
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ValueError, match="must strictly increase"):
                gyrocore.read_log(path, time_unit=unit).process("raw")

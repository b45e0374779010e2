"""Readers (CSV, Parquet, NumPy, log folders, ROS bags), units and their sanity checks, malformed
files, heading conventions and the atomic heading-table writer."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pa_csv
import pyarrow.parquet as pq
import pytest

import gyrocore
from gyrocore import batch, io

from .conftest import REAL_LOGS, real_log_path

T = 1.7e9 + np.cumsum(np.full(1000, 0.01) + np.linspace(0, 1e-3, 1000))  # irregular, Unix epoch
RATE = 0.3 * np.sin(np.arange(1000) / 50.0) + 0.002


def read_all(path: Path, rows: int = 64, **options: object) -> tuple[np.ndarray, np.ndarray]:
    chunks = list(io.open_source(path, **options).chunks(rows))
    assert all(len(c) <= rows for c in chunks)
    return np.concatenate([c.t for c in chunks]), np.concatenate([c.rate for c in chunks])


def write_csv(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


# --- formats -------------------------------------------------------------------------------


@pytest.mark.filterwarnings("ignore:.*read as a file alone")  # the gyro file itself is what is compared
@pytest.mark.parametrize("name", REAL_LOGS)
def test_csv_reader_matches_numpy_loadtxt_bit_for_bit(name: str) -> None:
    gyro = real_log_path(name) / "gyro.csv"
    expected = np.loadtxt(gyro, delimiter=",", skiprows=1)
    t, rate = read_all(gyro, rows=1000)
    assert t.tobytes() == expected[:, 0].tobytes()
    assert rate.tobytes() == expected[:, 1].tobytes()


def test_every_format_reads_the_same_samples(tmp_path: Path) -> None:
    table = pa.table({"t": T, "other": np.zeros_like(T), "gyro_z": RATE})
    pa_csv.write_csv(table, tmp_path / "a.csv")
    pq.write_table(table, tmp_path / "a.parquet")
    np.save(tmp_path / "plain.npy", np.column_stack([T, RATE]))
    np.save(tmp_path / "fortran.npy", np.asfortranarray(np.column_stack([RATE, T])))
    rec = np.empty(len(T), dtype=[("t", "<f8"), ("x", "i4"), ("gyro_z", ">f8")])
    rec["t"], rec["x"], rec["gyro_z"] = T, 7, RATE
    np.save(tmp_path / "structured.npy", rec)
    np.savez(tmp_path / "a.npz", t=T, gyro_z=RATE)
    cases = [("a.csv", {}), ("a.parquet", {}), ("plain.npy", {}), ("fortran.npy", {"time_col": "1", "rate_col": "0"})]
    cases += [("structured.npy", {}), ("a.npz", {})]
    for file, options in cases:
        t, rate = read_all(tmp_path / file, rows=97, **options)
        assert t.tobytes() == T.tobytes(), file
        assert rate.tobytes() == RATE.tobytes(), file


def test_units_are_converted_to_seconds_and_rad_per_s(tmp_path: Path) -> None:
    ms = np.round((T - T[0]) * 1e3, 3)
    pq.write_table(pa.table({"time": ms, "wz": np.degrees(RATE)}), tmp_path / "a.parquet")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t, rate = read_all(tmp_path / "a.parquet", time_col="time", rate_col="wz", time_unit="ms", rate_unit="deg/s")
    assert t.tobytes() == (ms / 1000.0).tobytes()
    np.testing.assert_allclose(rate, RATE, rtol=1e-15, atol=1e-18)


def test_units_stated_by_parquet_and_csv_column_names(tmp_path: Path) -> None:
    ms = np.round((T - T[0]) * 1e3, 3)
    pq.write_table(pa.table({"time (ms)": ms, "wz [deg/s]": np.degrees(RATE)}), tmp_path / "a.parquet")
    pa_csv.write_csv(pa.table({"t_us": ms * 1e3, "gyro_z_dps": np.degrees(RATE)}), tmp_path / "a.csv")
    cases = [(tmp_path / "a.parquet", {"time_col": "time", "rate_col": "wz"}, "ms"), (tmp_path / "a.csv", {}, "us")]
    for path, options, time_unit in cases:
        src = io.open_source(path, **options)
        assert (src.options.time_unit, src.options.rate_unit) == (time_unit, "deg/s")
        t, rate = read_all(path, **options)
        np.testing.assert_allclose(t, ms / 1000.0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(rate, RATE, rtol=1e-15, atol=1e-18)
    pa_csv.write_csv(pa.table({"t [s]": ms, "t [ms]": ms, "gyro_z": RATE}), tmp_path / "two.csv")
    with pytest.raises(ValueError, match=r"column 't' matches 't \[s\]', 't \[ms\]'; give the whole name \(--time-col\)"):
        io.open_source(tmp_path / "two.csv")
    assert io.open_source(tmp_path / "two.csv", time_col="t [ms]").options.time_unit == "ms"


def test_parquet_timestamp_columns_carry_their_unit(tmp_path: Path) -> None:
    ns = np.array([1_700_000_000_000_000_000, 1_700_000_000_010_000_000, 1_700_000_000_020_000_000])
    stamps = pa.array(ns).cast(pa.timestamp("ns"))
    pq.write_table(pa.table({"t": stamps, "gyro_z": [0.1, 0.2, 0.3]}), tmp_path / "a.parquet")
    with pytest.warns(UserWarning, match=r"a.parquet: column t is a timestamp\[ns\] with its own unit \(ns\): "
                                         "time_unit 'ms' \\(--time-unit\\) is not used"):
        t, _ = read_all(tmp_path / "a.parquet", time_unit="ms")  # the type's unit wins
    assert t.tolist() == [1.7e9, 1.70000000001e9, 1.70000000002e9]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the unit the column has, or none given: nothing to say
        for unit in ("ns", None):
            assert read_all(tmp_path / "a.parquet", time_unit=unit)[0].tolist() == t.tolist()


def test_log_folder_gives_the_rest_window_of_its_meta_json() -> None:
    folder = real_log_path("f110_ds3")
    src = io.open_source(folder)
    assert src.kind == "log folder" and src.data_path == folder / "gyro.csv"
    assert src.stationary == (1651541251.8307054, 1651541253.6700983)
    log = gyrocore.read_log(folder)
    assert log.stationary == src.stationary and len(log.t) == 2736 and log.t_ref is not None


def test_read_log_reads_any_format_with_options(tmp_path: Path) -> None:
    np.savez(tmp_path / "drive.npz", time=(T - T[0]) * 1e3, wz=np.degrees(RATE))
    log = gyrocore.read_log(tmp_path / "drive.npz", time_col="time", rate_col="wz", time_unit="ms", rate_unit="deg/s")
    assert log.name == "drive" and log.stationary is None
    np.testing.assert_allclose(log.t, T - T[0], rtol=0, atol=1e-9)
    np.testing.assert_allclose(log.rate, RATE, rtol=1e-15)


def test_read_csv_columns_still_reads_named_columns(tmp_path: Path) -> None:
    path = write_csv(tmp_path / "r.csv", "t, heading ,x\n0,1.5,2\n1,-0.25,3\n")
    cols = io.read_csv_columns(path, ("t", "heading"))
    assert cols["heading"].tolist() == [1.5, -0.25] and cols["t"].flags.c_contiguous


# --- malformed files -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("t,gyro_z\n0,1\n1,2\n2,abc\n3,4\n", "line 4, column 2 (gyro_z): 'abc' is not a number"),
        ("t,gyro_z\n0,1\n1,2,5\n", "line 3: 3 fields, but the header has 2"),
        ("t,gyro_z\n0,1\n1\n", "line 3: 1 field, but the header has 2"),
        ("t,gyro_z\n0,1\n\n2,3\n", "line 3, column 1 (t): blank line"),
        ("t,gyro_z\n0,1\n,3\n", "line 3, column 1 (t): empty timestamp"),
        ("x,t,gyro_z\n0,0,1\n0,1_000,2\n", "line 3, column 2 (t): '1_000' is not a number"),
        # numbers to Python's float(), not to pyarrow: the error named no line
        ("t,gyro_z\n0,1\n1,\u0663\n", "line 3, column 2 (gyro_z): '\u0663' is not a number"),
        ("t,gyro_z\n0,1\n1,2\u00a0\n", "line 3, column 2 (gyro_z): '2\\xa0' is not a number"),
        ("t,gyro_z\n0,1\n1,2\v\n", "line 3, column 2 (gyro_z): '2\\x0b' is not a number"),
        ("time,gyro_z\n0,1\n", "missing column(s) t"),
        ("", "line 1: no header line"),
    ],
)
def test_malformed_csv_names_file_line_and_column(tmp_path: Path, text: str, where: str) -> None:
    path = write_csv(tmp_path / "bad.csv", text)
    with pytest.raises(ValueError) as e:
        read_all(path)
    assert str(e.value).startswith(f"{path}: ")
    assert where in str(e.value)


def test_a_bad_value_deep_in_a_large_csv_is_located_exactly(tmp_path: Path) -> None:
    n = 200_000
    lines = [f"{i * 0.01:.2f},{math.sin(i):.6f}" for i in range(n)]
    lines[150_000] = "1500.00,0.5x"
    path = write_csv(tmp_path / "big.csv", "t,gyro_z\n" + "\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"big\.csv: line 150002, column 2 \(gyro_z\): '0\.5x' is not a number"):
        read_all(path, rows=10_000)


def test_empty_rates_become_nan_for_the_input_policy(tmp_path: Path) -> None:
    path = write_csv(tmp_path / "gap.csv", "t,gyro_z\n0,1\n1,\n2,nan\n3,4\n")
    _, rate = read_all(path)
    assert rate[0] == 1 and np.isnan(rate[1]) and np.isnan(rate[2]) and rate[3] == 4


@pytest.mark.parametrize(
    ("file", "make", "message"),
    [
        ("a.npy", lambda p: np.save(p, np.arange(5.0)), "expected a structured array"),
        ("b.npy", lambda p: p.write_bytes(b"not numpy"), "not a NumPy .npy file"),
        ("c.npy", lambda p: np.save(p, np.zeros((3, 2))), "plain 2-D array has numbered columns"),
        ("d.parquet", lambda p: p.write_bytes(b"PAR1 broken"), "not a readable Parquet file"),
        (
            "e.parquet",
            lambda p: pq.write_table(pa.table({"t": [0.0, None], "gyro_z": [1.0, 2.0]}), p),
            "row 1, column t: empty timestamp",
        ),
        (
            "f.parquet",
            lambda p: pq.write_table(pa.table({"t": [0.0], "gyro_z": ["x"]}), p),
            "column gyro_z holds string",
        ),
        ("g.npz", lambda p: np.savez(p, t=np.zeros(3), gyro_z=np.zeros(2)), "t has 3 samples but gyro_z has 2"),
        ("h.txt", lambda p: p.write_text("t,gyro_z\n"), "unknown kind of file"),
        ("i.npy", lambda p: np.save(p, np.full((3, 2), "x")), "the array holds <U1, not real numbers"),
        ("j.npz", lambda p: p.write_bytes(b"PK\x03\x04 cut"), "not a readable NumPy .npz file"),
    ],
)
def test_malformed_binary_files_name_the_file_and_problem(
    tmp_path: Path, file: str, make: object, message: str
) -> None:
    path = tmp_path / file
    make(path)  # type: ignore[operator]
    options = {"time_col": "x"} if file == "c.npy" else {}
    with pytest.raises(ValueError, match=str(path).replace(".", r"\.")) as e:
        read_all(path, **options)
    assert message in str(e.value)


@pytest.mark.parametrize("option", ["time_col", "rate_col"])
def test_a_column_number_that_is_no_text_is_named(tmp_path: Path, option: str) -> None:
    # an int reached the reader, whose str methods raised AttributeError
    path = tmp_path / "plain.npy"
    np.save(path, np.column_stack([T, RATE]))
    with pytest.raises(TypeError, match=rf"^{option} must be text: .* \({option}='1'\), got 1$"):
        gyrocore.read_log(path, **{option: 1})


def test_truncated_npy_is_an_error_not_short_data(tmp_path: Path) -> None:
    path = tmp_path / "cut.npy"
    np.save(path, np.column_stack([T, RATE]))
    path.write_bytes(path.read_bytes()[:-100])
    with pytest.raises(ValueError, match="file ends early"):
        read_all(path, rows=100)


@pytest.mark.parametrize("fortran", [False, True])
def test_an_npy_header_claiming_more_than_the_file_holds_is_refused_before_reading(tmp_path: Path, fortran: bool) -> None:
    # a block of rows of this shape asked numpy for terabytes (MemoryError)
    path = tmp_path / "wide.npy"
    with open(path, "wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": fortran, "shape": (3, 10**12)})
        f.write(np.zeros(6).tobytes())
    with pytest.raises(ValueError, match=r"wide\.npy: file ends early \(truncated \.npy\): its header's shape "
                       r"\(3, 1000000000000\) of float64 takes 24000000000000 bytes, the file holds 48 after"):
        read_all(path)


# --- unit checks ---------------------------------------------------------------------------


def unit_warnings(path: Path, **options: object) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gyrocore.read_log(path, **options)
    return [str(w.message) for w in caught if issubclass(w.category, gyrocore.InputWarning)]


def test_real_logs_raise_no_unit_warning() -> None:
    for name in REAL_LOGS:
        assert unit_warnings(real_log_path(name)) == [], name


def test_rates_in_deg_per_s_read_as_rad_per_s_warn(tmp_path: Path) -> None:
    log = gyrocore.read_log(real_log_path("f110_ds3"))
    np.savez(tmp_path / "dps.npz", t=log.t, gyro_z=np.degrees(log.rate))
    found = unit_warnings(tmp_path / "dps.npz")
    assert any("look like deg/s" in w and "--rate-unit deg/s" in w for w in found), found
    assert unit_warnings(tmp_path / "dps.npz", rate_unit="deg/s") == []


@pytest.mark.parametrize("name", REAL_LOGS)
def test_rates_in_rad_per_s_read_as_deg_per_s_warn(name: str) -> None:
    found = unit_warnings(real_log_path(name), rate_unit="deg/s")
    assert any("look like rad/s" in w and "--rate-unit rad/s" in w for w in found), found
    # A record known to be at rest (for an Allan deviation) reads small rates: no sign of a mistake.
    assert not any("look like rad/s" in w for w in unit_warnings(real_log_path(name), rate_unit="deg/s", static=True))


def test_timestamps_in_another_unit_warn(tmp_path: Path) -> None:
    log = gyrocore.read_log(real_log_path("broad_10"))  # 285.7 Hz from 0 s
    assert any("look like s, not ms" in w for w in unit_warnings(real_log_path("broad_10"), time_unit="ms"))
    t_ms = 1.7e12 + np.arange(1000.0)  # an epoch in ms at 1 kHz: 1 s intervals read as s, no gaps
    np.savez(tmp_path / "epoch_ms.npz", t=t_ms, gyro_z=RATE)
    assert any("look like ms, not s" in w and "--time-unit ms" in w for w in unit_warnings(tmp_path / "epoch_ms.npz"))
    assert unit_warnings(tmp_path / "epoch_ms.npz", time_unit="ms") == []
    np.savez(tmp_path / "ms.npz", t=log.t * 1e3, gyro_z=log.rate)
    assert unit_warnings(tmp_path / "ms.npz", time_unit="ms") == []


def test_timestamps_that_are_all_gaps_stop_with_the_option_to_add(tmp_path: Path) -> None:
    log = gyrocore.read_log(real_log_path("broad_10"))
    np.savez(tmp_path / "ms.npz", t=log.t * 1e3, gyro_z=log.rate)  # 3.5 "s" intervals: every one a gap
    with pytest.raises(ValueError, match=r"ms\.npz: each of the \d+ intervals is longer than 2 s.*--time-unit ms"):
        gyrocore.read_log(tmp_path / "ms.npz")
    np.savez(tmp_path / "epoch_ns.npz", t=(T * 1e9).astype(np.int64), gyro_z=RATE)  # epoch in ns as s
    with pytest.raises(ValueError, match=r"look like ns, not s.*--time-unit ns"):
        gyrocore.read_log(tmp_path / "epoch_ns.npz")
    assert unit_warnings(tmp_path / "epoch_ns.npz", time_unit="ns") == []


# --- ROS bags ------------------------------------------------------------------------------


def write_bag(
    path: Path,
    stamps_ns: list[int],
    rates: list[float],
    *,
    ros1: bool,
    topics: tuple[str, ...] = ("/imu",),
    gyro: np.ndarray | None = None,
    accel: np.ndarray | None = None,
) -> None:
    """A bag written by rosbags' own writer (sensor_msgs/Imu): angular velocity (0.1, -0.2, rate)
    and linear acceleration (0, 0, 9.81), or the rows of ``gyro`` and ``accel`` (samples x 3)."""
    typesys = pytest.importorskip("rosbags.typesys")
    store = typesys.get_typestore(typesys.Stores.ROS1_NOETIC if ros1 else typesys.Stores.ROS2_HUMBLE)
    types = store.types
    header_type = types["std_msgs/msg/Header"]
    vector, quaternion = types["geometry_msgs/msg/Vector3"], types["geometry_msgs/msg/Quaternion"]

    n = len(stamps_ns)
    gyro_rows = np.column_stack([np.full(n, 0.1), np.full(n, -0.2), rates]) if gyro is None else gyro
    accel_rows = np.tile([0.0, 0.0, 9.81], (n, 1)) if accel is None else accel

    def imu(k: int, ns: int) -> object:
        stamp = types["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
        header = header_type(seq=0, stamp=stamp, frame_id="imu") if ros1 else header_type(stamp=stamp, frame_id="imu")
        (gx, gy, gz), (ax, ay, az) = map(float, gyro_rows[k]), map(float, accel_rows[k])
        return types["sensor_msgs/msg/Imu"](
            header=header,
            orientation=quaternion(x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=np.zeros(9),
            angular_velocity=vector(x=gx, y=gy, z=gz),
            angular_velocity_covariance=np.zeros(9),
            linear_acceleration=vector(x=ax, y=ay, z=az),
            linear_acceleration_covariance=np.zeros(9),
        )

    def received(k: int) -> int:
        """The bag's own (receive) time of message k [ns]: increasing, whatever the header stamps."""
        return 1_700_000_000_000_000_000 + k * 10_000_000 + 1000

    msgtype = "sensor_msgs/msg/Imu"
    if ros1:
        from rosbags.rosbag1 import Writer

        with Writer(path) as writer:
            connections = [writer.add_connection(t, msgtype, typestore=store) for t in topics]
            for k, ns in enumerate(stamps_ns):
                for c in connections:
                    writer.write(c, received(k), store.serialize_ros1(imu(k, ns), msgtype))
    else:
        from rosbags.rosbag2 import Writer

        with Writer(path, version=9) as writer:
            connections = [writer.add_connection(t, msgtype, typestore=store) for t in topics]
            for k, ns in enumerate(stamps_ns):
                for c in connections:
                    writer.write(c, received(k), store.serialize_cdr(imu(k, ns), msgtype))


STAMPS = [1_700_000_000_000_000_000 + 9_999_937 * i for i in range(250)]
Z = [0.01 * math.sin(i / 10) for i in range(250)]


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_bags_give_imu_z_at_header_stamps(tmp_path: Path, ros1: bool) -> None:
    path = tmp_path / ("drive.bag" if ros1 else "drive")
    write_bag(path, STAMPS, Z, ros1=ros1)
    src = io.open_source(path)
    assert src.kind == "bag" and src.options.topic == "/imu" and src.progress_total == 250
    t, rate = read_all(path, rows=60)
    assert t.tobytes() == (np.array(STAMPS) / 1e9).tobytes()
    assert rate.tolist() == Z


def test_bag_with_two_imu_topics_needs_the_topic(tmp_path: Path) -> None:
    path = tmp_path / "two"
    write_bag(path, STAMPS[:5], Z[:5], ros1=False, topics=("/imu/a", "/imu/b"))
    with pytest.raises(ValueError, match="give the topic .*: /imu/a, /imu/b"):
        io.open_source(path)
    with pytest.raises(ValueError, match="no sensor_msgs/msg/Imu messages on /imu/c"):
        io.open_source(path, topic="/imu/c")
    assert read_all(path, topic="/imu/b")[1].tolist() == Z[:5]


def test_errors_of_a_chunk_name_the_global_row_and_the_line(tmp_path: Path) -> None:
    rows = [f"{k * 0.1:.1f},0.01" for k in range(10)]
    rows[7] = rows[6]  # a duplicate timestamp at sample 7, which a 3-row chunking puts in chunk 3
    path = write_csv(tmp_path / "a.csv", "t,gyro_z\n" + "\n".join(rows) + "\n")
    with pytest.raises(ValueError) as info:
        batch.process_file(path, tmp_path / "o.csv", preset="raw", chunk_rows=3)
    assert str(info.value) == f"timestamps must strictly increase: t[7] = 0.6 follows 0.6 (sort the log and " \
        f"drop duplicate timestamps) ({path}, line 9)"
    assert not (tmp_path / "o.csv").exists()


# --- heading conventions and output --------------------------------------------------------


def test_compass_heading_is_clockwise_from_north() -> None:
    # A quarter turn counter-clockwise from east ends facing north: ENU yaw pi/2, compass 0.
    t = np.linspace(0.0, 10.0, 1001)
    result = gyrocore.process(t, np.full_like(t, math.pi / 20), "raw")
    enu = io.convert_heading(result, "enu")
    compass = io.convert_heading(result, "compass")
    assert enu.heading[0] == 0.0 and enu.heading[-1] == pytest.approx(math.pi / 2, abs=1e-12)
    assert compass.heading[0] == pytest.approx(math.pi / 2) and compass.heading[-1] == pytest.approx(0.0, abs=1e-12)
    assert np.all(compass.rate == -result.rate)  # clockwise positive: still the heading's derivative
    with pytest.raises(ValueError, match="heading convention 'ned'"):
        io.convert_heading(result, "ned")


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
@pytest.mark.filterwarnings("ignore:the rest window")  # the synthetic drive turns in its first 2 s
def test_heading_table_reads_back_bit_identically(tmp_path: Path, suffix: str) -> None:
    result = gyrocore.process(T, RATE, "hdr", bias_duration=2.0)
    out = tmp_path / f"h{suffix}"
    with io.HeadingWriter(out) as writer:
        writer.write(result)
    assert writer.rows == len(T)
    table = pq.read_table(out) if suffix == ".parquet" else pa_csv.read_csv(out)
    assert table.column_names == ["t", "heading", "rate", "drift"]
    for name in table.column_names:
        expected = getattr(result, name)
        if suffix == ".csv":  # text holds no -0.0: zero is written (and so read back) without a sign
            expected = expected + 0.0
        assert table[name].to_numpy().tobytes() == expected.tobytes(), name
    if suffix == ".csv":
        assert out.read_text().splitlines()[0] == "t,heading,rate,drift"
        assert np.loadtxt(out, delimiter=",", skiprows=1)[:, 0].tobytes() == T.tobytes()


def test_writer_leaves_nothing_when_interrupted(tmp_path: Path) -> None:
    out = tmp_path / "h.csv"
    out.write_text("previous result\n")
    result = gyrocore.process(T, RATE, "raw")
    with pytest.raises(KeyboardInterrupt), io.HeadingWriter(out) as writer:
        writer.write(result)
        raise KeyboardInterrupt
    assert out.read_text() == "previous result\n"  # the old output is intact, not half replaced
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]  # no temporary file left


def test_writer_refuses_unknown_formats(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"must end in \.csv or \.parquet"):
        io.HeadingWriter(tmp_path / "h.txt")


def test_fuzz_finding_a_carriage_return_inside_the_header(tmp_path: Path) -> None:
    # Found by fuzz/python/readers.py: csv.Error escaped instead of a ValueError naming the file.
    # Its bytes are now refused earlier as binary (not named as columns); a bare carriage return in
    # a text header still reaches the csv module's error.
    path = tmp_path / "cr.csv"
    path.write_bytes(b"\x01\x00\x00\r0,0\x0e")
    with pytest.raises(ValueError, match=r"cr\.csv: not a text CSV file \(binary data on line 1"):
        io.read_log(path)
    path.write_bytes(b"t\rx,gyro_z\n0,0\n")
    with pytest.raises(ValueError, match=r"cr\.csv: line 1: malformed header"):
        io.read_log(path)


@pytest.mark.parametrize(
    ("name", "data", "message"),
    [
        # Found by fuzz/python/readers.py: a header numpy's parser rejects with TokenError.
        ("bad.npy", b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False, 'shape': (" + b" " * 100 + b"\n",
         "not a NumPy .npy file"),
        ("empty.npz", b"", "not a readable NumPy .npz file"),
        ("bad.parquet", b"PAR1garbagePAR1", "Parquet"),
    ],
)
def test_fuzz_findings_malformed_binary_files_are_value_errors(tmp_path: Path, name: str, data: bytes, message: str) -> None:
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(ValueError, match=message):
        io.read_log(path)


def test_fuzz_finding_an_npz_member_that_is_not_an_array(tmp_path: Path) -> None:
    import zipfile

    path = tmp_path / "raw.npz"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("t", b"0.0")
        z.writestr("gyro_z", b"0.1")
    with pytest.raises(ValueError, match="member t is not a NumPy array"):
        io.read_log(path)


def test_fuzz_finding_a_damaged_bag_is_a_value_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Found by fuzz/python/readers.py: rosbags reports some damage (a bad index record size) with a
    # bare AssertionError; whatever rosbags raises must come out as a ValueError naming the file.
    highlevel = pytest.importorskip("rosbags.highlevel")
    path = tmp_path / "damaged.bag"
    write_bag(path, STAMPS[:5], Z[:5], ros1=True)

    def broken_open(self: object) -> None:
        raise AssertionError

    monkeypatch.setattr(highlevel.AnyReader, "open", broken_open)
    with pytest.raises(ValueError, match=r"damaged\.bag: not a readable ROS bag \(AssertionError"):
        io.read_log(path)

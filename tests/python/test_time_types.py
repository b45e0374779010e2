"""timedelta64 timestamps are durations converted with their unit (not read as raw counts, which
made a heading 1000x too large); datetime64 is refused with what to do in the API, and read as
seconds since the Unix epoch from a file, as a Parquet timestamp column is."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import _rests

COUNTS = np.arange(0, 5000, 7)  # irregular enough to see any scale error
RATE = 0.3 * np.sin(COUNTS / 900.0)
# counts read as seconds look like a 0.14 Hz gyro with gaps: warned about, beside the point here
pytestmark = pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")


@pytest.mark.parametrize(("unit", "per_second"), [("s", 1), ("ms", 1e3), ("us", 1e6), ("ns", 1e9)])
def test_timedelta_timestamps_are_seconds_in_their_unit(unit: str, per_second: float) -> None:
    seconds = COUNTS / per_second
    durations = COUNTS.astype(f"timedelta64[{unit}]")
    expected = gyrocore.process(seconds, RATE, "raw")
    assert np.array_equal(gyrocore.process(durations, RATE, "raw").heading, expected.heading)
    assert np.array_equal(gyrocore.integrate(durations, RATE), expected.heading)


def test_datetime_timestamps_are_refused_with_the_conversion() -> None:
    with pytest.raises(TypeError, match=r"^t holds datetime64\[ms\] times: give seconds, e\.g\. \(t - t\.min\(\)\) / "):
        gyrocore.process(COUNTS.astype("datetime64[ms]"), RATE, "raw")


def test_timedelta_columns_of_numpy_files_carry_their_unit(tmp_path: Path) -> None:
    record = np.zeros(len(COUNTS), dtype=[("t", "timedelta64[ms]"), ("gyro_z", "f8")])
    record["t"], record["gyro_z"] = COUNTS, RATE
    np.save(tmp_path / "d.npy", record)
    np.savez(tmp_path / "d.npz", t=record["t"], gyro_z=RATE)
    for name in ("d.npy", "d.npz"):
        assert np.array_equal(gyrocore.read_log(tmp_path / name).t, COUNTS / 1e3)


def test_datetime_columns_of_numpy_files_are_epoch_seconds(tmp_path: Path) -> None:
    """They were refused (`t holds datetime64[ms], not real numbers or durations`) with nothing
    to give instead, where a Parquet file's timestamps are read: pandas' times saved with numpy."""
    epoch_ms = 1_714_557_600_000 + COUNTS
    record = np.zeros(len(COUNTS), dtype=[("t", "datetime64[ms]"), ("gyro_z", "f8")])
    record["t"], record["gyro_z"] = epoch_ms, RATE
    np.save(tmp_path / "e.npy", record)
    np.savez(tmp_path / "e.npz", t=record["t"].astype("datetime64[ns]"), gyro_z=RATE)
    for name in ("e.npy", "e.npz"):
        assert np.allclose(gyrocore.read_log(tmp_path / name).t, epoch_ms / 1e3, rtol=0, atol=1e-6)
    np.save(tmp_path / "y.npy", record.astype([("t", "datetime64[Y]"), ("gyro_z", "f8")]))
    with pytest.raises(ValueError, match=r"y\.npy: t holds datetime64\[Y\], which has no fixed length in seconds"):
        gyrocore.read_log(tmp_path / "y.npy")
    np.save(tmp_path / "s.npy", record.astype([("t", "f8"), ("gyro_z", "U3")]))
    with pytest.raises(ValueError, match=r"s\.npy: gyro_z holds <U3, not real numbers$"):
        gyrocore.read_log(tmp_path / "s.npy")


def test_timestamps_beyond_the_cores_limit_are_refused_before_processing() -> None:
    """+-1.5e308 are finite, but their interval is not: the heading was NaN. The core refuses a
    timestamp beyond +-2^40 s (gyrocore::MAX_TIME), naming it."""
    with pytest.raises(gyrocore.SampleError, match=r"^t\[0\] = -1\.5e308 s is beyond \+-1099511627776 s") as e:
        gyrocore.process([-1.5e308, 0.0, 1.5e308], [0.1, 0.1, 0.1], "recommended", bias=0.0)
    assert (e.value.index, e.value.what) == (0, "t")
    pipeline = gyrocore.Pipeline("raw")
    pipeline.process([0.0], [0.1])
    with pytest.raises(gyrocore.SampleError, match=r"^t\[1\] = 1\.5e308 s is beyond"):  # also in a later chunk
        pipeline.process([1.0, 1.5e308], [0.1, 0.1])
    # the chunk changed nothing, and the widest timestamps the core takes give a finite heading
    far = pipeline.process([1.0, 2.0**40 * (1 - 1e-9)], [0.1, 0.1])
    assert np.isfinite(far.heading).all() and far.heading[-1] > 1e10


@pytest.mark.parametrize("unit", ["as", "fs", "ps", "m", "h", "D", "W"])
def test_every_fixed_timedelta_unit_converts(tmp_path: Path, unit: str) -> None:
    """Found by fuzz/python/readers.py: numpy's own division overflowed for attoseconds."""
    seconds = {"as": 1e-18, "fs": 1e-15, "ps": 1e-12, "m": 60.0, "h": 3600.0, "D": 86400.0, "W": 604800.0}[unit]
    record = np.zeros(3, dtype=[("t", f"timedelta64[{unit}]"), ("gyro_z", "f8")])
    record["t"] = np.arange(3)
    np.save(tmp_path / "d.npy", record)
    expected = np.arange(3) / (1 / seconds) if seconds < 1 else np.arange(3) * seconds
    # The reader converts; a whole log of minutes or longer would be all gaps (an error of its own).
    chunk = next(gyrocore.io.open_source(tmp_path / "d.npy").chunks())
    assert np.array_equal(chunk.t, expected)


def test_timedelta_units_without_a_fixed_length_are_refused(tmp_path: Path) -> None:
    with pytest.raises(TypeError, match=r"^t holds timedelta64\[M\], which has no fixed length in seconds$"):
        gyrocore.process(np.arange(3).astype("timedelta64[M]"), RATE[:3], "raw")
    record = np.zeros(3, dtype=[("t", "timedelta64[Y]"), ("gyro_z", "f8")])
    np.save(tmp_path / "y.npy", record)
    with pytest.raises(ValueError, match=r"y\.npy: t holds timedelta64\[Y\], which has no fixed length in seconds$"):
        gyrocore.read_log(tmp_path / "y.npy")


@pytest.mark.parametrize("interval", [1e-301, 1e-310, 1e-13])
def test_timestamps_closer_than_a_picosecond_are_refused(interval: float) -> None:
    """Intervals near 1e-310 s gave a NaN heading with the HDR presets. The core refuses an
    interval below 1e-12 s (gyrocore::MIN_INTERVAL), naming the sample, also one among normal ones."""
    t = np.arange(100) * interval
    with pytest.raises(gyrocore.SampleError, match=r"^t\[1\] = .* under the shortest interval of 1e-12 s") as e:
        gyrocore.process(t, np.full(100, 0.1), "hdr", bias=0.0)
    assert (e.value.index, e.value.what) == (1, "t")
    normal = np.arange(100) * 0.01
    normal[50] = normal[49] + interval
    with pytest.raises(gyrocore.SampleError, match=r"t\[50\] = "):  # below float spacing: a duplicate
        gyrocore.process(normal, np.full(100, 0.1), "hdr", bias=0.0)
    # just above the limit (exactly 1e-12 apart, float rounding puts some intervals below it)
    at_limit = np.arange(100) * 1.01e-12
    assert np.isfinite(gyrocore.process(at_limit, np.full(100, 0.1), "hdr", bias=0.0).heading).all()


def test_float32_epoch_times_say_why_they_do_not_increase(tmp_path: Path) -> None:
    # Near 1.7e9 s, float32 steps by 128 s: 100 Hz samples read as equal, and the error alone
    # ("t[1] = 1700000000 follows 1700000000") did not say why.
    t = (1.7e9 + np.arange(200) * 0.01).astype(np.float32)
    with pytest.warns(gyrocore.InputWarning, match=r"the times are float32, which at their size resolve only 128 s"):
        with pytest.raises(gyrocore.SampleError, match="must strictly increase"):
            gyrocore.process(t, np.zeros(len(t)), "raw", mode="causal")
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    from .conftest import gyrocore_cli

    path = tmp_path / "f32.parquet"
    pq.write_table(pa.table({"t": pa.array(t, pa.float32()), "gyro_z": np.zeros(len(t))}), path)
    # in a batch, the failed file's report keeps what came before its error, the files on
    # parallel threads each their own (the warnings module's hooks are global)
    good = tmp_path / "good.csv"
    good.write_text("t,gyro_z\n" + "".join(f"{k * 0.01},0.001\n" for k in range(300)))
    batch = gyrocore_cli("process", path, good, "--out", tmp_path / "outs", "--jobs", "2", code=1)
    assert f"gyrocore: warning: {path}: the times are float32" in batch.stderr
    assert f"{good}: the times are float32" not in batch.stderr
    # seconds from the first sample fit float32 well enough: no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", gyrocore.InputWarning)
        gyrocore.process((np.arange(200) * 0.01).astype(np.float32), np.zeros(200), "raw", mode="causal")


def test_float32_times_in_a_rest_window_read_alone_say_why() -> None:
    """A tuning case in causal mode measures its log's rest window by itself, a pass that reads
    that window alone: its error about the window's times said "sort the log" where the whole
    log's said they were rounded to float32."""
    t_ref = 1.7e9 + np.arange(0.0, 600.0, 0.1)
    log = gyrocore.io.Log("f32", t_ref.astype(np.float32), np.zeros(len(t_ref)), t_ref=t_ref,
                          heading_ref=np.zeros(len(t_ref)), stationary=(1.7e9, 1.7e9 + 200.0))
    with pytest.raises(gyrocore.SampleError, match=r"must strictly increase: .*\(the times repeat: .* every time is a "
                                                   r"float32 value, .*: they were rounded to float32 before"):
        gyrocore.tune.Case.from_log(log, mode="causal")


def test_a_rest_window_read_alone_names_the_logs_sample() -> None:
    """The pass that measures a rest window alone reads only the window's samples, from chunks of a
    stream: its error about a time stepping back named the sample by its place in the window
    (t[1006] for the log's t[5005])."""
    t = np.arange(0.0, 100.0, 0.01)
    t[5005] = t[5003]
    rate = np.zeros(len(t))
    rate[4500] = np.nan  # a reading the window leaves out moves no later index
    for size in (len(t), 777):
        chunks = [(t[i:i + size], rate[i:i + size]) for i in range(0, len(t), size)]
        with pytest.raises(gyrocore.SampleError, match=r"t\[5005\] = 50\.03 follows 50\.04") as caught:
            _rests.measure_rest(chunks, (40.0, 60.0), "given: bias_window")
        assert caught.value.index == 5005

"""Inputs in other units and encodings whose errors gave the wrong advice: times from a counter
that wrapped round, or rounded to float32 before they were written, were told to be sorted (which
would put the samples after the wrap first, or keep one sample in 128 s), a CSV line of spaces was
called a line cut off mid-write, and compressed logs in a folder were passed over."""

from __future__ import annotations

import gzip
import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan, batch, calibration

from .conftest import gyrocore_cli

# times that wrap or repeat are warned about as another unit or coarse: beside the point here
pytestmark = pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")

N = 6000  # 60 s at 100 Hz
RATE = 0.2 * np.sin(np.arange(N) / 300.0)
US = np.arange(N, dtype=np.int64) * 10_000 + 2**32 - 30_000_000  # a micros() counter 30 s before its wrap
WRAPPED = (US % 2**32) / 1e6  # seconds, as read from the counter


def test_a_32_bit_microsecond_counter_that_wraps_is_named_not_sorted() -> None:
    with pytest.raises(gyrocore.SampleError) as info:
        gyrocore.process(WRAPPED, RATE, "raw")
    message = str(info.value)
    assert message.startswith("timestamps must strictly increase: t[3000] = 0 follows 4294.957296 (a 32-bit counter of "
                              "us that wrapped round: 4294.957296 is just short of 2^32 us = 4294.967296 s, where it "
                              "starts again at 0; unwrap the times first: add 4294.967296 to each time from here on, "
                              "e.g. t = numpy.unwrap(t, period=4294.967296))")
    assert "sort" not in message
    # the advice given mends the log: the heading of the times unwrapped, as of the counter's own
    unwrapped = gyrocore.process(np.unwrap(WRAPPED, period=4294.967296), RATE, "raw")
    assert np.allclose(unwrapped.heading, gyrocore.process(US / 1e6, RATE, "raw").heading, rtol=0, atol=1e-9)


def test_a_counter_of_ms_given_as_counts_and_a_16_bit_one_are_named() -> None:
    counts = (np.arange(N, dtype=np.int64) * 10 + 2**32 - 30_000) % 2**32
    with pytest.raises(gyrocore.SampleError, match=r"\(a 32-bit counter that wrapped round: 4294967286 is just short "
                                                   r"of 2\^32 = 4294967296, where it starts again at 0; "):
        gyrocore.process(counts.astype(np.uint32), RATE, "raw")
    ms16 = (np.arange(N, dtype=np.int64) * 20) % 2**16 / 1e3  # 120 s of a 16-bit ms counter: wraps at 65.536 s
    with pytest.raises(gyrocore.SampleError, match=r"\(a 16-bit counter of ms that wrapped round: 65.52 is just short "
                                                   r"of 2\^16 ms = 65.536 s, "):
        gyrocore.process(ms16, RATE, "raw")
    signed = (np.arange(N, dtype=np.int64) * 10 + 2**31 - 30_000 + 2**31) % 2**32 - 2**31  # an int32 counter
    with pytest.raises(gyrocore.SampleError, match=r"\(a signed 32-bit counter that wrapped round: 2147483638 is just "
                                                   r"short of 2\^31 = 2147483648, where it goes on at -2\^31; unwrap "
                                                   r"the times first: add 4294967296 "):
        gyrocore.process(signed.astype(np.int32), RATE, "raw")


def fused(t: np.ndarray, rate: np.ndarray) -> object:
    return gyrocore.fuse(t, rate, gyrocore.fixes.Fixes.empty())


@pytest.mark.parametrize("call", [gyrocore.integrate, gyrocore.downsample, allan.deviation_from_timestamps, fused])
def test_a_wrap_is_named_by_every_function_that_takes_times(call: Callable[..., object]) -> None:
    with pytest.raises(gyrocore.SampleError, match=r"t\[3000\] = 0 follows 4294.957296 \(a 32-bit counter of us "):
        call(WRAPPED, RATE)


def test_a_wrap_between_two_chunks_of_a_stream_is_named() -> None:
    pipeline = gyrocore.Pipeline("raw")
    pipeline.process(WRAPPED[:3000], RATE[:3000])
    with pytest.raises(gyrocore.SampleError, match=r"t\[0\] = 0 follows 4294.957296 \(a 32-bit counter of us "):
        pipeline.process(WRAPPED[3000:], RATE[3000:])


def test_a_time_going_back_that_is_no_wrap_keeps_the_advice_to_sort() -> None:
    back = WRAPPED.copy()
    back[3000] = 100.0  # 4194.96 s back, not the 4294.96 s of a wrap
    with pytest.raises(gyrocore.SampleError, match=r"follows 4294.957296 \(sort the log and drop duplicate"):
        gyrocore.process(back, RATE, "raw")
    with pytest.raises(ValueError, match=r"t must strictly increase: t\[3000\] = 0.0 follows 4294.957296 \(a 32-bit "):
        calibration.static_bias(WRAPPED, RATE)


def test_a_wrapped_counter_in_a_file_is_named_with_its_line(tmp_path: Path) -> None:
    path = tmp_path / "wrap.csv"
    path.write_text("t [us],gyro_z\n" + "".join(f"{t},{r!r}\n" for t, r in zip((US % 2**32).tolist(), RATE.tolist())))
    with pytest.raises(gyrocore.SampleError) as info:
        gyrocore.read_log(path).process("raw")
    assert "(a 32-bit counter of us that wrapped round: 4294.957296 is just short of 2^32 us = 4294.967296 s" in str(
        info.value)
    assert str(info.value).endswith(f"numpy.unwrap(t, period=4294.967296)) ({path}, line 3002)")
    for command in (("process", path, "--out", tmp_path / "h.csv"), ("calibrate", path), ("allan", path)):
        proc = gyrocore_cli(*command, code=2)
        assert "32-bit counter of us that wrapped round" in proc.stderr and "line 3002" in proc.stderr
        assert "sort" not in proc.stderr


def test_epoch_seconds_rounded_to_float32_in_a_file_are_named(tmp_path: Path) -> None:
    # a float32 column written out: the file holds float64 numbers, each a multiple of 128 s
    times = (1.7e9 + np.arange(N) * 0.05).astype(np.float32).astype(np.float64)
    path = tmp_path / "epoch.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{t!r},{r!r}\n" for t, r in zip(times.tolist(), RATE.tolist())))
    with pytest.raises(gyrocore.SampleError) as info:
        gyrocore.read_log(path).process("raw")
    assert str(info.value).startswith(
        "timestamps must strictly increase: t[1] = 1700000000 follows 1700000000 (the times repeat: 5997 of these 5999 "
        "intervals are 0, and every time is a float32 value, which near 1.7e+09 resolves only 128 s: they were rounded "
        "to float32 before they were written or given; keep them as float64 from their source, or as seconds from the "
        f"first sample) ({path}, line 3)")


def test_a_genuine_duplicate_of_whole_epoch_seconds_keeps_the_advice_to_sort() -> None:
    times = 1_700_000_000.0 + np.arange(100.0)  # 1 Hz, float64: only every 128th a float32 value
    times[50] = times[49]
    with pytest.raises(gyrocore.SampleError, match=r"\(sort the log and drop duplicate timestamps\)$"):
        gyrocore.process(times, np.zeros(100), "raw")
    ms = np.arange(0.0, 60_000.0, 10.0)  # ms read as s, all float32 values: one duplicate is no rounding
    ms[7] = ms[6]
    with pytest.raises(gyrocore.SampleError, match=r"\(sort the log and drop duplicate timestamps\)$"):
        gyrocore.process(ms, np.zeros(len(ms)), "raw")


@pytest.mark.parametrize("tail", ["   \n", "\t\n\n", " \n0.05,0.1\n"])
def test_a_csv_line_of_spaces_is_named_as_such_not_as_cut_off(tmp_path: Path, tail: str) -> None:
    path = tmp_path / "ws.csv"
    path.write_text("t,gyro_z\n0.0,0.1\n0.01,0.1\n0.02,0.1\n" + tail)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError) as info:
            gyrocore.read_log(path)
    assert str(info.value) == f"{path}: line 5: spaces or tabs alone, no values (delete the line, or leave it empty)"


def test_compressed_logs_in_a_folder_are_named_not_passed_over(tmp_path: Path) -> None:
    text = "t,gyro_z\n" + "".join(f"{i / 100!r},0.1\n" for i in range(300))
    logs = tmp_path / "logs"
    logs.mkdir()
    for name in ("a.csv.gz", "b.csv.gz"):
        (logs / name).write_bytes(gzip.compress(text.encode()))
    named = "2 compressed log(s) that are not read (a.csv.gz, b.csv.gz): decompress them first"
    proc = gyrocore_cli("process", logs, "--out", tmp_path / "out", code=2)
    assert proc.stderr.strip().endswith(f"no logs in this folder (.csv, .tsv, .parquet, .pq, .npy, .npz, .bag, log "
                                        f"or bag folders); it holds {named}")
    (logs / "c.csv").write_text(text)  # beside a log read, they were left out of the batch without a word
    with pytest.warns(gyrocore.InputWarning, match=f"^{logs}: {re.escape(named)}$"):
        assert batch.expand_inputs([logs]) == [logs / "c.csv"]
    folder = tmp_path / "drive"  # a log folder whose gyro.csv is compressed
    folder.mkdir()
    (folder / "gyro.csv.gz").write_bytes(gzip.compress(text.encode()))
    with pytest.raises(ValueError, match=r"not a log folder \(no gyro.csv\) nor a ROS 2 bag \(no metadata.yaml\); it "
                                         r"holds 1 compressed log\(s\) that are not read \(gyro.csv.gz\): decompress"):
        gyrocore.read_log(folder)


def test_a_one_axis_gyro_column_named_rate_with_its_unit_is_offered(tmp_path: Path) -> None:
    path = tmp_path / "phone.csv"
    path.write_text("t(s),rate(deg/s)\n" + "".join(f"{i / 100!r},{5.0 + i % 3}\n" for i in range(300)))
    with pytest.raises(ValueError, match=r"it has t\(s\), rate\(deg/s\) \(.*; rate_col='rate' \(--rate-col rate\) "
                                         r"looks like it\)$"):
        gyrocore.read_log(path)
    log = gyrocore.read_log(path, rate_col="rate")  # as offered: its unit from the header
    assert np.allclose(log.rate, np.radians(5.0 + np.arange(300) % 3))


@pytest.mark.parametrize("kind", ["datetime64[ns]", "timedelta64[ms]"])
def test_numpy_times_with_their_own_unit_read_without_a_time_unit_say_nothing_of_one(tmp_path: Path,
                                                                                    kind: str) -> None:
    # the reader assumes s for a field that states no unit: it warned that time_unit 's' was not used
    times = (np.arange(300) * 10).astype("timedelta64[ms]") + (np.datetime64("2024-01-01", "ms") if kind[1] == "a"
                                                               else np.timedelta64(0, "ms"))
    record = np.zeros(300, dtype=[("t", kind), ("gyro_z", "f8")])
    record["t"] = times
    np.save(tmp_path / "d.npy", record)
    np.savez(tmp_path / "d.npz", t=record["t"], gyro_z=record["gyro_z"])
    for name in ("d.npy", "d.npz"):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            log = gyrocore.read_log(tmp_path / name)
        assert np.allclose(np.diff(log.t), 0.01, rtol=0, atol=5e-7)  # float64 resolves 2.4e-7 s near 1.7e9 s
        with pytest.warns(gyrocore.InputWarning, match=r"with its own unit \((ns|ms)\): time_unit 'us' \(--time-unit\) "
                                                       r"is not used"):
            gyrocore.read_log(tmp_path / name, time_unit="us")  # one given is still said to be unused
        proc = gyrocore_cli("process", tmp_path / name, "--preset", "raw", "--out", tmp_path / f"{name}.csv",
                            "--overwrite", code=0)
        assert "time_unit" not in proc.stderr


@pytest.mark.parametrize(("stray", "said"), [
    ("# logger restarted\n", "1 field, but the header has 2 (a line of text among the samples, a logger's note: "
                             "delete the line)"),
    ("t,gyro_z\n", "the header line again (logs joined one after another?): delete the line, or read each log alone"),
])
def test_a_stray_text_row_among_the_samples_says_what_it_is(tmp_path: Path, stray: str, said: str) -> None:
    # it said only "1 field, but the header has 2", or "'t' is not a number"
    rows = [f"{i / 100!r},0.1\n" for i in range(200)]
    path = tmp_path / "x.csv"
    path.write_text("t,gyro_z\n" + "".join(rows[:100]) + stray + "".join(rows[100:]))
    with pytest.raises(ValueError) as info:
        gyrocore.read_log(path)
    assert str(info.value) == f"{path}: line 102: {said}"
    path.write_text("t,gyro_z\n" + "".join(rows) + "0.0")  # a last line cut off mid-write is still said so
    with pytest.raises(ValueError, match=r"line 202: 1 field, but the header has 2 \(the file's last line, cut off"):
        gyrocore.read_log(path)


DEG_BIAS = 1.416  # a bias in deg/s, given as rad/s (the heading turned 57 times too far each second)
IMPLAUSIBLE = re.compile(r"bias = 1\.416 rad/s \(81\.13 deg/s\) is beyond any gyro's at rest \(more than 0\.5 rad/s\): a "
                         r"bias in deg/s given as rad/s\? Give it in deg/s as bias_dps=1\.416")


@pytest.mark.filterwarnings("default::gyrocore.InputWarning")
@pytest.mark.parametrize("call", [
    lambda t, r: gyrocore.process(t, r, "recommended", bias=DEG_BIAS),
    lambda t, r: gyrocore.process(t, r, "recommended", mode="causal", bias=DEG_BIAS),
    lambda t, r: gyrocore.Pipeline("hdr", bias=DEG_BIAS).process(t, r),
], ids=["whole", "causal", "stream"])
def test_a_bias_in_deg_per_s_given_as_rad_per_s_is_warned(call: Callable[[np.ndarray, np.ndarray], object]) -> None:
    t = np.arange(N) / 100.0
    with pytest.warns(gyrocore.InputWarning, match=IMPLAUSIBLE):
        call(t, np.radians(np.full(N, DEG_BIAS)))
    with warnings.catch_warnings():  # the same bias in deg/s, or a plausible one in rad/s: nothing to say
        warnings.simplefilter("error", gyrocore.InputWarning)
        gyrocore.process(t, np.radians(np.full(N, DEG_BIAS)), "recommended", bias_dps=DEG_BIAS)
        gyrocore.Pipeline("hdr", bias=-0.5).process(t, np.full(N, -0.5))


def test_a_bias_in_deg_per_s_given_as_rad_per_s_is_warned_of_the_file(tmp_path: Path) -> None:
    drive = tmp_path / "drive.csv"
    drive.write_text("t,gyro_z,heading_true\n" + "".join(f"{i / 100},{np.radians(DEG_BIAS)},0\n" for i in range(N)))
    for command in (("process", drive, "--out", tmp_path / "h.csv"), ("evaluate", drive)):
        proc = gyrocore_cli(*command, "--param", f"bias={DEG_BIAS}", code=0)
        assert re.search(r"gyrocore: warning: \S*drive\.csv: " + IMPLAUSIBLE.pattern, proc.stderr), proc.stderr


def test_static_bias_of_times_in_ms_warns_of_them_once() -> None:
    t = np.arange(0.0, 60_000.0, 10.0)  # 60 s in ms
    rate = np.random.default_rng(0).normal(0.01, 0.001, t.size)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        calibration.static_bias(t, rate)  # the rest searched for: detect_rest checked the series again
    said = [str(w.message) for w in caught if issubclass(w.category, gyrocore.InputWarning)]
    assert len(said) == 1 and said[0].startswith("timestamps look like ms, us or ns, not seconds"), said


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_rest_window_that_reads_a_bias_no_gyro_has_is_said_once_of_the_window(mode: str) -> None:
    t = np.arange(N) / 100.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gyrocore.process(t, np.radians(np.full(N, DEG_BIAS)) * 57.3, "recommended", mode=mode, bias_window=(0, 10))
    said = [str(w.message) for w in caught if issubclass(w.category, gyrocore.InputWarning)]
    assert [s for s in said if "beyond any gyro's at rest" in s] == [next(s for s in said if "rest window" in s)], said

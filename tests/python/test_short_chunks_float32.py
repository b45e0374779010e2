"""A stream fed chunks of one or two samples: its error about float32 times named their rounding,
as a longer chunk's does, where it said "sort the log" (the hint judged the chunk alone)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import gyrocore_cli

SORT = r"\(sort the log and drop duplicate timestamps\)"


def _stream(t: np.ndarray, size: int) -> None:
    p = gyrocore.Pipeline("raw", bias=0.0)
    for k in range(0, len(t), size):
        p.process(t[k:k + size], np.zeros(len(t[k:k + size])))


@pytest.mark.parametrize("size", [1, 2])
def test_float32_epoch_times_in_short_chunks_are_named(size: int) -> None:
    t = (1.7e9 + np.arange(200) * 0.01).astype(np.float32).astype(np.float64)
    with pytest.raises(gyrocore.SampleError, match=r"every time is a float32 value, which near 1\.7e\+09 resolves "
                                                   r"only 128 s: they were rounded to float32") as info:
        _stream(t, size)
    assert info.value.what == "t"


@pytest.mark.parametrize("size", [1, 2])
def test_float32_times_since_boot_in_short_chunks_are_named(size: int) -> None:
    # 1 kHz at 1e5 s since boot: float32 resolves 1/128 s there, so the times repeat further on
    t = (1e5 + np.arange(100) * 1e-3).astype(np.float32).astype(np.float64)
    with pytest.raises(gyrocore.SampleError, match=r"resolves only 0\.0078125 s: they were rounded to float32"):
        _stream(t, size)


@pytest.mark.parametrize("size", [1, 2])
def test_a_float64_duplicate_in_short_chunks_keeps_the_advice_to_sort(size: int) -> None:
    t = 1.7e9 + np.arange(200) * 0.01  # float64 times, not float32 values
    t[51] = t[50]
    with pytest.raises(gyrocore.SampleError, match=SORT):
        _stream(t, size)
    ms = np.arange(0.0, 2000.0, 10.0)  # ms read as s, all float32 values, where float32 resolves far below 1 ms
    ms[51] = ms[50]
    with pytest.raises(gyrocore.SampleError, match=SORT):
        _stream(ms, size)


def test_float32_times_read_two_rows_at_a_time_are_named(tmp_path: Path) -> None:
    t = (1.7e9 + np.arange(200) * 0.01).astype(np.float32).astype(np.float64)
    path = tmp_path / "f32.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{x!r},0.0\n" for x in t.tolist()))
    ran = gyrocore_cli("process", path, "-o", tmp_path / "out.csv", "--causal", "--chunk-rows", "2", code=2)
    assert "they were rounded to float32 before they were written or given" in ran.stderr, ran.stderr

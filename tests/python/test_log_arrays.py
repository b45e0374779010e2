"""A ``Log`` holds series of its own, read-only: the caller's arrays were kept as they were, so that a
change of one after the log was made, or a write through ``log.rate``, changed the heading the log
gave without a word (two calls of ``Log.process`` gave two answers)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import datasets


def _drive() -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(3000) * 0.01
    return t, 0.002 + np.where(t < 5.0, 0.0, 0.1 * np.sin(t / 3.0))


def test_a_change_of_the_caller_s_arrays_after_the_log_is_made_does_not_reach_it() -> None:
    t, rate = _drive()
    log = gyrocore.Log("x", t, rate, stationary=(0.0, 5.0))
    first = log.process("static_bias").heading
    rate += 0.5  # the caller's own array, reused for something else
    t *= 2.0
    again = log.process("static_bias").heading
    assert np.array_equal(first, again)
    assert np.array_equal(log.t, _drive()[0]) and not np.shares_memory(log.rate, rate)


@pytest.mark.parametrize("name", ["t", "rate", "t_ref", "heading_ref", "speed"])
def test_a_write_through_the_log_s_series_fails_loudly(name: str) -> None:
    t, rate = _drive()
    log = gyrocore.Log("x", t, rate, t_ref=t, heading_ref=np.cumsum(rate) * 0.01, speed=np.full_like(t, 2.0))
    series = getattr(log, name)
    with pytest.raises(ValueError, match="read-only"):
        series[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        series += 1.0
    assert series[0] != 1.0


def test_a_read_only_array_is_taken_as_it_is_and_a_converted_one_is_the_log_s_own() -> None:
    t, rate = _drive()
    t.flags.writeable = False
    log = gyrocore.Log("x", t, rate.astype(np.float32))
    assert log.t is t  # a memory map opened read-only, a frozen column: no copy of millions of samples
    assert log.rate.dtype == np.float64 and not log.rate.flags.writeable
    again = gyrocore.Log("y", log.t, log.rate)  # another log's series: shared, nothing copied
    assert again.t is log.t and again.rate is log.rate
    lists = gyrocore.Log("z", t.tolist(), rate.tolist())
    assert not lists.rate.flags.writeable and np.array_equal(lists.rate, rate)


def test_a_pandas_column_is_copied_even_where_pandas_hands_over_a_read_only_view() -> None:
    # docs/python.md said a column under pandas' copy-on-write is taken as it is; but the read-only
    # view pandas hands numpy still changes with a write through its DataFrame
    pd = pytest.importorskip("pandas")
    t, rate = _drive()
    df = pd.DataFrame({"t": t, "rate": rate})
    log = gyrocore.Log("x", df["t"], df["rate"], stationary=(0.0, 5.0))
    first = log.process("static_bias").heading
    df.loc[0, "rate"] = 1.0  # into the buffer a read-only numpy view of df["rate"] shares
    df["t"] *= 2.0
    assert np.array_equal(log.process("static_bias").heading, first)
    assert log.rate[0] == rate[0] and np.array_equal(log.t, t)


def test_a_log_read_from_a_file_holds_read_only_series(tmp_path: Path) -> None:
    t, rate = _drive()
    path = tmp_path / "drive.csv"
    np.savetxt(path, np.column_stack([t, rate, np.cumsum(rate) * 0.01, np.ones_like(t)]), delimiter=",",
               header="t,gyro_z,heading_true,speed", comments="", fmt="%.17g")
    log = gyrocore.read_log(path)
    for name in ("t", "rate", "t_ref", "heading_ref", "t_odometry", "speed"):
        assert not getattr(log, name).flags.writeable, name
    assert np.array_equal(log.rate, rate)
    with pytest.raises(ValueError, match="read-only"):
        datasets.sample_drive().rate[0] = 0.0

"""pandas columns and tables given to gyrocore as a user holds them: each gives the heading of the
same data as plain float64 arrays, or an error that says what and where."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import gyrocore

pd = pytest.importorskip("pandas")


def _table(n: int = 3000) -> pd.DataFrame:
    t = 10.0 + np.arange(n) * 0.01
    return pd.DataFrame({"t": t, "gyro_z": 0.002 + (t > 20.0) * 0.2 * np.sin(t / 3.0)})


@pytest.mark.parametrize("dtype", ["Float64", "Int64", "object"])
def test_a_gap_in_a_nullable_column_is_a_missing_reading_as_nan_is(dtype: str) -> None:
    df = _table()
    rate = (df.gyro_z * 10).round() if dtype == "Int64" else df.gyro_z  # Int64: whole counts of 0.1 rad/s
    gappy = rate.astype("Float64" if dtype == "object" else dtype)
    gappy.iloc[500] = pd.NA
    # pandas before 2.2 hands numpy such a column as objects with pandas.NA in the gap (later
    # releases give NaN): that was "rate must hold real numbers, got dtype object: rate[500] is <NA>",
    # and nonfinite= could not hold or skip it
    given = gappy.to_numpy(dtype=object) if dtype == "object" else gappy
    plain = rate.to_numpy(dtype=np.float64).copy()
    plain[500] = np.nan
    with pytest.raises(gyrocore.SampleError, match=r"^rate\[500\] is NaN: samples must be finite"):
        gyrocore.process(df.t, given, "hdr", bias=0.002)
    for policy in ("hold", "skip"):
        with pytest.warns(gyrocore.InputWarning):
            got = gyrocore.process(df.t, given, "hdr", bias=0.002, nonfinite=policy)
        with pytest.warns(gyrocore.InputWarning):
            expected = gyrocore.process(df.t.to_numpy(), plain, "hdr", bias=0.002, nonfinite=policy)
        assert np.array_equal(got.heading, expected.heading) and np.array_equal(got.t, expected.t)
    assert gappy.iloc[500] is pd.NA  # the caller's column is left as it was


def test_a_logs_rest_window_given_as_a_pandas_series_is_read_by_position_and_kept_as_numbers() -> None:
    df = _table()
    window = df.t.iloc[[0, 900]]  # labels 0 and 900: its [1] is a look-up by label
    log = gyrocore.Log("mine", df.t, df.gyro_z, stationary=window)
    # the Series was kept as given: repr(log) raised a bare KeyError (its [1] a label), and
    # log.stationary[1] did so for the caller too
    assert log.stationary == (10.0, 19.0) and all(type(v) is float for v in log.stationary)
    assert repr(log).endswith("rest +0 .. +9 s)")
    expected = gyrocore.Log("mine", df.t.to_numpy(), df.gyro_z.to_numpy(), stationary=(10.0, 19.0))
    assert np.array_equal(log.process("hdr").heading, expected.process("hdr").heading)


def test_a_rest_window_of_durations_is_refused_not_read_as_seconds() -> None:
    df = _table()
    durations = pd.to_timedelta(df.t.iloc[[0, 900]], unit="s")  # counts in ns or us: read as seconds, a window 1e6 or more off
    with pytest.raises(ValueError, match=r"^log mine: stationary = array\(\[10000.*\): give the rest window as \(start, end\) \[s\]"):
        gyrocore.Log("mine", df.t, df.gyro_z, stationary=durations)
    with pytest.raises(ValueError, match=r"^the rest window must be \(start, end\) in seconds, got array\(.*\): give seconds \(a numpy duration"):
        gyrocore.calibration.static_bias(df.t, df.gyro_z, window=durations)


def test_a_csv_file_of_pandas_durations_or_with_its_unnamed_index_says_what_to_write(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    df = _table()
    durations = tmp_path / "durations.csv"
    df.assign(t=pd.to_timedelta(df.t, unit="s")).to_csv(durations, index=False)  # 0 days 00:00:10 ...
    # "line 2, column 1 (t): '0 days 00:00:10' is not a number", with nothing to do about it
    with pytest.raises(ValueError, match=r"line 2, column 1 \(t\): '0 days 00:00:10(\.0+)?' is not a number \(a duration as "
                                         r"pandas writes one: write seconds, the column's \.dt\.total_seconds\(\), or "
                                         r"write the table to Parquet"):
        gyrocore.read_log(durations)
    parquet = tmp_path / "durations.parquet"
    df.assign(t=pd.to_timedelta(df.t, unit="s")).to_parquet(parquet)  # as the error advises
    np.testing.assert_allclose(gyrocore.read_log(parquet).t, df.t, rtol=0, atol=1e-9)
    unnamed = tmp_path / "unnamed.csv"
    df.set_index("t").rename_axis(None).to_csv(unnamed)  # header ",gyro_z": the times' column has no name
    # "missing column(s) t; it has , gyro_z", and time_col='' is no name: no way to read it was said
    with pytest.raises(ValueError, match=r"missing column\(s\) t; it has '', gyro_z \(.*; a column without a name \(as "
                                         r"pandas' df\.to_csv\(\) writes an unnamed index\) cannot be chosen: name it, "
                                         r"e\.g\. df\.to_csv\(path, index_label='t'\)\)$"):
        gyrocore.read_log(unnamed)
    named = tmp_path / "named.csv"
    df.set_index("t").rename_axis(None).to_csv(named, index_label="t")  # as the error advises
    assert np.array_equal(gyrocore.read_log(named).t, df.t.to_numpy())


def _as_held(df: pd.DataFrame, how: str) -> tuple[object, object]:
    """``(t, rate)`` of ``df`` as a user may hold them in pandas."""
    if how == "cut by label, labels shuffled":
        cut = df.iloc[100:]
        return cut.set_axis(np.random.default_rng(0).permutation(len(cut))).pipe(lambda d: (d.t, d.gyro_z))
    if how == "duplicated labels":
        return df.set_axis(np.arange(len(df)) // 2).pipe(lambda d: (d.t, d.gyro_z))
    if how == "index of times":
        s = df.set_index("t").gyro_z
        return s.index, s
    if how == "seconds from a DatetimeIndex with a zone":
        times = pd.DatetimeIndex(pd.to_datetime(np.round(df.t * 1e9).astype(np.int64), unit="ns", utc=True))
        times = times.tz_convert("Europe/Berlin")
        return (times - times.min()) / np.timedelta64(1, "s") + df.t.iloc[0], df.gyro_z
    if how == "TimedeltaIndex":
        return pd.to_timedelta(np.round(df.t * 1e9).astype(np.int64), unit="ns"), df.gyro_z
    if how == "read-only arrays":
        t, rate = df.t.to_numpy().copy(), df.gyro_z.to_numpy().copy()
        t.flags.writeable = rate.flags.writeable = False
        return t, rate
    return df.t.astype(how), df.gyro_z.astype(how)  # a dtype


@pytest.mark.parametrize("how", ["cut by label, labels shuffled", "duplicated labels", "index of times",
                                 "seconds from a DatetimeIndex with a zone", "TimedeltaIndex", "read-only arrays",
                                 "Float64", "double[pyarrow]", "category", "object"])
def test_pandas_columns_give_the_heading_of_the_same_data_as_float64_arrays(how: str) -> None:
    if how == "double[pyarrow]":
        pytest.importorskip("pyarrow")
    df = _table()
    t, rate = _as_held(df, how)
    before = df.copy(deep=True)
    first = 100 if how.startswith("cut") else 0
    expected = gyrocore.process(df.t.to_numpy()[first:], df.gyro_z.to_numpy()[first:], "hdr", bias=0.002)
    got = gyrocore.process(t, rate, "hdr", bias=0.002)
    # times through nanoseconds are equal to float64 rounding of the times, not bit for bit
    exact = how not in ("seconds from a DatetimeIndex with a zone", "TimedeltaIndex")
    np.testing.assert_allclose(got.t, expected.t, rtol=0, atol=0 if exact else 1e-9)
    np.testing.assert_allclose(got.heading, expected.heading, rtol=0, atol=0 if exact else 1e-9)
    pd.testing.assert_frame_equal(df, before)  # nothing the caller gave was changed


@pytest.mark.parametrize("write", ["to_json", "to_feather"])
def test_a_table_pandas_wrote_in_a_format_not_read_says_what_to_write(tmp_path: Path, write: str) -> None:
    pytest.importorskip("pyarrow")
    path = tmp_path / "drive.dat"
    getattr(_table(), write)(path)
    # JSON was "its content is text (a CSV file?): name it drive.csv", which then failed as CSV
    what = "JSON" if write == "to_json" else r"an Arrow IPC \(Feather\) file"
    with pytest.raises(ValueError, match=rf"drive\.dat: unknown kind of file \(.*\); (its content is|it is) {what}, "
                                         r"which is not read: write the samples as Parquet or CSV \(pandas: "
                                         r"df\.to_parquet\(path\), df\.to_csv\(path, index=False\)\)$"):
        gyrocore.read_log(path)

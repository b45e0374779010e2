"""The first samples: no finite rate in the first chunk is named, not a crash; the unit check sees
the same first samples whatever the chunk size."""

from __future__ import annotations

from functools import partial
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import SampleError

from .conftest import gyrocore_cli


def test_no_finite_rate_is_a_sample_error_at_index_0() -> None:
    for rates in ([np.nan], [np.inf, np.nan, -np.inf]):
        t = np.arange(len(rates), dtype=float)
        with pytest.raises(SampleError) as e:
            gyrocore.process(t, rates, "raw")
        assert e.value.index == 0 and str(e.value).startswith("rate[0] is ")


@pytest.mark.parametrize("nonfinite", ["hold", "skip"])
def test_no_finite_first_reading_is_skipped_under_hold_and_skip(nonfinite: str) -> None:
    t = np.arange(4) * 0.01
    r = np.array([np.nan, np.nan, 0.1, 0.1])
    with pytest.warns(gyrocore.InputWarning, match=r"2 reading\(s\) not finite or beyond \+-1048576 skipped \(first at index 0"):
        result = gyrocore.process(t, r, "raw", nonfinite=nonfinite)
    # nothing to hold yet: both are left out, and the heading starts at the first finite reading
    assert np.array_equal(result.heading, [0.0, 0.0, 0.0, 0.5 * (0.1 + 0.1) * (t[3] - t[2])])
    # a whole log of nothing else has no heading to give (a heading of 0 was made of no data)
    with pytest.raises(ValueError, match=r"^no usable reading: all 2 readings are NaN or beyond"):
        gyrocore.process([0.0, 1.0], [np.nan, np.nan], "raw", nonfinite=nonfinite)


run_cli = partial(gyrocore_cli, timeout=120)


def test_a_csv_whose_first_rates_are_empty(tmp_path: Path) -> None:
    src = tmp_path / "first_empty.csv"
    src.write_text("t,gyro_z\n0,\n0.01,\n0.02,0.1\n0.03,0.1\n")
    out = tmp_path / "h.csv"
    proc = run_cli("process", src, "--out", out, "--preset", "raw")
    assert proc.returncode == 2 and not out.exists()
    assert proc.stderr == (
        f"gyrocore: error: rate[0] is NaN: samples must be finite (drop or fill them first) ({src}, line 2); "
        "or keep the file as it is: nonfinite='hold' (--nonfinite hold) uses the last usable reading there, "
        "'skip' leaves the sample out\n"  # the option, not only an edit of the file
    )
    proc = run_cli("process", src, "--out", out, "--preset", "raw", "--nonfinite", "skip")
    assert proc.returncode == 0
    assert proc.stderr == (
        f"gyrocore: warning: {src}: 2 sample(s) skipped (readings not finite or beyond +-2^20; their rows have a NaN rate)\n"
    )


@pytest.mark.parametrize("chunk_rows", [1, 2, 7, 65536])
def test_unit_warnings_do_not_depend_on_the_chunk_size(tmp_path: Path, chunk_rows: int) -> None:
    """Timestamps in ms and rates in deg/s, read as s and rad/s: both said, with any --chunk-rows."""
    src = tmp_path / "ms_dps.csv"
    # ms, 10 ms apart on average; every other interval (1 ms, read as 1 s) is not a gap, since a
    # log whose every interval is a gap is an error, not a warning
    t = np.cumsum(np.tile([1.0, 19.0], 150))
    src.write_text("t,gyro_z\n" + "".join(f"{a},{30 + 5 * np.sin(a / 300)}\n" for a in t))
    proc = run_cli(
        "process", src, "--out", tmp_path / "h.csv", "--preset", "raw", "--gap-limit", "100",
        "--chunk-rows", str(chunk_rows),
    )
    assert proc.returncode == 0
    warned = proc.stderr.splitlines()
    assert len(warned) == 2
    assert warned[0].startswith(f"gyrocore: warning: {src}: rates look like deg/s, not rad/s")
    assert warned[1].startswith(f"gyrocore: warning: {src}: timestamps look like ms, not s")


def test_a_reading_beyond_the_limit_is_reported_without_a_numpy_warning(tmp_path: Path) -> None:
    src = tmp_path / "big.csv"
    src.write_text("t,gyro_z\n" + "".join(f"{i / 100},{1e300 if i == 7 else 0.01}\n" for i in range(3000)))
    proc = run_cli("process", src, "--out", tmp_path / "h.csv", "--nonfinite", "hold")  # whole mode finds rests
    assert proc.returncode == 0
    assert f"gyrocore: warning: {src}: 1 reading(s) not finite or beyond +-2^20 replaced by the last usable one\n" in proc.stderr
    assert "overflow" not in proc.stderr

"""A whole log of which no reading is usable (every rate NaN, infinite or beyond +-2^20) is refused under
``nonfinite="hold"`` or ``"skip"`` by every entry point that knows where the log ends: it gave a
heading of 0 throughout, "ok", made of no data. A log with some usable readings is still processed."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import batch

from .test_batch import synthetic_csv
from .test_errors_named import run_cli

NONE_USABLE = "no usable reading: all {n} readings are NaN or beyond +-2^20 rad/s"


def with_nan(path: Path, n: int, nan: Callable[[int], bool] = lambda i: True) -> Path:
    """A synthetic log of ``n`` samples whose rate is NaN where ``nan(index)``."""
    lines = synthetic_csv(path, n).read_text().splitlines()
    rows = [f"{line.split(',')[0]},nan" if nan(i) else line for i, line in enumerate(lines[1:])]
    path.write_text("\n".join([lines[0], *rows]) + "\n")
    return path


@pytest.mark.parametrize("nonfinite", ["hold", "skip"])
@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_the_api_refuses_a_log_with_no_usable_reading(tmp_path: Path, nonfinite: str, mode: str) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    rate = np.full_like(t, np.nan)
    rate[3] = np.inf
    with pytest.raises(ValueError, match=r"^" + NONE_USABLE.format(n=1000).replace("+", r"\+").replace("^", r"\^")):
        gyrocore.process(t, rate, nonfinite=nonfinite, mode=mode)
    with pytest.raises(ValueError, match=r"^log x: no usable reading: all 1000 readings"):
        gyrocore.Log(t=t, rate=rate, name="x").process(nonfinite=nonfinite, mode=mode)
    src = with_nan(tmp_path / "nan.csv", 1000)
    with pytest.raises(ValueError, match=rf"^{src}: no usable reading: all 1000 readings"):
        gyrocore.read_log(src).process(nonfinite=nonfinite, mode=mode)
    with pytest.raises(ValueError, match=rf"^{src}: no usable reading: all 1000 readings"):
        batch.process_file(src, tmp_path / "h.csv", nonfinite=nonfinite, mode=mode)
    assert not (tmp_path / "h.csv").exists()
    summary = batch.process_many([src], out_dir=tmp_path / "out", nonfinite=nonfinite, mode=mode)
    assert summary.files[0].error is not None and "no usable reading: all 1000" in summary.files[0].error


def test_the_command_line_refuses_a_file_with_no_usable_reading(tmp_path: Path) -> None:
    src = with_nan(tmp_path / "nan.csv", 3000)
    ref = tmp_path / "ref.csv"  # the file's times: only the rates are wrong
    ref.write_text("t,heading\n" + "".join(f"{line.split(',')[0]},0\n" for line in src.read_text().splitlines()[1:]))
    for nonfinite in ("hold", "skip"):
        for args in (("process", src, "--out", tmp_path / "h.csv", "--nonfinite", nonfinite),
                     ("process", src, "--out", tmp_path / "h.csv", "--nonfinite", nonfinite, "--causal"),
                     ("evaluate", src, "--reference", ref, "--preset", "raw", "--param", f"nonfinite={nonfinite}")):
            proc = run_cli(*args)
            assert proc.returncode == 2, proc.stdout
            assert proc.stderr.splitlines()[-1].startswith(f"gyrocore: error: {src}: {NONE_USABLE.format(n=3000)}")
    assert not (tmp_path / "h.csv").exists()


def test_readings_held_after_some_skipped_before_the_first_usable_one_are_said_so(tmp_path: Path) -> None:
    # NaN first (nothing to hold yet: skipped), then good readings with 2 NaN among them (held)
    src = with_nan(tmp_path / "lead.csv", 3000, lambda i: i < 10 or i in (100, 101))
    proc = run_cli("process", src, "--out", tmp_path / "h.csv", "--nonfinite", "hold")
    assert proc.returncode == 0, proc.stderr
    assert "2 reading(s) not finite or beyond +-2^20 replaced by the last usable one" in proc.stderr
    assert ("10 sample(s) skipped (readings not finite or beyond +-2^20, before the first usable one: none to hold "
            "yet; their rows have a NaN rate)") in proc.stderr

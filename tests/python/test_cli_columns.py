"""``gyrocore process --columns``: only the columns asked for are written, and the core computes
only the outputs they need."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrocore
from gyrocore import Pipeline
from gyrocore.cli import main

from .conftest import real_log_path


def run_process(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gyrocore.cli", "process", *args], capture_output=True, text=True)


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    header = path.read_text().splitlines()[0].split(",")
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


@pytest.mark.parametrize("heading", ["enu", "compass"])
def test_columns_writes_those_columns_in_that_order_with_the_full_tables_values(tmp_path: Path, heading: str) -> None:
    log = str(real_log_path("f110_ds3"))
    full, some = tmp_path / "full.csv", tmp_path / "some.csv"
    assert run_process(log, "--out", str(full), "--preset", "combined", "--heading", heading).returncode == 0
    proc = run_process(
        log, "--out", str(some), "--preset", "combined", "--heading", heading, "--columns", "heading, t,drift"
    )
    assert proc.returncode == 0, proc.stderr
    full_header, full_data = read_csv(full)
    header, data = read_csv(some)
    assert header == ["heading", "t", "drift"]
    expected = full_data[:, [full_header.index(c) for c in header]]
    np.testing.assert_array_equal(data, expected)


def test_columns_reach_the_pipeline_as_the_outputs_it_computes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    asked: list[tuple[str, ...]] = []
    process = Pipeline.process

    def spy(self: Pipeline, *args: Any, **kwargs: Any) -> Any:
        asked.append(kwargs["outputs"])
        return process(self, *args, **kwargs)

    monkeypatch.setattr(Pipeline, "process", spy)
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0.1\n1,0.2\n2,0.1\n")
    for columns, outputs in [
        ("t,heading", ("heading",)),
        ("rate", ("heading", "rate")),
        ("drift,t", ("heading", "drift")),
        (None, ("heading", "rate", "drift")),
    ]:
        out = tmp_path / f"{columns}.csv"
        extra = [] if columns is None else ["--columns", columns]
        assert main(["process", str(src), "--out", str(out), "--preset", "raw", *extra]) == 0
        assert asked[-1] == outputs
        assert out.read_text().splitlines()[0] == (columns or "t,heading,rate,drift")


def test_columns_to_parquet(tmp_path: Path) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0.1\n1,0.2\n2,0.1\n")
    out = tmp_path / "h.parquet"
    proc = run_process(str(src), "--out", str(out), "--preset", "raw", "--columns", "t,heading")
    assert proc.returncode == 0, proc.stderr
    table = pq.read_table(out)
    assert table.column_names == ["t", "heading"]
    expected = gyrocore.process([0.0, 1.0, 2.0], [0.1, 0.2, 0.1], "raw").heading
    np.testing.assert_array_equal(table.column("heading").to_numpy(), expected)


@pytest.mark.parametrize(
    ("columns", "message"),
    [
        ("t,yaw", "--columns t,yaw: unknown column 'yaw'; choose from t, heading, rate, drift, heading_sigma"),
        ("t,,heading", "--columns t,,heading: unknown column ''; choose from t, heading, rate, drift, heading_sigma"),
        ("t,t", "--columns t,t: each column once; choose from t, heading, rate, drift, heading_sigma"),
    ],
)
def test_bad_columns_are_a_one_line_usage_error_before_any_output(tmp_path: Path, columns: str, message: str) -> None:
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0.1\n1,0.2\n")
    for out in (tmp_path / "h.csv", tmp_path / "folder"):
        proc = run_process(str(src), "--out", str(out), "--preset", "raw", "--columns", columns)
        assert proc.returncode == 2
        assert proc.stderr == f"gyrocore: error: {message}\n"
        assert not out.exists()

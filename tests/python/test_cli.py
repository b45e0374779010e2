"""The gyrocore command: demo (the README's main command), process, presets, error exits."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gyrocore.cli import main

from .conftest import real_log_path


def test_demo_prints_every_preset_and_writes_a_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plot = tmp_path / "demo.png"
    assert main(["demo", "--duration", "300", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    for preset in ("raw", "static_bias", "hong_park", "hdr", "combined"):
        assert f"\n{preset} " in out
    assert plot.read_bytes()[:4] == b"\x89PNG"


def test_demo_json_rows_beat_raw(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--duration", "300", "--plot", "", "--json"]) == 0
    rows = {r["preset"]: r for r in json.loads(capsys.readouterr().out)}
    assert rows["static_bias"]["e_psi_deg"] < rows["raw"]["e_psi_deg"]


def test_process_writes_csv_with_one_row_per_sample(tmp_path: Path) -> None:
    log = real_log_path("f110_ds3")
    out = tmp_path / "heading.csv"
    assert main(["process", str(log), "--out", str(out), "--preset", "hdr"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert out.read_text().splitlines()[0] == "t,heading,rate,drift"
    assert data.shape == (2736, 4)
    assert not list(tmp_path.glob(".*tmp")), "no temporary file may be left behind"


def test_process_refuses_to_write_into_the_input(tmp_path: Path) -> None:
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0\n1,0\n")
    before = src.read_bytes()
    assert main(["process", str(src), "--out", str(src)]) == 2
    assert src.read_bytes() == before


def test_user_errors_exit_2_with_one_line_and_no_traceback(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("t,gyro_z\n0,0\n0,1\n")
    proc = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "process", str(bad), "--out", str(tmp_path / "o.csv"), "--preset", "raw"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert proc.stderr.startswith("gyrocore: error: timestamps must strictly increase: t[1]")
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


def test_every_subcommand_help_shows_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    for cmd in ("demo", "process", "presets"):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        assert "example: gyrocore " + cmd in capsys.readouterr().out

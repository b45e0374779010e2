"""Shared fixtures: the real logs in ../shared/data (read in place, never copied), and the
command line run as a user runs it."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import gyrocore

DATA = Path(__file__).resolve().parents[3] / "shared" / "data"
REAL_LOGS = ("f110_ds3", "broad_10", "comma_seg40")


def real_log_path(name: str) -> Path:
    path = DATA / "real" / name
    if not path.is_dir():
        pytest.skip(f"shared data not found at {path}")
    return path


def gyrocore_cli(*args: str | Path, code: int | None = None, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    """Run ``gyrocore ARGS`` in a new process; check that it prints no traceback and, where
    ``code`` is given, that it exits with it."""
    proc = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", *map(str, args)], capture_output=True, text=True, timeout=timeout
    )
    if code is not None:
        assert proc.returncode == code, proc.stderr
    assert "Traceback" not in proc.stderr
    return proc


@pytest.fixture(scope="session", params=REAL_LOGS)
def real_log(request: pytest.FixtureRequest) -> gyrocore.Log:
    return gyrocore.read_log(real_log_path(request.param))

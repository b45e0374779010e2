"""Shared fixtures: the real logs in ../shared/data (read in place, never copied)."""

from __future__ import annotations

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


@pytest.fixture(scope="session", params=REAL_LOGS)
def real_log(request: pytest.FixtureRequest) -> gyrocore.Log:
    return gyrocore.read_log(real_log_path(request.param))

"""One version and one license for the crate and the Python package."""

from __future__ import annotations

import importlib.metadata
from pathlib import Path

import pytest

import gyrocore

ROOT = Path(__file__).resolve().parents[2]


def test_the_version_comes_from_cargo_toml_alone() -> None:
    tomllib = pytest.importorskip("tomllib")
    cargo = tomllib.loads((ROOT / "Cargo.toml").read_text(encoding="utf-8"))
    binding = tomllib.loads((ROOT / "rust" / "python" / "Cargo.toml").read_text(encoding="utf-8"))
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    version = cargo["workspace"]["package"]["version"]
    assert cargo["package"]["version"] == binding["package"]["version"] == {"workspace": True}
    assert "version" not in project and project["dynamic"] == ["version"]
    assert gyrocore.__version__ == importlib.metadata.version("gyrocore") == version


def test_the_license_file_is_the_declared_mit() -> None:
    tomllib = pytest.importorskip("tomllib")
    assert (ROOT / "LICENSE").read_text(encoding="utf-8").startswith("MIT License\n")
    assert tomllib.loads((ROOT / "Cargo.toml").read_text(encoding="utf-8"))["package"]["license"] == "MIT"
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert project["license"] == {"text": "MIT"}

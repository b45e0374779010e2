"""The sdist builds: it holds every file Cargo reads with the manifest (.ci/run builds it too, slowly)."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_the_sdist_holds_every_bench_that_cargo_toml_names() -> None:
    tomllib = pytest.importorskip("tomllib")
    cargo = tomllib.loads((ROOT / "Cargo.toml").read_text(encoding="utf-8"))
    maturin = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["maturin"]
    in_sdist = {item["path"] for item in maturin.get("include", []) if item.get("format") == "sdist"}
    benches = {bench.get("path", f"benches/{bench['name']}.rs") for bench in cargo.get("bench", [])}
    assert benches, "Cargo.toml names no bench: drop the sdist include in pyproject.toml"
    assert benches <= in_sdist, f"the sdist lacks {sorted(benches - in_sdist)}: add them to [tool.maturin] include"
    assert all((ROOT / path).is_file() for path in in_sdist)

"""A fleet's outputs in a messy output folder: no input and no other output is written over."""

from __future__ import annotations

from pathlib import Path

import pytest

from gyrocore.batch import process_many

from .conftest import gyrocore_cli
from .test_batch import synthetic_csv


def _two_logs(tmp_path: Path) -> tuple[Path, Path, Path]:
    """Two logs in a folder of their own, and an output folder beside it."""
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    out.mkdir()
    return synthetic_csv(logs / "a.csv", 300), synthetic_csv(logs / "b.csv", 400, seed=1), out


def test_an_output_name_linked_to_another_input_is_refused_before_any_work(tmp_path: Path) -> None:
    # out/a.csv -> ../logs/b.csv: b.csv, an input, was replaced by a.csv's heading (300 rows of
    # t, heading, rate, drift), and both files were reported ok
    a, b, out = _two_logs(tmp_path)
    (out / "a.csv").symlink_to(Path("..") / "logs" / "b.csv")
    before = b.read_bytes()
    with pytest.raises(ValueError, match=rf"^refusing to write {out / 'a.csv'} over or inside the input {b} "
                                         r"\(.* is a symbolic link to '../logs/b.csv'\); remove the link"):
        process_many([a.parent], out_dir=out, preset="raw")
    assert b.read_bytes() == before
    proc = gyrocore_cli("process", a.parent, "--out", out, "--overwrite", "--preset", "raw", code=2)
    assert "over or inside the input" in proc.stderr and b.read_bytes() == before


def test_an_output_name_linked_to_another_output_is_refused_before_any_work(tmp_path: Path) -> None:
    # out/a.csv -> b.csv: a's heading went to b.csv, then b's over it (or the other way round),
    # and the report said 400 rows out -> out/b.csv for a file of 300
    a, b, out = _two_logs(tmp_path)
    (out / "b.csv").write_text("kept\n")
    (out / "a.csv").symlink_to("b.csv")
    with pytest.raises(ValueError, match=rf"^{a} and {b} would both be written to {out.resolve() / 'b.csv'} "
                                         r"\(.* is a symbolic link to 'b.csv'\); remove the link, or process them"):
        process_many([a.parent], out_dir=out, preset="raw")
    assert (out / "b.csv").read_text() == "kept\n"


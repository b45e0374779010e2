"""Inputs a hostile user gives: each refused with one line naming the file or parameter and what
to do, never a traceback, a silent wrong result or an overwritten input."""

from __future__ import annotations

from pathlib import Path

import pytest

from gyrocore.calibration import Calibration

from .test_batch import synthetic_csv
from .test_errors_named import run_cli

#: JSON that Python's parser cannot read without running out of recursion.
DEEP_JSON = "[" * 100_000 + "]" * 100_000


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (DEEP_JSON, "JSON nested too deeply to read"),
        ('{"stationary": [0, 1' + "0" * 400 + "]}", "stationary must be [t0, t1] in seconds"),
    ],
)
def test_a_hostile_meta_json_is_named(tmp_path: Path, content: str, message: str) -> None:
    folder = tmp_path / "log"
    folder.mkdir()
    synthetic_csv(folder / "gyro.csv", 3000)
    (folder / "meta.json").write_text(content)
    for args in (("process", folder, "--out", tmp_path / "h.csv"), ("allan", folder)):
        proc = run_cli(*args)
        assert proc.returncode == 2
        assert proc.stderr.startswith(f"gyrocore: error: {folder / 'meta.json'}: {message}")


@pytest.mark.parametrize("option", ["--calibration", "--params"])
def test_a_deeply_nested_json_file_is_named(tmp_path: Path, option: str) -> None:
    path = tmp_path / "deep.json"
    path.write_text(DEEP_JSON)
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    args = ("process", log, "--out", tmp_path / "h.csv") if option == "--calibration" else ("evaluate", tmp_path)
    proc = run_cli(*args, option, path)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {path}: JSON nested too deeply to read (arrays or objects inside each other)\n"


@pytest.mark.parametrize("option", ["--fixes", "--calibration"])
def test_a_file_an_option_names_is_never_the_output(tmp_path: Path, option: str) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    given = tmp_path / "given.csv"  # a calibration is JSON whatever its file is called
    if option == "--fixes":
        given.write_text("t,heading,sigma\n1700000001,0.1,0.05\n")
    else:
        Calibration(method="static", bias=0.001).save(given)
    before = given.read_bytes()
    proc = run_cli("process", log, "--out", given, option, given)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: refusing to write {given} over or inside the input {given}; write it elsewhere\n"
    assert given.read_bytes() == before

"""Paths that are not plain files where a file is expected: symbolic links that cannot be followed,
folders and named pipes. Each is an error naming it, never a traceback, a hang or a file quietly
left out."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from .test_batch import synthetic_csv
from .test_errors_named import run_cli
from .test_hostile_inputs import log_folder_with

REFERENCE = "t,heading\n1700000000.5,0.1\n1700000010.5,0.2\n1700000020.5,0.3\n"


def loop(path: Path) -> Path:
    """A symbolic link to itself at ``path``."""
    path.symlink_to(path)
    return path


@pytest.mark.parametrize("option", ["--fixes", "--calibration", "--plot-dir"])
def test_a_link_loop_an_option_names_is_an_error_not_a_traceback(tmp_path: Path, option: str) -> None:
    given = loop(tmp_path / "loop")
    if option == "--plot-dir":
        proc = run_cli("evaluate", log_folder_with(tmp_path, "reference.csv", REFERENCE), "--preset", "raw", option, given)
    else:
        proc = run_cli("process", synthetic_csv(tmp_path / "log.csv", 3000), "--out", tmp_path / "h.csv", option, given)
    assert proc.returncode == 2
    assert proc.stderr.startswith("gyrocore: error: ") and proc.stderr.count("\n") == 1, proc.stderr
    assert str(given) in proc.stderr


@pytest.mark.parametrize(("command", "option"), [("process", "--calibration"), ("evaluate", "--params")])
def test_a_named_pipe_given_as_a_json_file_is_refused_not_waited_on(tmp_path: Path, command: str, option: str) -> None:
    pipe = tmp_path / "settings.json"
    os.mkfifo(pipe)  # nothing writes to it: reading it would wait for ever
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    args = ("--out", tmp_path / "h.csv") if command == "process" else ()
    proc = run_cli(command, log, *args, option, pipe)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {pipe}: a named pipe, socket or device, not a file\n"

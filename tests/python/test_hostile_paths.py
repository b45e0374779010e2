"""Paths that are not plain files where a file is expected (symbolic links that cannot be followed,
folders, named pipes), and a log's name that is a path where it names a file. Each is an error
naming it, never a traceback, a hang, a file quietly left out or one written elsewhere."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

import gyrocore

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


@pytest.mark.parametrize("batch", [False, True])
def test_a_link_loop_given_as_the_output_is_an_error_not_a_traceback(tmp_path: Path, batch: bool) -> None:
    # one output file, or the output folder of a folder of logs
    logs = tmp_path / "logs"
    logs.mkdir()
    src = synthetic_csv(logs / "log.csv", 3000)
    given = loop(tmp_path / ("out" if batch else "h.csv"))
    proc = run_cli("process", logs if batch else src, "--out", given)
    assert proc.returncode == 2
    assert proc.stderr.startswith("gyrocore: error: ") and proc.stderr.count("\n") == 1, proc.stderr
    assert str(given) in proc.stderr and "Traceback" not in proc.stderr
    if batch:
        assert "a symbolic link to" in proc.stderr and "which cannot be followed" in proc.stderr
    assert given.is_symlink() and os.readlink(given) == str(given)  # left as it was


@pytest.mark.parametrize(("command", "option"), [("process", "--calibration"), ("evaluate", "--params")])
def test_a_named_pipe_given_as_a_json_file_is_refused_not_waited_on(tmp_path: Path, command: str, option: str) -> None:
    pipe = tmp_path / "settings.json"
    os.mkfifo(pipe)  # nothing writes to it: reading it would wait for ever
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    args = ("--out", tmp_path / "h.csv") if command == "process" else ()
    proc = run_cli(command, log, *args, option, pipe)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {pipe}: a named pipe, socket or device, not a file\n"


def not_a_file(path: Path, kind: str) -> str:
    """Put a ``kind`` of thing that is no regular file at ``path``; what an error says of it."""
    if kind == "folder":
        path.mkdir()
        return "a folder, not a file"
    if kind == "pipe":
        os.mkfifo(path)
        return "a named pipe, socket or device, not a file"
    path.symlink_to(path if kind == "loop" else path.with_name("gone"))
    return "which cannot be followed (" + ("Too many levels of symbolic links" if kind == "loop" else "No such file")


@pytest.mark.parametrize("kind", ["folder", "pipe", "loop", "dangling link"])
@pytest.mark.parametrize("name", ["gyro.csv", "meta.json", "reference.csv", "odometry.csv", "fixes.csv"])
def test_a_log_folder_file_that_is_no_file_is_named_not_left_out(tmp_path: Path, name: str, kind: str) -> None:
    # left out, a meta.json's rest window or an odometry's speed was lost without a word, and a
    # gyro.csv was said to be missing
    folder = log_folder_with(tmp_path, "reference.csv", REFERENCE)
    (folder / name).unlink(missing_ok=True)
    said = not_a_file(folder / name, kind)
    with pytest.raises((ValueError, OSError)) as e:
        gyrocore.read_log(folder)
    assert str(e.value).startswith(f"{folder / name}: ") and said in str(e.value)


def test_evaluate_names_a_meta_json_that_is_a_folder(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "reference.csv", REFERENCE)
    (folder / "meta.json").mkdir()
    proc = run_cli("evaluate", folder, "--preset", "raw")
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {folder / 'meta.json'}: a folder, not a file\n"


@pytest.mark.parametrize("name", ["../outside", "PLOTS/../../outside", "TMP/outside"])
def test_a_log_name_that_is_a_path_never_puts_its_plot_outside_the_plot_folder(tmp_path: Path, name: str) -> None:
    folder = log_folder_with(tmp_path, "reference.csv", REFERENCE)
    plots = tmp_path / "plots"
    (folder / "meta.json").write_text(json.dumps({"name": name.replace("PLOTS", str(plots)).replace("TMP", str(tmp_path))}))
    proc = run_cli("evaluate", folder, "--preset", "raw", "--plot-dir", plots)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {folder}: the log's name ") and "is no file name for its plot" in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log"]


@pytest.mark.parametrize("name", [5, ["a"], "", " "])
def test_a_meta_json_name_that_is_no_text_is_named(tmp_path: Path, name: object) -> None:
    folder = log_folder_with(tmp_path, "meta.json", json.dumps({"name": name}))
    with pytest.raises(ValueError, match=re.escape(f"{folder / 'meta.json'}: name must be the log's name as text")):
        gyrocore.read_log(folder)


def test_a_meta_json_name_of_null_is_the_folders_name(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "meta.json", json.dumps({"name": None}))
    assert gyrocore.read_log(folder).name == "log"

"""Files and folders this user may not read: one line naming the file or folder and what to
change, never Python's bare ``[Errno 13] Permission denied: 'x'``.

Root reads anything, so under root the command runs without the capabilities that let it
(``setpriv``, where there is one); the in-process tests make opening fail instead."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from gyrocore.cli import main
from gyrocore.io import _paths

from .test_batch import synthetic_csv

#: Run a command as a user whom file permissions bind (root keeps them but loses the overrides).
_DROP = ["setpriv", "--bounding-set=-dac_override,-dac_read_search", "--inh-caps=-dac_override,-dac_read_search"]


def unprivileged(*args: str | Path) -> subprocess.CompletedProcess[str]:
    """``gyrocore ARGS`` run by a user whom a file's permissions bind; skips where none can be."""
    prefix: list[str] = []
    if os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.skip("root reads files without read permission, and setpriv is not here to drop that")
        prefix = _DROP
    proc = subprocess.run([*prefix, sys.executable, "-m", "gyrocore.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=120)
    if "setpriv:" in proc.stderr:
        pytest.skip(f"setpriv cannot drop the capabilities here: {proc.stderr.strip()}")
    assert "Traceback" not in proc.stderr
    return proc


def write_input(tmp_path: Path, kind: str) -> Path:
    """A readable log of ``kind`` (csv, parquet, npy, npz, folder), 3000 samples."""
    csv = synthetic_csv(tmp_path / "src.csv", 3000)
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    if kind == "csv":
        return csv
    if kind == "parquet":
        pq.write_table(pa.table({"t": data[:, 0], "gyro_z": data[:, 1]}), tmp_path / "log.parquet")
        return tmp_path / "log.parquet"
    if kind == "npy":
        np.save(tmp_path / "log.npy", data)
        return tmp_path / "log.npy"
    if kind == "npz":
        np.savez(tmp_path / "log.npz", t=data[:, 0], gyro_z=data[:, 1])
        return tmp_path / "log.npz"
    folder = tmp_path / "drive"
    folder.mkdir()
    shutil.copy(csv, folder / "gyro.csv")
    return folder


@pytest.mark.parametrize("kind", ["csv", "parquet", "npy", "npz"])
def test_an_unreadable_file_is_named_with_what_to_do(tmp_path: Path, kind: str) -> None:
    log = write_input(tmp_path, kind)
    log.chmod(0)
    for args in (("process", log, "--out", tmp_path / "h.csv"), ("allan", log), ("calibrate", log)):
        proc = unprivileged(*args)
        assert proc.returncode == 2
        assert proc.stderr == (f"gyrocore: error: {log}: permission denied: this user may not read the file; "
                               f"make it readable (chmod +r {log}) or copy it somewhere readable\n")
    assert not (tmp_path / "h.csv").exists()


@pytest.mark.parametrize("mode", [0, 0o600])  # not listed; listed but not entered
def test_an_unreadable_log_folder_is_named_not_taken_for_another_folder(tmp_path: Path, mode: int) -> None:
    folder = write_input(tmp_path, "folder")
    folder.chmod(mode)
    try:
        for args in (("process", folder, "--out", tmp_path / "h.csv"), ("evaluate", folder)):
            proc = unprivileged(*args)
            assert proc.returncode == 2
            assert proc.stderr == (f"gyrocore: error: {folder}: permission denied: this user may not list the "
                                   f"folder; make it readable (chmod +rx {folder}) or copy it somewhere readable\n")
    finally:
        folder.chmod(0o755)  # for pytest to remove it


def test_an_unreadable_file_of_a_batch_is_its_failed_line(tmp_path: Path) -> None:
    locked = synthetic_csv(tmp_path / "locked.csv", 3000)
    locked.chmod(0)
    proc = unprivileged("process", locked, synthetic_csv(tmp_path / "good.csv", 3000), "--out", tmp_path / "out")
    assert proc.returncode == 1
    assert f"FAILED {locked}: permission denied: this user may not read the file; make it readable" in proc.stdout
    assert (tmp_path / "out" / "good.csv").is_file()


def _deny(real: object, denied: Path) -> object:
    """``os.open`` that refuses ``denied`` as a file without read permission does."""
    def fake(path: object, *args: object, **kwargs: object) -> int:
        if Path(str(path)) == denied:
            raise PermissionError(13, "Permission denied", str(path))
        return real(path, *args, **kwargs)  # type: ignore[operator]
    return fake


@pytest.mark.parametrize("option", ["--params", "--calibration", "log"])
def test_a_denied_file_is_named_in_process(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                           capsys: pytest.CaptureFixture[str], option: str) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    given = tmp_path / "given.json"
    given.write_text(json.dumps({"format": "gyrocore-params", "version": 1, "name": "x", "preset": "hdr",
                                 "overrides": {}}))
    denied = log if option == "log" else given
    monkeypatch.setattr(_paths.os, "open", _deny(os.open, denied))
    if option == "--params":
        args = ["evaluate", str(log), option, str(given)]
    else:
        args = ["process", str(log), "--out", str(tmp_path / "h.csv")] + ([option, str(given)] if option != "log" else [])
    assert main(args) == 2
    assert capsys.readouterr().err == (f"gyrocore: error: {denied}: permission denied: this user may not read the "
                                       f"file; make it readable (chmod +r {denied}) or copy it somewhere readable\n")


def test_a_permission_error_of_python_names_the_file_and_what_to_do() -> None:
    error = PermissionError(13, "Permission denied", "/x/y.csv")
    assert _paths.error_text(error) == ("/x/y.csv: permission denied: this user may not open it; change its "
                                        "permissions (chmod) or use another path")
    assert _paths.error_text(PermissionError("out.csv: cannot write in . (Permission denied)")) == (
        "out.csv: cannot write in . (Permission denied)")

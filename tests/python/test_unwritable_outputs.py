"""Outputs that cannot be written: a disk that fills while an output is written, a read-only
filesystem. The error names the output and what to do (it was "[Errno 28] No space left on device"
alone, or "[Errno 30] Read-only file system" naming the hidden temporary file), no partial or
temporary file is left, and a file of that name stays as it was. (Checked by hand on a 64 kB and a
read-only tmpfs; here the operating system's answers are stood in for.)"""

from __future__ import annotations

import errno
import io
from pathlib import Path
from typing import Any

import pytest

import gyrocore.io.atomic
import gyrocore.io.writer
from gyrocore.batch import process_file
from gyrocore.cli import main
from gyrocore.io import StagedFile, atomic_path
from gyrocore.io.atomic import make_folder

from .test_batch import leftovers, synthetic_csv

FULL = "No space left on device while writing it (the output is not written, and a file of that name is left as it was): free space, or write elsewhere"


class _FillingFile(io.RawIOBase):
    """A file that takes the header and then finds the disk full."""

    def __init__(self, room: int) -> None:
        self.room = room

    def writable(self) -> bool:
        return True

    def write(self, data: Any) -> int:
        if len(data) > self.room:
            raise OSError(errno.ENOSPC, "No space left on device")
        self.room -= len(data)
        return len(data)


@pytest.fixture
def full_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    real_open = open

    def filling_open(path: Any, mode: str = "r", *args: Any, **kwargs: Any) -> Any:
        if "w" in mode:
            real_open(path, mode).close()  # the temporary file is there, as on a real disk
            return _FillingFile(room=64)
        return real_open(path, mode, *args, **kwargs)

    monkeypatch.setattr(gyrocore.io.writer, "open", filling_open, raising=False)


@pytest.mark.usefixtures("full_disk")
def test_a_full_disk_names_the_output_and_keeps_the_file_there(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = synthetic_csv(tmp_path / "log.csv", 3000)
    out = tmp_path / "heading.csv"
    out.write_text("previous output\n")
    with pytest.raises(OSError, match="^" + str(out) + ": " + FULL.replace("(", r"\(").replace(")", r"\)") + "$") as e:
        process_file(src, out, preset="raw")
    assert e.value.errno == errno.ENOSPC
    assert out.read_text() == "previous output\n" and not leftovers(tmp_path)
    assert main(["process", str(src), "--out", str(out), "--overwrite"]) == 2
    assert capsys.readouterr().err == f"gyrocore: error: {out}: {FULL}\n"
    assert out.read_text() == "previous output\n" and not leftovers(tmp_path)


def test_a_full_disk_under_atomic_path_names_the_output(tmp_path: Path) -> None:
    out = tmp_path / "calibration.json"
    with pytest.raises(OSError, match=f"^{out}: Disk quota exceeded while writing it .*: free space, or write elsewhere$") as e:
        with atomic_path(out) as tmp:
            tmp.write_text("{")
            raise OSError(errno.EDQUOT, "Disk quota exceeded")
    assert e.value.errno == errno.EDQUOT and not out.exists() and not leftovers(tmp_path)
    with pytest.raises(OSError, match=r"^\[Errno 5\] Input/output error$"):  # any other error is as it was
        with atomic_path(out):
            raise OSError(errno.EIO, "Input/output error")


def test_a_read_only_filesystem_names_the_output_not_the_temporary_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    src = synthetic_csv(tmp_path / "log.csv", 3000)
    out = tmp_path / "heading.csv"

    def read_only(*args: Any, **kwargs: Any) -> Any:
        raise OSError(errno.EROFS, "Read-only file system", str(args[0]))

    with monkeypatch.context() as m:  # the temporary file cannot be made
        m.setattr(gyrocore.io.atomic.os, "open", read_only)
        with pytest.raises(PermissionError, match=f"^{out}: cannot write in {tmp_path} \\(Read-only file system\\); "
                           "write the output elsewhere$"):
            StagedFile(out)
    with monkeypatch.context() as m:  # the output folder cannot be made
        m.setattr(Path, "mkdir", read_only)
        with pytest.raises(PermissionError, match=f"^{tmp_path / 'new'}: cannot make the output folder \\(Read-only "
                           "file system\\); write the output elsewhere$"):
            make_folder(tmp_path / "new")
    with monkeypatch.context() as m:  # the folder is there but cannot be written: said before any work
        m.setattr(gyrocore.io.atomic.os, "access", lambda path, mode: False)
        assert main(["process", str(src), "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"gyrocore: error: {out}: cannot write in {tmp_path} (no permission to write "
                                       "there, or a read-only filesystem); write the output elsewhere\n")
    assert not out.exists() and not leftovers(tmp_path)

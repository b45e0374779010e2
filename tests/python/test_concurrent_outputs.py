"""Two runs writing one output at once: a run told not to replace an output (``gyrocore process``
without --overwrite, ``overwrite=False``) checks before its work that there is none, and another
run's output that appeared meanwhile was replaced at the end without a word, both reported ok.
The other run is played here by a file written while the log is processed."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import numpy as np
import pytest

from gyrocore import batch_job
from gyrocore.batch import process_file, process_many
from gyrocore.cli import main
from gyrocore import HeadingResult
from gyrocore.io import HeadingWriter, atomic

from .test_batch import leftovers, synthetic_csv

KEPT = "t,heading\n0,1\n"  # the other run's output


def _written_meanwhile(out: Path) -> batch_job.Progress:
    """A progress callback that writes ``out`` as another run would, after the first chunk."""
    def progress(rows: int, total: int | None, name: str) -> None:
        if not out.exists():
            out.write_text(KEPT)
    return progress


def test_an_output_written_meanwhile_is_kept_unless_overwrite(tmp_path: Path) -> None:
    log, out = synthetic_csv(tmp_path / "a.csv", 3000), tmp_path / "h.csv"
    with pytest.raises(FileExistsError, match=rf"^{out}: written meanwhile by something else \(another run writing "
                                              r"the same output\?\); it is kept, and this run's output is not "
                                              "written: run it again with overwrite=True to replace it, or write elsewhere$"):
        process_file(log, out, preset="raw", chunk_rows=1000, progress=_written_meanwhile(out), overwrite=False)
    assert out.read_text() == KEPT
    assert leftovers(tmp_path) == []
    # replacing is what overwrite (the default) asks for
    report = process_file(log, out, preset="raw", chunk_rows=1000, progress=_written_meanwhile(out))
    assert report.rows_out == 3000 and len(out.read_text().splitlines()) == 3001


def test_a_heading_writer_names_its_own_option(tmp_path: Path) -> None:
    # the writer's option is replace=True; it advised the command line's --overwrite
    out = tmp_path / "h.csv"
    with pytest.raises(FileExistsError, match=r"it is kept, and this run's output is not written: run it again with replace=True "):
        with HeadingWriter(out, replace=False) as writer:
            writer.write(HeadingResult(np.arange(3.0), np.zeros(3), np.zeros(3), np.zeros(3)))
            out.write_text(KEPT)
    assert out.read_text() == KEPT and leftovers(tmp_path) == []


def test_a_batch_fails_the_file_whose_output_was_written_meanwhile(tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    synthetic_csv(logs / "a.csv", 300)
    synthetic_csv(logs / "b.csv", 300, seed=1)
    plan = batch_job._FileJob._plan

    def plan_then_other_run(job: batch_job._FileJob, *args: object) -> object:
        if job.out.name == "a.csv":
            job.out.write_text(KEPT)
        return plan(job, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(batch_job._FileJob, "_plan", plan_then_other_run)
    summary = process_many([logs], out_dir=out, preset="raw", overwrite=False, jobs=1)
    assert [r.ok for r in summary.files] == [False, True]
    assert (summary.files[0].error or "").startswith(f"{out / 'a.csv'}: written meanwhile by something else")
    # the advice is the function's own option, also from the worker's thread: --overwrite was named
    assert "run it again with overwrite=True to replace it" in (summary.files[0].error or "")
    assert (out / "a.csv").read_text() == KEPT and leftovers(out) == []


def test_the_command_line_keeps_an_output_written_meanwhile_unless_overwrite(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    logs = tmp_path / "logs"
    logs.mkdir()
    log = synthetic_csv(logs / "a.csv", 300)
    plan = batch_job._FileJob._plan

    def plan_then_other_run(job: batch_job._FileJob, *args: object) -> object:
        job.out.write_text(KEPT)
        return plan(job, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(batch_job._FileJob, "_plan", plan_then_other_run)
    one, folder = tmp_path / "h.csv", tmp_path / "out"
    assert main(["process", str(log), "--out", str(one), "--preset", "raw"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"gyrocore: error: {one}: written meanwhile by something else")
    assert "run it again with --overwrite to replace it" in err  # the command's option, not the function's it calls
    assert main(["process", str(logs), "--out", str(folder), "--preset", "raw"]) == 1
    out_text = capsys.readouterr().out
    assert f"FAILED {log}: {folder / 'a.csv'}: written meanwhile" in out_text and "again with --overwrite to" in out_text
    assert one.read_text() == KEPT and (folder / "a.csv").read_text() == KEPT
    for out in (one, folder):
        assert main(["process", str(log if out == one else logs), "--out", str(out), "--preset", "raw",
                     "--overwrite"]) == 0
    assert len(one.read_text().splitlines()) == len((folder / "a.csv").read_text().splitlines()) == 301


def test_without_hard_links_the_name_is_checked_then_renamed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # a FAT card or a network share that refuses hard links: the same refusal, and a free name is
    # still written
    def no_links(src: object, dst: object) -> None:
        raise OSError(errno.EPERM, "Operation not permitted")

    monkeypatch.setattr(atomic.os, "link", no_links)
    for taken in (True, False):
        path = tmp_path / f"{taken}.csv"
        staged = atomic.StagedFile(path, replace=False)
        try:
            staged.tmp.write_text("new")
            if taken:
                path.write_text(KEPT)
                with pytest.raises(FileExistsError, match="written meanwhile"):
                    staged.commit()
            else:
                staged.commit()
        finally:
            staged.discard()
        assert path.read_text() == (KEPT if taken else "new")
    assert leftovers(tmp_path) == []
    assert sorted(os.listdir(tmp_path)) == ["False.csv", "True.csv"]


@pytest.mark.parametrize("replace", [True, False])
def test_an_output_s_name_is_put_on_disk_after_its_rename(replace: bool, tmp_path: Path,
                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """The data was synced before the rename, but not the folder that holds the new name: after a
    power cut a finished output could be gone, or the file it replaced back."""
    done: list[tuple[str, str]] = []
    sync, rename, link = os.fsync, os.replace, os.link

    def fsync(fd: int) -> None:
        done.append(("sync", os.readlink(f"/proc/self/fd/{fd}")))
        sync(fd)

    def renamed(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> None:
        done.append(("name", str(b)))
        rename(a, b)

    def linked(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> None:
        done.append(("name", str(b)))
        link(a, b)

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(os, "replace", renamed)
    monkeypatch.setattr(os, "link", linked)
    staged = atomic.StagedFile(tmp_path / "h.csv", replace=replace)
    staged.tmp.write_text("t,heading\n")
    staged.commit()
    named = done.index(("name", str(tmp_path / "h.csv")))
    assert ("sync", str(tmp_path)) in done[named + 1:], done
    assert (tmp_path / "h.csv").read_text() == "t,heading\n"


#: Every other command that writes a file named on its command line, with arguments that run in
#: seconds ({log}: a log folder with a reference, {tmp}: a scratch folder), and the file it writes.
OTHER_WRITERS = {
    "simulate": (("simulate", "--out", "{tmp}/out.csv", "--duration", "30"), "out.csv"),
    "calibrate": (("calibrate", "{log}", "--save", "{tmp}/out.json"), "out.json"),
    "tune": (("tune", "--sim-drive", "city:1", "--no-harm", "--max-evals", "2", "--out", "{tmp}/out.json"),
             "out.json"),
    "allan plot": (("allan", "{log}", "--plot", "{tmp}/out.png"), "out.png"),
    "allan kalibr": (("allan", "{log}", "--kalibr", "{tmp}/out.yaml", "--rrw", "1e-5"), "out.yaml"),
    "evaluate": (("evaluate", "{log}", "--preset", "raw", "--plot-dir", "{tmp}/plots"), "plots/sample_drive.png"),
    "reproduce": (("reproduce", "hong-allan", "--out", "{tmp}/figures"), "figures/hong_allan.png"),
    "demo": (("demo", "--duration", "60", "--drives", "1", "--plot", "{tmp}/out.png"), "out.png"),
}


@pytest.fixture(scope="module")
def sample_log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from gyrocore import datasets

    return datasets.write_sample(tmp_path_factory.mktemp("logs") / "drive")


@pytest.mark.parametrize("name", OTHER_WRITERS)
def test_every_command_keeps_an_output_written_meanwhile_unless_overwrite(
        name: str, sample_log: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    # simulate, calibrate, tune, allan, evaluate, reproduce and demo checked that their output was
    # not there before their work, then replaced one another run wrote meanwhile, both reported ok
    pattern, target = OTHER_WRITERS[name]
    args, out = [a.format(log=sample_log, tmp=tmp_path) for a in pattern], tmp_path / target
    staged = atomic.StagedFile.__init__

    def staged_then_other_run(self: atomic.StagedFile, path: str | Path, **options: bool) -> None:
        staged(self, path, **options)
        if Path(path) == out:
            out.write_text(KEPT)

    monkeypatch.setattr(atomic.StagedFile, "__init__", staged_then_other_run)
    assert main(args) == 2
    assert f"gyrocore: error: {out}: written meanwhile by something else" in capsys.readouterr().err
    assert out.read_text() == KEPT and leftovers(out.parent) == []
    out.unlink()
    assert main([*args, "--overwrite"]) == 0
    assert out.read_bytes() != KEPT.encode()


def test_an_output_written_meanwhile_with_this_runs_bytes_is_this_runs(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    # A Dask cluster runs a file again when the worker holding its report dies before the report
    # is read: the second run found the first's output, the same bytes, and the file that was
    # written whole was reported failed, "written meanwhile by something else".
    log, first, out = synthetic_csv(tmp_path / "a.csv", 3000), tmp_path / "first.csv", tmp_path / "h.csv"
    process_file(log, first, preset="raw", chunk_rows=1000)

    def first_run_done(rows: int, total: int | None, name: str) -> None:
        if not out.exists():
            out.write_bytes(first.read_bytes())

    report = process_file(log, out, preset="raw", chunk_rows=1000, progress=first_run_done, overwrite=False)
    assert report.ok and report.rows_out == 3000 and out.read_bytes() == first.read_bytes()
    assert leftovers(tmp_path) == []
    # also where the folder takes no hard links; a file that differs by one byte is still kept
    def no_links(src: object, dst: object) -> None:
        raise OSError(errno.EPERM, "Operation not permitted")

    monkeypatch.setattr(atomic.os, "link", no_links)
    for other in (first.read_bytes(), first.read_bytes()[:-2] + b"9\n"):
        out.unlink()

        def other_run(rows: int, total: int | None, name: str, other: bytes = other) -> None:
            if not out.exists():
                out.write_bytes(other)

        if other == first.read_bytes():
            assert process_file(log, out, preset="raw", chunk_rows=1000, progress=other_run, overwrite=False).ok
        else:
            with pytest.raises(FileExistsError, match="written meanwhile"):
                process_file(log, out, preset="raw", chunk_rows=1000, progress=other_run, overwrite=False)
        assert out.read_bytes() == other and leftovers(tmp_path) == []

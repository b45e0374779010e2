"""No command replaces a file the user has: an output that exists already is refused before any
work, in one line naming it, unless ``--overwrite`` is given (or, for a batch, ``--skip-existing``
keeps it and skips its input); the output is never an input, even with ``--overwrite``."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

from gyrocore import batch_run, datasets
from gyrocore.cli import main

from .conftest import gyrocore_cli
from .test_batch import read_table, synthetic_csv

MINE = "the user's own file\n"

#: Every command that writes a file named on its command line: its arguments ({log}: a log folder
#: with a reference, {tmp}: a scratch folder holding small.csv) and the file it would write.
WRITERS = {
    "process to a file": (("process", "{tmp}/small.csv", "--out", "{tmp}/victim.csv"), "victim.csv"),
    "process to a folder": (("process", "{tmp}/small.csv", "--out", "{tmp}/outF"), "outF/small.csv"),
    "simulate": (("simulate", "--out", "{tmp}/victim.csv", "--duration", "30"), "victim.csv"),
    "calibrate": (("calibrate", "{log}", "--save", "{tmp}/victim.json"), "victim.json"),
    "tune": (("tune", "{log}", "--out", "{tmp}/victim.json"), "victim.json"),
    "allan plot": (("allan", "{log}", "--plot", "{tmp}/victim.png"), "victim.png"),
    # the drive shows no rate random walk (its motion's bend at 0.1 s was read as one): --rrw gives it
    "allan kalibr": (("allan", "{log}", "--kalibr", "{tmp}/victim.yaml", "--rrw", "1e-5"), "victim.yaml"),
    "evaluate": (  # the plot is named after meta.json's name
        ("evaluate", "{log}", "--preset", "raw", "--plot-dir", "{tmp}/plots"), "plots/sample_drive.png"),
    "reproduce": (("reproduce", "hong-allan", "--out", "{tmp}/figures"), "figures/hong_allan.png"),
    "demo": (("demo", "--duration", "60", "--drives", "1", "--plot", "{tmp}/victim.png"), "victim.png"),
}


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return datasets.write_sample(tmp_path_factory.mktemp("logs") / "drive")


def _command(name: str, log: Path, tmp: Path) -> tuple[list[str], Path]:
    """The arguments of the writer ``name`` and the file it writes, with a user's file there."""
    args, target = WRITERS[name]
    synthetic_csv(tmp / "small.csv", 3000)
    path = tmp / target
    path.parent.mkdir(exist_ok=True)
    path.write_text(MINE)
    return [a.format(log=log, tmp=tmp) for a in args], path


@pytest.mark.parametrize("name", WRITERS)
def test_an_output_that_exists_is_refused_before_any_work(name: str, log: Path, tmp_path: Path) -> None:
    args, target = _command(name, log, tmp_path)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    # tune would fit for minutes, the demo simulate for seconds: the refusal comes first
    proc = gyrocore_cli(*args, code=2, timeout=60)
    assert proc.stderr == (f"gyrocore: error: {target} already exists; pass --overwrite to replace it, or write "
                           "elsewhere (nothing was written)\n")
    assert target.read_text() == MINE
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before


@pytest.mark.parametrize("name", ["process to a file", "process to a folder", "simulate", "calibrate", "allan kalibr"])
def test_overwrite_replaces_the_output(name: str, log: Path, tmp_path: Path) -> None:
    args, target = _command(name, log, tmp_path)
    gyrocore_cli(*args, "--overwrite", code=0)
    assert target.read_text() != MINE
    assert not list(target.parent.glob(".*.tmp"))


def test_an_output_folder_is_checked_for_every_file_before_any_is_written(tmp_path: Path) -> None:
    inputs = [synthetic_csv(tmp_path / f"{name}.csv", 3000) for name in ("a", "b", "c")]
    out = tmp_path / "out"
    out.mkdir()
    (out / "b.csv").write_text(MINE)
    (out / "c.csv").write_text(MINE)
    proc = gyrocore_cli("process", *inputs, "--out", out, code=2)
    assert proc.stderr.startswith(f"gyrocore: error: {out / 'b.csv'}, {out / 'c.csv'} already exist; "
                                  "pass --overwrite to replace them")
    assert sorted(p.name for p in out.iterdir()) == ["b.csv", "c.csv"]
    assert (out / "b.csv").read_text() == MINE


@pytest.mark.parametrize("overwrite", [(), ("--overwrite",)])
def test_the_input_is_never_the_output(tmp_path: Path, overwrite: tuple[str, ...]) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 300)
    before = src.read_bytes()
    proc = gyrocore_cli("process", src, "--out", src, *overwrite, code=2)
    assert proc.stderr.startswith(f"gyrocore: error: refusing to write {src} over or inside the input")
    assert src.read_bytes() == before


def test_the_demo_replaces_its_own_plot_and_no_other_file_of_its_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    demo = ["demo", "--duration", "60", "--drives", "1"]
    plot = Path("gyrocore_demo.png")
    assert main([*demo, "--seed", "1"]) == 0
    first = plot.read_bytes()
    assert main([*demo, "--seed", "2"]) == 0  # the previous run's plot is replaced
    assert plot.read_bytes().startswith(b"\x89PNG") and plot.read_bytes() != first
    capsys.readouterr()
    # a file of that name the demo did not write (the user's own picture, notes) is kept
    for theirs in (b"my notes", first.replace(b"gyrocore demo", b"another tool!")):
        plot.write_bytes(theirs)
        assert main(demo) == 2
        assert capsys.readouterr().err.strip() == (
            "gyrocore: error: gyrocore_demo.png already exists and is not a plot gyrocore demo wrote; pass "
            "--overwrite to replace it, or --plot FILE to write elsewhere (nothing was written)")
        assert plot.read_bytes() == theirs
    assert main([*demo, "--overwrite"]) == 0
    assert plot.read_bytes().startswith(b"\x89PNG") and plot.read_bytes() != theirs


def test_skip_existing_resumes_an_interrupted_batch(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    logs = tmp_path / "logs"
    logs.mkdir()
    short, long = synthetic_csv(logs / "short.csv", 1000), synthetic_csv(logs / "long.csv", 3_000_000)
    out = tmp_path / "out"
    args = ["process", str(logs), "--out", str(out), "--preset", "raw", "--jobs", "2"]

    def interrupt(self: object, n: int = 1) -> None:  # as the first file is done
        raise KeyboardInterrupt

    monkeypatch.setattr(batch_run._NoBar, "update", interrupt)
    assert main(args) == 130
    line = capsys.readouterr().err.strip()
    assert line.startswith("gyrocore: interrupted; no partial output was left; 1 file(s) finished before it")
    assert line.endswith("; to go on, run it again with --skip-existing: it processes only the inputs without an "
                         "output")
    monkeypatch.undo()
    finished = (out / "short.csv").read_bytes()
    assert sorted(p.name for p in out.iterdir()) == ["short.csv"]
    # the finished output is kept, its input named as skipped and counted; the other one is processed
    assert main([*args, "--skip-existing"]) == 0
    stdout = capsys.readouterr().out
    assert f"skipped {short}: {out / 'short.csv'} exists already\n" in stdout and f"ok     {long}: " in stdout
    assert "1 of 2 files processed, 1 skipped (their outputs exist already), 0 failed; " in stdout
    assert (out / "short.csv").read_bytes() == finished and len(read_table(out / "long.csv")) == 3_000_000
    assert main([*args, "--skip-existing", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["ok"], summary["skipped"], summary["failed"], summary["rows_in"]) == (0, 2, 0, 0)
    assert all(f["output_existed"] and not f["ok"] and f["error"] is None for f in summary["files"])


def test_skip_existing_is_for_an_output_folder_without_overwrite(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "small.csv", 300)
    folder = tmp_path / "outF"
    proc = gyrocore_cli("process", src, "--out", folder, "--skip-existing", "--overwrite", code=2)
    assert "argument --overwrite: not allowed with argument --skip-existing" in proc.stderr
    proc = gyrocore_cli("process", src, "--out", tmp_path / "h.csv", "--skip-existing", code=2)
    assert proc.stderr == (f"gyrocore: error: --skip-existing is for a batch into an output folder, and --out "
                           f"{tmp_path / 'h.csv'} is one file: leave the option out (an output that exists is "
                           "refused unless --overwrite is given)\n")
    # no run writes a folder where an output goes: that is refused before any work, as without the option
    (folder / "small.csv").mkdir(parents=True)
    proc = gyrocore_cli("process", src, "--out", folder, "--skip-existing", code=2)
    assert proc.stderr.startswith(f"gyrocore: error: {folder / 'small.csv'}: a folder, where an output file goes")


@pytest.mark.parametrize("name", [n for n in WRITERS if n != "process to a folder"])
@pytest.mark.parametrize("overwrite", [False, True])
def test_a_folder_where_the_output_file_goes_is_refused_before_any_work(name: str, overwrite: bool, log: Path,
                                                                        tmp_path: Path) -> None:
    args, target = _command(name, log, tmp_path)
    target.unlink()
    target.mkdir()
    (target / "keep.txt").write_text(MINE)
    proc = gyrocore_cli(*args, *(["--overwrite"] if overwrite else []), code=2, timeout=60)
    assert proc.stderr == (f"gyrocore: error: {target}: a folder, where an output file goes; move it or write elsewhere "
                           "(--overwrite replaces files, never a folder; nothing was written)\n")
    assert proc.stdout == ""  # refused before any work: no report
    assert [p.name for p in target.iterdir()] == ["keep.txt"] and (target / "keep.txt").read_text() == MINE


@pytest.mark.parametrize("name", [n for n in WRITERS if n not in ("process to a folder", "evaluate", "reproduce")])
@pytest.mark.parametrize("parent", ["missing", "file", "under a file"])
def test_an_output_without_its_folder_is_refused_before_any_work(name: str, parent: str, log: Path,
                                                                 tmp_path: Path) -> None:
    # under a file (notes.csv/sub/x.csv) it said "the folder notes.csv/sub does not exist; create
    # it", which no one can
    args, target = _command(name, log, tmp_path)
    target.unlink()
    blocker = tmp_path / "not_here"
    folder = blocker / "sub" if parent == "under a file" else blocker
    if parent != "missing":
        blocker.write_text(MINE)
    moved = folder / target.name
    args = [str(moved) if a == str(target) else a for a in args]
    proc = gyrocore_cli(*args, code=2, timeout=60)
    reason = f"{blocker} is not a folder; write the output elsewhere" if parent != "missing" else (
        f"the folder {folder} does not exist; create it or write elsewhere")
    assert (proc.stdout, proc.stderr) == ("", f"gyrocore: error: {moved}: {reason}\n")
    assert not blocker.is_dir() and (parent == "missing" or blocker.read_text() == MINE)


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="no /proc here")
@pytest.mark.parametrize("inputs", [1, 2])
def test_an_output_in_a_folder_that_takes_no_files_is_not_said_to_be_missing(inputs: int, log: Path,
                                                                             tmp_path: Path) -> None:
    """/proc exists, but nothing can be created in it, not even by root, whose creation fails as
    if it were missing: it said ``the folder /proc does not exist`` (a file), or gave a bare
    ``[Errno 2] No such file or directory: '/proc/x'`` (the folder of two inputs' outputs)."""
    output = "/proc/gyrocore.csv" if inputs == 1 else "/proc/gyrocore_out"
    logs = [log, shutil.copytree(log, tmp_path / "again")][:inputs]
    proc = gyrocore_cli("process", *map(str, logs), "--out", output, code=2, timeout=60)
    if os.access("/proc", os.W_OK):  # root: the permission bits allow it
        why = "it exists, but nothing can be created in it, as in a virtual filesystem such as /proc"
        said = (f"{output}: cannot write in /proc ({why})" if inputs == 1 else
                f"{output}: cannot make the output folder in /proc ({why})")
    else:
        said = (f"{output}: cannot write in /proc (no permission to write there, or a read-only filesystem)"
                if inputs == 1 else f"{output}: cannot make the output folder (Permission denied)")
    assert (proc.stdout, proc.stderr) == ("", f"gyrocore: error: {said}; write the output elsewhere\n")


@pytest.mark.parametrize("name", ["process to a folder", "evaluate", "reproduce"])
def test_a_file_in_the_way_of_a_folder_a_command_makes_is_refused_before_any_work(name: str, log: Path,
                                                                                   tmp_path: Path) -> None:
    args, target = _command(name, log, tmp_path)
    folder = target.parent  # outF, plots, figures: made by the command where missing
    target.unlink()
    folder.rmdir()
    blocker = tmp_path / "notes.txt"
    blocker.write_text(MINE)
    args = [a.replace(str(folder), str(blocker / "sub")) for a in args]
    proc = gyrocore_cli(*args, code=2, timeout=60)
    output = blocker / "sub" / target.name
    assert (proc.stdout, proc.stderr) == ("", f"gyrocore: error: {output}: {blocker} is not a folder; write the "
                                              "output elsewhere\n")
    assert blocker.read_text() == MINE


def test_allan_refused_for_a_missing_rrw_writes_no_plot_and_runs_again_with_it(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # the plot was written before --kalibr found no rate random walk (exit 2), and the run again
    # with --rrw was refused: "adev.png already exists"
    log = datasets.write_sample(tmp_path / "sample")
    plot, kalibr = tmp_path / "adev.png", tmp_path / "imu.yaml"
    args = ["allan", str(log), "--window", "+0", "+60", "--plot", str(plot), "--kalibr", str(kalibr)]
    assert main(args) == 2
    out, err = capsys.readouterr()
    assert "the rate random walk was not found" in err and out == ""
    assert not plot.exists() and not kalibr.exists()
    assert main([*args, "--rrw", "1e-5"]) == 0
    assert plot.exists() and "1e-05" in kalibr.read_text()

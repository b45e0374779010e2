"""An output that is there before a call told not to replace it (``overwrite=False``, ``replace=False``)
is refused before the call's work, in the words the command line uses: it exists, and what replaces
it. It was refused only when the output was written, after the work, as "written meanwhile by
something else (another run writing the same output?)": a user who saved twice was told of a race
that never was. A file that appears during the work is still another run's, written meanwhile."""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from gyrocore import datasets, paper
from gyrocore.calibration import Calibration
from gyrocore.evaluate import compare, plot_log
from gyrocore.io import atomic
from gyrocore.tune import ParameterSet

pytest.importorskip("matplotlib")

KEPT = "the user's file\n"


def _refusal(path: Path, option: str) -> str:
    return rf"^{re.escape(str(path))} already exists; pass {option} to replace it, or write elsewhere \(nothing was written\)$"


def _plot_sample(path: Path) -> None:
    log = datasets.sample_drive()
    plot_log(path, log, {"raw": log.process("raw")}, overwrite=False)


#: Each call of the API told not to replace its output, the output it writes (in a scratch folder)
#: and the option that replaces it.
API_WRITERS: dict[str, tuple[Callable[[Path], object], str, str]] = {
    "Calibration.save": (lambda d: Calibration("static_bias", bias=0.01).save(d / "c.json", overwrite=False),
                         "c.json", "overwrite=True"),
    "ParameterSet.write": (lambda d: ParameterSet("mine", "raw", {}).write(d / "p.json", overwrite=False),
                           "p.json", "overwrite=True"),
    "evaluate.compare": (lambda d: compare([datasets.sample_drive()], ["raw"], plot_dir=d, overwrite=False),
                         "sample_drive.png", "overwrite=True"),
    "evaluate.plot_log": (lambda d: _plot_sample(d / "x.png"), "x.png", "overwrite=True"),
    "paper.reproduce": (lambda d: paper.reproduce("hong-allan", out_dir=d, overwrite=False),
                        "hong_allan.png", "overwrite=True"),
    "io.write_text_atomically": (lambda d: atomic.write_text_atomically(d / "t.txt", "new", replace=False),
                                 "t.txt", "replace=True"),
    "io.write_atomically": (lambda d: atomic.write_atomically(d / "w.bin", lambda tmp: Path(tmp).write_text("new"),
                                                              replace=False), "w.bin", "replace=True"),
}


@pytest.mark.parametrize("name", API_WRITERS)
def test_an_output_there_before_the_call_is_said_to_exist(name: str, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    call, target, option = API_WRITERS[name]
    out = tmp_path / target
    out.write_text(KEPT)
    with pytest.raises(FileExistsError, match=_refusal(out, option)):
        call(tmp_path)
    assert out.read_text() == KEPT and sorted(p.name for p in tmp_path.iterdir()) == [target]
    assert capsys.readouterr().out == ""  # before the work: a reproduction's table is not printed
    out.unlink()
    call(tmp_path)  # a free name is written
    assert out.read_bytes() != KEPT.encode()


def test_a_reproduction_s_figure_there_before_is_refused_by_plot_too(tmp_path: Path) -> None:
    result = paper.hong_allan()
    out = tmp_path / "f.png"
    out.write_text(KEPT)
    with pytest.raises(FileExistsError, match=_refusal(out, "overwrite=True")):
        result.plot(out, overwrite=False)
    assert out.read_text() == KEPT
    assert result.plot(out) == out and out.read_bytes().startswith(b"\x89PNG")


def test_an_atomic_path_there_before_the_block_is_refused_before_it_runs(tmp_path: Path) -> None:
    out, ran = tmp_path / "a.txt", []
    out.write_text(KEPT)
    with pytest.raises(FileExistsError, match=_refusal(out, "replace=True")):
        with atomic.atomic_path(out, replace=False):
            ran.append(True)
    assert ran == [] and out.read_text() == KEPT


def test_an_output_written_during_the_call_is_still_written_meanwhile(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    # the reproduction runs, then another run writes its figure: a race, kept and said to be one
    out = tmp_path / "hong_allan.png"
    run, figure = paper.REPRODUCTIONS["hong-allan"]

    @functools.wraps(run)  # its seed, which reproduce prints
    def run_then_other_run() -> Any:
        result = run()
        out.write_text(KEPT)
        return result

    monkeypatch.setitem(paper.REPRODUCTIONS, "hong-allan", (run_then_other_run, figure))
    with pytest.raises(FileExistsError, match=rf"^{re.escape(str(out))}: written meanwhile by something else"):
        paper.reproduce("hong-allan", out_dir=tmp_path, overwrite=False)
    assert out.read_text() == KEPT and sorted(p.name for p in tmp_path.iterdir()) == ["hong_allan.png"]


def test_a_heading_file_there_before_process_file_or_process_many_is_refused_before_the_work(tmp_path: Path) -> None:
    from gyrocore.batch import process_file, process_many

    from .test_batch import synthetic_csv

    logs = tmp_path / "logs"
    logs.mkdir()
    log, other = synthetic_csv(logs / "a.csv", 300), synthetic_csv(logs / "b.csv", 300, seed=1)
    out, folder = tmp_path / "h.csv", tmp_path / "out"
    folder.mkdir()
    for kept in (out, folder / "a.csv"):
        kept.write_text(KEPT)
    with pytest.raises(FileExistsError, match=_refusal(out, "overwrite=True")):
        process_file(log, out, preset="raw", overwrite=False)
    with pytest.raises(FileExistsError, match=_refusal(folder / "a.csv", "overwrite=True")):
        process_many([logs], out_dir=folder, preset="raw", overwrite=False, jobs=1)
    assert out.read_text() == KEPT and sorted(p.name for p in folder.iterdir()) == ["a.csv"]  # b.csv not written
    # a complete output skipped is no refusal; the input as its own output is refused as that
    (folder / "a.csv").write_text("t,heading\n0,0\n")
    assert [r.output_existed for r in process_many([logs], out_dir=folder, preset="raw", overwrite=False,
                                            skip_existing=True, jobs=1).files] == [True, False]
    with pytest.raises(ValueError, match="input"):
        process_file(other, other, preset="raw", overwrite=False)
    assert process_file(log, out, preset="raw", overwrite=True).rows_out == 300


def test_a_heading_writer_s_output_there_before_it_is_made_is_refused_at_once(tmp_path: Path) -> None:
    # it was refused only at the block's end, as "written meanwhile by something else", after the
    # rows were written, naming --overwrite, which the writer does not have
    from gyrocore.io import HeadingWriter

    out = tmp_path / "h.csv"
    out.write_text(KEPT)
    with pytest.raises(FileExistsError, match=_refusal(out, "replace=True")):
        HeadingWriter(out, replace=False)
    assert out.read_text() == KEPT and sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]
    with HeadingWriter(out, replace=True) as writer:  # what the refusal says to do
        writer.write(datasets.sample_drive().process("raw"))
    assert out.read_text() != KEPT


def test_a_heading_writer_keeps_a_file_written_meanwhile(tmp_path: Path) -> None:
    from gyrocore.io import HeadingWriter

    result = datasets.sample_drive().process("raw")
    out = tmp_path / "h.csv"
    with pytest.raises(FileExistsError, match=rf"^{re.escape(str(out))}: written meanwhile by something else"):
        with HeadingWriter(out, replace=False) as writer:
            out.write_text(KEPT)
            writer.write(result)
    assert out.read_text() == KEPT and sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]
    out.unlink()
    with HeadingWriter(out, replace=False) as writer:
        writer.write(result)
    assert writer.rows == len(result.t) and len(out.read_text().splitlines()) == len(result.t) + 1

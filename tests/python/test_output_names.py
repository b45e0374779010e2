"""Outputs whose names one output folder holds as one file (``Drive.csv`` and ``drive.csv`` where
it ignores case): refused before any work, naming both inputs; apart where the folder holds them
apart. A folder that ignores case cannot be made here without root and loop devices, so such a
folder's answer to :func:`gyrocore.batch_names.folding` is put in its place; the probe itself is
checked against what this machine's temporary folder does."""

from __future__ import annotations

import shutil
import subprocess
import sys
import unicodedata
from pathlib import Path

import pytest

from gyrocore import batch_names
from gyrocore.batch import process_many
from gyrocore.batch_names import Folding
from gyrocore.cli import main

from .test_batch import synthetic_csv

NFC = unicodedata.normalize("NFC", "caf\u00e9")
NFD = unicodedata.normalize("NFD", "caf\u00e9")


def _ignores_case(monkeypatch: pytest.MonkeyPatch, case: bool = True, normalization: bool = False) -> list[Path]:
    """Make the output folder answer as one that ignores case (and composes names alike); the
    folders asked."""
    asked: list[Path] = []

    def fake(folder: Path) -> Folding:
        asked.append(folder)
        return Folding(case=case, normalization=normalization)

    monkeypatch.setattr(batch_names, "folding", fake)
    return asked


def _holds_apart(folder: Path, a: str, b: str) -> bool:
    """Whether ``folder`` holds the names ``a`` and ``b`` as two files (asked by creating ``a``)."""
    (folder / a).write_text("x")
    try:
        return not (folder / b).exists()
    finally:
        (folder / a).unlink()


def test_names_one_in_case_are_refused_before_any_work_where_the_folder_ignores_case(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Drive.csv's output was replaced by drive.csv's on macOS or Windows: 1 file left, 2 reported ok
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    a, b = synthetic_csv(logs / "Drive.csv", 300), synthetic_csv(logs / "drive.csv", 400, seed=1)
    asked = _ignores_case(monkeypatch)
    with pytest.raises(ValueError, match=rf"^{a} and {b} would both be written to {out / 'Drive.csv'}: {out} ignores "
                                         r"case, and holds Drive.csv and drive.csv as one file; rename one of the "
                                         "inputs, or process them separately$"):
        process_many([logs], out_dir=out, preset="raw")
    assert asked == [out]
    assert not out.exists()  # before any work: not even the folder was made


def test_names_one_in_case_are_two_outputs_where_the_folder_holds_them_apart(tmp_path: Path) -> None:
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    if not _holds_apart(logs, "Drive.csv", "drive.csv"):
        pytest.skip("this machine's temporary folder ignores case")
    synthetic_csv(logs / "Drive.csv", 300)
    synthetic_csv(logs / "drive.csv", 400, seed=1)
    summary = process_many([logs], out_dir=out, preset="raw")
    assert not summary.failed and [r.rows_out for r in summary.files] == [300, 400]
    assert sorted(p.name for p in out.iterdir()) == ["Drive.csv", "drive.csv"]
    assert len((out / "Drive.csv").read_text().splitlines()) == 301
    assert len((out / "drive.csv").read_text().splitlines()) == 401


def test_the_command_line_refuses_names_one_in_case_with_its_error(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    a, c = synthetic_csv(logs / "RUN.csv", 300), synthetic_csv(tmp_path / "run.csv", 300, seed=2)
    _ignores_case(monkeypatch)
    assert main(["process", str(logs), str(c), "--out", str(out), "--preset", "raw"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"gyrocore: error: {a} and {c} would both be written to {out / 'RUN.csv'}: {out} ignores case")
    assert not out.exists()


def test_names_composed_and_decomposed_are_refused_where_the_folder_composes_them_alike(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # macOS: café.csv with its é as one character (NFC, typed on Linux) and as e + accent (NFD,
    # as a Mac names files) are one file
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    a, b = synthetic_csv(tmp_path / "one" / f"{NFC}.csv", 300), synthetic_csv(tmp_path / "two" / f"{NFD}.csv", 300)
    _ignores_case(monkeypatch, case=False, normalization=True)
    with pytest.raises(ValueError, match=r"composes accented letters alike \(Unicode NFC and NFD\)"):
        process_many([a, b], out_dir=tmp_path / "out", preset="raw")
    _ignores_case(monkeypatch, case=True, normalization=False)  # Windows: NFC and NFD are two names
    summary = process_many([a, b], out_dir=tmp_path / "out", preset="raw")
    assert len(summary.succeeded) == 2


def test_the_folder_is_asked_only_where_names_could_be_one_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    synthetic_csv(tmp_path / "a.csv", 100)
    synthetic_csv(tmp_path / "b.csv", 100)
    asked = _ignores_case(monkeypatch)
    process_many([tmp_path / "a.csv", tmp_path / "b.csv"], out_dir=tmp_path / "out", preset="raw")
    assert asked == []


def test_the_probe_says_what_the_folder_does_and_leaves_nothing(tmp_path: Path) -> None:
    folder = tmp_path / "out"
    folder.mkdir()
    expected = Folding(case=not _holds_apart(folder, "Ab.csv", "aB.csv"),
                       normalization=not _holds_apart(folder, f"{NFC}.csv", f"{NFD}.csv"))
    assert batch_names.folding(folder) == expected
    assert list(folder.iterdir()) == []
    # an output folder not made yet: the folder it will be made in is asked, and nothing is made
    assert batch_names.folding(folder / "new" / "deeper") == expected
    assert list(folder.iterdir()) == []


def test_a_folder_that_cannot_be_asked_is_taken_as_its_system_usually_does(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: object) -> int:
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(batch_names.os, "open", refuse)
    assert batch_names.folding(tmp_path) == batch_names.USUAL
    assert not batch_names.atomic._live


def test_the_keys_fold_what_the_folder_folds() -> None:
    both = Folding(case=True, normalization=True)
    names = [Path(n) for n in ("x/a.csv", "x/B.csv", "x/b.csv")]
    assert batch_names.first_clash(names, both) == (1, 2)
    assert batch_names.first_clash(names, Folding(case=False, normalization=True)) is None
    # the same name twice is the same-name check's, which names it otherwise
    assert batch_names.first_clash([Path("a.csv"), Path("a.csv")], both) is None
    # casefold folds ß as ss, as some filesystems do not: refused rather than risked
    assert batch_names.key("Stra\u00dfe.csv", both) == batch_names.key("STRASSE.csv", both)
    assert batch_names.key(f"{NFC}.csv", Folding(case=False, normalization=False)) != batch_names.key(
        f"{NFD}.csv", Folding(case=False, normalization=False))


def test_an_input_of_a_long_name_gets_its_output(tmp_path: Path) -> None:
    # a name of 238-255 bytes is a valid output name, but the hidden file it is written under
    # (.NAME.<12 hex>.tmp) was not: FAILED ...: [Errno 36] File name too long: 'out/.aaa...tmp'
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    name = "\u00e9" + "a" * 244 + ".csv"  # 250 bytes, a two-byte character first
    synthetic_csv(logs / name, 300)
    summary = process_many([logs], out_dir=out, preset="raw")
    assert not summary.failed, summary
    assert [p.name for p in out.iterdir()] == [name]
    assert len((out / name).read_text().splitlines()) == 301


def test_the_hidden_name_fits_and_keeps_whole_characters() -> None:
    from gyrocore.io.atomic import temporary_name

    for name in ("h.csv", "a" * 255, "\u00e9" * 127, "x" + "\u00e9" * 126):
        hidden = temporary_name(name)
        assert len(hidden.encode()) <= 255 and hidden.startswith(f".{name[:20]}") and hidden.endswith(".tmp")
        hidden.encode()  # no character cut in half (it would not encode)
    assert temporary_name("h.csv").startswith(".h.csv.")


def test_an_output_name_longer_than_the_folder_takes_is_refused_before_any_work(tmp_path: Path) -> None:
    # a 253-byte .pq log into parquet outputs: out/NAME.parquet is 258 bytes, and the file failed
    # after its work with [Errno 36] File name too long
    import pyarrow.parquet as pq
    import pyarrow.csv as pa_csv

    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    long = logs / ("b" * 250 + ".pq")
    pq.write_table(pa_csv.read_csv(synthetic_csv(tmp_path / "x.csv", 300)), long)
    with pytest.raises(ValueError, match=rf"^{long}: its output's name, b+\.parquet, is 258 bytes long, and {out} "
                                         r"takes names of 255 at most; give the input a shorter name"):
        process_many([logs, tmp_path / "x.csv"], out_dir=out, fmt="parquet", preset="raw")
    assert not out.exists()


def _cli_where_one_folder_has_two_names(folder: Path, other: Path, *args: str | Path) -> subprocess.CompletedProcess[str]:
    """``gyrocore ARGS`` where ``other`` is ``folder`` under another name, which ``os.path.realpath``
    does not unify, as ``Logs`` is ``logs`` on a filesystem that ignores case: a bind mount, in a
    mount namespace of the test's own (Linux, no root needed where user namespaces are allowed)."""
    if shutil.which("unshare") is None:
        pytest.skip("no unshare here")
    other.mkdir()
    mount = 'mount --bind "$1" "$2" || exit 99; shift 2; exec "$@"'
    proc = subprocess.run(["unshare", "-Urm", "sh", "-c", mount, "sh", str(folder), str(other),
                           sys.executable, "-m", "gyrocore.cli", *map(str, args)], capture_output=True, text=True)
    if proc.returncode == 99 or "unshare:" in proc.stderr:
        pytest.skip(f"no bind mount in a namespace of its own here: {proc.stderr.strip()}")
    assert "Traceback" not in proc.stderr
    return proc


def test_an_output_inside_a_log_folder_under_another_name_is_refused(tmp_path: Path) -> None:
    # on macOS, --out DRIVE/reference.csv for the log folder drive: realpath keeps the case given,
    # the output was not seen inside the input, and with --overwrite the log's reference was
    # replaced by its heading table (t,heading,rate,drift), reported ok
    drive = tmp_path / "drive"
    drive.mkdir()
    synthetic_csv(drive / "gyro.csv", 300)
    (drive / "reference.csv").write_text("t,heading\n1700000000,0\n1700000001,0.1\n")
    before = (drive / "reference.csv").read_bytes()
    proc = _cli_where_one_folder_has_two_names(drive, tmp_path / "DRIVE", "process", drive, "--out",
                                               tmp_path / "DRIVE" / "reference.csv", "--overwrite", "--preset", "raw")
    assert proc.returncode == 2, proc.stdout
    assert proc.stderr == (f"gyrocore: error: refusing to write {tmp_path / 'DRIVE' / 'reference.csv'} over or inside "
                           f"the input {drive}; write it elsewhere\n")
    assert (drive / "reference.csv").read_bytes() == before


def test_an_output_folder_that_is_an_input_folder_under_another_name_is_refused(tmp_path: Path) -> None:
    logs = tmp_path / "logs"
    logs.mkdir()
    a = synthetic_csv(logs / "a.csv", 300)
    proc = _cli_where_one_folder_has_two_names(logs, tmp_path / "LOGS", "process", a, "--out", tmp_path / "LOGS",
                                               "--overwrite", "--preset", "raw")
    assert proc.returncode == 2, proc.stdout
    assert proc.stderr.startswith(f"gyrocore: error: refusing to write into {tmp_path / 'LOGS'}: it holds the input {a}")
    assert [p.name for p in logs.iterdir()] == ["a.csv"]


def test_a_name_with_a_line_break_is_reported_on_one_line(tmp_path: Path) -> None:
    # "ok     logs/a" and "b.csv: 300 rows in, 300 out -> out/a" were two lines of the report
    logs, out = tmp_path / "logs", tmp_path / "out"
    logs.mkdir()
    synthetic_csv(logs / "a\nb.csv", 300)
    summary = process_many([logs], out_dir=out, preset="raw")
    assert [p.name for p in out.iterdir()] == ["a\nb.csv"]
    first = str(summary).splitlines()[0]
    assert first.startswith(f"ok     {logs}/a\\nb.csv: 300 rows in, 300 out -> {out}/a\\nb.csv (")
    summary = process_many([logs], out_dir=out, preset="raw", skip_existing=True)
    assert str(summary).splitlines()[0] == f"skipped {logs}/a\\nb.csv: {out}/a\\nb.csv exists already"


def test_evaluate_refuses_plots_one_in_case_where_the_folder_ignores_case(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    # evaluate --plot-dir of Drive.csv and drive.csv: drive.png replaced Drive.png on macOS
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    rows = "t,gyro_z,heading_true\n" + "".join(f"{k / 100},0.01,{k / 10000}\n" for k in range(500))
    a, b = tmp_path / "one" / "Drive.csv", tmp_path / "two" / "drive.csv"
    a.write_text(rows)
    b.write_text(rows)
    plots = tmp_path / "plots"
    _ignores_case(monkeypatch)
    assert main(["evaluate", str(a), str(b), "--preset", "raw", "--plot-dir", str(plots)]) == 2
    assert capsys.readouterr().err == (f"gyrocore: error: --plot-dir: {a} and {b} would both be plotted to "
                                       f"{plots / 'Drive.png'}: {plots} ignores case, and holds Drive.png and "
                                       "drive.png as one file; plot them in separate runs\n")
    assert not plots.exists()

"""A fleet's outputs in a messy output folder: no input and no other output is written over, and a
scheduler that is no Dask scheduler is named, not waited on."""

from __future__ import annotations

import os
import re
import socket
import stat
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from gyrocore.batch import process_many

from .conftest import gyrocore_cli
from .test_batch import leftovers, synthetic_csv


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


@contextmanager
def _not_a_scheduler(answer: bytes) -> Iterator[str]:
    """The address of a server of another kind: it takes connections and answers each with
    ``answer`` (nothing: it waits, as a web server does for a request it can read)."""
    server = socket.create_server(("127.0.0.1", 0))
    held: list[socket.socket] = []

    def serve() -> None:
        while True:
            try:
                conn, _ = server.accept()
            except OSError:  # closed
                return
            held.append(conn)
            conn.sendall(answer)

    threading.Thread(target=serve, daemon=True).start()
    try:
        yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    finally:
        server.close()
        for conn in held:
            conn.close()


@pytest.mark.parametrize("answer, said", [
    # distributed of early 2023 (2023.1) waits for the greeting within its connect timeout, 1 s
    # here; later ones wait without a limit, and gyrocore gives it twice that
    (b"", "no greeting in (1|2) s"),
    (b"HTTP/1.1 400 Bad Request\r\n\r\n", "an answer Dask cannot read: MemoryError"),
])
def test_a_scheduler_address_where_another_server_answers_is_named_not_waited_on(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, answer: bytes, said: str) -> None:
    # Dask's Client waits for the greeting without a limit: a server that does not answer held
    # the command for ever, and one whose answer reads as a huge length failed with a traceback
    # (numpy's "Unable to allocate 3.07 EiB")
    pytest.importorskip("dask.distributed")
    monkeypatch.setenv("DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT", "1s")
    log = synthetic_csv(tmp_path / "a.csv", 300)
    with _not_a_scheduler(answer) as address:
        proc = gyrocore_cli("process", log, "--scheduler", address, "--out", tmp_path / "out", code=2, timeout=40)
    assert re.fullmatch(re.escape(f"gyrocore: error: something answered at {address!r}, but not as a Dask scheduler (")
                        + said + re.escape(f"); check that {address!r} is the scheduler's address as `dask scheduler` "
                                           "prints it (tcp://host:8786; the dashboard's http://host:8787 is another); "
                                           "without a scheduler the files run on this machine's cores"),
                        proc.stderr.splitlines()[-1])
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("fmt, columns", [("csv", None), ("parquet", None), ("csv", ("t", "heading"))])
def test_an_earlier_runs_output_given_as_input_is_named_as_one(tmp_path: Path, fmt: str,
                                                               columns: tuple[str, ...] | None) -> None:
    # a pattern or folder that reached an earlier run's outputs failed each with "missing column(s)
    # gyro_z; ... (choose with time_col/rate_col, --time-col/--rate-col)", which led to processing
    # the output again, its corrected rate taken for the gyro's
    log = synthetic_csv(tmp_path / "a.csv", 300)
    process_many([log], out_dir=tmp_path / "first", fmt=fmt, preset="raw", columns=columns)
    report = process_many([tmp_path / "first"], out_dir=tmp_path / "second", preset="raw")
    header = ", ".join(columns or ("t", "heading", "rate", "drift"))
    assert report.files[0].error == (
        f"{tmp_path / 'first' / f'a.{fmt}'}: missing column(s) gyro_z; it has {header}, the columns of a heading "
        "table gyrocore writes: give the log it was made from (inputs that reach an earlier run's output folder: "
        "leave that folder out), or for a gyro's log of these columns choose with time_col/rate_col, "
        "--time-col/--rate-col")


@pytest.mark.parametrize("pattern, out, reached", [
    ("logs/*", "logs/out", "logs/out"),
    ("logs/**/*.csv", "logs/out", "logs/out/a.csv"),
    ("logs/*.csv", "logs/h.csv", "logs/h.csv"),
])
def test_an_output_a_pattern_reaches_is_refused_before_the_first_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                                     pattern: str, out: str, reached: str) -> None:
    # the first run went through, and the same command again, --skip-existing to go on after an
    # interruption, was refused (`refusing to write logs/out over or inside the input logs/out`)
    # or read the outputs as logs
    monkeypatch.chdir(tmp_path)
    Path("logs").mkdir()
    synthetic_csv(Path("logs/a.csv"), 300)
    proc = gyrocore_cli("process", pattern, "--out", out, "--preset", "raw", code=2)
    assert proc.stderr == (f"gyrocore: error: refusing to write {reached}: the pattern {pattern!r} reaches it, and the "
                           "same run again (--skip-existing to go on after an interruption, --overwrite) would read "
                           "the outputs as logs; write them where the pattern does not reach\n")
    assert sorted(p.name for p in Path("logs").iterdir()) == ["a.csv"]
    if out == "logs/out":
        with pytest.raises(ValueError, match=f"^refusing to write {reached}: the pattern"):
            process_many([pattern], out_dir=out, preset="raw")


def test_an_output_folder_a_pattern_does_not_reach_is_taken(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("logs").mkdir()
    synthetic_csv(Path("logs/a.csv"), 300)
    for again in ((), ("--skip-existing",)):
        gyrocore_cli("process", "logs/*.csv", "--out", "logs/h", "--preset", "raw", *again, code=0)
    assert sorted(p.name for p in Path("logs/h").iterdir()) == ["a.csv"]


def test_an_output_name_linked_to_a_file_an_option_names_is_refused(tmp_path: Path) -> None:
    # out/a.csv -> ../p.json: the parameter file --params read was replaced by a heading table
    from gyrocore.tune_params import ParameterSet

    a, _, out = _two_logs(tmp_path)
    params = tmp_path / "p.json"
    ParameterSet("mine", "raw", {}).write(params)
    (out / "a.csv").symlink_to(Path("..") / "p.json")
    before = params.read_bytes()
    proc = gyrocore_cli("process", a.parent, "--out", out, "--params", params, "--overwrite", code=2)
    assert proc.stderr.splitlines()[-1] == (
        f"gyrocore: error: refusing to write {out / 'a.csv'} over or inside the input {params} ({out / 'a.csv'} is a "
        "symbolic link to '../p.json'); remove the link, or write the outputs elsewhere")
    assert params.read_bytes() == before


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes")
@pytest.mark.parametrize("linked", [False, True])
def test_overwrite_never_replaces_a_named_pipe_or_device(tmp_path: Path, linked: bool) -> None:
    # the staged file was renamed over it: a link to /dev/null, written by root, replaced the
    # device node with a heading table (a named pipe stands in for the device here)
    a, _, out = _two_logs(tmp_path)
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    given = tmp_path / "h.csv"
    if linked:
        given.symlink_to(pipe)
    else:
        given = pipe.rename(given)
    fifo = pipe if linked else given

    def said(name: Path, leads: bool) -> str:
        where = f" (where its symbolic link leads, {fifo})" if leads else ""
        return f"{name}: a named pipe, socket or device{where}, not a file; an output replaces files only: write it elsewhere"

    proc = gyrocore_cli("process", a, "--out", given, "--overwrite", "--preset", "raw", code=2)
    assert proc.stderr.splitlines()[-1] == f"gyrocore: error: {said(given, linked)}"
    (out / "a.csv").symlink_to(fifo)
    report = process_many([a], out_dir=out, preset="raw")  # replaces outputs: the file fails alone
    assert report.files[0].error == said(out / "a.csv", True)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


@pytest.mark.parametrize("options", [{}, {"bias_duration": 5.0}])
def test_an_interrupted_batch_stops_a_file_in_its_first_pass(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                             options: dict[str, float]) -> None:
    # the batch's stop was checked by the streamed pass alone: after Ctrl-C the batch waited for
    # the first pass over each running file, which reads the whole log to find its rests (4.6 s
    # for two CSV files of 6e6 samples), before the file stopped
    from gyrocore import batch_run, io

    log = synthetic_csv(tmp_path / "a.csv", 3000)
    stop, read = threading.Event(), []
    chunks = io.GyroSource.chunks

    def counted(self: io.GyroSource, rows: int = io.DEFAULT_CHUNK_ROWS) -> Iterator[io.Chunk]:
        for chunk in chunks(self, rows):
            read.append(len(chunk))
            if len(read) == 3:  # Ctrl-C while the third chunk of the first pass is read
                stop.set()
            yield chunk

    monkeypatch.setattr(io.GyroSource, "chunks", counted)
    job = batch_run._FileJob(log, tmp_path / "h.csv", "recommended", "enu", 100, dict(options))
    report = batch_run._run_job(job, stop)
    assert "stopped before the end" in (report.error or "") and len(read) == 3
    assert not (tmp_path / "h.csv").exists() and leftovers(tmp_path) == []


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_a_file_name_that_is_not_utf8_is_read_and_written(tmp_path: Path, fmt: str) -> None:
    # a logger's FAT card written in Latin-1: pyarrow encoded the name itself and failed, "'utf-8'
    # codec can't encode character '\udce9' in position 5: surrogates not allowed"
    import pyarrow.csv as pa_csv
    import pyarrow.parquet as pq

    logs = tmp_path / "logs"
    logs.mkdir()
    written = synthetic_csv(logs / "a.csv", 300)
    pq.write_table(pa_csv.read_csv(written), logs / "a.parquet")
    try:
        for name in ("caf\xe9.csv", "th\xe9.parquet"):
            (logs / ("a" + Path(name).suffix)).rename(logs / os.fsdecode(name.encode("latin-1")))
    except (OSError, UnicodeError):
        pytest.skip("this filesystem takes UTF-8 names only")
    report = process_many([logs], out_dir=tmp_path / "out", fmt=fmt, preset="raw")
    assert [(Path(r.input).name, r.error, r.rows_out) for r in report.files] == [
        (os.fsdecode(b"caf\xe9.csv"), None, 300), (os.fsdecode(b"th\xe9.parquet"), None, 300)]
    assert sorted(os.listdir(os.fsencode(tmp_path / "out"))) == [b"caf\xe9." + fmt.encode(), b"th\xe9." + fmt.encode()]


def test_a_pattern_through_a_folder_named_with_brackets_says_how_to_match_them(tmp_path: Path) -> None:
    # "run[1]/*.csv: no such file or folder, and no file matches it", beside the folder run[1]:
    # the brackets are a set of characters, which matched run1 alone
    folder = tmp_path / "run[1]"
    folder.mkdir()
    synthetic_csv(folder / "a.csv", 300)
    pattern, literal = f"{folder}/*.csv", f"{tmp_path}/run[[]1]/*.csv"
    with pytest.raises(ValueError, match=re.escape(
            f"{pattern}: no such file or folder, and no file matches it; in a pattern, brackets are a set of "
            f"characters ([1] matches 1): give {literal!r} to match the brackets in a name")):
        process_many([pattern], out_dir=tmp_path / "out", preset="raw")
    assert process_many([literal], out_dir=tmp_path / "out", preset="raw").files[0].rows_out == 300

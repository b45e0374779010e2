"""A file's reading and a heading table being written, used from several threads: a second thread's
call is refused with ``InUseError`` naming the object, and the first thread's reading or table
comes out whole (issue: chunks taken by two threads from one reading were split between them
without a word, and two threads' writes mixed their rows in one file)."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrocore
from gyrocore import InUseError, io
from gyrocore.io import writer as writer_module

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pa_csv = pytest.importorskip("pyarrow.csv")

N = 5000


def _sources(folder: Path) -> dict[str, Path]:
    """One log as CSV, Parquet and .npy (the rows of each the same)."""
    t = np.arange(N) * 0.01
    rate = 0.01 * np.sin(t)
    paths = {"csv": folder / "a.csv", "parquet": folder / "a.parquet", "npy": folder / "a.npy"}
    np.savetxt(paths["csv"], np.column_stack([t, rate]), delimiter=",", header="t,gyro_z", comments="", fmt="%.17g")
    pq.write_table(pa.table({"t": t, "gyro_z": rate}), paths["parquet"])
    np.save(paths["npy"], np.column_stack([t, rate]))
    return paths


def _on_thread(work: Callable[[], Any]) -> tuple[threading.Thread, list[Any]]:
    done: list[Any] = []
    runner = threading.Thread(target=lambda: done.append(work()))
    runner.start()
    return runner, done


@pytest.mark.parametrize("kind", ["csv", "parquet", "npy"])
def test_a_second_thread_on_one_reading_is_refused_and_the_first_reads_every_row(kind: str, tmp_path: Path) -> None:
    path = _sources(tmp_path)[kind]
    reading = io.open_source(path).chunks(1000)
    took, go_on = threading.Event(), threading.Event()

    def read_all() -> np.ndarray:
        t = []
        for chunk in reading:
            t.append(chunk.t)
            took.set()
            assert go_on.wait(30)
        return np.concatenate(t)

    runner, done = _on_thread(read_all)
    assert took.wait(30)
    try:
        for call in (lambda: next(reading), reading.close, lambda: list(reading)):
            with pytest.raises(InUseError, match=rf"^this reading of {path} is in use by another thread \(its "
                               r"GyroSource\.chunks\(\) runs there\): a reading gives its chunks in order to the "
                               r"thread that began it; give each thread its own"):
                call()
    finally:
        go_on.set()
        runner.join()
    assert np.array_equal(done[0], np.arange(N) * 0.01)
    # ended, it holds nothing: another thread finds its end
    other, after = _on_thread(lambda: list(reading))
    other.join()
    assert after == [[]]


def test_each_thread_s_own_reading_of_one_source_reads_the_whole_file(tmp_path: Path) -> None:
    source = io.open_source(_sources(tmp_path)["csv"])
    threads = [_on_thread(lambda: sum(len(c) for c in source.chunks(700))) for _ in range(3)]
    for runner, _ in threads:
        runner.join()
    assert [done for _, done in threads] == [[N]] * 3


@pytest.fixture
def held_write(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[threading.Event, threading.Event]]:
    """The first write waits, once its result is converted, until released: the writer is then
    in use by that write's thread."""
    entered, release = threading.Event(), threading.Event()
    convert = writer_module.convert_heading

    def held(result: gyrocore.HeadingResult, convention: str = "enu") -> gyrocore.HeadingResult:
        if not entered.is_set():
            entered.set()
            assert release.wait(30)
        return convert(result, convention)

    monkeypatch.setattr(writer_module, "convert_heading", held)
    yield entered, release
    release.set()


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_a_second_thread_on_one_heading_writer_is_refused_and_the_first_write_is_whole(
        suffix: str, tmp_path: Path, held_write: tuple[threading.Event, threading.Event]) -> None:
    entered, release = held_write
    t = np.arange(N) * 0.01
    result = gyrocore.Pipeline("raw").process(t, 0.01 * np.sin(t))
    out = tmp_path / f"h{suffix}"
    with io.HeadingWriter(out) as writer:
        runner, _ = _on_thread(lambda: writer.write(result))
        assert entered.wait(30)
        try:
            with pytest.raises(InUseError, match=rf"^this gyrocore\.io\.HeadingWriter of {out} is in use by another "
                               r"thread \(its HeadingWriter\.write\(\) runs there\): a table takes one write at a "
                               r"time, its rows in order; hold a lock around its calls, or give each thread its own"):
                writer.write(result)
            with pytest.raises(InUseError, match="HeadingWriter.write"):
                writer.__exit__(None, None, None)
        finally:
            release.set()
            runner.join()
    assert writer.rows == N
    table = pq.read_table(out) if suffix == ".parquet" else pa_csv.read_csv(out)
    assert np.array_equal(table.column("t").to_numpy(), t)
    assert np.array_equal(table.column("heading").to_numpy(), result.heading)

"""``io.HeadingWriter`` used outside its block, twice, or given columns of other dtypes and lengths:
a Parquet table took rows written after its block into nothing (counted, not written) and rows
before it silently; a CSV table said "'NoneType' object has no attribute 'write'", failed on a
float32 column that Parquet took (``type mismatch``), and a column of another length was named by
neither format; leaving the block twice raised ``FileNotFoundError`` of the hidden temporary file,
and entering it again orphaned the first one."""

from __future__ import annotations

import dataclasses
import gc
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import io

pq = pytest.importorskip("pyarrow.parquet")
pa_csv = pytest.importorskip("pyarrow.csv")

SUFFIXES = [".csv", ".parquet"]


def _result(n: int = 100) -> gyrocore.HeadingResult:
    t = np.arange(n) * 0.01
    return gyrocore.Pipeline("raw").process(t, np.full(n, 0.01))


def _table(path: Path) -> dict[str, np.ndarray]:
    table = pq.read_table(path) if path.suffix == ".parquet" else pa_csv.read_csv(path)
    return {name: table.column(name).to_numpy() for name in table.column_names}


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_a_write_outside_the_block_is_refused_and_the_table_is_as_written_in_it(suffix: str, tmp_path: Path) -> None:
    out, r = tmp_path / f"h{suffix}", _result()
    writer = io.HeadingWriter(out)
    with pytest.raises(ValueError, match=r"HeadingWriter\.write\(\) before its table was opened: write in its block"):
        writer.write(r)
    with writer:
        writer.write(r)
    with pytest.raises(ValueError, match=r"HeadingWriter\.write\(\) after its table was closed \(100 rows\): a writer "
                                         "writes one table"):
        writer.write(r)
    assert writer.rows == 100 and np.array_equal(_table(out)["t"], r.t)
    writer.__exit__(None, None, None)  # left twice: nothing more, as a file closed twice
    with pytest.raises(ValueError, match="entered already"):
        writer.__enter__()
    assert sorted(p.name for p in tmp_path.iterdir()) == [out.name]  # no hidden file left
    with pytest.raises(ValueError, match="left before it was entered"):
        io.HeadingWriter(tmp_path / f"other{suffix}").__exit__(None, None, None)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_columns_of_other_real_dtypes_are_written_as_float64_in_both_formats(suffix: str, tmp_path: Path) -> None:
    r = _result()
    given = dataclasses.replace(r, t=np.arange(100), heading=r.heading.astype(np.float32), rate=list(r.rate))
    out = tmp_path / f"h{suffix}"
    with io.HeadingWriter(out) as writer:
        writer.write(given)
    table = _table(out)
    assert np.array_equal(table["t"], np.arange(100.0))
    assert np.array_equal(table["heading"], r.heading.astype(np.float32).astype(np.float64))
    assert np.array_equal(table["rate"], r.rate)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_a_column_of_another_length_is_named_and_nothing_of_its_result_written(suffix: str, tmp_path: Path) -> None:
    r = _result()
    out = tmp_path / f"h{suffix}"
    with io.HeadingWriter(out) as writer:
        writer.write(r)
        with pytest.raises(ValueError, match=r"the result's heading has 50 values, its t 100: a table takes one value "
                                             r"of each column per sample \(nothing of this result was written\)"):
            writer.write(dataclasses.replace(r, heading=r.heading[:50]))
        with pytest.raises(TypeError, match="takes a HeadingResult .* got dict"):
            writer.write(r.columns())  # type: ignore[arg-type]
        writer.write(r)
    assert writer.rows == 200 and len(_table(out)["t"]) == 200


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_a_writer_entered_by_hand_and_never_left_keeps_no_temporary_file(suffix: str, tmp_path: Path) -> None:
    # a notebook's cell that entered the block by hand and lost the writer: its hidden temporary
    # file stayed in the output's folder for good; nothing of the output is written
    out = tmp_path / f"h{suffix}"
    writer = io.HeadingWriter(out).__enter__()
    writer.write(_result())
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] != []
    del writer
    gc.collect()  # the Parquet writer's own cycles, if any
    assert list(tmp_path.iterdir()) == []


def test_a_script_that_ends_with_its_writer_open_keeps_no_temporary_file(tmp_path: Path) -> None:
    # the object outlives the script's last line (a module global): the exit removes its file
    out = tmp_path / "h.csv"
    script = ("import sys, numpy as np, gyrocore\nfrom gyrocore import io\n"
              "w = io.HeadingWriter(sys.argv[1]).__enter__()\n"
              "w.write(gyrocore.Pipeline('raw').process(np.arange(10) * 0.01, np.zeros(10)))\n"
              "print(len(list(io.atomic._live)))\n")
    done = subprocess.run([sys.executable, "-c", script, str(out)], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert done.returncode == 0, done.stderr
    assert done.stdout == "1\n"  # the file was there while the script ran
    assert list(tmp_path.iterdir()) == []

"""Files at the edges of the readers: lines longer than a block (a long text in an ignored column,
a long header) read the same with any --chunk-rows; a header without samples is an error."""

from __future__ import annotations

import gzip
import re
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import gyrocore
from gyrocore.io import CSV_BLOCK_BYTES, _csvfile

from .conftest import gyrocore_cli as run_cli

N = 200


def expected_t() -> np.ndarray:
    return np.arange(N) * 0.01


def long_field_csv(path: Path) -> Path:
    """A 2 MB note (twice the reader's largest block) in a column that is not read, on line 52."""
    with open(path, "w") as f:
        f.write("t,gyro_z,note\n")
        for i, t in enumerate(expected_t()):
            f.write(f"{float(t)!r},0.01,{'x' * 2_000_000 if i == 50 else 'ok'}\n")
    return path


def long_header_csv(path: Path) -> Path:
    """A header of 1.3 MB (120,000 columns), longer than any block."""
    names = ",".join(f"extra{i}" for i in range(120_000))
    with open(path, "w") as f:
        f.write(f"t,gyro_z,{names}\n")
        empty = "," * 120_000
        for t in expected_t():
            f.write(f"{float(t)!r},0.01{empty}\n")
    return path


@pytest.mark.parametrize("make", [long_field_csv, long_header_csv])
def test_lines_longer_than_a_block_read_with_any_chunk_size(tmp_path: Path, make: Callable[[Path], Path]) -> None:
    src = make(tmp_path / "in.csv")
    assert max(map(len, src.read_bytes().split(b"\n"))) > CSV_BLOCK_BYTES
    outputs = []
    for chunk_rows in ("1", "7", "65536"):
        out = tmp_path / f"h{chunk_rows}.csv"
        proc = run_cli("process", src, "--out", out, "--preset", "raw", "--chunk-rows", chunk_rows)
        assert proc.returncode == 0, proc.stderr
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1] == outputs[2]
    assert np.array_equal(gyrocore.read_log(src).t, expected_t())


def test_a_bad_value_after_a_long_line_is_still_located(tmp_path: Path) -> None:
    src = long_field_csv(tmp_path / "in.csv")
    lines = src.read_bytes().split(b"\n")
    lines[120] = b"1.19,abc,ok"
    src.write_bytes(b"\n".join(lines))
    proc = run_cli("process", src, "--out", tmp_path / "h.csv", "--chunk-rows", "10")
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {src}: line 121, column 2 (gyro_z): 'abc' is not a number\n"


@pytest.mark.parametrize("suffix", [".csv", ".csv (no line end)", ".npy", ".npz", ".parquet"])
def test_a_header_without_samples_is_an_error(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"empty{suffix.split()[0]}"
    if suffix == ".csv":
        path.write_text("t,gyro_z\n")
    elif suffix.startswith(".csv"):
        path.write_text("t,gyro_z")
    elif suffix == ".npy":
        np.save(path, np.zeros((0, 2)))
    elif suffix == ".npz":
        np.savez(path, t=np.zeros(0), gyro_z=np.zeros(0))
    else:
        pq.write_table(pa.table({"t": pa.array([], pa.float64()), "gyro_z": pa.array([], pa.float64())}), path)
    with pytest.raises(ValueError, match=f"^{path}: no samples$"):
        gyrocore.read_log(path)
    proc = run_cli("process", path, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2 and proc.stderr == f"gyrocore: error: {path}: no samples\n"


def test_a_first_line_longer_than_any_read_is_refused_without_reading_it_whole(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the header was read up to the first line end however far: a file of gigabytes without one
    # took three times its size in memory before the line was refused
    monkeypatch.setattr(_csvfile, "MAX_LINE_BYTES", 1 << 20)
    path = tmp_path / "one_line.csv"
    path.write_bytes(b"t,gyro_z," + b"x" * (32 << 20))
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=rf"^{re.escape(str(path))}: line 1 is longer than 1048576 bytes, the longest read$"):
            gyrocore.read_log(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 8 << 20


def test_a_compressed_file_named_csv_is_refused_without_printing_its_bytes(tmp_path: Path) -> None:
    path = tmp_path / "drive.csv"
    path.write_bytes(gzip.compress(b"t,gyro_z\n0,0\n0.01,0\n"))
    proc = run_cli("process", path, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr == (
        f"gyrocore: error: {path}: not a text CSV file (binary data on line 1; decompress a .gz file first)\n"
    )


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-be", "utf-32"])
def test_a_csv_in_utf16_is_named_as_such(tmp_path: Path, encoding: str) -> None:
    # its zero bytes read as binary data, and the error said to decompress the file
    path = tmp_path / "excel.csv"
    text = "t,gyro_z\n0,0.1\n0.01,0.1\n"
    path.write_bytes(text.encode(encoding) if encoding != "utf-16-be" else b"\xfe\xff" + text.encode(encoding))
    with pytest.raises(ValueError, match=rf"^{re.escape(str(path))}: text in UTF-16 \(or UTF-32\), not UTF-8: save it as UTF-8$"):
        gyrocore.read_log(path)


def gyro_text() -> str:
    return "t,gyro_z\n" + "".join(f"{float(t)!r},0.01\n" for t in expected_t())


REFERENCE_TEXT = "t,heading,x,y\n0,0.1,0,0\n1,0.2,1,0\n2,0.3,2,0\n"
FIXES_TEXT = "t,heading,sigma\n0,0.1,0.05\n1,0.2,0.05\n"


@pytest.mark.parametrize("tail", ["\n", "\n\n", "\r\n\r\n", "\n\n\n\n\n"])
def test_blank_lines_at_the_end_of_a_csv_are_read_as_its_end(tmp_path: Path, tail: str) -> None:
    # an editor's extra line end carries no data, as numpy.loadtxt and pandas read it; it was
    # "line 202, column 1 (t): blank line" (an empty value in a reference or fixes file)
    gyro = tmp_path / "gyro.csv"
    gyro.write_bytes((gyro_text() + tail).encode())
    np.testing.assert_array_equal(gyrocore.read_log(gyro).t, expected_t())
    reference = tmp_path / "reference.csv"
    reference.write_bytes((REFERENCE_TEXT + tail).encode())
    assert gyrocore.io.read_reference_file(reference)["heading"].tolist() == [0.1, 0.2, 0.3]
    fixes = tmp_path / "fixes.csv"
    fixes.write_bytes((FIXES_TEXT + tail).encode())
    assert len(gyrocore.fixes.read_fixes_csv(fixes).t) == 2


def test_a_blank_line_before_the_last_sample_is_an_error_naming_it(tmp_path: Path) -> None:
    # a blank line inside the data may be a lost sample: never skipped (a reference's was an "empty value")
    reference = tmp_path / "reference.csv"
    reference.write_text("t,heading\n0,0.1\n\n2,0.3\n\n")
    with pytest.raises(ValueError, match=rf"^{re.escape(str(reference))}: line 3, column 1 \(t\): blank line$"):
        gyrocore.io.read_reference_file(reference)


COMMENTS = "# recorded 2024-05-01 on the test car\n# sensor: CRS03, 100 Hz, rates in rad/s\n"


@pytest.mark.filterwarnings("ignore:.*read as a file alone")  # a gyro.csv beside the other files
def test_comment_lines_before_the_header_are_skipped_and_lines_still_counted(tmp_path: Path) -> None:
    # it was "missing column(s) t, gyro_z; it has # recorded 2024-05-01 on the test car"
    gyro = tmp_path / "gyro.csv"
    gyro.write_text(COMMENTS + gyro_text())
    np.testing.assert_array_equal(gyrocore.read_log(gyro).t, expected_t())
    reference = tmp_path / "reference.csv"
    reference.write_text(COMMENTS + REFERENCE_TEXT)
    assert gyrocore.io.read_reference_file(reference)["t"].tolist() == [0.0, 1.0, 2.0]
    fixes = tmp_path / "fixes.csv"
    fixes.write_text(COMMENTS + FIXES_TEXT)
    assert len(gyrocore.fixes.read_fixes_csv(fixes).t) == 2
    # lines are the file's lines, comments counted
    reference.write_text(COMMENTS + "t,heading\n0,0.1\n1,nan\n")
    with pytest.raises(ValueError, match=r"reference\.csv: line 5, column 2 \(heading\): nan"):
        gyrocore.io.read_reference_file(reference)
    gyro.write_text(COMMENTS + "t,gyro_z\n0,0.1\n0.01,abc\n")
    with pytest.raises(ValueError, match=r"gyro\.csv: line 5, column 2 \(gyro_z\): 'abc' is not a number"):
        gyrocore.read_log(gyro)
    gyro.write_text(COMMENTS + "t,gyro_z\n" + "".join(f"{i / 100},0.01\n" for i in range(100)) + "1,nan\n")
    proc = run_cli("process", gyro, "--out", tmp_path / "h.csv", "--preset", "raw")
    assert proc.returncode == 2 and f"({gyro}, line 104)" in proc.stderr, proc.stderr


def test_a_header_that_starts_with_a_hash_is_still_the_header(tmp_path: Path) -> None:
    # EuRoC's "#timestamp [ns],w_RS_S_x ..." is its header: the line after it is a sample
    gyro = tmp_path / "data.csv"
    gyro.write_text("# EuRoC MAV\n#timestamp [ns],gyro_z\n" + "".join(f"{i * 10**7},0.01\n" for i in range(N)))
    np.testing.assert_allclose(gyrocore.read_log(gyro, time_col="timestamp").t, expected_t())


@pytest.mark.filterwarnings("ignore:.*read as a file alone")  # a gyro.csv beside the other files
def test_a_csv_not_in_utf8_names_the_line_and_byte(tmp_path: Path) -> None:
    # a Latin-1 degree sign (byte 0xB0) was shown as U+FFFD in "missing column(s) ...; it has ..."
    gyro = tmp_path / "gyro.csv"
    gyro.write_bytes("t,gyro_z [°/s]\n0,1\n".encode("latin-1"))
    message = (f"{gyro}: line 1: not UTF-8 (byte 0xb0 at byte offset 10 of the file): save it as UTF-8, "
               "e.g. iconv -f latin1 -t utf-8 old.csv > new.csv")
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        gyrocore.read_log(gyro)
    reference = tmp_path / "reference.csv"
    reference.write_bytes(b"# r\xe9f\xe9rence\nt,heading [\xb0]\n0,1\n")
    with pytest.raises(ValueError, match=rf"^{re.escape(str(reference))}: line 2: not UTF-8 \(byte 0xb0 at byte offset 23 "):
        gyrocore.io.read_reference_file(reference)
    # in a sample's value, the byte was shown as U+FFFD in "is not a number", with no word of why
    gyro.write_bytes(b"t,gyro_z\n0,0.1\n0.01,0.1\xb0\n0.02,0.1\n")
    with pytest.raises(ValueError, match=r"line 3, column 2 \(gyro_z\): '0.1\ufffd' is not a number \(bytes that are not "
                       r"UTF-8: save the file as UTF-8, e\.g\. iconv"):
        gyrocore.read_log(gyro)


@pytest.mark.parametrize(("rows", "header"), [("0,0.1\n0.01,0.1\n0.02,0.1\n", "t,gyro_z"),
                                              ("0,0.1,5\n0.01,0.1,5\n", "t,gyro_z,col3")])
def test_a_csv_without_a_header_line_is_said_to_have_none(tmp_path: Path, rows: str, header: str) -> None:
    # "missing column(s) t, gyro_z; it has 0, 0.1" left the cause to guess
    path = tmp_path / "bare.csv"
    path.write_text(rows)
    with pytest.raises(ValueError, match=re.escape("its first line holds numbers, not column names: the file has no "
                                                   f"header line; add one as its first line, e.g. {header})")):
        gyrocore.read_log(path)
    path.write_text(f"{header}\n{rows}")  # what it says to do reads the file
    assert len(gyrocore.read_log(path).t) == rows.count("\n")

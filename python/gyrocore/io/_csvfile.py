"""Reading CSV files: pyarrow's streaming reader, and the line and column of a malformed value.

A CSV file has a header line, then one sample per line. pyarrow parses it block by block on its own
thread; when it rejects a value, the file is read again from that block with Python's csv module to
find the line and column, which pyarrow's message does not name.
"""

from __future__ import annotations

import csv
import io as _io
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import FloatArray
from .._extras import require
from ._columns import CHOOSE_COLUMNS, column_positions, concat, first_null, import_pyarrow_lazy_modules

if TYPE_CHECKING:
    import pyarrow as pa

    from .source import GyroSource

#: Bytes of CSV text parsed at a time. pyarrow's streaming reader reads about 32 blocks ahead, so
#: this sets the reader's memory (1 MiB: about 40 MB, and the fastest size measured).
CSV_BLOCK_BYTES = 1 << 20
#: The longest CSV line read [bytes]; pyarrow reads a few blocks of this size ahead.
MAX_LINE_BYTES = 1 << 28
_FIELD_LIMIT_LOCK = threading.Lock()
_GZIP = b"\x1f\x8b"
#: Byte order marks of UTF-16 (and UTF-32, which begins like it), as Excel's "Unicode Text" and
#: Windows PowerShell's ``>`` write text.
_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")
_UTF8_BOM = b"\xef\xbb\xbf"


def _csv_header(path: Path, delimiter: str) -> list[str]:
    with open(path, "rb") as f:
        line = f.readline(MAX_LINE_BYTES + 1)  # bounded: a file of gigabytes without a line end
    if not line.removeprefix(_UTF8_BOM).strip():  # an empty file that an editor saved with its BOM too
        raise ValueError(f"{path}: line 1: no header line (expected column names)")
    if line.startswith(_UTF16_BOMS):
        raise ValueError(f"{path}: text in UTF-16 (or UTF-32), not UTF-8: save it as UTF-8")
    if line.startswith(_GZIP) or any(b < 32 and b not in b"\t\r\n" for b in line[:4096]):
        # naming the columns would print the binary bytes
        raise ValueError(f"{path}: not a text CSV file (binary data on line 1; decompress a .gz file first)")
    if not line.endswith(b"\n") and b"\r" in line.rstrip(b"\r"):
        # classic Mac OS line ends: the reader splits lines at \n only, so the whole file is "line 1"
        raise ValueError(f"{path}: lines end in a bare carriage return (classic Mac OS line ends), not a line "
                         "feed: convert them, e.g. tr '\\r' '\\n' < old.csv > new.csv")
    if len(line) > MAX_LINE_BYTES:
        raise ValueError(f"{path}: line 1 is longer than {MAX_LINE_BYTES} bytes, the longest read")
    text = line.decode("utf-8-sig", errors="replace").rstrip("\r\n")
    try:
        with _long_fields():
            return [name.strip() for name in next(csv.reader([text], delimiter=delimiter))]
    except csv.Error as e:  # e.g. a bare carriage return inside the header
        raise ValueError(f"{path}: line 1: malformed header: {e}") from None


def _read_csv(
    path: Path,
    columns: tuple[str, ...],
    *,
    delimiter: str = ",",
    block_bytes: int = CSV_BLOCK_BYTES,
    required: dict[str, str] | None = None,
    choose: str = CHOOSE_COLUMNS,
) -> Iterator[tuple[int, dict[str, pa.Array], int]]:
    """Yield ``(first_row, {column: pyarrow array}, bytes read)`` of a CSV file, block by block.

    Empty values become nulls; blank lines are rows of nulls, so that row ``k`` is line ``k + 2``
    (for files with one sample per line: a quoted line break would shift the line numbers).
    ``required`` names the columns whose empty value the caller refuses, with what to call it
    (``{"t": "timestamp"}``), so that an error in a block names the first bad line of either kind;
    ``choose`` says what to do about a missing column (:func:`column_positions`).
    pyarrow needs every line inside one block: at a longer line (a long text in a column that is
    not read) the reading goes on from that line with blocks four times larger, so that neither
    the chunk size nor the block size decides whether a file can be read.
    """
    pa = require("pyarrow", f"{path}: reading CSV files")
    pa_csv = require("pyarrow.csv", f"{path}: reading CSV files")

    header = _csv_header(path, delimiter)
    positions = column_positions(path, header, columns, choose, where="line 1: ")
    keys = {c: f"{positions[c]}:{c}" for c in columns}
    convert = pa_csv.ConvertOptions(
        include_columns=list(keys.values()),
        column_types={k: pa.float64() for k in keys.values()},
        null_values=[""],
        strings_can_be_null=False,
        quoted_strings_can_be_null=True,
    )
    parse = pa_csv.ParseOptions(delimiter=delimiter, ignore_empty_lines=False)
    first, block = 0, block_bytes
    if _line_offset(path, 1) >= path.stat().st_size:
        return  # a header and no samples (pyarrow would call the file empty)
    while True:
        read = pa_csv.ReadOptions(
            column_names=[f"{i}:{name}" for i, name in enumerate(header)],  # unique even if the header is not
            block_size=block,
            use_threads=False,  # parallel files scale better than parallel blocks (and it was not faster)
        )
        # pyarrow reads the file itself, on its own thread and without the GIL
        with pa.OSFile(str(path)) as f:
            f.seek(_line_offset(path, first + 1))  # past the header (which may be longer than a block)
            try:
                for batch in pa_csv.open_csv(f, read_options=read, parse_options=parse, convert_options=convert):
                    yield first, {c: batch.column(keys[c]) for c in columns}, f.tell()
                    first += batch.num_rows
                return
            except pa.ArrowInvalid as e:
                if "straddl" not in str(e):
                    raise ValueError(_csv_error(path, e, first + 2, header, positions, delimiter, required or {})) from None
                if block >= MAX_LINE_BYTES:
                    raise ValueError(
                        f"{path}: a line after line {first + 1} is longer than {MAX_LINE_BYTES} bytes, the longest read"
                    ) from None
                block = min(4 * block, MAX_LINE_BYTES)


def _line_offset(path: Path, lines: int) -> int:
    """The byte offset of the start of line ``lines + 1`` (past ``lines`` line ends)."""
    with open(path, "rb") as f:
        _skip_lines(f, lines)
        return f.tell()


def _csv_error(
    path: Path,
    error: Exception,
    first_line: int,
    header: list[str],
    positions: dict[str, int],
    delimiter: str,
    required: dict[str, str],
) -> str:
    """Find the line and column of a value pyarrow could not read (its message names neither).

    Reads on from ``first_line``, the first line not yet handed out; runs only after an error.
    pyarrow rejects a whole block for one unreadable value, so an empty ``required`` value earlier
    in the block (which pyarrow reads as a null) is the first error of the file: it is reported.
    """
    with open(path, "rb") as f, _long_fields():
        _skip_lines(f, first_line - 1)
        text = _io.TextIOWrapper(f, encoding="utf-8", errors="replace", newline="")
        reader = csv.reader(text, delimiter=delimiter)
        read = 0  # lines read so far; a record may span lines (a quoted line break)
        for fields in reader:
            line, read = first_line + read, reader.line_num
            if not any(fields):  # a blank line or a row of delimiters: pyarrow reads it as empty values
                for name in required:
                    return f"{path}: line {line}, column {positions[name] + 1} ({name}): blank line"
                continue
            if len(fields) != len(header):
                return f"{path}: line {line}: {_count(len(fields), 'field')}, but the header has {len(header)}"
            for name, pos in positions.items():
                value = fields[pos].strip(" \t")  # what pyarrow trims
                where = f"{path}: line {line}, column {pos + 1} ({name})"
                if fields[pos] and not value:
                    return f"{where}: blank value {fields[pos]!r} (leave it empty for a missing value)"
                if value and not _is_number(value):
                    return f"{where}: {value!r} is not a number"
                if not fields[pos] and name in required:
                    return f"{where}: empty {required[name]}"
    return f"{path}: after line {first_line}: {error}"


@contextmanager
def _long_fields() -> Iterator[None]:
    """Let Python's csv module read fields as long as pyarrow does (it refuses over 128 KiB by
    default; a long text in a column that is not read is legal). The limit is global, hence the
    lock; only headers and the search for a bad value use the csv module."""
    with _FIELD_LIMIT_LOCK:
        previous = csv.field_size_limit(MAX_LINE_BYTES)
        try:
            yield
        finally:
            csv.field_size_limit(previous)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _is_number(text: str) -> bool:
    """Whether pyarrow reads ``text`` (trimmed of spaces and tabs) as a float. Python's float() also
    takes ``1_000``, digits beyond ASCII (``\u0663``) and other white space around (a no-break
    space), which pyarrow refuses: taken for numbers, the search passed the bad value by."""
    if "_" in text or not text.isascii() or text.strip() != text:
        return False
    try:
        float(text)
    except ValueError:
        return False
    return True


def _skip_lines(f: Any, count: int) -> None:
    """Move the binary file ``f`` past ``count`` line ends (counted in C, block by block)."""
    while count > 0:
        start = f.tell()
        block = f.read(1 << 20)
        if not block:
            return
        found = block.count(b"\n")
        if found < count:
            count -= found
            continue
        end = -1
        for _ in range(count):
            end = block.index(b"\n", end + 1)
        f.seek(start + end + 1)
        return


def csv_chunks(src: GyroSource, rows: int, columns: tuple[str, ...]) -> Iterator[tuple[np.ndarray, list[np.ndarray], float, int]]:
    """CSV blocks of at most ``rows`` samples of the time and ``columns``; an empty time is an
    error, an empty value is NaN."""
    o = src.options
    path = src.data_path
    block = min(CSV_BLOCK_BYTES, max(4096, rows * _bytes_per_line(path)))
    header = None
    required = {o.time: "timestamp"}
    blocks = _read_csv(path, (o.time, *columns), delimiter=o.delimiter, block_bytes=block, required=required)
    for first, cols, done in blocks:
        t = cols[o.time]
        bad = first_null(t)
        if bad is not None:
            header = header or _csv_header(path, o.delimiter)
            blank = all(cols[c][bad].as_py() is None for c in columns)
            raise ValueError(
                f"{path}: line {first + bad + 2}, column {header.index(o.time) + 1} ({o.time}): "
                + ("blank line" if blank else "empty timestamp")
            )
        values = [cols[c].to_numpy(zero_copy_only=False) for c in columns]
        yield t.to_numpy(), values, o.counts_per_second, done


def _bytes_per_line(path: Path) -> int:
    """Mean length of the first lines (to size CSV blocks for a number of rows)."""
    with open(path, "rb") as f:
        head = f.read(1 << 16)
    return max(1, len(head) // max(1, head.count(b"\n")))


def read_csv_columns(path: Path, columns: tuple[str, ...], *, optional: tuple[str, ...] = ()) -> dict[str, FloatArray]:
    """Read the named columns of a CSV file with a header line (all of it, as float64); an empty
    value of an ``optional`` column is NaN (the caller decides what a missing value means).

    Raises ValueError naming the file, line and column of a malformed value, or of an empty value
    of another column. Row ``k`` is line ``k + 2``.
    """
    path = Path(path)
    import_pyarrow_lazy_modules()
    parts: dict[str, list[np.ndarray]] = {c: [] for c in columns}
    header = _csv_header(path, ",")
    choose = f"{path.name} has the columns {', '.join(columns)}"  # not gyro data: no reading option names them
    required = [c for c in columns if c not in optional]
    for first, cols, _ in _read_csv(path, columns, required=dict.fromkeys(required, "value"), choose=choose):
        for c in columns:
            bad = None if c in optional else first_null(cols[c])
            if bad is not None:
                raise ValueError(f"{path}: line {first + bad + 2}, column {header.index(c) + 1} ({c}): empty value")
            parts[c].append(cols[c].to_numpy(zero_copy_only=False))  # with nulls: NaN
    return {c: concat(parts[c]) for c in columns}

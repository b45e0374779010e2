"""Reading CSV files: pyarrow's streaming reader, and the line and column of a malformed value.

A CSV file has a header line (after any comment lines, :func:`csv_layout`), then one sample per
line, then maybe blank lines, which are left out. pyarrow parses it block by block on its own
thread; when it rejects a value, the file is read again from that block with Python's csv module to
find the line and column, which pyarrow's message does not name.
"""

from __future__ import annotations

import csv
import io as _io
import re
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO, TypeAlias

import numpy as np

from .._arrays import FloatArray
from .._extras import require
from ._columns import (
    ALIGNED, CHOOSE_COLUMNS, column_positions, concat, delimiter_option, first_null, import_pyarrow_lazy_modules,
    is_number,
)
from ._paths import arrow_path, content_kind
from .units import is_unit

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
#: A date, maybe with a time, as loggers write them (``2024-05-03T14:00:00.010Z``, ``2024-05-03 14:00``).
#: What a last line with too few fields most likely is.
_CUT_OFF = " (the file's last line, cut off: a log whose writing stopped mid-line; delete the line)"
#: A line of words among the samples (``# logger restarted``): a note, not a sample cut short.
_TEXT = " (a line of text among the samples, a logger's note: delete the line)"
#: The first line of a CSV file that names its delimiter, as Excel writes it (``sep=;``).
_SEP = re.compile(rb'"?sep=(.)"?')
_DATE = re.compile(r"\d{4}-\d{2}-\d{2}(?:[T ]\d{2}:\d{2})?")
#: A duration as pandas writes a timedelta column (``0 days 00:00:00.010000``, ``-1 days +23:59:59``).
_DURATION = re.compile(r"-?\d+ days? [+-]?\d{2}:\d{2}:\d{2}")
#: How other tools write a missing value (pandas' and R's defaults, spreadsheets'): not numbers
#: here, where a missing reading is an empty field or NaN.
_MISSING = frozenset({"NA", "N/A", "n/a", "#N/A", "#NA", "NULL", "null", "None", "<NA>", "-", "?"})
#: Rows read from a CSV file and not yet handed out: first row, columns, bytes read, rows.
_HeldRows: TypeAlias = "tuple[int, dict[str, pa.Array], int, int]"


@dataclass(frozen=True)
class CsvLayout:
    """Where a CSV file's samples begin: its column names and the lines up to and including the
    header (comment lines and the header), so that sample ``row`` is line :meth:`line`."""

    header: list[str]
    header_lines: int

    def line(self, row: int) -> int:
        """The line of sample ``row`` (0-based), as an editor numbers the file's lines."""
        return row + self.header_lines + 1


def csv_layout(path: Path, delimiter: str) -> CsvLayout:
    """The header of a CSV file, after the comment lines (``#``) before it.

    A leading line that starts with ``#`` is a comment, unless the line after it is already a
    sample: then it is the header, as EuRoC writes it (``#timestamp [ns],w_RS_S_x ...``), and
    :func:`~gyrocore.io.units.split_unit` reads its names without the ``#``. Blank lines after a
    comment are skipped with it (a logger's notes, a blank line, then the header), and so is a
    first line ``sep=;`` that names the ``delimiter`` (Excel's; another delimiter is an error).

    Raises:
        ValueError: no header, binary data, UTF-16, classic Mac OS line ends, a line longer than
            :data:`MAX_LINE_BYTES`, or a header that is not UTF-8 or not a CSV line, naming the line.
    """
    with open(path, "rb") as f:
        line = _first_line(path, f)
        number, offset = 1, 0
        named = _SEP.fullmatch(line.removeprefix(_UTF8_BOM).rstrip(b"\r\n"))
        if named:  # a spreadsheet's line naming the delimiter: "sep=;" was read as the header
            _check_named_delimiter(path, named[1].decode("utf-8", errors="replace"), delimiter)
            number, offset, line = 2, len(line), f.readline(MAX_LINE_BYTES + 1)
            if not line.strip():
                raise ValueError(f"{path}: line 2: no header line (expected column names)")
        while line.removeprefix(_UTF8_BOM).startswith(b"#"):
            following, skipped = f.readline(MAX_LINE_BYTES + 1), [line]
            while following and not following.strip():  # blank lines between the comments and the header
                skipped.append(following)
                following = f.readline(MAX_LINE_BYTES + 1)
            if not following.strip() or _is_sample(following, delimiter):
                break
            number, offset, line = number + len(skipped), offset + sum(map(len, skipped)), following
            if len(line) > MAX_LINE_BYTES:
                raise ValueError(f"{path}: line {number} is longer than {MAX_LINE_BYTES} bytes, the longest read")
    text = _decode(path, number, offset, line).rstrip("\r\n")
    try:
        with _long_fields():
            header = [name.strip() for name in next(csv.reader([text], delimiter=delimiter))]
            ends_quoted = _quote_ends_on_line(text, delimiter)
    except csv.Error as e:  # e.g. a bare carriage return inside the header
        raise ValueError(f"{path}: line {number}: malformed header: {e}") from None
    if not ends_quoted:  # the rest of the name was read as the first sample: "line 2: 1 field"
        raise ValueError(f"{path}: line {number}: a quoted column name goes on past the line's end (a line break in "
                         "a name, as a spreadsheet cell of two lines writes it): write the header on one line")
    return CsvLayout(header, number)


def _quote_ends_on_line(text: str, delimiter: str) -> bool:
    """Whether every quoted field of the line ``text`` ends on it (csv's strict reader says so)."""
    try:
        next(csv.reader([text], delimiter=delimiter, strict=True))
    except csv.Error as e:
        return "unexpected end of data" not in str(e)
    return True


def _check_named_delimiter(path: Path, named: str, delimiter: str) -> None:
    """Refuse a file whose ``sep=`` line (Excel's) names another delimiter than the one read with."""
    if named != delimiter:
        raise ValueError(f"{path}: line 1: {'sep=' + named!r} names the file's delimiter, {named!r}, and it is read with "
                         f"{delimiter!r}: give delimiter={named!r} ({delimiter_option(named)})")


def refuse_not_text(path: Path, line: bytes, what: str) -> None:
    """Refuse a file whose first ``line`` shows it is no UTF-8 text: UTF-16 (or UTF-32) text, or
    binary data (a gzip file, control bytes), named as ``what`` (``CSV file``) it is not; the
    binary bytes are never shown."""
    if line.startswith(_UTF16_BOMS):
        raise ValueError(f"{path}: text in UTF-16 (or UTF-32), not UTF-8: save it as UTF-8")
    if line.startswith(_GZIP) or any(b < 32 and b not in b"\t\r\n" for b in line[:4096]):
        # a Parquet or NumPy file given as a reference or fixes file was told to decompress it
        kind = content_kind(line)
        why = f"it is {kind}" if kind else "binary data on line 1; decompress a .gz file first"
        raise ValueError(f"{path}: not a text {what} ({why})")


def _first_line(path: Path, f: BinaryIO) -> bytes:
    """The first line of the file ``f``, refused if it shows the file is no UTF-8 text CSV."""
    line = f.readline(MAX_LINE_BYTES + 1)  # bounded: a file of gigabytes without a line end
    if not line.removeprefix(_UTF8_BOM).strip():  # an empty file that an editor saved with its BOM too
        raise ValueError(f"{path}: line 1: no header line (expected column names)")
    refuse_not_text(path, line, "CSV file")
    if not line.endswith(b"\n") and b"\r" in line.rstrip(b"\r"):
        # classic Mac OS line ends: the reader splits lines at \n only, so the whole file is "line 1"
        raise ValueError(f"{path}: lines end in a bare carriage return (classic Mac OS line ends), not a line "
                         "feed: convert them, e.g. tr '\\r' '\\n' < old.csv > new.csv")
    if len(line) > MAX_LINE_BYTES:
        raise ValueError(f"{path}: line 1 is longer than {MAX_LINE_BYTES} bytes, the longest read")
    return line


def _is_sample(line: bytes, delimiter: str) -> bool:
    """Whether ``line`` is a sample: every value that is not empty is a number (a header has names)."""
    values = [v.strip(" \t") for v in line.decode("utf-8", errors="replace").rstrip("\r\n").split(delimiter)]
    return any(values) and all(is_number(v) for v in values if v)


def _decode(path: Path, number: int, offset: int, line: bytes) -> str:
    """Line ``number`` of ``path``, which starts at byte ``offset``, as text, or an error naming
    the first byte that is not UTF-8 (decoded with replacement characters, a Latin-1 ``°`` was
    shown as U+FFFD in the column names)."""
    body = line.removeprefix(_UTF8_BOM) if number == 1 else line
    try:
        return body.decode("utf-8")
    except UnicodeDecodeError as e:
        at = offset + len(line) - len(body) + e.start
        raise ValueError(
            f"{path}: line {number}: not UTF-8 (byte 0x{body[e.start]:02x} at byte offset {at} of the file): "
            "save it as UTF-8, e.g. iconv -f latin1 -t utf-8 old.csv > new.csv"
        ) from None


def _read_csv(
    path: Path,
    layout: CsvLayout,
    columns: tuple[str, ...],
    *,
    delimiter: str = ",",
    block_bytes: int = CSV_BLOCK_BYTES,
    required: dict[str, str] | None = None,
    choose: str = CHOOSE_COLUMNS,
) -> Iterator[tuple[int, dict[str, pa.Array], int]]:
    """Yield ``(first_row, {column: pyarrow array}, bytes read)`` of a CSV file, block by block.

    Empty values become nulls; blank lines are rows of nulls, so that row ``k`` is line
    ``layout.line(k)`` (for files with one sample per line: a quoted line break would shift the
    line numbers), except the blank lines that end the file, which hold no sample and are left out.
    ``required`` names the columns whose empty value the caller refuses, with what to call it
    (``{"t": "timestamp"}``), so that an error in a block names the first bad line of either kind;
    ``choose`` says what to do about a missing column (:func:`column_positions`).
    pyarrow needs every line inside one block: at a longer line (a long text in a column that is
    not read) the reading goes on from that line with blocks four times larger, so that neither
    the chunk size nor the block size decides whether a file can be read.
    """
    pa = require("pyarrow", f"{path}: reading CSV files")
    pa_csv = require("pyarrow.csv", f"{path}: reading CSV files")

    header = layout.header
    positions = column_positions(path, header, columns, choose, where=f"line {layout.header_lines}: ")
    keys = {c: f"{positions[c]}:{c}" for c in columns}
    convert = pa_csv.ConvertOptions(
        include_columns=list(keys.values()),
        column_types={k: pa.float64() for k in keys.values()},
        null_values=[""],
        strings_can_be_null=False,
        quoted_strings_can_be_null=True,
    )
    parse = pa_csv.ParseOptions(delimiter=delimiter, ignore_empty_lines=False)
    blank_tail = _blank_tail_rows(path, _line_offset(path, layout.header_lines))
    if blank_tail is None:
        return  # a header and no samples, or only blank lines after it (pyarrow would call the file empty)
    # rows are held back until blank_tail rows follow them: the last blank_tail rows read are the
    # blank lines that end the file, known as such only once pyarrow has read to its end
    held: list[_HeldRows] = []
    read, block = 0, block_bytes
    while True:
        options = pa_csv.ReadOptions(
            column_names=[f"{i}:{name}" for i, name in enumerate(header)],  # unique even if the header is not
            block_size=block,
            use_threads=False,  # parallel files scale better than parallel blocks (and it was not faster)
        )
        # pyarrow reads the file itself, on its own thread and without the GIL
        with pa.OSFile(arrow_path(path)) as f:
            f.seek(_line_offset(path, layout.header_lines + read))  # past the header (which may be longer than a block)
            try:
                for batch in pa_csv.open_csv(f, read_options=options, parse_options=parse, convert_options=convert):
                    held.append((read, {c: batch.column(keys[c]) for c in columns}, f.tell(), batch.num_rows))
                    read += batch.num_rows
                    while held and read - (held[0][0] + held[0][3]) >= blank_tail:
                        yield held.pop(0)[:3]
                for first, cols, done, rows in held:
                    # the blank tail's rows are blank lines (line ends alone), so nothing is dropped but them
                    keep = min(rows, read - blank_tail - first)
                    if keep > 0:
                        yield first, {c: a.slice(0, keep) for c, a in cols.items()}, done
                return
            except pa.ArrowInvalid as e:
                if "straddl" not in str(e):
                    # the search starts at the first row not handed out: an empty value held back is the first error
                    unchecked = held[0][0] if held else read
                    raise ValueError(
                        _csv_error(path, e, layout.line(unchecked), header, positions, delimiter, required or {})
                    ) from None
                if block >= MAX_LINE_BYTES:
                    raise ValueError(
                        f"{path}: a line after line {layout.line(read) - 1} is longer than {MAX_LINE_BYTES} bytes, "
                        "the longest read"
                    ) from None
                block = min(4 * block, MAX_LINE_BYTES)


def _blank_tail_rows(path: Path, start: int) -> int | None:
    """How many rows pyarrow reads from the blank lines that end the file, whose samples begin at
    byte ``start`` (the line ends after the last byte that is none, less the one that ends its
    line; ``\\r\\n``, ``\\n`` and a bare ``\\r`` each end one, as pyarrow counts them); None when
    nothing but line ends follows ``start``."""
    tail, end = b"", path.stat().st_size
    with open(path, "rb") as f:
        while end > start:
            size = min(1 << 16, end - start)
            f.seek(end - size)
            block = f.read(size)
            data = block.rstrip(b"\r\n")
            tail = block[len(data):] + tail
            if data:
                ends = tail.count(b"\n") + tail.count(b"\r") - tail.count(b"\r\n")
                return max(0, ends - 1)
            end -= size
    return None


def _line_offset(path: Path, lines: int) -> int:
    """The byte offset of the start of line ``lines + 1`` (past ``lines`` line ends)."""
    with open(path, "rb") as f:
        _skip_lines(f, lines)
        return f.tell()


def _why_not_a_number(value: str, delimiter: str, required: str | None) -> str:
    """A hint for a value that is no number, where its form says why: a decimal comma (with the
    command that mends a file whose fields a comma does not separate), another tool's spelling of
    a missing value (``required``: what the column holds, if it may not be missing), a date, a
    duration, or bytes that are not UTF-8 (read as U+FFFD)."""
    if "\ufffd" in value:
        return " (bytes that are not UTF-8: save the file as UTF-8, e.g. iconv -f latin1 -t utf-8 old.csv > new.csv)"
    if "," in value and is_number(value.replace(",", ".", 1)):
        # a European export: fields separated by ';' (or tabs), numbers with a comma
        mend = "" if delimiter == "," else ", e.g. tr ',' '.' < old.csv > new.csv"
        return f" (a decimal comma: write numbers with a decimal point{mend})"
    if value in _MISSING and required is not None:
        return f" (a spelling of a missing value, and a {required} cannot be missing: drop the row)"
    if value in _MISSING:
        return (" (a spelling of a missing reading: leave the field empty or write NaN, which are read as missing; "
                "then nonfinite='hold' or 'skip' (--nonfinite hold, --nonfinite skip) carries the log over it)")
    if _DATE.match(value):
        return (" (a date and time: a CSV file's times are numbers, in s, ms, us or ns; write them as numbers, "
                "or convert the file to Parquet with this column as a timestamp, read as seconds since the Unix "
                "epoch: docs/reading-logs.md, \"Dates and times\")")
    if _DURATION.match(value):
        return (" (a duration as pandas writes one: write seconds, the column's .dt.total_seconds(), or write "
                "the table to Parquet, whose durations are read as seconds)")
    return ""


def _units_row_hint(line: int, header: list[str], fields: list[str], positions: dict[str, int]) -> str:
    """What to do with a row of units under the header (``s,deg/s``; phone apps and spreadsheets
    write one): state the units in the header, where gyrocore reads them, or give them as options."""
    named = ",".join(f"{header[pos].strip()} [{fields[pos].strip(' []()')}]" for pos in sorted(positions.values()))
    return (f" (a row of units: delete line {line} and state them in the header, {named}, or give them with "
            "time_unit=/rate_unit=, --time-unit/--rate-unit)")


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
            if len(fields) != len(header) and not "".join(fields).strip(" \t"):
                # spaces or a tab alone (an editor's last line): no line cut off, as the hint below would say
                return f"{path}: line {line}: spaces or tabs alone, no values (delete the line, or leave it empty)"
            if len(fields) != len(header):
                # too few fields on the last line (any() stops at the next line with a value): cut off
                hint = (f" ({ALIGNED})" if delimiter == " " and "" in (*header, *fields)
                        else _TEXT if len(fields) < len(header) and re.search("[A-Za-z]{2}", "".join(fields))
                        else _CUT_OFF if len(fields) < len(header) and not any(map(any, reader)) else "")
                return f"{path}: line {line}: {_count(len(fields), 'field')}, but the header has {len(header)}{hint}"
            if [f.strip(" \t") for f in fields] == [h.strip(" \t") for h in header]:
                return (f"{path}: line {line}: the header line again (logs joined one after another?): delete the "
                        "line, or read each log alone")
            for name, pos in positions.items():
                value = fields[pos].strip(" \t")  # what pyarrow trims
                where = f"{path}: line {line}, column {pos + 1} ({name})"
                if "\n" in value or "\r" in value:  # a quote left open: the rest of the file was shown as the value
                    end = first_line + reader.line_num - 1
                    reach = f"to the end of the file, line {end}" if not any(True for _ in reader) else f"to line {end}"
                    return (f"{where}: a value in quotes runs over the line ends that follow, {reach}: "
                            f"{_shown(value)}; a quote left open joins the lines after it into one value: close or "
                            "delete it")
                if fields[pos] and not value:
                    return f"{where}: blank value {fields[pos]!r} (leave it empty for a missing value)"
                if value and not is_number(value):
                    if is_unit(value):
                        return f"{where}: {value!r} is not a number{_units_row_hint(line, header, fields, positions)}"
                    return f"{where}: {_shown(value)} is not a number{_why_not_a_number(value, delimiter, required.get(name))}"
                if not fields[pos] and name in required:
                    return f"{where}: empty {required[name]}"
    return f"{path}: after line {first_line}: {error}"


#: The characters of a value a message shows.
SHOWN = 60


def _shown(value: str) -> str:
    """``value`` as a message shows it: its first :data:`SHOWN` characters where it is longer (a field
    of 128 KiB of text was shown whole)."""
    return repr(value) if len(value) <= SHOWN else f"{value[:SHOWN]!r}... ({len(value)} characters)"


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
    layout = src.csv_table()  # read as the file was opened
    required = {o.time: "timestamp"}
    blocks = _read_csv(path, layout, (o.time, *columns), delimiter=src.delimiter, block_bytes=block, required=required)
    for first, cols, done in blocks:
        t = cols[o.time]
        bad = first_null(t)
        if bad is not None:
            raise ValueError(_empty(path, layout, cols, first, bad, o.time, "empty timestamp"))
        values = [cols[c].to_numpy(zero_copy_only=False) for c in columns]
        yield t.to_numpy(), values, o.counts_per_second, done


def _empty(path: Path, layout: CsvLayout, cols: dict[str, pa.Array], first: int, bad: int, name: str, what: str) -> str:
    """Where the empty value ``bad`` of the block of row ``first`` in column ``name`` is, and what:
    ``what``, or a blank line if every column read is empty there."""
    blank = all(a[bad].as_py() is None for a in cols.values())
    column = layout.header.index(name) + 1
    return f"{path}: line {layout.line(first + bad)}, column {column} ({name}): {'blank line' if blank else what}"


def _bytes_per_line(path: Path) -> int:
    """Mean length of the first lines (to size CSV blocks for a number of rows)."""
    with open(path, "rb") as f:
        head = f.read(1 << 16)
    return max(1, len(head) // max(1, head.count(b"\n")))


def read_csv_columns(path: Path, columns: tuple[str, ...], *, optional: tuple[str, ...] = (),
                     what: str = "the file", layout: CsvLayout | None = None) -> dict[str, FloatArray]:
    """Read the named columns of a CSV file with a header line (all of it, as float64); an empty
    value of an ``optional`` column is NaN (the caller decides what a missing value means).
    ``what`` names the kind of file (``a reference``) in the error of a missing column; ``layout``
    is the file's as the caller read it (:func:`csv_layout`, its names perhaps without their units).

    Raises ValueError naming the file, line and column of a malformed value, or of an empty value
    of another column. Row ``k`` is line ``csv_layout(path, ",").line(k)``.
    """
    path = Path(path)
    import_pyarrow_lazy_modules()
    parts: dict[str, list[np.ndarray]] = {c: [] for c in columns}
    layout = layout or csv_layout(path, ",")
    # not gyro data: no reading option names them. What such a file needs, not what this one has
    # ("it has t, x (ref.csv has the columns t, heading)" said both of the same file)
    choose = f"{what} needs the columns {', '.join(columns)}"
    required = dict.fromkeys((c for c in columns if c not in optional), "value")
    for first, cols, _ in _read_csv(path, layout, columns, required=required, choose=choose):
        for c in columns:
            bad = None if c in optional else first_null(cols[c])
            if bad is not None:
                raise ValueError(_empty(path, layout, cols, first, bad, c, "empty value"))
            parts[c].append(cols[c].to_numpy(zero_copy_only=False))  # with nulls: NaN
    return {c: concat(parts[c]) for c in columns}

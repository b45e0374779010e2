"""Writing heading tables: the pipeline's output as CSV or Parquet, in a heading convention.

:class:`HeadingWriter` takes the output chunk after chunk and writes it through a staged file
(:mod:`gyrocore.io.atomic`), so that the table appears only once it is complete.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import replace
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _gyrocore
from .._arrays import FloatArray, as_float_array
from .._checks import require_choice
from .._inuse import Turn, one_at_a_time
from .._extras import require
from ..pipeline import HeadingResult
from ._columns import import_pyarrow_lazy_modules
from ._paths import arrow_path
from .atomic import StagedFile, named_if_no_room, refuse_present

if TYPE_CHECKING:
    from .source import GyroSource

#: Heading conventions of the output: ENU yaw (counter-clockwise from east) or compass heading
#: (clockwise from north).
HEADING_CONVENTIONS = ("enu", "compass")
#: Columns of a heading table.
OUTPUT_COLUMNS = ("t", "heading", "rate", "drift")
#: Columns written only when asked for: the heading's standard deviation from heading fixes.
FIX_COLUMNS = ("heading_sigma",)
#: Rows per Parquet row group written (256 Ki rows: 8 MiB of doubles per column; larger groups
#: raised the peak memory without writing faster).
PARQUET_ROW_GROUP = 1 << 18
#: Rows of a CSV table formatted at a time (about 5 MiB of text).
CSV_BLOCK_ROWS = 1 << 16


def convert_heading(result: HeadingResult, convention: str = "enu") -> HeadingResult:
    """The pipeline's output in a heading convention.

    ``enu``: as computed, ENU yaw [rad], counter-clockwise from east (ROS REP-103), with rate and
    drift counter-clockwise positive. ``compass``: heading = pi/2 - yaw, clockwise from north, with
    rate and drift clockwise positive, so that heading is still the integral of rate (and so the
    fix stage's heading and bias, ``fusion``, which ``columns()`` gives beside them). Both stay
    continuous (unwrapped); the yaw starts at the pipeline's ``initial_heading`` (default 0, east,
    which is 90 deg as a compass heading).
    """
    require_choice("heading convention", convention, HEADING_CONVENTIONS)
    if convention == "enu":
        return result
    rate, drift = (None if a is None else -a for a in (result.rate, result.drift))  # compass: clockwise from north
    fusion = result.fusion
    if fusion is not None:  # its bias was counter-clockwise beside a clockwise rate, its heading the ENU yaw
        bias = None if fusion.bias is None else -fusion.bias
        fusion = replace(fusion, heading=math.pi / 2 - fusion.heading, bias=bias)
    return replace(result, heading=math.pi / 2 - result.heading, rate=rate, drift=drift, fusion=fusion)


def check_columns(columns: Sequence[str], what: str = "columns") -> tuple[str, ...]:
    """``columns`` as a tuple, if it names one or more of :data:`OUTPUT_COLUMNS` (or
    :data:`FIX_COLUMNS`), each once; else a
    ``ValueError`` that names ``what`` was given (a parameter, an option) and the valid columns."""
    valid = OUTPUT_COLUMNS + FIX_COLUMNS
    if isinstance(columns, str):  # its letters were the columns: "unknown column ',', 'h', 'e', ..."
        raise TypeError(f"{what} {columns!r}: give a sequence of column names, e.g. ('t', 'heading'), not one string")
    unknown = [c for c in columns if c not in valid]
    if not columns or unknown or len(set(columns)) != len(columns):
        problem = f"unknown column {', '.join(map(repr, unknown))}" if unknown else "each column once"
        raise ValueError(f"{what} {','.join(columns)}: {problem}; choose from {', '.join(valid)}")
    return tuple(columns)


def output_format(path: str | Path) -> str:
    """``csv`` or ``parquet`` from an output file's suffix."""
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        return "csv"
    if suffix in (".parquet", ".pq"):
        return "parquet"
    raise ValueError(f"{path}: output must end in .csv or .parquet")


def check_output(out: Path, source: GyroSource) -> None:
    """Refuse an output that is the input, or lies inside an input folder."""
    check_not_input(out, (source.path, source.data_path))


def check_not_input(out: str | Path, inputs: Iterable[str | Path]) -> None:
    """Refuse an output that is one of ``inputs`` (also through a link) or lies inside one that is
    a folder: nothing a user gave is overwritten, and no output becomes part of a log."""
    out = Path(out)  # exported: paths as text failed on a missing is_dir
    # realpath, not Path.resolve: a symbolic link loop (given as the output or as a file an option
    # names) makes resolve raise RuntimeError; realpath leaves the loop's name, which reading or
    # writing it then names as an error
    target = Path(os.path.realpath(out))
    above = _folders_above(out)
    for p in map(Path, inputs):
        real = Path(os.path.realpath(p))
        # by name, and as the same folder under another name, which realpath does not see: one in
        # another case where the filesystem ignores case (macOS, Windows), a bind mount
        inside = p.is_dir() and (real in target.parents or file_id(p) in above)
        if target == real or inside or (out.exists() and p.exists() and os.path.samefile(out, p)):
            raise ValueError(f"refusing to write {out} over or inside the input {p}; write it elsewhere")


def file_id(path: str | Path) -> tuple[int, int] | None:
    """What makes ``path`` the file or folder it is (its device and inode, as ``os.path.samefile``
    compares them), whatever its name; None where nothing is there."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return st.st_dev, st.st_ino


def _folders_above(out: Path) -> set[tuple[int, int] | None]:
    """The identities (:func:`file_id`) of the folders that hold ``out``, as far as they exist."""
    found: set[tuple[int, int] | None] = set()
    for folder in out.absolute().parents:
        if (got := file_id(folder)) is not None:
            found.add(got)
    return found


def _float_column(name: str, values: Any) -> FloatArray:
    """A result's column ``name`` as a 1-D float64 array: a pipeline's as it is (checked at 8 us a
    column, one-row writes took 3 times as long), anything else through :func:`as_float_array`,
    named so that ``t`` is not checked again for coarse times, which the pipeline said."""
    if isinstance(values, np.ndarray) and values.dtype == np.float64 and values.ndim == 1:
        return values
    return as_float_array(f"the result's {name}", values)


class HeadingWriter:
    """Writes a heading table (columns t, heading, rate, drift, or those asked for) chunk after chunk.

    Use as a context manager: the table goes to a temporary file next to ``path``, which replaces
    ``path`` only when the block ends without error; on an error or an interruption it is removed.
    CSV floats are written in their shortest form that reads back bit-identically (``NaN`` for the
    rate of a skipped sample). A writer writes one table: a write outside its block, or a second
    block, is a ValueError (as a closed file's); leaving the block twice does nothing more.

    Args:
        path: ``.csv`` or ``.parquet`` output.
        heading: ``enu`` (default) or ``compass`` (see :func:`convert_heading`).
        columns: the columns to write, in this order (see :func:`check_columns`); the results
            written need only hold those (``outputs=`` of :meth:`gyrocore.Pipeline.process`).
        replace: False: a file at ``path`` when the writer is made is refused at once
            (FileExistsError naming ``replace=True``, :func:`gyrocore.io.atomic.refuse_present`);
            one that appears there while the table is written is another run's, kept, and the
            table is not written (FileExistsError at the end, "written meanwhile").
    """

    def __init__(self, path: str | Path, *, heading: str = "enu", columns: Sequence[str] = OUTPUT_COLUMNS,
                 replace: bool = True) -> None:
        self.path = Path(path)
        self.replace = replace  # False: a file that appears at path meanwhile is kept (StagedFile)
        self.columns = check_columns(columns)
        self.format = output_format(self.path)
        require_choice("heading convention", heading, HEADING_CONVENTIONS)
        # before the caller's work: a file there already was refused only at the end, as if
        # another run had written it meanwhile
        refuse_present([self.path], replace, "replace=True")
        # two threads' writes mixed their rows in the file (and lost some of a Parquet row group's)
        self._turn = Turn("a table takes one write at a time, its rows in order; hold a lock around its calls, "
                          "or give each thread its own writer and file")
        self.heading = heading
        self.rows = 0
        self._staged: StagedFile | None = None
        self._sink: Any = None  # the open file (Parquet: pyarrow's, which its writer does not close)
        self._writer: Any = None  # Parquet: the pyarrow writer, its schema and rows not yet written
        self._schema: Any = None
        #: Parquet: the rows of the row group being filled, one array per column (None: none yet)
        self._group: list[FloatArray] | None = None
        self._filled = 0
        self._closed = False  # the block has ended: the table is written, or given up

    @one_at_a_time
    def __enter__(self) -> HeadingWriter:
        if self._staged is not None:  # a second staged file orphaned the first, and rows counted on
            raise ValueError(f"{self.path}: this HeadingWriter's block was entered already (a writer writes one "
                             "table): make another HeadingWriter for another table")
        if self.format == "parquet":  # before the staged file: nothing to remove if pyarrow is missing
            pa = require("pyarrow", f"{self.path}: writing Parquet files")
            pq = require("pyarrow.parquet", f"{self.path}: writing Parquet files")
            import_pyarrow_lazy_modules()
        self._staged = StagedFile(self.path, replace=self.replace)
        tmp = self._staged.tmp
        try:
            if self.format == "csv":
                self._sink = open(tmp, "wb")
                self._sink.write(",".join(self.columns).encode() + b"\n")
            else:
                units = {"t": "s", "heading": "rad", "rate": "rad/s", "drift": "rad/s", "heading_sigma": "rad"}
                self._schema = pa.schema([(c, pa.float64()) for c in self.columns]).with_metadata(
                    {"gyrocore": json.dumps({"heading": self.heading, "units": units})}
                )
                # dictionary encoding only costs memory and time on float signals that never repeat
                self._sink = pa.OSFile(arrow_path(tmp), "wb")
                self._writer = pq.ParquetWriter(self._sink, self._schema, use_dictionary=False)
        except BaseException:
            if self._sink is not None:
                self._sink.close()
            self._staged.discard()
            self._staged = None  # nothing was begun: the block may be entered again
            raise
        return self

    @one_at_a_time
    def write(self, result: HeadingResult) -> None:
        """Append the rows of one chunk: each column one value per sample of ``result.t``, as float64
        (another real dtype converted); a result whose columns differ in length is refused before
        any of its rows is written."""
        self._require_open()
        columns, rows = self._columns(result)
        if self.format == "csv":
            # formatted in Rust without the GIL (pyarrow's float-to-text cast was the slow part), a
            # block at a time: a result written whole (a log read in one piece) was copied and
            # formatted whole, its text as long as the file (1.1 GB resident for 4*10^6 samples);
            # + 0.0 turns -0.0 (the compass rate of a gyro at rest) into 0.0, a sign that is not there
            for at in range(0, rows, CSV_BLOCK_ROWS):
                block = [c[at:at + CSV_BLOCK_ROWS] + 0.0 for c in columns]
                self._sink.write(_gyrocore.format_csv_rows(block))
        else:
            self._write_parquet(columns)
        self.rows += rows

    def _require_open(self) -> None:
        """Refuse a write outside the block: before it a CSV table failed with "'NoneType' object
        has no attribute 'write'" and a Parquet one took the rows silently; after it a Parquet
        table counted rows that went nowhere."""
        if self._staged is None:
            raise ValueError(f"{self.path}: HeadingWriter.write() before its table was opened: write in its block, "
                             "with HeadingWriter(path) as writer: writer.write(result)")
        if self._closed:
            raise ValueError(f"{self.path}: HeadingWriter.write() after its table was closed ({self.rows} rows): a "
                             "writer writes one table; make another HeadingWriter for more rows")

    def _columns(self, result: HeadingResult) -> tuple[list[FloatArray], int]:
        """The columns of ``result`` to write, each a float64 array one value per sample, and the
        rows: float32 columns failed in CSV (``type mismatch``) where Parquet took them, and a
        column of another length was an error naming no column, or none at all."""
        if not isinstance(result, HeadingResult):
            raise TypeError(f"{self.path}: HeadingWriter.write() takes a HeadingResult (of gyrocore.process or "
                            f"Pipeline.process), got {type(result).__name__}")
        r = convert_heading(result, self.heading)
        t = _float_column("t", r.t)
        rows = len(t)
        columns = [t if c == "t" else _float_column(c, r.output(c)) for c in self.columns]
        for name, column in zip(self.columns, columns):
            if len(column) != rows:
                raise ValueError(f"{self.path}: the result's {name} has {len(column)} values, its t {rows}: a table "
                                 "takes one value of each column per sample (nothing of this result was written)")
        return columns, rows

    def _write_parquet(self, columns: list[FloatArray]) -> None:
        """Append a chunk's columns to row groups of :data:`PARQUET_ROW_GROUP` rows. A chunk's rows
        are copied into one group's arrays as they come (whole groups of a long chunk go straight to
        the file): kept as a record batch each, with their count summed again for every chunk, a
        stream of one-row chunks took 28.5 s for 40,000 rows (0.15 s as CSV), the time growing with
        the square of the rows, and 3.4 kB a row (888 MiB for 300,000 rows)."""
        rows, at = len(columns[0]), 0
        while at < rows:
            if self._filled == 0 and rows - at >= PARQUET_ROW_GROUP:
                self._write_group([c[at:at + PARQUET_ROW_GROUP] for c in columns])
                at += PARQUET_ROW_GROUP
                continue
            if self._group is None:
                self._group = [np.empty(PARQUET_ROW_GROUP) for _ in columns]
            take = min(rows - at, PARQUET_ROW_GROUP - self._filled)
            for group, column in zip(self._group, columns):
                group[self._filled:self._filled + take] = column[at:at + take]
            self._filled += take
            at += take
            if self._filled == PARQUET_ROW_GROUP:
                self._flush()

    def _write_group(self, columns: list[FloatArray]) -> None:
        import pyarrow as pa  # present: __enter__ required it

        self._writer.write_table(pa.Table.from_batches([pa.record_batch(columns, schema=self._schema)]))

    def _flush(self) -> None:
        """Write the rows of the group being filled (its arrays are filled again afterwards)."""
        if self._group is not None and self._filled:
            self._write_group([c[: self._filled] for c in self._group])
            self._filled = 0

    @one_at_a_time
    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None, tb: TracebackType | None) -> None:
        if self._staged is None:
            raise ValueError(f"{self.path}: HeadingWriter's block left before it was entered")
        if self._closed:  # left twice: as a file closed twice, nothing more
            return
        self._closed = True
        try:
            try:
                if self.format == "parquet":
                    if error is None:
                        self._flush()
                    self._writer.close()
            finally:
                self._sink.close()
            if error is None:
                self._staged.commit()
        except OSError as e:  # closing flushes the last rows: a full disk shows here too
            raise named_if_no_room(self.path, e) from None
        finally:
            self._staged.discard()
        if error is not None and (named := named_if_no_room(self.path, error)) is not error:
            raise named from None

    @property
    def _in_use_name(self) -> str:
        """What this writer is, in the words of a call refused while another thread's runs."""
        return f"this gyrocore.io.HeadingWriter of {self.path}"

"""Inputs read chunk after chunk: what a file or folder is, and its samples in SI units.

:func:`open_source` recognises an input by its suffix or folder layout and reads only its headers
and metadata; :meth:`GyroSource.chunks` then reads the samples with flat memory through the
reader of its format and converts them to s and rad/s (what ``gyrocore process`` and
:mod:`gyrocore.batch` use).
"""

from __future__ import annotations

from collections.abc import Generator, Iterator
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from .._arrays import FloatArray
from .._checks import check_count, first_infinite, keep_readings, require_choice
from .._gyrocore import SampleError
from .._inuse import OneReader
from ._axes import measure_up, project
from ._columns import METRES, METRES_PER_SECOND, RADIANS, concat, import_pyarrow_lazy_modules, in_si_units
from ._csvfile import CsvLayout, csv_chunks, csv_layout
from ._kitti import KIND as KITTI_KIND
from ._kitti import DATA as KITTI_DATA
from ._kitti import frame_count, log_name, oxts_chunks, oxts_folder, oxts_options, sensor_folder_hint
from ._logfolder import GYRO_CSV, is_log_folder, read_meta, warn_gyro_alone
from ._npyfile import check_npz, npy_chunks, npy_fields, npy_shape, npz_chunks, npz_names
from ._options_given import checked_options
from ._parquetfile import parquet_chunks, parquet_file, warn_given_time_unit
from ._paths import check_file, check_readable, compressed_logs, content_hint, missing
from ._rosbag import bag_chunks, bag_columns, imu_topic, is_bag_folder, storage_file_hint
from .read_options import ReadOptions
from .units import header_options, seconds_from_counts

#: Samples per chunk, at most (a CSV chunk also ends with a block of :data:`CSV_BLOCK_BYTES`).
DEFAULT_CHUNK_ROWS = 1 << 16

#: The column of a CSV or Parquet file that holds the vehicle's speed [m/s] per sample (what
#: ``gyrocore simulate`` writes): whole mode takes its stops as rests, as a log folder's odometry.
SPEED_COLUMN = "speed"
#: The SI unit (and its spellings) of each per-sample column of a file besides the gyro's: its
#: speed, and the reference that ``gyrocore simulate`` writes beside it (:data:`gyrocore.io.log.TRUTH_COLUMNS`).
EXTRA_UNITS = {SPEED_COLUMN: ("m/s", METRES_PER_SECOND), "heading_true": ("rad", RADIANS), "x": ("m", METRES),
               "y": ("m", METRES)}
#: Suffixes of the files :func:`open_source` reads.
FILE_SUFFIXES = (".csv", ".tsv", ".parquet", ".pq", ".npy", ".npz", ".bag")
#: What a file's reading that is not finite (or beyond the core's limit) can be given instead of an edit.
NONFINITE_FIX = keep_readings("the file as it is", "nonfinite='hold' (--nonfinite hold)", "'skip'")

#: What the core says of any time beyond +-2^40 s, whatever its unit.
_CORE_UNIT_GUESS = " (nanoseconds read as seconds are this large)"


@dataclass(frozen=True, repr=False, eq=False)
class Chunk:
    """Consecutive samples of one input, in SI units.

    Attributes:
        t: timestamps [s].
        rate: yaw rate [rad/s], counter-clockwise positive (NaN where a value was empty).
        first_row: index of the first sample in the whole input (0-based).
        done: progress through the input after this chunk, in :attr:`GyroSource.progress_unit`.
    """

    t: FloatArray
    rate: FloatArray
    first_row: int
    done: int

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return f"Chunk(rows {self.first_row}..{self.first_row + len(self.t)})"


@dataclass(frozen=True)
class GyroSource:
    """One input, ready to be read chunk after chunk (see :func:`open_source`).

    Attributes:
        path: the input as given.
        kind: ``csv``, ``parquet``, ``npy``, ``npz``, ``bag``, ``log folder`` or ``kitti oxts``.
        data_path: the file whose rows are counted (``gyro.csv`` of a log folder, the ``oxts``
            folder of a KITTI raw drive, else ``path``).
        options: columns and units.
        stationary: rest window ``(t0, t1)`` [s] from a log folder's meta.json, or None.
        progress_total: size of the input in :attr:`progress_unit`, or None if unknown.
        progress_unit: ``B`` (bytes of a CSV file) or ``rows``.
        meta: a log folder's meta.json (a KITTI OXTS folder's: its drive's name).
        layout: a CSV file's (a log folder's gyro.csv's) header and the lines before its first
            sample, as read when it was opened; None for another input.
        read_once: what a reader of a whole input parsed once, for every later reading of the
            source (a KITTI OXTS folder's frames: its gyro's chunks, then its reference and
            odometry, which read every data file again).
    """

    path: Path
    kind: str
    data_path: Path
    options: ReadOptions
    stationary: tuple[float, float] | None = None
    progress_total: int | None = None
    progress_unit: str = "rows"
    meta: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)
    layout: CsvLayout | None = field(default=None, repr=False, compare=False)
    read_once: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)

    @property
    def delimiter(self) -> str:
        """The CSV delimiter of :attr:`data_path` (:func:`csv_delimiter`)."""
        return csv_delimiter(self.data_path, self.options)

    def csv_table(self) -> CsvLayout:
        """:attr:`layout`, or for a source built without it, the file's layout read now."""
        return self.layout if self.layout is not None else csv_layout(self.data_path, self.delimiter)

    @property
    def name(self) -> str:
        """The log's name: the file name without its suffix, or the folder name."""
        return str(self.meta.get("name") or (self.path.stem if self.path.is_file() else self.path.name))

    def where(self, row: int) -> str:
        """Where sample ``row`` (0-based) is in the file, in the file's own terms."""
        if self.kind in ("csv", "log folder"):
            return f"line {self.csv_table().line(row)}"
        if self.kind == "bag":
            return f"message {row} on {self.options.topic}"
        if self.kind == KITTI_KIND:
            return f"frame {row} ({KITTI_DATA}/{row:010d}.txt)"
        return f"row {row}"

    def locate(self, error: SampleError, time_fix: str | None = None, reading_fix: str | None = NONFINITE_FIX) -> str:
        """The pipeline's error about sample ``error.index`` of this file in the file's words: the
        core's message (its ``log_message``, where the API added how to keep samples in memory),
        the file and the line (row, message) of the sample, then what to do: ``time_fix`` for a
        time (:meth:`UnitCheck.time_fix`, the unit the timestamps look like), ``reading_fix`` for
        a reading (the option that keeps the file as it is). Every command and
        :meth:`gyrocore.Log.process` name a bad sample of a file so."""
        message = getattr(error, "log_message", str(error))
        fix = time_fix if error.what == "t" else reading_fix if error.what == "rate" else None
        if error.what == "t" and fix:
            # the unit the times look like replaces the core's guess of one (ms times were said
            # to be nanoseconds and ms in one line)
            message = message.replace(_CORE_UNIT_GUESS, "")
        return f"{message} ({self.data_path}, {self.where(error.index)})" + (f"; {fix}" if fix else "")

    def chunks(self, rows: int = DEFAULT_CHUNK_ROWS) -> Iterator[Chunk]:
        """The samples, at most ``rows`` at a time, converted to SI units (three-axis input: the
        rate along :meth:`up`, projected chunk after chunk).

        Each call is a reading of its own, from the file's start; a reading belongs to the thread
        that takes its first chunk: another thread's ``next()`` on it is refused
        (:class:`gyrocore.InUseError`), and the first thread's reading goes on whole.

        Raises:
            ValueError: a malformed file (naming the file and the line, row or message), a missing
                column, an empty timestamp, or an ``up`` that cannot be measured.
            ImportError: a bag without the ``rosbags`` package.
        """
        rows = check_count("rows per chunk", rows)  # at the call: 1.5 failed at the first chunk, True read 1
        return OneReader(self._chunks(rows), f"this reading of {self.data_path}", "GyroSource.chunks()",
                         "a reading gives its chunks in order to the thread that began it; give each thread its "
                         "own (source.chunks() reads the file again from its start)")

    def _chunks(self, rows: int) -> Iterator[Chunk]:
        """:meth:`chunks`, read on one thread."""
        import_pyarrow_lazy_modules()
        o = self.options
        up = self.up()
        columns = (o.rate,) if o.gyro_cols is None else o.gyro_cols
        first = 0
        for t, values, done in self._read(rows, columns):
            rate = np.asarray(values[0] if up is None else project(values, up), dtype=np.float64)
            if o.rate_unit == "deg/s":
                rate = np.radians(rate)
            for start in range(0, len(t), rows):  # a CSV block can hold more than ``rows``
                yield Chunk(t[start : start + rows], rate[start : start + rows], first + start, done)
            first += len(t)

    def speed(self, rows: int = DEFAULT_CHUNK_ROWS) -> FloatArray | None:
        """The vehicle's speed [m/s] per sample from a CSV or Parquet file's :data:`SPEED_COLUMN`
        (an empty value NaN: unknown there), or None for an input without one (a log folder's
        speed is its odometry.csv, which :func:`gyrocore.io.read_log` reads)."""
        speed = self.optional_columns((SPEED_COLUMN,), rows).get(SPEED_COLUMN)
        return None if speed is None else finite_speed(self, speed)

    def column_names(self) -> list[str]:
        """The columns of a CSV or Parquet file, read from its header or schema; none for another
        input (another format, or a log folder: its tables are files of their own)."""
        if self.kind == "csv":
            return list(self.csv_table().header)
        if self.kind == "parquet":
            return list(parquet_file(self.data_path).schema_arrow.names)
        return []

    def extra_columns(self, names: tuple[str, ...]) -> dict[str, str]:
        """The header's name of each of the columns ``names`` (of :data:`EXTRA_UNITS`) that a CSV or
        Parquet file has: the name itself, or with its SI unit (``speed [m/s]``, as a gyro column
        may state its unit; such a column was left out without a word). A name that states another
        unit (``speed [km/h]``) is an error, as in a log folder's odometry.csv."""
        header = self.column_names()
        bare = in_si_units(self.data_path, header, {n: EXTRA_UNITS[n] for n in names})
        return {n: header[bare.index(n)] for n in names if n in bare}

    def optional_columns(self, names: tuple[str, ...], rows: int = DEFAULT_CHUNK_ROWS) -> dict[str, FloatArray]:
        """Those of the columns ``names`` that a CSV or Parquet file has (:meth:`extra_columns`),
        one value per sample (an empty value NaN), read in one pass; none for another input
        (another format, or a log folder: its tables are files of their own)."""
        present = self.extra_columns(names)
        if not present:
            return {}
        parts: list[list[np.ndarray]] = [[] for _ in present]
        for _, values, _ in self._read(rows, tuple(present.values())):
            for part, v in zip(parts, values):
                part.append(np.asarray(v, dtype=np.float64))
        return {n: concat(part) for n, part in zip(present, parts)}

    def up(self) -> tuple[float, float, float] | None:
        """The vector that points up in the sensor frame (not normalised), for three-axis input:
        the one given, or the mean accelerometer reading over the rest window (``up_window``, else
        the log folder's), which reads the file up to the window's end. None for one axis.

        Raises:
            ValueError: no rest window, or one without accelerometer readings or in which the
                accelerometer does not read gravity (naming the file and the window).
        """
        o = self.options
        if not o.three_axis:
            return None
        if isinstance(o.up, tuple):
            return o.up
        window = o.up_window if o.up_window is not None else self.stationary
        if window is None or o.accel_cols is None:
            raise ValueError(
                f"{self.data_path}: up is measured from the accelerometer at rest, and no rest window is "
                "given: give one (--up-window T0 T1, or the command's rest window: --bias-window, --bias-duration, or "
                "--window of calibrate and allan; up_window=), or give up (--up, up=)"
            )
        samples = self._read(DEFAULT_CHUNK_ROWS, o.accel_cols)
        try:
            return measure_up(self.data_path, window, ((t, values) for t, values, _ in samples))
        finally:
            samples.close()  # the reader closes its file

    def _read(self, rows: int, columns: tuple[str, ...]) -> Generator[tuple[FloatArray, list[np.ndarray], int]]:
        """(t [s], the ``columns`` as read, progress) of the format's reader, block after block."""
        for t_raw, values, per_second, done in _READERS[self.kind](self, rows, columns):
            yield seconds_from_counts(t_raw, per_second), values, done


def finite_speed(source: GyroSource, speed: FloatArray) -> FloatArray:
    """``speed``, a file's speed column, if no value is infinite (NaN, an empty value, is a speed
    unknown there); else a ValueError naming the file, the sample and the column."""
    i = first_infinite(speed)
    if i is not None:
        raise ValueError(
            f"{source.data_path}: {source.where(i)}, column {SPEED_COLUMN}: {speed[i]} is not a finite speed "
            "[m/s] (leave it empty where it is unknown, or give --no-speed, use_speed=False)"
        )
    return speed


_READERS = {
    "csv": csv_chunks,
    "log folder": csv_chunks,
    "parquet": parquet_chunks,
    "npy": npy_chunks,
    "npz": npz_chunks,
    "bag": bag_chunks,
    KITTI_KIND: oxts_chunks,
}


def csv_delimiter(path: Path, options: ReadOptions) -> str:
    """The delimiter of the CSV file ``path``: the one ``options`` give, else a tab for a ``.tsv``
    file (tab-separated values) and ``,`` for any other."""
    if options.delimiter is not None:
        return options.delimiter
    return "\t" if path.suffix.lower() == ".tsv" else ","


def open_source(path: str | Path, options: ReadOptions | None = None, **kwargs: Any) -> GyroSource:
    """Recognise an input by its suffix or layout; read nothing but headers and metadata yet.

    Args:
        path: a ``.csv`` (``.tsv``: tab-separated), ``.parquet``/``.pq``, ``.npy``, ``.npz`` or ``.bag`` file, a log folder
            (with ``gyro.csv``), a ROS 2 bag folder (with ``metadata.yaml``) or a KITTI raw drive's
            ``oxts`` folder (or the drive folder that holds it).
        options: columns and units; or give the :class:`ReadOptions` fields as keywords.

    Raises:
        FileNotFoundError: no such file or folder, or a symbolic link that cannot be followed.
        ValueError: an unknown kind of file or folder, or not a regular file (a named pipe).
    """
    if options is None:
        for name in kwargs:  # "ReadOptions.__init__() got an unexpected keyword argument", with no hint
            require_choice("reading option", name, [f.name for f in fields(ReadOptions)])
        options = ReadOptions(**kwargs)
    elif kwargs:
        raise TypeError("give either options or keywords, not both")
    return checked_options(_recognise(Path(path), options), options)


def _recognise(p: Path, options: ReadOptions) -> GyroSource:
    """The input ``p`` by its suffix or layout, its headers read."""
    if not p.exists():
        raise FileNotFoundError(missing(p))
    if p.is_dir():
        check_readable(p)  # unlisted, it would be "not a log folder"
        if is_log_folder(p):
            data = p / GYRO_CSV
            check_file(data)
            meta, stationary = read_meta(p)
            layout = csv_layout(data, csv_delimiter(data, options))
            options = header_options(data, layout.header, options)
            return GyroSource(p, "log folder", data, options, stationary, data.stat().st_size, "B", meta, layout)
        if is_bag_folder(p):
            return _open_bag(p, header_options(p, None, options))
        oxts = oxts_folder(p)
        if oxts is not None:
            return GyroSource(p, KITTI_KIND, oxts, oxts_options(p, options), progress_total=frame_count(oxts),
                              meta={"name": log_name(p, oxts)})
        try:
            entries = list(p.iterdir())
        except OSError:  # the hint is a kindness: an unlisted folder gives the error without it
            entries = []
        packed = compressed_logs(entries, FILE_SUFFIXES)
        raise ValueError(f"{p}: not a log folder (no gyro.csv) nor a ROS 2 bag (no metadata.yaml)"
                         + (f"; it holds {packed}" if packed else sensor_folder_hint(p)))
    if not p.is_file():  # reading a named pipe or a device would wait for ever, or never end
        raise ValueError(f"{p}: not a regular file (a named pipe, socket or device); give a file or folder")
    check_readable(p)
    warn_gyro_alone(p)
    try:
        return _open_file(p, options)
    except ValueError as e:
        hint = content_hint(p)  # a suffix that lies: the reader's error does not say so
        if hint:
            raise ValueError(f"{e}{hint}") from None
        raise


def _open_file(p: Path, options: ReadOptions) -> GyroSource:
    """The file ``p`` by its suffix, its headers read."""
    suffix = p.suffix.lower()
    if suffix in (".csv", ".tsv"):
        layout = csv_layout(p, csv_delimiter(p, options))
        options = header_options(p, layout.header, options)
        return GyroSource(p, "csv", p, options, progress_total=p.stat().st_size, progress_unit="B", layout=layout)
    if suffix in (".parquet", ".pq"):
        pf = parquet_file(p)
        warn_given_time_unit(p, pf, options.time, options.time_unit)
        options = header_options(p, pf.schema_arrow.names, options)
        return GyroSource(p, "parquet", p, options, progress_total=pf.metadata.num_rows)
    # the time unit the caller gave, if any: the header's reading assumes s, which a duration field
    # does not use, and warned of that assumption as if it were given
    given = options.time_unit
    if suffix == ".npy":
        options = header_options(p, npy_fields(p), options)  # field names state units as a header's do
        shape = npy_shape(p, replace(options, time_unit=given))
        return GyroSource(p, "npy", p, options, progress_total=shape[0] if shape else 0)
    if suffix == ".npz":
        options = header_options(p, npz_names(p), options)
        check_npz(p, replace(options, time_unit=given))
        return GyroSource(p, "npz", p, options)
    if suffix == ".bag":
        return _open_bag(p, header_options(p, None, options))
    raise ValueError(
        f"{p}: unknown kind of file (read are {', '.join(FILE_SUFFIXES)}, log folders and ROS 2 bag folders)"
        f"{storage_file_hint(p)}"
    )


def _open_bag(path: Path, options: ReadOptions) -> GyroSource:
    """A bag on its Imu topic (the one given, or the only one), with the topic's message count."""
    options = bag_columns(path, options)
    topic, count = imu_topic(path, options.topic)
    return GyroSource(path, "bag", path, replace(options, topic=topic), progress_total=count)


def is_input(path: str | Path) -> bool:
    """Whether ``path`` is something :func:`open_source` reads (by suffix or folder layout)."""
    path = Path(path)  # exported: a path as text was "'str' object has no attribute 'is_dir'"
    if path.is_dir():
        try:
            check_readable(path)
        except PermissionError:  # kept as an input: reading it names the folder and what to do
            return True
        return is_log_folder(path) or is_bag_folder(path) or oxts_folder(path) is not None
    return path.is_file() and path.suffix.lower() in FILE_SUFFIXES

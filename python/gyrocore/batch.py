"""Heading of whole files: one log streamed chunk by chunk (:func:`process_file`), or a fleet of
logs in parallel on all cores or on a Dask cluster (:func:`process_many`).

A log far larger than memory streams through :class:`gyrocore.Pipeline` in chunks (bit-identical to
one call), and its heading table (t, heading, rate, drift) is written as it goes to a temporary file
that replaces the output only when every row is through: an error or an interruption leaves no
half-written output, and the output is never the input. Each file gets a :class:`FileReport` with
its rows in and out; in a batch one bad file fails alone, with its reason, and the others finish.

    >>> from gyrocore.batch import process_many
    >>> summary = process_many(["logs/*.csv", "logs/drive_7"], out_dir="headings", jobs=2)  # doctest: +SKIP
    >>> print(summary)  # doctest: +SKIP
"""

from __future__ import annotations

import glob
import os
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from . import _signals, io, rests, wholelog
from ._arrays import FloatArray
from ._checks import warn
from ._extras import require, tqdm_class
from ._gyrocore import SampleError
from .io._columns import concat
from .io._logfolder import FIXES_CSV, read_odometry
from .pipeline import Pipeline, RestWindowError, _to_si, has_bias_source, uses_static_bias
from .window import Window, time_range

#: ``progress(done, total, unit)``: called after each chunk with the progress through the input.
Progress = Callable[[int, "int | None", str], None]

_READ_OPTIONS = {f.name for f in fields(io.ReadOptions)}


@dataclass(frozen=True)
class FileReport:
    """What happened to one input.

    Attributes:
        input: the input path.
        output: the heading table written, or None if the file failed.
        rows_in: samples read (up to the failure, for a failed file).
        rows_out: rows written (equal to ``rows_in`` for a file that succeeded; 0 if it failed).
        seconds: wall time.
        error: why the file failed, or None.
        warnings: what looked wrong but was processed (units, a missing rest window, repairs).
        bias_source: where the static bias came from (None if the file failed).
        rests: the rests whose bias was used in whole mode.
    """

    input: str
    output: str | None
    rows_in: int
    rows_out: int
    seconds: float
    error: str | None = None
    warnings: tuple[str, ...] = ()
    bias_source: str | None = None
    rests: tuple[wholelog.Rest, ...] = ()

    @property
    def ok(self) -> bool:
        """Whether the file was processed completely."""
        return self.error is None

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        return {
            **asdict(self),
            "warnings": list(self.warnings),
            "rests": [r.as_dict() for r in self.rests],
            "ok": self.ok,
        }

    def __str__(self) -> str:
        if not self.ok:  # most reasons already name the file
            return f"FAILED {self.error}" if self.input in (self.error or "") else f"FAILED {self.input}: {self.error}"
        lines = [
            f"ok     {self.input}: {self.rows_in} rows in, {self.rows_out} out -> {self.output} ({self.seconds:.2f} s)",
            f"       bias: {self.bias_source}",
        ]
        lines += wholelog.rest_lines(self.bias_source or "", self.rests, " " * 9)
        return "\n".join(lines)


@dataclass(frozen=True)
class BatchReport:
    """The reports of a batch, in the order of the inputs."""

    files: tuple[FileReport, ...]
    seconds: float

    @property
    def succeeded(self) -> tuple[FileReport, ...]:
        """The files processed completely."""
        return tuple(r for r in self.files if r.ok)

    @property
    def failed(self) -> tuple[FileReport, ...]:
        """The files that failed, with their reason."""
        return tuple(r for r in self.files if not r.ok)

    @property
    def rows_in(self) -> int:
        """Samples read, over all files."""
        return sum(r.rows_in for r in self.files)

    @property
    def rows_out(self) -> int:
        """Rows written, over all files."""
        return sum(r.rows_out for r in self.files)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        return {
            "ok": len(self.succeeded),
            "failed": len(self.failed),
            "rows_in": self.rows_in,
            "rows_out": self.rows_out,
            "seconds": self.seconds,
            "files": [r.as_dict() for r in self.files],
        }

    def __str__(self) -> str:
        lines = [str(r) for r in self.files]
        lines.append(
            f"{len(self.succeeded)} of {len(self.files)} files processed, {len(self.failed)} failed; "
            f"{self.rows_in} rows in, {self.rows_out} out, {self.seconds:.2f} s"
        )
        return "\n".join(lines)


def split_options(options: dict[str, Any]) -> tuple[io.ReadOptions, dict[str, Any]]:
    """Separate reader options (:class:`gyrocore.io.ReadOptions` fields) from pipeline overrides."""
    read = {k: v for k, v in options.items() if k in _READ_OPTIONS}
    return io.ReadOptions(**read), {k: v for k, v in options.items() if k not in _READ_OPTIONS}


class _FileJob:
    """One input streamed to one output; counts rows as it goes so a failure can say how far it got."""

    def __init__(
        self,
        path: Path,
        out: Path,
        preset: str,
        heading: str,
        chunk_rows: int,
        options: dict[str, Any],
        columns: Sequence[str] = io.OUTPUT_COLUMNS,
        mode: str = "whole",
        use_speed: bool = True,
    ):
        self.path, self.out, self.preset, self.heading, self.chunk_rows = path, out, preset, heading, chunk_rows
        self.mode, self.use_speed = mode, use_speed
        self.read_options, self.overrides = split_options(options)
        self.columns = io.check_columns(columns)
        # the core computes the heading always, the rate and drift only for a column of theirs
        self.outputs = ("heading", *(c for c in ("rate", "drift") if c in self.columns))
        self.rows_in = 0

    def run(self, progress: Progress | None = None) -> FileReport:
        start = time.perf_counter()
        source = io.open_source(self.path, self.read_options)
        io.check_output(self.out, source)
        overrides = dict(self.overrides)
        window = overrides.get("bias_window")
        if window is not None:
            t0 = _first_time(source)
            if isinstance(window, Window):  # a window after the first sample: the log says where that is
                overrides["bias_window"] = window.resolve(t0)
            if overrides["bias_window"][1] < t0:
                raise ValueError(
                    f"{source.data_path}: the rest window {_window_text(window)} ends before the first sample; "
                    + time_range(t0)
                )
        notes: list[str] = []
        if source.kind == "log folder" and (source.path / FIXES_CSV).is_file():
            notes.append(f"{FIXES_CSV} is not used when logs are streamed: process the log alone with "
                         "`gyrocore process` or gyrocore.Log.process to fuse its heading fixes")
        from_meta = False
        if uses_static_bias(self.preset) and not has_bias_source(overrides) and source.stationary is not None:
            overrides["bias_window"], from_meta = source.stationary, True
        plan = self._plan(source, overrides, from_meta)
        if plan.warning and self.mode == "whole":  # a causal pipeline warns itself
            warn(plan.warning)
        if plan.warning:
            notes.append(plan.warning)
        pipeline = Pipeline(self.preset, **plan.overrides)
        check = io.UnitCheck(source.options)
        with io.HeadingWriter(self.out, heading=self.heading, columns=self.columns) as writer:
            for chunk in source.chunks(self.chunk_rows):
                _signals.check()  # a signal whose KeyboardInterrupt a library swallowed stops here
                check.update(chunk.t, chunk.rate)
                try:
                    result = pipeline.process(
                        chunk.t,
                        chunk.rate - plan.bias(chunk.t),
                        index_offset=chunk.first_row,
                        outputs=self.outputs,
                    )
                except SampleError as e:
                    # a timestamp beyond the core's limits is most often an epoch in a smaller unit
                    fix = check.time_fix() if e.what == "t" else None
                    raise ValueError(source.locate(e) + (f"; {fix}" if fix else "")) from None
                except ValueError as e:
                    raise _in_file(source, e, from_meta) from None
                writer.write(result)
                self.rows_in += len(chunk)
                if progress is not None:
                    progress(chunk.done, source.progress_total, source.progress_unit)
            if self.rows_in == 0:
                raise ValueError(f"{source.data_path}: no samples")
            if check.error() is not None:
                raise ValueError(f"{source.data_path}: {check.error()}")
            try:
                pipeline.finish()
            except ValueError as e:
                raise _in_file(source, e, from_meta) from None
            if writer.rows != self.rows_in:  # the pipeline returns one row per sample; prove it
                raise RuntimeError(f"{self.path}: {self.rows_in} rows read but {writer.rows} written")
        notes += check.problems() + _repairs(pipeline.report)
        return FileReport(
            str(self.path),
            str(self.out),
            self.rows_in,
            writer.rows,
            time.perf_counter() - start,
            None,
            tuple(notes),
            plan.source,
            plan.rests,
        )

    def _plan(self, source: io.GyroSource, overrides: dict[str, Any], from_meta: bool) -> wholelog.BiasPlan:
        """Where the bias comes from: in whole mode a first pass over the file (see
        :func:`gyrocore.wholelog.plan_stream`), in causal mode the pipeline's own rest window."""
        if self.mode == "causal":
            wholelog.refuse_whole_options(_to_si(overrides))
            causal = wholelog.causal_source(self.preset, _to_si(overrides))
            warning = None
            if uses_static_bias(self.preset) and not has_bias_source(overrides):
                warning = (
                    f"preset {self.preset!r} removes a static bias but the log gives no rest window: "
                    "the bias is taken as 0 (give bias_window, bias_duration or bias; "
                    "--bias-window, --bias-duration or --bias-dps)"
                )
            return wholelog.BiasPlan(causal, overrides=overrides, warning=warning)
        wholelog.refuse_tracking(_to_si(overrides))

        def chunks() -> Iterator[tuple[FloatArray, FloatArray]]:
            for chunk in source.chunks(self.chunk_rows):
                yield chunk.t, chunk.rate

        def read_all() -> tuple[FloatArray, FloatArray, FloatArray | None]:
            read = list(source.chunks(self.chunk_rows))
            t, rate = concat([c.t for c in read]), concat([c.rate for c in read])
            odometry = read_odometry(source.path) if self.use_speed and source.kind == "log folder" else {}
            if not odometry:
                return t, rate, None
            where = str(source.path / "odometry.csv")
            return t, rate, rests.speed_on(t, odometry["t"], odometry["speed"], where=where)

        try:
            return wholelog.plan_stream(self.preset, overrides, chunks, read_all)
        except SampleError:
            # A rest's measurement saw a slice of the log: the streamed pass names the row.
            return wholelog.BiasPlan("none: the log has invalid samples", overrides={**_to_si(overrides), "bias": 0.0})
        except ValueError as e:
            raise _in_file(source, e, from_meta) from None

    def failure(self, error: BaseException, seconds: float) -> FileReport:
        reason = str(error) if isinstance(error, (ValueError, TypeError, OSError, ImportError)) else repr(error)
        return FileReport(str(self.path), None, self.rows_in, 0, seconds, reason or type(error).__name__)


def _window_text(window: Window | tuple[float, float]) -> str:
    return str(window) if isinstance(window, Window) else f"{window[0]:.10g} .. {window[1]:.10g} s"


def _first_time(source: io.GyroSource) -> float:
    """The first timestamp of an input [s] (reads its first block only)."""
    first = next(source.chunks(1), None)  # the reader closes its file as the generator goes
    if first is None:
        raise ValueError(f"{source.data_path}: no samples")
    return float(first.t[0])


def _in_file(source: io.GyroSource, error: ValueError, window_from_meta: bool) -> ValueError:
    """The pipeline's error about a file, naming it (unless a reader did) and meta.json where
    the rest window is its."""
    meta = window_from_meta and isinstance(error, RestWindowError)
    where = f" (the rest window is the stationary of {source.path / 'meta.json'})" if meta else ""
    text = str(error)
    return ValueError(f"{text if str(source.data_path) in text else f'{source.data_path}: {text}'}{where}")


def _repairs(report: dict[str, float]) -> list[str]:
    """What the pipeline's input policy repaired (NaN readings held or skipped, gaps)."""
    notes = []
    if report["held"]:
        notes.append(f"{int(report['held'])} non-finite readings replaced by the last finite one")
    if report["skipped"]:
        notes.append(f"{int(report['skipped'])} samples skipped (non-finite readings; their rows have a NaN rate)")
    if report["gaps"]:
        notes.append(f"{int(report['gaps'])} gaps, the longest {report['longest_gap']:.6g} s")
    return notes


def process_file(
    path: str | Path,
    out: str | Path,
    *,
    preset: str = "recommended",
    heading: str = "enu",
    chunk_rows: int = io.DEFAULT_CHUNK_ROWS,
    progress: Progress | None = None,
    columns: Sequence[str] = io.OUTPUT_COLUMNS,
    mode: str = "whole",
    use_speed: bool = True,
    **options: Any,
) -> FileReport:
    """Stream one log through the pipeline into a heading table, with flat memory.

    Args:
        path: any input :func:`gyrocore.io.open_source` reads.
        out: ``.csv`` or ``.parquet`` output (columns t [s], heading [rad], rate, drift [rad/s]);
            written to a temporary file and renamed at the end; never the input.
        preset: pipeline preset.
        heading: ``enu`` (counter-clockwise from east, default) or ``compass`` (clockwise from
            north); see :func:`gyrocore.io.convert_heading`.
        chunk_rows: samples per chunk (memory; the output does not depend on it).
        progress: called after each chunk (see :data:`Progress`); may raise to stop.
        columns: the output's columns, in this order (some of ``t``, ``heading``, ``rate``,
            ``drift``); the pipeline computes the rate and the drift only for their columns.
        mode: ``whole`` (default): the bias from the log's rest window, or from every rest found in
            it (and where a log folder's odometry.csv speed is zero, unless ``use_speed`` is
            False), known from the first sample (:mod:`gyrocore.wholelog`). A given rest window is
            measured by a first pass up to its end (flat memory); finding the rests reads the
            log's times and rates into memory first (16 bytes a sample); the heading is then
            streamed. ``causal``: one streamed pass, what a :class:`gyrocore.Pipeline` gives.
        **options: reader options (``time_col``, ``rate_col``, ``time_unit``, ``rate_unit``,
            ``topic``, ``delimiter``) and pipeline parameters (``bias_window=(t0, t1)`` [s] in
            the log's time base, or a :class:`gyrocore.window.Window` whose bounds may count from
            the first sample; ``bias_duration`` [s], ``bias_dps``, ...). The rest window of a log
            folder's meta.json is used unless a bias or rest window is given; a rest window that
            holds no sample is an error naming the log's time range.

    Returns:
        The file's report (rows in = rows out).

    Raises:
        ValueError: a malformed file or bad samples (naming the file and line or row), an output
            over the input, invalid options. No output is left then.
    """
    wholelog.check_mode(mode)
    return _FileJob(
        Path(path), Path(out), preset, heading, chunk_rows, options, columns, mode, use_speed
    ).run(progress)


def expand_inputs(items: Iterable[str | Path]) -> list[Path]:
    """Files and folders from paths, folders of logs and glob patterns (``logs/**/*.csv``).

    A log folder or ROS 2 bag folder is one input; any other folder stands for the inputs directly
    in it. Every path named, and every name with an input's suffix that a folder or pattern gives,
    is kept even if it cannot be read (a dangling symbolic link, a loop, no permission): it fails
    later with its reason instead of silently dropping out. Raises ValueError for an item that
    matches nothing.
    """
    found: list[Path] = []
    for item in items:
        named, matches = _matches(item)
        for m in matches:
            if m.is_dir() and not io.is_input(m):
                inside = sorted(c for c in m.iterdir() if _named_as_input(c))
                if not inside and named:
                    raise ValueError(f"{m}: no logs in this folder ({', '.join(io.FILE_SUFFIXES)}, log or bag folders)")
                found += inside
            elif named or _named_as_input(m):
                found.append(m)
    return list(dict.fromkeys(found))


def check_outside_inputs(items: Iterable[str | Path], out: Path, inputs: Sequence[Path] = ()) -> None:
    """Refuse an output (file or folder) that is, or lies inside, a folder given as input (directly
    or by a pattern), or an output folder that holds one of ``inputs``: a later run over that
    folder would read the outputs as logs (and a CSV output could be its own input)."""
    io.check_not_input(out, [m for item in items for m in _matches(item)[1] if m.is_dir()])
    for p in inputs:
        if p.parent.resolve() == out.resolve():
            raise ValueError(
                f"refusing to write into {out}: it holds the input {p}, and the outputs would be read as "
                "logs by a later run over it; give an output folder outside the inputs"
            )


def _matches(item: str | Path) -> tuple[bool, list[Path]]:
    """Whether ``item`` names a path itself, and the paths it stands for (itself, or a pattern's
    matches); raises ValueError if it matches nothing."""
    p = Path(item)
    if os.path.lexists(p):  # also true for a dangling link, which exists() is not
        return True, [p]
    matches = [Path(m) for m in sorted(glob.glob(str(item), recursive=True))]
    if not matches:
        raise ValueError(f"{item}: no such file or folder, and no file matches it")
    return False, matches


def _named_as_input(path: Path) -> bool:
    """An input, or a name that says it is one but cannot be read as one (a dangling link)."""
    return io.is_input(path) or (not path.is_dir() and path.suffix.lower() in io.FILE_SUFFIXES)


def output_paths(inputs: Sequence[Path], out_dir: Path, fmt: str) -> list[Path]:
    """``out_dir/<input name without suffix>.<fmt>`` for each input; refuses two inputs that would
    share an output."""
    outs = [out_dir / f"{p.name if p.is_dir() else p.stem}.{fmt}" for p in inputs]
    seen: dict[Path, Path] = {}
    for p, o in zip(inputs, outs):
        if o in seen:
            raise ValueError(f"{seen[o]} and {p} would both be written to {o}; process them separately")
        seen[o] = p
    return outs


def process_many(
    paths: Iterable[str | Path],
    *,
    preset: str = "recommended",
    out_dir: str | Path,
    client: Any = None,
    jobs: int | None = None,
    fmt: str = "csv",
    heading: str = "enu",
    chunk_rows: int = io.DEFAULT_CHUNK_ROWS,
    progress: bool = False,
    columns: Sequence[str] = io.OUTPUT_COLUMNS,
    mode: str = "whole",
    use_speed: bool = True,
    **options: Any,
) -> BatchReport:
    """Process a fleet of logs in parallel: threads on this machine, or a Dask cluster.

    Args:
        paths: files, log folders, folders of logs and glob patterns (see :func:`expand_inputs`).
        preset: pipeline preset for every file.
        out_dir: folder for the heading tables (created), one ``<name>.<fmt>`` per input.
        client: a ``dask.distributed.Client`` or a scheduler address (``"tcp://host:8786"``) to run
            on a Dask cluster (whose workers must see the paths and have gyrocore installed);
            None: threads here.
        jobs: threads (default: every core). The Rust core and pyarrow release the GIL, so files
            run in parallel. Ignored with a Dask client.
        fmt: ``csv`` or ``parquet``.
        heading, chunk_rows, columns, mode, use_speed, **options: as for :func:`process_file`.
        progress: show a bar over the files on a terminal.

    Returns:
        Reports of all files, in input order: the ones that failed with their reason, the others
        with rows in and out.

    Raises:
        ValueError: no input, invalid options, two inputs mapping to one output, or an output
            folder inside an input folder (before any work).
    """
    start = time.perf_counter()
    items = [paths] if isinstance(paths, (str, Path)) else list(paths)
    inputs = expand_inputs(items)
    check_outside_inputs(items, Path(out_dir), inputs)
    if not inputs:
        raise ValueError("no input files")
    if fmt not in ("csv", "parquet"):
        raise ValueError(f"fmt must be 'csv' or 'parquet', got {fmt!r}")
    if jobs is not None and jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    if chunk_rows < 1:
        raise ValueError(f"chunk_rows must be >= 1, got {chunk_rows}")
    if heading not in io.HEADING_CONVENTIONS:
        raise ValueError(f"heading convention {heading!r} is not one of {', '.join(io.HEADING_CONVENTIONS)}")
    io.check_columns(columns)
    wholelog.check_mode(mode)
    _, overrides = split_options(options)
    # invalid parameters fail here, before any work (a stand-in bias keeps the check quiet)
    pipeline_overrides = _to_si(overrides)
    if mode == "whole":
        wholelog.refuse_tracking(pipeline_overrides)
        wholelog.Options.pop(pipeline_overrides)
    else:
        wholelog.refuse_whole_options(pipeline_overrides)
    Pipeline(preset, **(pipeline_overrides if has_bias_source(overrides) else {**pipeline_overrides, "bias": 0.0}))
    outputs = output_paths(inputs, Path(out_dir), fmt)
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    jobs_list = [
        _FileJob(p, o, preset, heading, chunk_rows, options, columns, mode, use_speed)
        for p, o in zip(inputs, outputs)
    ]
    if client is not None:
        reports = _run_on_dask(client, jobs_list, progress)
    else:
        reports = _run_on_threads(jobs_list, jobs or os.cpu_count() or 1, progress)
    return BatchReport(tuple(reports), time.perf_counter() - start)


def _run_job(job: _FileJob, stop: threading.Event | None = None) -> FileReport:
    """Run one job; any error becomes a failed report (a bad file fails alone)."""
    start = time.perf_counter()

    def check_stop(done: int, total: int | None, unit: str) -> None:
        if stop is not None and stop.is_set():
            raise _Stopped("stopped before the end")

    try:
        return job.run(check_stop)
    except Exception as e:  # noqa: BLE001 - every failure is reported and the batch goes on
        return job.failure(e, time.perf_counter() - start)


class _Stopped(Exception):
    """The batch was interrupted; the file's temporary output is removed."""


def _bar(total: int, enabled: bool) -> Any:
    """A bar over the files on stderr, only when asked for and stderr is a terminal."""
    tqdm = tqdm_class() if enabled and sys.stderr.isatty() else None
    return _NoBar() if tqdm is None else tqdm(total=total, unit="file", leave=False)


class _NoBar:
    """Stands in for a bar that is not drawn (tqdm would still start its monitor thread)."""

    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def update(self, n: int = 1) -> None:
        return None


def _run_on_threads(jobs: list[_FileJob], workers: int, progress: bool) -> list[FileReport]:
    stop = threading.Event()
    reports: dict[int, FileReport] = {}
    with _bar(len(jobs), progress) as bar:
        executor = ThreadPoolExecutor(max_workers=min(workers, len(jobs)), thread_name_prefix="gyrocore")
        try:
            futures = {executor.submit(_run_job, job, stop): i for i, job in enumerate(jobs)}
            for future in as_completed(futures):
                reports[futures[future]] = future.result()
                bar.update(1)
        except BaseException:
            stop.set()  # running files stop at their next chunk and remove their temporary output
            executor.shutdown(wait=True, cancel_futures=True)
            raise
        executor.shutdown()
    return [reports[i] for i in range(len(jobs))]


def _run_on_dask(client: Any, jobs: list[_FileJob], progress: bool) -> list[FileReport]:
    distributed = require("dask.distributed", "running on a Dask cluster")
    Client, dask_completed = distributed.Client, distributed.as_completed
    own = not isinstance(client, Client)
    if own:
        client = Client(client)
    reports: dict[int, FileReport] = {}
    try:
        futures = [
            client.submit(_run_job, job, key=f"gyrocore-{i}-{job.path.name}", pure=False) for i, job in enumerate(jobs)
        ]
        index = {f.key: i for i, f in enumerate(futures)}
        with _bar(len(jobs), progress) as bar:
            try:
                for future in dask_completed(futures):
                    i = index[future.key]
                    try:
                        reports[i] = future.result()
                    except Exception as e:  # noqa: BLE001 - a lost worker fails its file only
                        reports[i] = jobs[i].failure(e, 0.0)
                    bar.update(1)
            except BaseException:
                client.cancel(futures)
                raise
    finally:
        if own:
            client.close()
    return [reports[i] for i in range(len(jobs))]

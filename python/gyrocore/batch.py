"""Heading of whole files: one log streamed chunk by chunk (:func:`process_file`), or a fleet of
logs in parallel on all cores or on a Dask cluster (:func:`process_many`).

A log far larger than memory streams through :class:`gyrocore.Pipeline` in chunks (bit-identical to
one call), and its heading table (t, heading, rate, drift) is written as it goes to a temporary file
that replaces the output only when every row is through: an error or an interruption leaves no
half-written output, and the output is never the input. Each file gets a :class:`FileReport` with
its rows in and out; in a batch one bad file fails alone, with its reason, and the others finish.
A log folder with heading fixes (``fixes.csv``) is read whole and fused (:meth:`gyrocore.Log.process`).

    >>> from gyrocore.batch import process_many
    >>> summary = process_many(["logs/*.csv", "logs/drive_7"], out_dir="headings", jobs=2)  # doctest: +SKIP
    >>> print(summary)  # doctest: +SKIP
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from . import io, wholelog
from ._checks import check_count, public_dir, require_choice, require_flag, warn_of_file
from .pipeline import Pipeline, has_bias_source
from .pipeline_params import _to_si
from .batch_inputs import check_outside_inputs, check_unreached, complete_output, expand_inputs, output_paths
from .batch_job import Progress, _FileJob, split_options
from .batch_report import BatchReport, FileReport
from .batch_run import BatchInterrupted, check_client, check_workers, connected, run_on_dask, run_on_threads
from .io._paths import unfollowable
from .io.atomic import make_folder, refuse_present

if TYPE_CHECKING:
    from .fixes import FixesLike

__all__ = [
    "BatchReport", "FileReport", "Progress", "check_outside_inputs", "check_unreached", "complete_output", "expand_inputs",
    "output_paths", "process_file", "process_many", "split_options",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


def process_file(
    path: str | Path,
    out: str | Path,
    *,
    preset: str = "recommended",
    heading: str = "enu",
    chunk_rows: int = io.DEFAULT_CHUNK_ROWS,
    progress: Progress | None = None,
    columns: Sequence[str] | None = None,
    mode: str = "whole",
    use_speed: bool = True,
    use_fixes: bool = True,
    fixes: FixesLike | None = None,
    overwrite: bool = True,
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
            ``drift``, and ``heading_sigma`` for a log with heading fixes); the pipeline computes
            the rate and the drift only for their columns. None (default): the first four, and
            ``heading_sigma`` for a log with heading fixes.
        mode: ``whole`` (default): the bias from the log's rest window, or from every rest found in
            it (and where a log folder's odometry.csv speed is zero, unless ``use_speed`` is
            False), known from the first sample (:mod:`gyrocore.wholelog`). A given rest window is
            measured by a first pass up to its end (flat memory); finding the rests reads the
            log's times and rates into memory first (16 bytes a sample); the heading is then
            streamed. ``causal``: one streamed pass, what a :class:`gyrocore.Pipeline` gives; a
            preset that tracks rests (``tracked``) with the log's speed (a log folder's
            odometry.csv, a file's speed column) reads the log whole, as
            :meth:`gyrocore.Log.process` does, the tracker taking the speed at its own times.
        use_speed: a log folder's odometry.csv speed (or a file's speed column) finds the rests of
            whole mode and feeds a rest-tracking preset, unless False (the rate alone).
        use_fixes: a log folder's ``fixes.csv`` (heading fixes, docs/fixes.md) is fused unless
            False. Such a log is read into memory whole (the smoother of whole mode needs every
            sample) and processed by :meth:`gyrocore.Log.process`; the report holds the fixes'
            counts.
        fixes: heading fixes for this input instead of a folder's own (:data:`gyrocore.fixes.FixesLike`:
            a :class:`gyrocore.fixes.Fixes`, a fixes or gnss file); the input is then read whole
            and fused as a folder with ``fixes.csv`` is.
        overwrite: replace a file at ``out`` (default). False: one there before is refused before
            any work, and one that appears there while the log is processed (another run's
            output) is kept; FileExistsError either way.
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
    _check_run(mode, chunk_rows, ("use_speed", use_speed), ("use_fixes", use_fixes), ("overwrite", overwrite))
    job = _FileJob(
        Path(path), Path(out), preset, heading, chunk_rows, options, columns, mode, use_speed, use_fixes=use_fixes,
        fixes=fixes,
    )
    job.overwrite = overwrite
    io.check_not_input(out, [path])  # the output that is the input is refused as such, not as existing
    refuse_present([out], overwrite, "overwrite=True")
    return job.run(progress)


def _check_run(mode: str, chunk_rows: object, *flags: tuple[str, object]) -> None:
    """The run's mode, rows per chunk and switches, checked before any work: ``chunk_rows=1.5``
    was a bare "'float' object cannot be interpreted as an integer" (True a chunk of one row), and a
    switch given as text was read as True (``use_speed="no"``, ``skip_existing="no"``)."""
    wholelog.check_mode(mode)
    check_count("chunk_rows", chunk_rows)
    for name, value in flags:
        require_flag(name, value)


def check_out_dir(out_dir: Path) -> None:
    """Refuse an output folder that is a file or a link that cannot be followed (mkdir would say
    only "File exists")."""
    if os.path.lexists(out_dir) and not out_dir.is_dir():
        what = "not a folder" if out_dir.exists() else unfollowable(out_dir)
        raise ValueError(f"{out_dir}: {what}, so no outputs can go into it; give a folder, or one output "
                         "file ending in .csv or .parquet")


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
    columns: Sequence[str] | None = None,
    mode: str = "whole",
    use_speed: bool = True,
    skip_existing: bool = False,
    use_fixes: bool = True,
    overwrite: bool = True,
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
        heading, chunk_rows, columns, mode, use_speed, use_fixes, **options: as for
            :func:`process_file` (each log folder's own ``fixes.csv`` is fused).
        progress: show a bar over the files on a terminal.
        skip_existing: a file whose output exists already is not processed, and its report says
            it was skipped (:attr:`BatchReport.skipped`): a batch that was interrupted or failed in
            part goes on where it stopped. An output that exists is complete (see
            :func:`complete_output`); neither its input nor its options are compared. Without it
            an existing output is replaced.
        overwrite: replace an output that exists (default). False: outputs there before are
            refused before any work (FileExistsError; with ``skip_existing`` a complete one is
            skipped), and one that appears while its input is processed (another run's) is kept,
            and that file fails with the reason.

    Returns:
        Reports of all files, in input order: the ones that failed with their reason, the ones
        skipped, the others with rows in and out.

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
    if client is not None:
        check_client(client)
    if jobs is not None:  # 1.5 threads were taken
        check_count("jobs", jobs)
        if client is not None:  # the cluster's workers ran the files, and jobs was left unused without a word
            raise ValueError(f"jobs={jobs} is the number of threads here, and client= runs the files on the Dask "
                             "cluster's workers (as many as it has): give one of them (--jobs or --scheduler)")
    require_choice("heading convention", heading, io.HEADING_CONVENTIONS)
    if columns is not None:
        io.check_columns(columns)
    _check_run(mode, chunk_rows, ("use_speed", use_speed), ("skip_existing", skip_existing), ("progress", progress),
               ("use_fixes", use_fixes), ("overwrite", overwrite))
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
    check_unreached(items, [Path(out_dir), *outputs])
    check_out_dir(Path(out_dir))
    refuse_present([o for o in outputs if not (skip_existing and complete_output(o))], overwrite, "overwrite=True")
    # a scheduler's address is connected to before the output folder is made: one that no
    # scheduler answers at, or that Dask cannot read, left an empty output folder behind
    client, own = connected(client) if client is not None else (None, False)
    try:
        if client is not None:
            check_workers(client)
        make_folder(Path(out_dir))
        jobs_list = [
            _FileJob(p, o, preset, heading, chunk_rows, options, columns, mode, use_speed, skip_existing, use_fixes)
            for p, o in zip(inputs, outputs)
        ]
        for job in jobs_list:  # raised below, from the caller's line, not a worker thread's
            job.raise_again, job.overwrite = False, overwrite
        if client is not None:
            reports = run_on_dask(client, jobs_list, progress)
        else:
            reports = run_on_threads(jobs_list, jobs or os.cpu_count() or 1, progress)
    except BatchInterrupted as e:  # the files finished before it say what they warned of too
        for report in e.finished:
            warn_of_file(report.input, report.warnings)
        raise
    finally:
        if own:
            client.close()
    for report in reports:
        warn_of_file(report.input, report.warnings)
    return BatchReport(tuple(reports), time.perf_counter() - start)

"""One file's job in a batch: stream a log through the pipeline into its output table, and report
what it did (:class:`~gyrocore.batch_report.FileReport`)."""

from __future__ import annotations

import copy
import dataclasses
import os
import socket
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from dataclasses import fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from . import _signals, io, rests, wholelog
from ._arrays import FloatArray
from ._checks import collected, no_usable_log, warn, warn_of_file
from ._gap_turn import LongestGap
from ._motion import TURNING
from ._gyrocore import SampleError, __version__
from .batch_inputs import complete_output
from .batch_report import FileReport, input_repairs
from .io import atomic
from .io._columns import concat
from .io._kitti import KIND as KITTI_KIND
from .io._kitti import oxts_tables
from .io._logfolder import FIXES_CSV, ODOMETRY_CSV, from_stationary, read_odometry
from .io._paths import error_text, has_file
from .io.log import tracks_rests
from .io.source import SPEED_COLUMN
from .pipeline import HeadingResult, has_bias_source, uses_static_bias
from .pipeline_params import _to_si, implausible_bias, unmeasured_bias
from .window import RestWindowError, Window, as_command_line_says, time_range

if TYPE_CHECKING:
    from .fixes import FixesLike

#: ``progress(done, total, unit)``: called after each chunk with the progress through the input.
Progress = Callable[[int, "int | None", str], None]

_READ_OPTIONS = {f.name for f in fields(io.ReadOptions)}


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
        columns: Sequence[str] | None = None,
        mode: str = "whole",
        use_speed: bool = True,
        skip_existing: bool = False,
        use_fixes: bool = True,
        fixes: FixesLike | None = None,
    ):
        self.path, self.out, self.preset, self.heading, self.chunk_rows = path, out, preset, heading, chunk_rows
        self.mode, self.use_speed, self.skip_existing, self.use_fixes = mode, use_speed, skip_existing, use_fixes
        self.fixes, self.raise_again = fixes, True  # False: a batch raises them in the caller's thread
        #: False: an output that appears while the file is processed (another run's) is kept, and
        #: this file fails (see :class:`gyrocore.io.atomic.StagedFile`)
        self.overwrite = True
        #: what replaces such an output, as the user knows it (the command line's ``--overwrite``)
        self.replace_option = atomic.replacing_option("overwrite=True")
        self.read_options, self.overrides = split_options(options)
        #: None: every column of :data:`io.OUTPUT_COLUMNS`, and the heading's sigma for a log with fixes
        self.columns = None if columns is None else io.check_columns(columns)
        # the core computes the heading always, the rate and drift only for a column of theirs
        self.outputs = ("heading", *(c for c in ("rate", "drift") if c in (self.columns or io.OUTPUT_COLUMNS)))
        self.rows_in = 0
        #: what looked wrong so far, for the report even of a file that then fails
        self.notes: list[str] = []
        #: called before each chunk of every pass over the input; raises to stop the file (a batch's stop)
        self.stop: Callable[[], None] | None = None
        #: the mark of the output's temporary file (:func:`gyrocore.io.atomic.tagged`); empty: none
        self.tag = ""
        #: on a Dask worker, the host of the client, which found the input (:meth:`for_a_worker`)
        self.client_host: str | None = None
        #: on a Dask worker, the gyrocore of the client (:meth:`for_a_worker`): the cluster's workers
        #: are asked theirs before the batch, a worker that joins later only here
        self.client_version: str | None = None

    def run(self, progress: Progress | None = None, stop: Callable[[], None] | None = None) -> FileReport:
        """The file processed (``progress`` after each chunk written), or stopped where ``stop``
        raises, which is called before each chunk read, also by the first pass that plans the bias."""
        self.stop = stop
        self._check_seen_here()
        # checked where the file is written (a Dask worker): its input is not even opened
        if self.skip_existing and complete_output(self.out):
            return FileReport(str(self.path), str(self.out), 0, 0, 0.0, output_existed=True)
        # every warning the file raises, from opening it to its last chunk, is a note of its
        # report, also of a file that then fails (what came before an error often says why)
        # the output was refused before the job where it was there (process_file, process_many, the
        # command line): one found there now was written meanwhile, by another run
        with (_noted(self.notes, self.path if self.raise_again else None), atomic.tagged(self.tag),
              atomic.outputs_checked(self.replace_option)):
            return self._stream(progress)

    def _stream(self, progress: Progress | None) -> FileReport:
        """Plan the bias and stream the file into its output."""
        start = time.perf_counter()
        source = io.open_source(self.path, self.read_options)
        io.check_output(self.out, source)
        overrides = dict(self.overrides)
        wholelog.check_parameters(self.preset, overrides)
        if (implausible := implausible_bias(_to_si(overrides))) is not None:  # a note of the file's report
            warn(implausible)
        window = overrides.get("bias_window")
        if window is not None:
            t0 = _first_time(source)
            if isinstance(window, Window):  # a window after the first sample: the log says where that is
                overrides["bias_window"] = window.resolve(t0)
            if overrides["bias_window"][1] < t0:
                raise ValueError(
                    f"{source.data_path}: the rest window {_window_text(window)} ends before the first sample; "
                    + time_range(t0, plus_t=True)
                )
        own = self.use_fixes and source.kind == "log folder" and (source.path / FIXES_CSV).is_file()
        if own or self.fixes is not None or self._tracks_with_speed(source, overrides):
            return self._fused(source, overrides, start, progress)
        if "heading_sigma" in (self.columns or ()):
            raise ValueError(f"{self.path}: the heading_sigma column comes with heading fixes, and this log has none "
                             f"(a log folder's {FIXES_CSV}{'' if self.use_fixes else ', which use_fixes=False leaves out'})")
        from_meta = False
        if uses_static_bias(self.preset) and not has_bias_source(overrides) and source.stationary is not None:
            overrides["bias_window"], from_meta = source.stationary, True
        plan = self._plan(source, overrides, from_meta)
        with _said_for_the_file():
            pipeline = plan.pipeline(self.preset)  # a bias constant over the log: the core's bias=, no copy per chunk
        check = io.UnitCheck(source.options)
        # the chunks' warnings (_said_for_the_file): the file's report says all but one below; that
        # one, a causal rest window with a turn in it, comes once, when its chunk closes the window
        said: list[str] = []
        gap, gaps = LongestGap(), 0
        with io.HeadingWriter(self.out, heading=self.heading, columns=self.columns or io.OUTPUT_COLUMNS,
                              replace=self.overwrite) as writer:
            for chunk in self._chunks(source):
                check.update(chunk.t, chunk.rate)
                try:
                    with collected(said):
                        result = pipeline.process(
                            chunk.t,
                            plan.corrected(chunk.t, chunk.rate),
                            index_offset=chunk.first_row,
                            outputs=self.outputs,
                        )
                except SampleError as e:
                    raise self._at_sample(source, e, check) from None
                except ValueError as e:
                    raise _in_file(source, e, from_meta) from None
                writer.write(result)
                gaps, gaps_before = int(pipeline.report["gaps"]), gaps
                gap.update(result.t, result.heading, gapped=gaps > gaps_before)
                self.rows_in += len(chunk)
                if progress is not None:
                    progress(chunk.done, source.progress_total, source.progress_unit)
            if self.rows_in == 0:
                raise ValueError(f"{source.data_path}: no samples")
            unusable = pipeline.report["held"] + pipeline.report["skipped"]
            if unusable == self.rows_in:  # held or skipped, all of them: a heading of 0 made of no data
                raise ValueError(f"{source.data_path}: {no_usable_log(self.rows_in)}")
            if check.error() is not None:
                raise ValueError(f"{source.data_path}: {check.error()}")
            try:
                pipeline.finish()
            except ValueError as e:
                raise _in_file(source, e, from_meta) from None
            if writer.rows != self.rows_in:  # the pipeline returns one row per sample; prove it
                raise RuntimeError(f"{self.path}: {self.rows_in} rows read but {writer.rows} written")
        policy = pipeline.report
        gap_turn = gap.turn_across(policy["longest_gap"])
        # the plan's warning is about the bias of the output (taken as 0 in causal mode without a
        # rest window): said once the output is written, not for a file that fails on the way
        turned = [m for m in said if m.startswith(TURNING)]  # a causal rest window with a turn in it, once
        repairs = input_repairs({**policy, "gap_turn": gap_turn})
        for message in [*([plan.warning] if plan.warning else []), *check.problems(), *repairs, *turned]:
            warn(message)
        return FileReport(
            str(self.path),
            str(self.out),
            self.rows_in,
            writer.rows,
            time.perf_counter() - start,
            None,
            tuple(dict.fromkeys(self.notes)),  # all of them: each warning is collected as it is raised
            plan.source,
            plan.rests,
            int(policy["held"]),
            int(policy["skipped"]),
            int(policy["gaps"]),
            policy["longest_gap"],
            gap_turn=gap_turn,
        )

    def _chunks(self, source: io.GyroSource) -> Iterator[io.Chunk]:
        """The input's chunks, each read only once the run may go on: no signal came (one whose
        KeyboardInterrupt a library swallowed), and the batch's :attr:`stop` does not raise. Every
        pass checks: an interrupted batch waited for the first pass over each running file, which
        reads the whole log to find its rests (4.6 s after Ctrl-C for two CSV files of 6e6 samples)."""
        for chunk in source.chunks(self.chunk_rows):
            _signals.check()
            if self.stop is not None:
                self.stop()
            yield chunk

    def _at_sample(self, source: io.GyroSource, e: SampleError, check: io.UnitCheck) -> ValueError:
        """The error of a bad sample, at its line of the file, with what to do; ``rows_in`` then
        counts the samples before it."""
        # every sample before the bad one was read and is good: the count up to the failure,
        # whatever the chunks (it stopped at the last whole chunk before it)
        self.rows_in = int(e.index)
        # a timestamp beyond the core's limits is most often an epoch in a smaller unit; a bad
        # reading, an empty cell a phone app left, has an option ("drop or fill them first" sent
        # users to edit the file); a file's chunks repeating a time at their edge is the file's
        # duplicate, which sorting the log mends, not a stream's chunk sent again (the core's words)
        return ValueError(source.locate(e, check.time_fix()))

    def _tracks_with_speed(self, source: io.GyroSource, overrides: dict[str, Any]) -> bool:
        """Whether a causal run tracks rests (``tracked``, ``track_rests=True``) with the speed of
        the log (a log folder's odometry.csv, a file's speed column): the tracker takes the speed
        at its own times, as :meth:`gyrocore.Log.process` gives it, which a stream of the gyro's
        chunks does not carry (it ran on the rate alone, another heading without a word)."""
        if self.mode != "causal" or not self.use_speed or not tracks_rests(self.preset, overrides):
            return False
        if source.kind == "log folder":
            return has_file(source.path / ODOMETRY_CSV)
        if source.kind == KITTI_KIND:
            return True  # its forward speed vf is its odometry
        return bool(source.extra_columns((SPEED_COLUMN,)))

    def _fused(
        self, source: io.GyroSource, overrides: dict[str, Any], start: float, progress: Progress | None
    ) -> FileReport:
        """A log with heading fixes (given, or its folder's ``fixes.csv``), or whose rests are
        tracked with its speed in causal mode: read whole, as the smoother of whole mode needs
        every sample and the tracker the speed at its own times, processed by
        :meth:`gyrocore.Log.process`, written in one piece."""
        reading = {f.name: getattr(self.read_options, f.name) for f in fields(io.ReadOptions)}
        log = io.read_log(self.path, use_fixes=self.fixes is None and self.use_fixes, **reading)
        self.rows_in = len(log.t)
        try:
            result = log.process(self.preset, mode=self.mode, use_speed=self.use_speed, fixes=self.fixes, **overrides)
        except SampleError as e:
            check = io.UnitCheck(source.options)
            check.update(log.t, log.rate)
            raise self._at_sample(source, e, check) from None
        except ValueError as e:
            raise _in_file(source, e, False, self._fixes_file(source)) from None
        written = _write_result(self.out, result, self.heading, self.columns, self.overwrite)
        if progress is not None:
            progress(len(result), len(result), "rows")
        assert result.report is not None
        policy = result.report  # what it repaired, the pipeline said already (the log was one block)
        fusion = result.fusion
        gap = LongestGap()
        gap.update(result.t, result.heading, gapped=policy["gaps"] > 0)
        return FileReport(str(self.path), str(self.out), self.rows_in, written, time.perf_counter() - start, None,
                          tuple(dict.fromkeys(self.notes)), result.bias_source, result.rests, int(policy["held"]),
                          int(policy["skipped"]), int(policy["gaps"]), policy["longest_gap"],
                          gap_turn=gap.turn_across(policy["longest_gap"]),
                          fixes=None if fusion is None else dict(fusion.counts),
                          fixes_file=None if fusion is None else self._fixes_file(source))

    def _fixes_file(self, source: io.GyroSource) -> str:
        """Where the fixes fused came from: their file, ``given`` (in memory), or the folder's."""
        if self.fixes is None:
            return str(source.path / FIXES_CSV)
        return str(self.fixes) if isinstance(self.fixes, (str, os.PathLike)) else "given"

    def _plan(self, source: io.GyroSource, overrides: dict[str, Any], from_meta: bool) -> wholelog.BiasPlan:
        """Where the bias comes from: in whole mode a first pass over the file (see
        :func:`gyrocore.wholelog.plan_stream`), in causal mode the pipeline's own rest window."""
        if self.mode == "causal":
            wholelog.refuse_whole_options(_to_si(overrides))
            causal = wholelog.causal_source(self.preset, _to_si(overrides))
            warning = unmeasured_bias(self.preset, _to_si(overrides))
            if warning is not None:  # the log gave no rest window either (its meta.json's is taken)
                warning += f" {wholelog.BIAS_OPTIONS_HINT}"
            return wholelog.BiasPlan(causal, overrides=overrides, warning=warning)
        wholelog.refuse_tracking(_to_si(overrides))

        def chunks() -> Iterator[tuple[FloatArray, FloatArray]]:
            for chunk in self._chunks(source):
                yield chunk.t, chunk.rate

        def read_all() -> tuple[FloatArray, FloatArray, FloatArray | None]:
            read = list(self._chunks(source))
            t, rate = concat([c.t for c in read]), concat([c.rate for c in read])
            return t, rate, self._speed(source, t)

        try:
            return wholelog.plan_stream(self.preset, overrides, chunks, read_all)
        except SampleError:
            # A rest's measurement saw a slice of the log: the streamed pass names the row.
            return wholelog.BiasPlan("none: the log has invalid samples", overrides=wholelog.without_bias(_to_si(overrides)))
        except ValueError as e:
            raise _in_file(source, e, from_meta) from None

    def _speed(self, source: io.GyroSource, t: FloatArray) -> FloatArray | None:
        """The speed [m/s] at each of the gyro's times ``t`` whose stops whole mode takes as rests:
        a log folder's odometry.csv, a KITTI OXTS folder's vf, a file's ``speed`` column; None without one or with
        ``--no-speed``."""
        if not self.use_speed:
            return None
        if source.kind == KITTI_KIND:  # read_log's odometry too: the OXTS's forward speed vf, frame by frame
            odometry, where = oxts_tables(source)[1], f"{source.data_path} (vf)"
        elif source.kind != "log folder":
            return source.speed(self.chunk_rows)
        else:
            odometry, where = read_odometry(source.path), str(source.path / ODOMETRY_CSV)
        if not odometry:
            return None
        return rests.speed_on(t, odometry["t"], odometry["speed"], where=where)

    def for_a_worker(self, tag: str) -> _FileJob:
        """This job with its input and output as absolute paths, for a Dask worker: its working
        folder is not this process's (another machine, a process started elsewhere), and a
        relative path named another file there, or none (``logs/d0.csv: no such file or folder``).
        Its temporary output is marked ``tag``, that the batch removes what a worker that dies
        leaves of it (:func:`gyrocore.io.atomic.discard_tagged`)."""
        job = copy.copy(self)
        # joined to the working folder, not tidied by their text (os.path.abspath): the system takes
        # link/../d0.csv through the link, and the tidied ./d0.csv was another file
        job.path, job.out, job.tag = Path.cwd() / self.path, Path.cwd() / self.out, tag
        job.notes = []  # its own, not this job's: a cluster of threads may run it without a copy
        job.client_host = socket.gethostname() if os.path.lexists(self.path) else None
        job.client_version = __version__
        return job

    def _check_seen_here(self) -> None:
        """On a Dask worker, refuse to run another gyrocore than the client's (a worker that joined
        after the batch began, which :func:`gyrocore.batch_run.check_workers` did not ask: its
        headings may differ from a run on the client, without a word), and an input or output
        folder that the client found and this machine does not: they said ``no such file or
        folder`` and ``the folder ... does not exist; create it``, of files the user sees there."""
        if self.client_version is not None and self.client_version != __version__:
            raise ValueError(f"the Dask worker at {socket.gethostname()} runs gyrocore {__version__}, the client "
                             f"{self.client_version} (a worker that joined after the batch began?): install "
                             f"gyrocore[dask]=={self.client_version} on every worker")
        if self.client_host is None:
            return
        for path, what in ((self.path, "input"), (self.out.parent, "output folder")):
            if not os.path.lexists(path):
                raise FileNotFoundError(
                    f"{path}: no such {what} on the Dask worker at {socket.gethostname()}, though the client at "
                    f"{self.client_host} found it: the workers must see the inputs and the output folder at the "
                    "paths the client gives (a shared filesystem, mounted at the same place)")

    def staging_folder(self) -> Path:
        """Where the output's temporary file is written: the folder of the file it replaces (see
        :class:`gyrocore.io.atomic.StagedFile`)."""
        return Path(os.path.realpath(self.out)).parent

    def as_given(self, report: FileReport, sent: _FileJob) -> FileReport:
        """The report of ``sent`` (this job :meth:`for_a_worker`) naming the input and the output
        as this job does, as a run here names them."""

        def named(text: str) -> str:
            return text.replace(str(sent.path), str(self.path)).replace(str(sent.out), str(self.out))

        return dataclasses.replace(
            report, input=str(self.path), output=None if report.output is None else str(self.out),
            error=None if report.error is None else named(report.error), warnings=tuple(map(named, report.warnings)),
            bias_source=None if report.bias_source is None else named(report.bias_source),
            fixes_file=None if report.fixes_file is None else named(report.fixes_file),
        )

    def failure(self, error: BaseException | str, seconds: float) -> FileReport:
        """The report of this file failed with ``error`` (or for the reason said, of the file)."""
        if isinstance(error, str):
            reason = f"{self.path}: {error}"
        elif isinstance(error, (ValueError, TypeError, OSError, ImportError)):
            reason = error_text(error)
        else:
            reason = repr(error)
        failed = reason or type(error).__name__
        return FileReport(str(self.path), None, self.rows_in, 0, seconds, failed, tuple(dict.fromkeys(self.notes)))


def _write_result(out: Path, result: HeadingResult, heading: str, columns: Sequence[str] | None,
                  overwrite: bool = True) -> int:
    """Write a result held in memory to ``out`` in one piece (``columns`` None: every column of
    :data:`io.OUTPUT_COLUMNS`, and the heading's sigma where heading fixes gave one); the rows written."""
    if columns is None:
        columns = (*io.OUTPUT_COLUMNS, *(("heading_sigma",) if result.heading_sigma is not None else ()))
    with io.HeadingWriter(out, heading=heading, columns=columns, replace=overwrite) as writer:
        writer.write(result)
    return writer.rows


def _said_for_the_file() -> AbstractContextManager[None]:
    """Drops the warnings the pipeline raises about one chunk (its units, on the first; what it
    repaired so far; no bias in causal mode): the file's report says each once for the whole file,
    whatever the chunks, naming the options that fix it (the unit check, :func:`~gyrocore.batch_report.input_repairs`, the
    plan's warning), and a caller of the API gets the report's warnings, no others."""
    return collected([])


@contextmanager
def _noted(notes: list[str], path: Path | None) -> Iterator[None]:
    """Run the block keeping each :class:`InputWarning` it raises as a note of the file's report
    (the command line prints the notes, with the file's name), and (``path`` given) raise them again."""
    try:
        with collected(notes):  # per thread: the files of a batch run side by side
            yield
    finally:  # also when the block fails: what came before an error often says why
        if path is not None:
            warn_of_file(str(path), notes)


def _window_text(window: Window | tuple[float, float]) -> str:
    return str(window) if isinstance(window, Window) else f"{window[0]:.10g} .. {window[1]:.10g} s"


def _first_time(source: io.GyroSource) -> float:
    """The first timestamp of an input [s] (reads its first block only)."""
    first = next(source.chunks(1), None)  # the reader closes its file as the generator goes
    if first is None:
        raise ValueError(f"{source.data_path}: no samples")
    return float(first.t[0])


def _in_file(source: io.GyroSource, error: ValueError, window_from_meta: bool, fixes: str | None = None) -> ValueError:
    """The pipeline's error about a file, naming it (unless a reader did, or the error is about the
    fixes file ``fixes``, which it names), or meta.json where the rest window is its."""
    if window_from_meta and isinstance(error, RestWindowError):
        return ValueError(from_stationary(source.path, error))
    text = as_command_line_says(str(error))  # a batch's windows take +T
    # named already: by the data file, or by another file of its log folder (odometry.csv)
    named = str(source.data_path) in text or (source.path.is_dir() and text.startswith(f"{source.path}{os.sep}"))
    named = named or (fixes is not None and text.startswith(f"{Path(fixes)}: "))
    return ValueError(text if named else f"{source.data_path}: {text}")

"""Methods (a preset with overrides) run on logs and scored against each log's reference, and
the tables of the scores (the plots: :mod:`gyrocore.evaluate_plot`); :mod:`gyrocore.evaluate`
re-exports the public names.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from . import deadreckon
from ._arrays import as_float_array, covered_share, span_text
from ._checks import check_number, json_ready, require_finite, require_flag, warn
from .batch_report import failed_line
from .evaluate_metrics import HeadingErrors, heading_errors, improvement
from .evaluate_plot import evaluation_pyplot, plot_log, plot_path
from .io import Log, read_log
from .io._logfolder import REFERENCE_CSV
from .io.atomic import kept_outputs
from .pipeline import HeadingResult, has_bias_source, process, recommended_preset, uses_static_bias
from .rests import rest_lines
from .wholelog import Rest, check_mode, check_parameters


@dataclass(frozen=True)
class Method:
    """A way to compute the heading: a preset with parameter overrides (SI names, see
    :func:`gyrocore.parameters`). ``name`` labels it in tables and plots."""

    name: str
    preset: str
    overrides: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        # Checked when built, in Pipeline's words: a preset 'xx' was taken, and overrides given as a
        # list failed inside a comparison ("dictionary update sequence element #0").
        if not isinstance(self.overrides, Mapping):
            raise TypeError(f"method {self.name!r}: overrides must be a mapping of parameter names to values (as "
                            f"Pipeline(preset, **overrides) takes them), not {type(self.overrides).__name__}")
        check_parameters(self.preset, dict(self.overrides))

    @classmethod
    def from_preset(cls, preset: str) -> "Method":
        """The preset as it is; ``recommended`` keeps its name and runs what it stands for."""
        return cls(preset, recommended_preset() if preset == "recommended" else preset)

    @property
    def _runs_as(self) -> str:
        """The name the pipeline is given: ``recommended`` as the user named it, so that its words
        name what was asked for (they named the preset it stands for), else the preset."""
        return "recommended" if self.name == "recommended" and self.preset == recommended_preset() else self.preset

    def run(
        self, log: Log, *, bias_duration: float | None = None, mode: str = "whole", use_speed: bool = True
    ) -> tuple[HeadingResult, str]:
        """Heading of ``log`` and where its static bias came from (the result's ``bias_source``).

        The bias: the method's own, else the log's rest window or ``bias_duration``
        (:func:`log_bias`), else in whole mode every rest found in the log (with its odometry's
        speed unless ``use_speed`` is False), in causal mode 0.
        """
        overrides = dict(self.overrides)
        if uses_static_bias(self.preset) and has_bias_source(overrides):
            return log.process(self._runs_as, mode=mode, use_speed=use_speed, **overrides), "given by the method"
        # the log's own rest window is Log.process's to apply: its error then names meta.json
        if uses_static_bias(self.preset) and log.stationary is None:
            if bias_duration is not None:
                overrides.update(log_bias(log, bias_duration=bias_duration)[0])
            elif mode == "causal":
                # said here rather than warned by the pipeline: a bias of 0 is the causal baseline
                bias, source = log_bias(log)
                return log.process(self._runs_as, mode=mode, use_speed=use_speed, **overrides, **bias), f"{source} (causal)"
        result = log.process(self._runs_as, mode=mode, use_speed=use_speed, **overrides)
        return result, result.bias_source


def log_bias(log: Log, *, bias_duration: float | None = None) -> tuple[dict[str, Any], str]:
    """Where the static bias of ``log`` comes from: pipeline overrides and a description.

    The log's rest window (meta.json) when it has one; otherwise the first ``bias_duration``
    seconds while moving (good only if the drive starts straight) when given, else a bias of 0.
    """
    if log.stationary is not None:
        return {"bias_window": log.stationary}, f"rest window [{log.stationary[0]:.3f}, {log.stationary[1]:.3f}] s"
    if bias_duration is not None:
        return {"bias_duration": bias_duration}, f"first {bias_duration:g} s (moving)"
    return {"bias": 0.0}, "none (no rest window; 0)"


@dataclass(frozen=True, repr=False)
class Score:
    """One method scored on one log."""

    log: str
    method: Method
    errors: HeadingErrors
    improvement: float
    """E_psi of plain integration / E_psi of this method (HDR Table II)."""
    bias_source: str
    return_error_deg: float | None = None
    """Return orientation error (FOG section 4.1) where the reference path is closed, else None."""
    position: deadreckon.PositionErrors | None = None
    """Dead reckoning with this heading and the log's odometry, against the reference track."""
    rests: tuple[Rest, ...] = ()
    """The rests whose bias the method used in whole mode."""
    path: str | None = None
    """Where the log was read, as given (:attr:`gyrocore.Log.path`); None for a log built in memory."""

    def __repr__(self) -> str:
        """One line (a list of scores shows as one line each): the log, the method and its figures;
        :meth:`as_dict` has every field."""
        e = self.errors
        extra = "" if self.return_error_deg is None else f", return error {self.return_error_deg:.3f} deg"
        if self.position is not None:
            extra += f", final position error {self.position.final_error_percent:.3g} %"
        return (f"Score({self.log!r}, {self.method.name!r}: E_psi {e.e_psi_deg:.3f} deg, NE_psi "
                f"{e.ne_psi_deg_per_min:.3f} deg/min, improvement {self.improvement:.3g}{extra})")

    @property
    def label(self) -> str:
        """How tables name the log: its path (names repeat), else its name."""
        return self.path if self.path is not None else self.log

    def as_dict(self) -> dict[str, Any]:
        """Flat JSON-ready dict: ``path`` and ``name`` (the log's), ``preset`` (the method's name),
        ``base_preset``, the heading metrics, ``improvement``, ``bias_source``, ``rests``,
        ``return_error_deg`` and, where the log has odometry, ``position_*_m`` and
        ``position_final_error_percent``; a value that is not finite is None (JSON has no inf: a
        method with no error at all improves infinitely)."""
        row: dict[str, Any] = {"path": self.path, "name": self.log, "preset": self.method.name,
                               "base_preset": self.method.preset}
        row.update(self.errors.as_dict())
        row["improvement"] = self.improvement
        row["bias_source"] = self.bias_source
        row["rests"] = [r.as_dict() for r in self.rests]
        row["return_error_deg"] = self.return_error_deg
        if self.position is not None:
            row.update({f"position_{k}": v for k, v in self.position.as_dict().items()})
        if self.method.overrides:
            row["overrides"] = dict(self.method.overrides)
        return json_ready(row)


#: A reference path that ends within this fraction of its length from its start is closed.
CLOSED_FRACTION = 0.01


def is_closed_path(x: ArrayLike, y: ArrayLike, *, fraction: float = CLOSED_FRACTION) -> bool:
    """Whether a track [m] ends within ``fraction`` of its length from where it started.

    Raises:
        ValueError: ``x`` and ``y`` of different lengths, or a position or ``fraction`` that is not
            finite (``fraction`` >= 0), naming the first: each answered False.
    """
    xa, ya = as_float_array("x", x), as_float_array("y", y)
    if len(xa) != len(ya):
        raise ValueError(f"y has {len(ya)} samples but x has {len(xa)}")
    require_finite("x", xa)
    require_finite("y", ya)
    check_number("fraction", fraction, strict=False)
    length = float(np.hypot(np.diff(xa), np.diff(ya)).sum())
    return length > 0 and math.hypot(xa[-1] - xa[0], ya[-1] - ya[0]) <= fraction * length


def score(log: Log, method: Method, result: HeadingResult, raw: HeadingErrors, bias_source: str) -> Score:
    """Score one heading of ``log`` (see :class:`Score`); ``raw`` is plain integration's errors. A
    heading fused with fixes is absolute, and scored so (no alignment at the start)."""
    errors = heading_errors(result.t, result.heading, *log.reference(), absolute=result.fusion is not None)
    # Aligned at the start, the error at the end of a closed path is its measured minus its actual
    # rotation: the return orientation error.
    closed = log.has_track and is_closed_path(*log.track()[1:]) and result.fusion is None
    return_error = errors.final_error_deg if closed else None
    position = None
    if log.has_track and log.t_odometry is not None and log.speed is not None and _odometry_overlaps(log, result):
        track = deadreckon.dead_reckon_log(log, result)
        position = deadreckon.position_errors(track, *log.track())
    return Score(
        log.name, method, errors, improvement(raw, errors), bias_source, return_error, position, result.rests, log.path
    )


#: A reference that covers less than this share of the log's time span: its scores are of that
#: part alone, which a warning says (a reference.csv cut short, or partly in another clock).
MIN_REFERENCE_SHARE = 0.5


def warn_partial_reference(log: Log) -> None:
    """Warn when the reference of ``log`` covers less than :data:`MIN_REFERENCE_SHARE` of its
    gyro's time span, naming both spans and the reference's file: the table shows the scores of
    the overlap as the log's. A reference with no overlap is left to the error of scoring it."""
    t_ref, _ = log.reference()
    share = covered_share(log.t, t_ref)
    if 0 < share < MIN_REFERENCE_SHARE:
        warn(
            f"{_reference_source(log)}: the reference covers {share * log.duration:.3g} s of the log's "
            f"{log.duration:.3g} s ({100 * share:.3g} %): it runs from {span_text(t_ref)}, the gyro from "
            f"{span_text(log.t)}; only that part is scored"
        )


def _reference_source(log: Log) -> str:
    """Where the reference of ``log`` was read: a log folder's reference.csv, the log's own file
    (its heading_true column), or ``log NAME`` for a log built in memory."""
    if log.path is None:
        return f"log {log.name}"
    return str(Path(log.path) / REFERENCE_CSV) if Path(log.path).is_dir() else log.path


def _odometry_overlaps(log: Log, result: HeadingResult) -> bool:
    """Whether two odometry samples lie inside the heading's span (dead reckoning needs them); if
    not, a warning: the log is scored without its track, as ``gyrocore process`` finds its rests
    without the speed (an odometry.csv in another time base, e.g. relative against epoch seconds)."""
    t = log.t_odometry
    assert t is not None  # the caller checked
    inside = np.count_nonzero((t >= result.t[0]) & (t <= result.t[-1]))
    if inside >= 2:
        return True
    times = f"times {t[0]:.10g} .. {t[-1]:.10g} s" if len(t) else "the odometry has none"
    warn(
        f"log {log.name}: {inside} odometry sample(s) ({times}) "
        f"lie inside the heading's {result.t[0]:.10g} .. {result.t[-1]:.10g} s: no dead reckoning; give the "
        "odometry's times in the gyro's clock, in seconds"
    )
    return False


#: The parameters that say how a log's samples are taken, which the raw baseline shares with the
#: methods scored against it.
INPUT_POLICY = ("nonfinite", "gap_limit", "gap_action")


def raw_baseline(log: Log, methods: Sequence[Method]) -> HeadingResult:
    """Plain integration of ``log``, the baseline of :func:`improvement`, under the methods' input
    policy (:data:`INPUT_POLICY`): with ``nonfinite=hold`` every method took a NaN reading that
    the baseline refused, so the log could not be scored at all."""
    return process(log.t, log.rate, "raw", **{k: v for k, v in methods[0].overrides.items() if k in INPUT_POLICY})


def compare(
    logs: Sequence[Log | str | Path],
    presets: Sequence[str | Method],
    params: Sequence[Method] | None = None,
    *,
    bias_duration: float | None = None,
    plot_dir: str | Path | None = None,
    mode: str = "whole",
    use_speed: bool = True,
    overwrite: bool = True,
) -> list[Score]:
    """Score every method on every log: one :class:`Score` per (log, method), logs in order.

    Args:
        logs: :class:`Log` objects or log folders.
        presets: preset names (``recommended`` runs the preset the README recommends) or methods.
        params: further methods, e.g. tuned parameter sets (:meth:`gyrocore.tune.ParameterSet.method`).
        bias_duration: for logs without a rest window, measure the static bias over the first
            ``bias_duration`` seconds while moving [s] (see :meth:`Method.run`). The same value is
            used for every such log: never tune it per log.
        plot_dir: write ``<log>.png`` there (heading vs reference and error vs time of each method;
            needs matplotlib).
        overwrite: replace a plot there; False refuses one there before its log is scored, and
            keeps one another run wrote meanwhile: FileExistsError.
        mode: ``whole`` (the bias from every rest, known from the first sample) or ``causal``
            (see :func:`gyrocore.process`).
        use_speed: also find rests where the odometry's speed is zero (whole mode's, and in causal
            mode a rest tracker's, as :meth:`Log.process` does).

    One log (a path or a :class:`Log`) or one preset may be given alone, as a list of one.

    Raises:
        ValueError: a mode, preset, method parameter or ``bias_duration`` that is refused (before
            any log is read), or a log that cannot be read or scored (naming it).
        TypeError: a preset that is no name, a ``bias_duration`` that is no number, a
            ``use_speed`` that is no bool.
    """
    check_mode(mode)
    # One path was taken as a sequence of one-letter logs ("/: not a log folder"), one preset as
    # one-letter presets ("unknown preset 'h'", blamed on the log).
    logs = [logs] if isinstance(logs, (str, os.PathLike, Log)) else logs
    presets = [presets] if isinstance(presets, (str, Method)) else presets
    methods = [m if isinstance(m, Method) else Method.from_preset(m) for m in presets] + list(params or [])
    if not methods:
        raise ValueError("no method to compare: give at least one preset or parameter set")
    _refuse_shared_names(methods)
    for method in methods:  # before any log is read, not as an error of the first log
        check_parameters(method.preset, dict(method.overrides))
    if bias_duration is not None:  # "5" failed as a format code, NaN as the first log's error
        check_number("bias_duration", bias_duration, unit=" [s]")
    require_flag("use_speed", use_speed)  # "no" was True
    if plot_dir is not None:
        evaluation_pyplot()  # fail before the work if plots cannot be drawn
    rows: list[Score] = []
    for item in logs:
        log = item if isinstance(item, Log) else read_log(item)
        plot = None if plot_dir is None else plot_path(plot_dir, log)
        with kept_outputs([] if plot is None else [plot], overwrite, "overwrite=True"):  # before its work
            rows += _scored(log, methods, bias_duration, mode, use_speed, plot, overwrite)
    return rows


def _scored(log: Log, methods: Sequence[Method], bias_duration: float | None,
            mode: str, use_speed: bool, plot: Path | None, overwrite: bool) -> list[Score]:
    """:func:`compare`'s rows of one log, and its plot at ``plot``."""
    rows: list[Score] = []
    try:
        reference = log.reference()  # before any work
        warn_partial_reference(log)
        raw_result = raw_baseline(log, methods)
        raw = heading_errors(raw_result.t, raw_result.heading, *reference)
        results = {}
        for method in methods:
            result, source = method.run(log, bias_duration=bias_duration, mode=mode, use_speed=use_speed)
            if plot is not None:  # for the plot alone, its times and heading: every method's result
                results[method.name] = HeadingResult(result.t, result.heading, None, None)  # held 4 arrays
            rows.append(score(log, method, result, raw, source))
    except ValueError as e:
        raise named_error(log, e) from None
    if plot is not None:
        plot_log(plot, log, results, overwrite=overwrite)
    return rows


def _refuse_shared_names(methods: Sequence[Method]) -> None:
    """Two different methods of one name are refused: their rows could not be told apart and the
    plot kept one of them (a method given twice as it is is scored twice, as asked)."""
    seen: dict[str, Method] = {}
    for method in methods:
        other = seen.setdefault(method.name, method)
        if (other.preset, dict(other.overrides)) != (method.preset, dict(method.overrides)):
            raise ValueError(
                f"two methods are named {method.name!r} ({other.preset} {dict(other.overrides)} and "
                f"{method.preset} {dict(method.overrides)}): their scores could not be told apart; give each "
                "its own name (Method(name, preset, overrides))"
            )


def named_error(log: Log, error: ValueError) -> ValueError:
    """``error``, raised on ``log``, naming the log once (:func:`naming_log`)."""
    return ValueError(naming_log(log, str(error)))


def naming_log(log: Log, text: str) -> str:
    """An error or warning about ``log`` that names it once: by its path where it was read from
    one (the log's own checks name it ``log NAME``, and names repeat), else as ``log NAME``; a
    text that names a file of the log's folder (``drive/meta.json``) names the log already."""
    text = text.removeprefix(f"log {log.name}: ")
    label = log.path if log.path is not None else f"log {log.name}"
    named = text.startswith(f"{label}: ") or (log.path is not None and text.startswith(os.path.join(log.path, "")))
    return text if named else f"{label}: {text}"


@dataclass(frozen=True)
class Failed:
    """A log that could not be scored, in a run over many: the path it was given as, and why."""

    path: str
    error: str

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: ``path`` and ``error``."""
        return {"path": self.path, "error": self.error}

    def __str__(self) -> str:
        return failed_line(self.path, self.error)


def format_table(rows: Sequence[Score | Failed], *, file: Any = None) -> None:
    """Print ``rows`` as a table (E_psi, NE_psi, final and maximum error, improvement over plain
    integration, ``vs plain``), a log that failed as its ``FAILED`` line where it comes.

    The improvement's baseline is plain integration of the readings as they are, no bias removed
    (:func:`raw_baseline`), for every row: the column was headed ``vs raw``, and a ``raw`` row
    given a bias (``--bias-dps``), which then is not plain integration, read 0.8x "vs raw". A line
    under the table says so where a ``raw`` row removes a bias."""
    out = file or sys.stdout
    scores = [r for r in rows if isinstance(r, Score)]
    has_position = any(r.position is not None for r in scores)
    width = max([14, *(len(r.label) for r in scores)])
    header = (
        f"{'log':<{width}} {'method':<16} {'E_psi':>8} {'NE_psi':>9} {'final':>8} {'max':>8} {'vs plain':>8}"
        f" {'return':>8}" + (f" {'pos mean':>9} {'pos end':>8}" if has_position else "")
    )
    print(header, file=out)
    print(f"{'':<{width}} {'':<16} {'[deg]':>8} {'[deg/min]':>9} {'[deg]':>8} {'[deg]':>8} {'':>8} {'[deg]':>8}"
          + (f" {'[m]':>9} {'[m]':>8}" if has_position else ""), file=out)
    for r in rows:
        if isinstance(r, Failed):
            print(r, file=out)
            continue
        e = r.errors
        ret = "-" if r.return_error_deg is None else f"{r.return_error_deg:.2f}"
        line = (
            f"{r.label:<{width}} {r.method.name:<16} {e.e_psi_deg:>8.3f} {e.ne_psi_deg_per_min:>9.4f} "
            f"{e.final_error_deg:>8.2f} {e.max_error_deg:>8.2f} {r.improvement:>7.1f}x {ret:>8}"
        )
        if has_position:
            p = r.position
            line += " " + (f"{p.mean_error_m:>9.2f} {p.final_error_m:>8.2f}" if p else f"{'-':>9} {'-':>8}")
        print(line, file=out)
    biased = [r.method.name for r in scores if r.method.preset == "raw" and has_bias_source(dict(r.method.overrides))]
    if biased:
        print(f"{', '.join(dict.fromkeys(biased))}: removes the bias given, so it is not plain integration, the "
              "baseline of 'vs plain' (the readings integrated as they are, no bias removed)", file=out)
    # the JSON's "gaps" had no place in the table: a log's score over a gap was taken for a whole one
    gaps: dict[str, int] = {}
    for r in scores:
        gaps[r.label] = max(gaps.get(r.label, 0), r.errors.gaps)
    for label, count in gaps.items():
        if count:
            print(f"{label}: {count} gap(s) of the gyro or the reference skipped: reference samples inside a gap of "
                  "the gyro are not scored, and across a gap of the reference its whole turns come from the "
                  "estimate", file=out)


def format_bias_sources(rows: Sequence[Score | Failed], *, file: Any = None) -> None:
    """Print where each method's static bias came from, per log; methods that share a source
    (and its rests) share a line, and each rest used is listed under it. Logs that failed have none."""
    out = file or sys.stdout
    groups: dict[tuple[str, str, tuple[Rest, ...]], list[str]] = {}
    for r in (r for r in rows if isinstance(r, Score)):
        names = groups.setdefault((r.label, r.bias_source, r.rests), [])
        if r.method.name not in names:  # a log given twice is one line
            names.append(r.method.name)
    width = max([14, *(len(log) for log, _, _ in groups)])
    print("bias source:", file=out)
    for (log, source, rests), names in groups.items():
        print(f"  {log:<{width}} {', '.join(names)}: {source}", file=out)
        for line in rest_lines(source, rests, " " * 19):
            print(line, file=out)

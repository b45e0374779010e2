"""``gyrocore evaluate``: score methods on log folders (or a file with its truth, as ``gyrocore
simulate`` writes it) against their reference (HDR eq 15-16)."""

from __future__ import annotations

import argparse
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import batch_names
from .._checks import keep_readings
from ..evaluate import Method, Score, compare, format_bias_sources, format_table, plot_path
from ..evaluate_compare import naming_log
from ..io import Log, check_not_input, open_source, read_log
from ..pipeline import has_bias_source, preset_names, recommended_preset
from ..tune import ParameterSet
from ._fixes import add_fix_options, evaluate_with_fixes, fixes_wanted, input_warnings, note_unused_gnss
from ._common import (
    BIAS_DPS,
    NAME,
    POSITIVE,
    REFERENCE_HELP,
    add_command,
    each_log,
    exit_code,
    named_path,
    once_each,
    print_failures,
    add_overwrite_option,
    add_override_options,
    add_reading_options,
    check_samples,
    pipeline_overrides,
    print_json,
    reading_options,
    refuse_existing,
    warn,
    with_reference,
)


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "evaluate",
        "score presets and tuned parameter sets on log folders (or files gyrocore simulate wrote) against "
        "their reference heading",
        "gyrocore evaluate sample_drive --preset static_bias --preset recommended",
        run,
    )
    p.add_argument("logs", nargs="+", type=NAME, metavar="LOGDIR",
                   help="log folders (gyro.csv, reference.csv, meta.json), or CSV or Parquet files with a heading_true "
                   "column [rad] (what gyrocore simulate writes); the reading options apply to the gyro's file")
    p.add_argument("--reference", type=named_path, metavar="FILE",
                   help=f"reference heading of a single log given (in place of its own): {REFERENCE_HELP}")
    p.add_argument(
        "--preset",
        action="append",
        metavar="NAME",
        help=f"method to score (repeatable): {', '.join(preset_names())} or recommended "
        "(default: every preset, unless --params is given)",
    )
    p.add_argument(
        "--params", action="append", type=NAME, metavar="FILE", help="parameter file written by gyrocore tune (repeatable)"
    )
    bias = p.add_mutually_exclusive_group()
    bias.add_argument(
        "--bias-duration",
        type=POSITIVE,
        metavar="S",
        help="for logs with no rest window: measure the static bias over the first S seconds while driving "
        "(only sound when the drive starts straight; the same S for every log)",
    )
    bias.add_argument("--bias-dps", type=BIAS_DPS, metavar="B",
                      help="known bias [deg/s] (what the gyro reads at rest), for every method and log")
    add_override_options(p.add_argument_group("pipeline parameters for every method"))
    add_reading_options(p, "--bias-duration")
    p.add_argument(
        "--causal",
        action="store_true",
        help="score what a streaming pipeline gives (a rest corrects only what follows it) instead of the "
        "whole log's bias from every rest, known from the first sample",
    )
    p.add_argument(
        "--no-speed",
        action="store_true",
        help="find rests from the rate alone (whole mode's, and with --causal a rest tracker's), not where the "
        "speed is zero (a log folder's odometry.csv, a file's speed column [m/s])",
    )
    add_fix_options(p, evaluate=True)
    p.add_argument("--json", action="store_true", help="print one JSON list, an object per (log, method)")
    p.add_argument("--plot-dir", type=NAME, metavar="DIR", help="write <log>.png (heading and error vs time) there")
    add_overwrite_option(p)


def run(args: argparse.Namespace) -> int:
    if args.bias_duration is not None and not (math.isfinite(args.bias_duration) and args.bias_duration > 0):
        raise ValueError(f"--bias-duration must be a positive number of seconds, got {args.bias_duration}")
    extra = pipeline_overrides(args, {"bias_dps": args.bias_dps})
    if args.bias_duration is not None and has_bias_source(extra):  # the method's own bias dropped it without a word
        given = next(k for k in extra if has_bias_source({k: extra[k]}))
        raise ValueError(f"--bias-duration and --param {given} both give the static bias: give one of them")
    # as a log given twice: a method given twice printed its rows twice
    # recommended and the preset it stands for are one method
    args.preset = once_each(args.preset or [], "a method (--preset)", "its rows would be printed twice",
                            lambda name: recommended_preset() if name == "recommended" else name)
    args.params = once_each(args.params or [], "a parameter file (--params)", "its rows would be printed twice")
    params = [ParameterSet.read(f).method() for f in args.params]
    presets = args.preset if args.preset else ([] if params else preset_names())
    methods = [_with(m, extra) for m in [*map(Method.from_preset, presets), *_named_apart(params, args.params, presets)]]
    if args.plot_dir:
        check_not_input(Path(args.plot_dir), [Path(p) for p in args.logs])
        if os.path.lexists(args.plot_dir) and not Path(args.plot_dir).is_dir():  # found only once plotting
            raise NotADirectoryError(f"--plot-dir {args.plot_dir}: not a folder; give a folder for the plots "
                                     "(one that does not exist is made)")
    args.logs = once_each(args.logs, "a log to score", "its rows would be printed twice")
    alone = len(args.logs) == 1
    if args.reference is not None and not alone:  # one file cannot be every log's reference
        raise ValueError(f"--reference {args.reference} is the reference heading of one log, and {len(args.logs)} "
                         "logs were given: score them in separate runs")
    # Each log opened now, and read only when its turn comes: all of them read first held a fleet's
    # logs in memory at once (40 drives of 2*10^5 samples: 397 MB resident, 285 MB for 20).
    logs = each_log(args.logs, lambda path: [_opened(path, args)], alone=alone)
    opened = [log for log in logs if isinstance(log, _Opened)]
    paths = [log.path if isinstance(log, _Opened) else log for log in logs]
    folders = [log.path for log in opened if log.folder]
    note_unused_gnss(args, folders, "" if alone else "in a run of FOLDER alone")
    if fixes_wanted(args, folders):
        return evaluate_with_fixes(args, paths, methods, lambda path: _read(path, args))
    if args.plot_dir:
        refuse_existing(_plot_paths(args.plot_dir, opened), args.overwrite, folders_exist=False)  # made

    def score(path: str) -> list[Score]:
        log = _read(path, args)
        with input_warnings() as messages:
            rows = compare([log], methods, bias_duration=args.bias_duration,
                           plot_dir=args.plot_dir, mode="causal" if args.causal else "whole",
                           use_speed=not args.no_speed, overwrite=args.overwrite)
        for message in messages:
            warn(naming_log(log, message))
        return rows

    rows = each_log(paths, score, alone=alone)
    if args.json:
        print_json([r.as_dict() for r in rows])
    else:
        format_table(rows)
        format_bias_sources(rows)
        print_failures(rows, len(args.logs))
        if args.plot_dir:  # "plots in DIR" named no file, nor which logs got one (a failed log gets none)
            scored = {r.path for r in rows if isinstance(r, Score)}
            written = [str(p) for p in _plot_paths(args.plot_dir, [log for log in opened if log.path in scored])]
            print(f"wrote {', '.join(written)}" if written else f"no plot written in {args.plot_dir}")
    return exit_code(rows)


@dataclass(frozen=True)
class _Opened:
    """A log to score, opened (its name known, its path checked) but not read yet."""

    path: str
    name: str
    folder: bool


def _opened(path: str, args: argparse.Namespace) -> _Opened:
    source = open_source(path, **reading_options(args))
    return _Opened(path, source.name, source.kind == "log folder")


def _read(path: str, args: argparse.Namespace) -> Log:
    """The log at ``path``, which must have a reference heading."""
    log = read_log(path, use_fixes=not args.no_fixes, **reading_options(args))
    if args.reference is not None:
        log = with_reference(log, args.reference)
    if not any(p.partition("=")[0].strip() == "nonfinite" for p in args.param):
        # the pipeline's own refusal named neither the line nor the option (it names the log)
        check_samples(Path(path), log, args,
                      keep_readings("the file as it is", "--param nonfinite=hold", "--param nonfinite=skip"))
    if log.heading_ref is None:
        raise ValueError(
            f"{path}: no reference heading to score against (a log folder's reference.csv, a CSV or "
            "Parquet file's heading_true column [rad], as gyrocore simulate writes it, or --reference FILE: "
            f"{REFERENCE_HELP})"
        )
    units = _units_apart(log)
    if units is not None:
        warn(f"{path}: {units}")
    return log


def _units_apart(log: Log) -> str | None:
    """Why the reference heading or the gyro looks like degrees, or None: over the reference's span
    the reference changes about 180/pi times as much as the gyro turns (its rate less the median,
    integrated), or the gyro turns about 180/pi times as much (each within a factor 2, as
    ``calibrate`` judges a fit). A reference in degrees that never wraps by 360 between two samples
    passed the reader's check, and a gyro in deg/s on a gentle drive (99 % of a highway's rates
    below 5 deg/s) passed the pipeline's; either was scored without a word."""
    t, rate, t_ref, heading = log.t, log.rate, log.t_ref, log.heading_ref
    if t_ref is None or heading is None or len(heading) < 2:
        return None
    inside = (t >= t_ref[0]) & (t <= t_ref[-1])
    if np.count_nonzero(inside) < 2:
        return None
    with np.errstate(invalid="ignore", over="ignore"):
        # less the median rate, about the bias: a large one (1.4 deg/s) looked like turning
        rate_in = rate[inside]
        turned = float(np.sum(np.abs(rate_in[1:] - np.median(rate_in)) * np.diff(t[inside])))
        changed = float(np.sum(np.abs(np.diff(np.unwrap(heading)))))
    if not (math.isfinite(turned) and math.isfinite(changed) and turned > 0 and changed > 0):
        return None
    ratio, factor = changed / turned, math.degrees(1)
    if 0.5 * factor <= ratio <= 2 * factor:
        return (f"the reference heading changes {ratio:.3g} times as much as the gyro turns, about 180/pi = 57.3: it "
                "looks like degrees, and it is read as radians (convert it with numpy.radians); its scores would be "
                "wrong")
    if 0.5 * factor <= 1 / ratio <= 2 * factor:
        return (f"the gyro turns {1 / ratio:.3g} times as much as the reference heading changes, about 180/pi = 57.3: "
                "its rates look like deg/s, and they are read as rad/s (give --rate-unit deg/s); its scores "
                "would be wrong")  # the option, not a conversion: the command reads deg/s itself
    return None


def _plot_paths(plot_dir: str, logs: list[_Opened]) -> list[Path]:
    """Where the logs' plots go (named by the logs' names); two logs of one name are refused,
    before any work, as one plot would replace the other."""
    paths: dict[Path, _Opened] = {}
    for log in logs:
        path = plot_path(plot_dir, log)
        if path in paths:
            raise ValueError(f"--plot-dir: {paths[path].path} and {log.path} would both be plotted to {path} "
                             f"(both logs are named {log.name}); plot them in separate runs")
        paths[path] = log
    # Drive.png and drive.png where the folder ignores case (macOS, Windows): one replaced the other
    said = batch_names.clash([log.path or log.name for log in paths.values()], list(paths), Path(plot_dir), "plotted")
    if said is not None:
        raise ValueError(f"--plot-dir: {said}; plot them in separate runs")
    return list(paths)


def _with(method: Method, extra: dict[str, Any]) -> Method:
    """``method`` with the command line's parameters; a parameter file that sets one too is an error."""
    twice = sorted(set(extra) & set(method.overrides))
    if twice:
        raise ValueError(f"{method.name} sets {', '.join(twice)}, which the command line gives too")
    return method if not extra else Method(method.name, method.preset, {**method.overrides, **extra})


def _named_apart(params: list[Method], files: list[str], presets: list[str]) -> list[Method]:
    """The parameter files' methods, each one whose name another method shares with other parameters
    named after its file too: two runs of gyrocore tune both write "hdr_tuned", and their rows (and
    JSON objects) could not be told apart. Two files of the same parameters keep the name (one file
    given twice is used once)."""
    out = []
    for method, path in zip(params, files):
        others = [Method.from_preset(p) for p in presets] + [m for m in params if m is not method]
        if any(m.name == method.name and (m.preset, dict(m.overrides)) != (method.preset, dict(method.overrides))
               for m in others):
            method = Method(f"{method.name} ({path})", method.preset, method.overrides)
        out.append(method)
    return out

"""``gyrocore calibrate``: static bias from a rest window (found automatically), least-squares
scale and bias against the log's reference heading (Hong eq 4-7) and the gyro's time offset
against it, from a log folder or any file with a reference file."""

from __future__ import annotations

import argparse
import dataclasses
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from .. import calibration, io
from .._checks import UnitError
from .._rests import SPEED_THRESHOLD, find_rests
from ..calibration.rest import MAX_RATE
from ..wholelog import times_ok
from ..window import Window
from ._common import (
    NAME,
    REFERENCE_HELP,
    POSITIVE,
    WINDOW_HELP,
    add_command,
    check_samples,
    add_overwrite_option,
    add_reading_options,
    named_path,
    print_json,
    reading_options,
    refuse_existing,
    with_reference,
)


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "calibrate",
        "calibrate a gyro from a log: static bias at rest, scale, bias and time offset against a reference heading",
        "gyrocore calibrate sample_drive --save calibration.json",
        run,
    )
    p.add_argument("input", type=NAME, help="log folder (gyro.csv; reference.csv and meta.json where present), or any "
                   "file the reading options describe")
    p.add_argument("--reference", type=named_path, metavar="FILE",
                   help=f"reference heading of a file input: {REFERENCE_HELP}")
    p.add_argument("--window", nargs=2, metavar=("T0", "T1"),
                   help=f"rest window instead of finding one: {WINDOW_HELP}")
    p.add_argument("--min-duration", type=POSITIVE, default=1.0, metavar="S", help="shortest rest [s] (default 1)")
    p.add_argument("--max-rate-dps", type=POSITIVE, default=None, metavar="DPS",
                   help="largest reading at rest [deg/s] (default 2.9); raise it for a gyro with a large bias")
    p.add_argument("--block", type=POSITIVE, default=None, metavar="S",
                   help="length [s] of the blocks a rest is found in (default 0.25); a slow gyro needs longer "
                        "ones (25 readings or more)")
    p.add_argument("--fit-window", nargs=2, metavar=("T0", "T1"),
                   help=f"span for the reference fit (default: the whole log): {WINDOW_HELP}")
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.add_argument("--save", type=named_path, metavar="FILE",
                   help="write the calibration (JSON): the reference fit where the log has a reference, "
                        "else the static bias; with the time offset where one was found")
    add_overwrite_option(p)
    add_reading_options(p, "--window")


#: What a folder needs to be calibrated from, said when it is not a log folder.
_FOLDER_NEEDS = (
    "a log folder needs gyro.csv (columns t [s] and gyro_z [rad/s]); reference.csv (t, heading [rad], x, y) "
    "for the scale fit and meta.json ({\"stationary\": [t0, t1]}) are optional. For another file, give it "
    "with the reading options (--time-col, --rate-col, --time-unit, --rate-unit) and --reference FILE"
)


def run(args: argparse.Namespace) -> int:
    source = Path(args.input)
    if source.is_dir() and not io.is_input(source):
        raise ValueError(f"{source}: not a log folder: {_FOLDER_NEEDS}")
    if args.save is not None and args.save.suffix.lower() != ".json":
        raise ValueError(f"{args.save}: the calibration file must end in .json")
    rest = None if args.window is None else Window.parse(args.window, "--window")
    span = None if args.fit_window is None else Window.parse(args.fit_window, "--fit-window")
    if args.save is not None:
        # e.g. the log's own meta.json, or the --reference file (a reference may be named .json)
        io.check_not_input(args.save, [source, *([args.reference] if args.reference is not None else [])])
        refuse_existing([args.save], args.overwrite)
    log = io.read_log(source, use_fixes=False, **reading_options(args))
    check_samples(source, log, args)
    if args.reference is not None:
        log = with_reference(log, args.reference)
    results: dict[str, Any] = {"log": log.name, "meta_stationary": log.stationary}
    static: calibration.Calibration | None = None
    options: dict[str, Any] = {}
    if args.max_rate_dps is not None:
        options["max_rate"] = math.radians(args.max_rate_dps)
    if args.block is not None:
        options["block"] = args.block
    if rest is not None and options:  # they choose how a rest is found, and --window gives it
        flags = " and ".join(flag for flag, key in (("--max-rate-dps", "max_rate"), ("--block", "block"))
                             if key in options)
        raise ValueError(f"{flags}: how a rest is found, and --window gives the rest: leave out one or the other")
    for given in (rest, span):  # an empty window is a usage error, with the log's range
        if given is not None:  # a rest window cut to the log: the bias was not measured where asked
            given.samples(log.t, minimum=2, within=given is rest)
    if span is not None and log.heading_ref is None:  # it was ignored without a word
        raise ValueError(f"--fit-window is the span of the reference fit, and {source} has no reference heading: "
                         "give one (--reference FILE, or reference.csv in a log folder) or leave --fit-window out")
    cut = False  # the rate's rest ended where the speed shows motion
    try:
        window, found_by = (None, "rate") if rest is None else (rest.resolve(float(log.t[0])), "given")
        if window is None and (stop := _first_stop(log, args.min_duration)) is not None:
            # the first rest of the log: the speed's first stop unless the rate shows one before it
            try:
                from_rate = calibration.detect_rest(log.t, log.rate, min_duration=args.min_duration, **options)
            except ValueError:
                from_rate = None
            still = _until_moving(log, from_rate, args.min_duration)
            cut = still is not None and from_rate is not None and still[1] < from_rate[1] and still[0] <= stop[0]
            # detected once: the rate's rest is then the window static_bias would detect itself
            window, found_by = (stop, "speed") if still is None or stop[0] < still[0] else (still, "rate")
        found = {} if window is not None else options  # a window found by the speed is not searched for
        static = calibration.static_bias(log.t, log.rate, window, min_duration=args.min_duration, **found)
        results["static_bias"] = static.to_dict()["calibration"]
        results["rest_found_by"] = found_by
    except ValueError as e:
        results["static_bias"] = {"error": _in_option_words(str(e), args.max_rate_dps)}
    fit: calibration.Calibration | None = None
    offset: calibration.TimeOffset | None = None
    if log.t_ref is not None and log.heading_ref is not None:
        fit_window = None if span is None else span.resolve(float(log.t[0]))
        try:
            fit = calibration.heading_reference(log.t, log.rate, log.t_ref, log.heading_ref, window=fit_window)
            results["heading_reference"] = fit.to_dict()["calibration"]
        except UnitError as e:  # a reference to correct: no calibration is saved from the log
            raise ValueError(f"{source}: {e}") from None
        except ValueError as e:
            results["heading_reference"] = {"error": str(e)}
        offset = _time_offset(log, fit_window, results)
    chosen = fit or static
    if chosen is not None and offset is not None:  # the offset belongs to the gyro and reference, either fit
        chosen = dataclasses.replace(chosen, time_offset=offset.offset, time_offset_stderr=offset.offset_stderr)
    if chosen is None:
        raise ValueError(
            f"{source}: nothing to calibrate from: {results['static_bias']['error']}"
            + ("" if "heading_reference" not in results else f"; {results['heading_reference']['error']}")
        )
    if args.save is not None:
        chosen.save(args.save, overwrite=args.overwrite)  # whole or not at all; refused before if it existed
        results["saved"] = {"file": str(args.save), "method": chosen.method}
    if args.json:
        print_json(results)
        return 0
    print(f"{log.name}:")
    t0 = float(log.t[0])
    if static is not None and static.window is not None:
        w = static.window
        print(f"  static bias: {static!r}")
        how = {"speed": " (the first stop the speed shows)",
               "rate": " (found from the rate" + (", ended where the speed shows motion)" if cut else ")")}
        print(f"  rest window used: {w[0] - t0:.4f} .. {w[1] - t0:.4f} s after the first sample"
              + how.get(results["rest_found_by"], ""))
    else:
        print(f"  static bias: {results['static_bias']['error']}")
    if log.stationary is not None:
        m = log.stationary
        print(f"  (meta.json rest window: {m[0] - t0:.4f} .. {m[1] - t0:.4f} s after the first sample)")
    if fit is not None:
        print(f"  reference fit: {fit!r}")
    elif "heading_reference" in results:
        print(f"  reference fit: {results['heading_reference']['error']}")
    if offset is not None:
        sign = "+" if offset.offset >= 0 else "-"
        print(f"  time offset: {offset!r}: the gyro's times t {sign} {abs(offset.offset):.4g} s are on the reference's "
              "clock")
    elif "time_offset" in results:
        print(f"  time offset: {results['time_offset']['error']}")
    if args.save is not None:
        print(f"  saved the {chosen.method} calibration to {args.save}; use it with gyrocore process ... "
              f"--calibration {args.save}")
    else:  # the bias printed is in rad/s, and how a run takes it was left to find
        use = f"gyrocore process ... --bias-dps {math.degrees(static.bias):.6g}, or " if static is not None else ""
        print(f"  to use it: {use}save it with --save FILE and give gyrocore process ... --calibration FILE "
              f"(the {chosen.method} calibration: {'scale and bias' if fit is not None else 'its bias'})")
    return 0


def _time_offset(
    log: io.Log, window: tuple[float, float] | None, results: dict[str, Any]
) -> calibration.TimeOffset | None:
    """The gyro's time offset against the log's reference over ``window`` (None: the whole log),
    put in ``results`` (its fields, or the error of a log that cannot tell it); None without one."""
    assert log.t_ref is not None and log.heading_ref is not None
    try:
        offset = calibration.time_offset(log.t, log.rate, log.t_ref, log.heading_ref, window=window)
    except ValueError as e:  # a drive without turns: the fits above still stand
        results["time_offset"] = {"error": str(e)}
        return None
    results["time_offset"] = dataclasses.asdict(offset)
    return offset


#: The static bias's settings as the library's errors name them (regular expressions), and as this
#: command takes them; ``{max_rate_dps}`` is the largest reading at rest in deg/s, as given (the
#: library says it in rad/s, and of the rest window it has no option for).
_OPTION_WORDS = (
    (r"min_duration = ", "--min-duration "),
    (r"a shorter min_duration / larger max_rate", "a shorter --min-duration / larger --max-rate-dps"),
    (r"give block=", "give --block "),
    (r"within \S+ rad/s of zero \(give the rest window", "within {max_rate_dps:g} deg/s of zero (give --window T0 T1"),
    (r"beyond \S+ rad/s: ", "beyond {max_rate_dps:g} deg/s: "),
    (r"\(give a rest window or the bias\)", "(give --window T0 T1)"),
)


def _in_option_words(message: str, max_rate_dps: float | None) -> str:
    """``message`` naming this command's options where the library's names the keyword arguments
    (``shorter than min_duration = 1 s`` left a command-line user to find ``--min-duration``), and
    the largest rate at rest in deg/s (``max_rate_dps``, None: the default) as the user gave it."""
    dps = math.degrees(MAX_RATE) if max_rate_dps is None else max_rate_dps
    for library, option in _OPTION_WORDS:
        words = option.format(max_rate_dps=dps)
        message = re.sub(library, lambda _: words, message)
    return message


def _until_moving(log: io.Log, window: tuple[float, float] | None, min_duration: float) -> tuple[float, float] | None:
    """The rest ``window`` the rate shows, ended at the last sample before the speed shows motion
    (above whole mode's stop threshold): a drive that pulls off straight reads as steady as a rest,
    and the sample log's 60 s rest ran on 5.5 s into the drive. None if it is then shorter than
    ``min_duration`` [s] or starts in motion; ``window`` as it is where no speed is known."""
    speed = log.speed_on_gyro_times()
    if window is None or speed is None:
        return window
    first, end = np.searchsorted(log.t, window[0]), np.searchsorted(log.t, window[1], side="right")
    moving = np.flatnonzero(np.abs(np.nan_to_num(speed[first:end])) > SPEED_THRESHOLD)  # NaN: unknown
    if len(moving) == 0:
        return window
    if moving[0] == 0:
        return None
    cut = (window[0], float(log.t[first + moving[0] - 1]))
    return cut if cut[1] - cut[0] >= min_duration else None


def _first_stop(log: io.Log, min_duration: float) -> tuple[float, float] | None:
    """The first stop the log's speed shows (a log folder's odometry, a file's speed column),
    trimmed at its ends as whole mode trims it and then at least ``min_duration`` [s] long (what
    the static bias test asks of its window); None without a speed or such a stop (the rest is
    then found from the rate)."""
    speed = log.speed_on_gyro_times()
    if speed is None or not (math.isfinite(min_duration) and min_duration > 0) or not times_ok(log.t):
        return None
    found = find_rests(log.t, log.rate, speed, min_duration).windows
    stops = [(a, b) for a, b, how in found if how == "speed" and b - a >= min_duration]
    return stops[0] if stops else None

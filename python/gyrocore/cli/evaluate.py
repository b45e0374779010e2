"""``gyrocore evaluate``: score methods on log folders against their reference (HDR eq 15-16)."""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path
from typing import Any

from .._checks import InputWarning
from ..evaluate import compare, format_bias_sources, format_table
from ..pipeline import preset_names
from ..tune import ParameterSet
from ._common import add_command, print_json, warn


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "evaluate",
        "score presets and tuned parameter sets on log folders against their reference heading",
        "gyrocore evaluate ../shared/data/real/* --preset static_bias --preset recommended --bias-duration 10",
        run,
    )
    p.add_argument("logs", nargs="+", metavar="LOGDIR", help="log folders (gyro.csv, reference.csv, meta.json)")
    p.add_argument(
        "--preset",
        action="append",
        metavar="NAME",
        help=f"method to score (repeatable): {', '.join(preset_names())} or recommended "
        "(default: every preset, unless --params is given)",
    )
    p.add_argument(
        "--params", action="append", metavar="FILE", help="parameter file written by gyrocore tune (repeatable)"
    )
    p.add_argument(
        "--bias-duration",
        type=float,
        metavar="S",
        help="for logs with no rest window: measure the static bias over the first S seconds while driving "
        "(only sound when the drive starts straight; the same S for every log)",
    )
    p.add_argument(
        "--causal",
        action="store_true",
        help="score what a streaming pipeline gives (a rest corrects only what follows it) instead of the "
        "whole log's bias from every rest, known from the first sample",
    )
    p.add_argument(
        "--no-speed", action="store_true", help="do not find rests where odometry.csv's speed is zero (whole mode)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON list, an object per (log, method)")
    p.add_argument("--plot-dir", metavar="DIR", help="write <log>.png (heading and error vs time) there")


def run(args: argparse.Namespace) -> int:
    if args.bias_duration is not None and not (math.isfinite(args.bias_duration) and args.bias_duration > 0):
        raise ValueError(f"--bias-duration must be a positive number of seconds, got {args.bias_duration}")
    params = [ParameterSet.read(f).method() for f in args.params or []]
    presets = args.preset if args.preset else ([] if params else preset_names())
    for path in args.logs:
        if not Path(path).is_dir():
            raise ValueError(f"{path}: not a log folder")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        rows = compare(
            args.logs,
            presets,
            params,
            bias_duration=args.bias_duration,
            plot_dir=args.plot_dir,
            mode="causal" if args.causal else "whole",
            use_speed=not args.no_speed,
        )
    for message in dict.fromkeys(str(w.message) for w in caught):  # one line each, not one per method
        warn(message)
    if args.json:
        print_json([_finite(r.as_dict()) for r in rows])
    else:
        format_table(rows)
        format_bias_sources(rows)
        if args.plot_dir:
            print(f"plots in {args.plot_dir}")
    return 0


def _finite(row: dict[str, Any]) -> dict[str, Any]:
    """JSON has no inf/nan: write them as null."""
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()}

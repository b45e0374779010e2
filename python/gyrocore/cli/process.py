"""``gyrocore process``: the heading of logs, streamed to CSV or Parquet; one file or a fleet."""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path
from typing import Any

from .. import io
from .._checks import InputWarning
from ..batch import expand_inputs, process_file, process_many
from ._common import add_command, print_json, progress_bar, terminate_cleanly, warn

_EPILOG = """
IN is a CSV, Parquet, .npy or .npz file, a ROS 1 .bag or ROS 2 bag folder, a log folder, a
folder of those, or a glob; give several. OUT ending in .csv or .parquet is one output file (one
input); otherwise a folder that receives <name>.csv (or --format parquet) per input, processed in
parallel (--jobs, or a Dask cluster with --scheduler). Exit code 0: all done; 1: some files
failed (listed with their reason); 2: bad usage or input (one line); 130: interrupted.
"""


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_command(
        sub,
        "process",
        "compute the heading of logs (CSV, Parquet, NumPy, ROS bags, log folders) into CSV or Parquet",
        "gyrocore process ../shared/data/real/f110_ds3 --out heading.csv --preset recommended",
        run,
    )
    p.epilog = f"{p.epilog}\n{_EPILOG}"
    p.formatter_class = argparse.RawDescriptionHelpFormatter
    p.add_argument("inputs", nargs="+", metavar="IN", help="input files, folders or glob patterns")
    p.add_argument("--out", required=True, help="output .csv/.parquet file, or a folder for several inputs")
    p.add_argument("--preset", default="recommended", help="preset name (default recommended)")

    read = p.add_argument_group("reading")
    read.add_argument("--time-col", help="time column (default t; column number for a plain .npy array)")
    read.add_argument("--rate-col", help="rate column (default gyro_z)")
    read.add_argument(
        "--time-unit", choices=tuple(io.TIME_UNITS), default="s", help="unit of the time column (default s)"
    )
    read.add_argument(
        "--rate-unit", choices=io.RATE_UNITS, default="rad/s", help="unit of the rate column (default rad/s)"
    )
    read.add_argument("--topic", help="bag topic with sensor_msgs/Imu (default: the only one)")
    read.add_argument("--delimiter", default=",", help="CSV delimiter (default ,)")

    bias = p.add_argument_group(
        "static bias (default: the rest window of a log folder's meta.json, else every rest found in the log, "
        "applied from the first sample; finding rests reads the log's times and rates into memory, 16 bytes a sample)"
    )
    bias.add_argument(
        "--causal",
        action="store_true",
        help="what a streaming pipeline gives: a rest corrects only what follows it, no rest search (one pass)",
    )
    bias.add_argument("--no-speed", action="store_true", help="do not find rests where odometry.csv's speed is zero")
    group = bias.add_mutually_exclusive_group()
    group.add_argument(
        "--bias-window", nargs=2, type=float, metavar=("T0", "T1"), help="rest window [s], the log's time base"
    )
    group.add_argument("--bias-duration", type=float, metavar="S", help="rest during the first S seconds")
    group.add_argument("--bias-dps", type=float, metavar="B", help="known bias [deg/s] (what the gyro reads at rest)")

    pipe = p.add_argument_group("pipeline")
    pipe.add_argument("--nonfinite", choices=("error", "hold", "skip"), help="NaN/inf readings (default error)")
    pipe.add_argument("--gap-limit", type=float, metavar="S", help="longest interval that is not a gap [s] (default 2)")
    pipe.add_argument("--gap-action", choices=("bridge", "reset"), help="at a gap (default bridge)")
    pipe.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="any pipeline parameter (gyrocore presets --json); repeatable",
    )

    out = p.add_argument_group("output")
    out.add_argument(
        "--heading",
        choices=io.HEADING_CONVENTIONS,
        default="enu",
        help="enu: yaw CCW from east (default); compass: CW from north",
    )
    out.add_argument(
        "--format", choices=("csv", "parquet"), default="csv", help="file format in an output folder (default csv)"
    )
    out.add_argument("--jobs", type=int, help="parallel files (default: all cores)")
    out.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask scheduler (tcp://host:8786)")
    out.add_argument(
        "--chunk-rows",
        type=int,
        default=io.DEFAULT_CHUNK_ROWS,
        help=f"samples per chunk (default {io.DEFAULT_CHUNK_ROWS})",
    )
    out.add_argument("--json", action="store_true", help="print the report as JSON")


def parse_value(text: str) -> Any:
    """A ``--param`` value: a bool, a number, numbers separated by commas (a tuple), or text."""
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    numbers = text.split(",")
    try:
        values = [float(v) for v in numbers]
    except ValueError:
        return text
    if len(values) > 1:
        return tuple(values)
    return int(text) if text.strip().lstrip("+-").isdigit() else values[0]


def options(args: argparse.Namespace) -> dict[str, Any]:
    """Reader options and pipeline overrides from the command line."""
    opts: dict[str, Any] = {
        "time_col": args.time_col,
        "rate_col": args.rate_col,
        "time_unit": args.time_unit,
        "rate_unit": args.rate_unit,
        "topic": args.topic,
        "delimiter": args.delimiter,
    }
    named = {
        "bias_window": tuple(args.bias_window) if args.bias_window else None,
        "bias_duration": args.bias_duration,
        "bias_dps": args.bias_dps,
        "nonfinite": args.nonfinite,
        "gap_limit": args.gap_limit,
        "gap_action": args.gap_action,
    }
    opts.update({k: v for k, v in named.items() if v is not None})
    for item in args.param:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise ValueError(f"--param {item!r}: expected NAME=VALUE")
        if name in opts:
            raise ValueError(f"--param {name} is also given by its own option")
        opts[name] = parse_value(value)
    return opts


def run(args: argparse.Namespace) -> int:
    inputs = expand_inputs(args.inputs)
    out = Path(args.out)
    kwargs = options(args)
    try:
        with terminate_cleanly(), warnings.catch_warnings():
            # every file's report carries these; print them once, with the file's name
            warnings.simplefilter("ignore", InputWarning)
            if out.suffix.lower() in (".csv", ".parquet", ".pq"):
                return _one(inputs, out, args, kwargs)
            return _many(inputs, out, args, kwargs)
    except ImportError as e:  # an optional dependency the input needs: the user can install it
        raise ValueError(str(e)) from None
    except KeyboardInterrupt:
        print("gyrocore: interrupted; no partial output was left", file=sys.stderr)
        return 130


def _one(inputs: list[Path], out: Path, args: argparse.Namespace, kwargs: dict[str, Any]) -> int:
    if len(inputs) != 1:
        raise ValueError(f"--out {out} is one file but there are {len(inputs)} inputs; give a folder")
    with progress_bar(inputs[0].name) as bar:
        report = process_file(
            inputs[0],
            out,
            preset=args.preset,
            heading=args.heading,
            chunk_rows=args.chunk_rows,
            progress=bar,
            mode="causal" if args.causal else "whole",
            use_speed=not args.no_speed,
            **kwargs,
        )
    for w in report.warnings:
        warn(f"{report.input}: {w}")
    if args.json:
        print_json(report.as_dict())
    else:
        print(report)
    return 0


def _many(inputs: list[Path], out: Path, args: argparse.Namespace, kwargs: dict[str, Any]) -> int:
    summary = process_many(
        inputs,
        preset=args.preset,
        out_dir=out,
        client=args.scheduler,
        jobs=args.jobs,
        fmt=args.format,
        heading=args.heading,
        chunk_rows=args.chunk_rows,
        progress=True,
        mode="causal" if args.causal else "whole",
        use_speed=not args.no_speed,
        **kwargs,
    )
    for report in summary.files:
        for w in report.warnings:
            warn(f"{report.input}: {w}")
    if args.json:
        print_json(summary.as_dict())
    else:
        print(summary)
    return 0 if not summary.failed else 1

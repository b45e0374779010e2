"""``gyrocore allan``: the Allan deviation of a log and the noise parameters read from it."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from .. import allan, io
from ._common import add_command, write_atomically


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "allan",
        "Allan deviation of a gyro log (best recorded at rest) with ARW, bias instability and RRW",
        "gyrocore allan ../shared/data/real/broad_10 --json",
        run,
    )
    p.add_argument("input", help="log folder (gyro.csv) or a file with time and rate columns")
    p.add_argument("--json", action="store_true", help="print the curve and parameters as JSON")
    p.add_argument("--taus", choices=("octave", "decade", "log", "all"), default="octave",
                   help="averaging times (default octave: 1, 2, 4, ... samples)")
    p.add_argument("--non-overlapping", action="store_true", help="non-overlapping estimator")
    p.add_argument("--kind", choices=("allan", "modified", "hadamard"), default="allan")
    p.add_argument("--window", nargs=2, type=float, metavar=("T0", "T1"),
                   help="analyse only this span [s, log time base], e.g. the rest")
    p.add_argument("--time-col", default=None, help="time column of a file input [s] (default t)")
    p.add_argument("--rate-col", default=None, help="rate column of a file input (default gyro_z)")
    p.add_argument("--time-unit", choices=tuple(io.TIME_UNITS), default="s",
                   help="unit of the time column of a file input (default s)")
    p.add_argument("--rate-unit", choices=io.RATE_UNITS, default="rad/s")
    p.add_argument("--plot", type=Path, help="write a log-log plot (PNG) to this file")
    p.add_argument("--kalibr", type=Path, help="write a Kalibr-style IMU noise YAML to this file")
    p.add_argument("--rrw", type=float, default=None,
                   help="rate random walk K [rad/s^2/sqrt(Hz)] for --kalibr when the record is too short to show it")


def run(args: argparse.Namespace) -> int:
    src = Path(args.input)
    for out in (args.plot, args.kalibr):
        if out is not None:
            io.check_not_input(out, [src])
    # A log folder names its columns and units; a file takes them from the options.
    columns = {} if src.is_dir() else {
        "time_col": args.time_col, "rate_col": args.rate_col, "time_unit": args.time_unit, "rate_unit": args.rate_unit
    }
    # A record for the Allan deviation is taken at rest: small rates are no sign of a unit mistake.
    log = io.read_log(src, static=True, **columns)
    t, rate = log.t, log.rate
    if args.window is not None:
        inside = (t >= args.window[0]) & (t <= args.window[1])
        if inside.sum() < 3:
            raise ValueError(f"the window {args.window[0]} .. {args.window[1]} s holds {int(inside.sum())} samples")
        t, rate = t[inside], rate[inside]
    result = allan.deviation_from_timestamps(
        t, rate, taus=args.taus, overlapping=not args.non_overlapping, kind=args.kind
    )
    params = allan.noise_parameters(result) if args.kind == "allan" else None
    if args.json:
        out = {"input": str(src), "allan": result.as_dict(), "noise": None if params is None else params.as_dict()}
        print(json.dumps(out, indent=2))
    else:
        print(f"{log.name}: {result}")
        print(f"{'tau [s]':>12} {'dev [rad/s]':>12} {'low':>11} {'high':>11} {'terms':>9}")
        for tau, d, lo, hi, n in zip(result.taus, result.adev, result.adev_low, result.adev_high, result.n):
            print(f"{tau:12.5g} {d:12.5g} {lo:11.4g} {hi:11.4g} {n:9d}")
        if params is not None:
            print(params)
    if args.plot is not None:
        try:
            import matplotlib
        except ImportError:
            raise ValueError("--plot needs matplotlib: pip install 'gyrocore[plot]'") from None
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.8))
        allan.plot(result, parameters=params, ax=ax)
        ax.set_title(f"{log.name}: {result.kind} deviation")
        write_atomically(args.plot, lambda tmp: fig.savefig(tmp, format="png", dpi=120))
        plt.close(fig)
    if args.kalibr is not None:
        if params is None:
            raise ValueError("--kalibr needs --kind allan")
        text = params.kalibr_yaml(rrw=args.rrw)
        write_atomically(args.kalibr, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
    return 0

"""``gyrocore allan``: the Allan deviation of a log and the noise parameters read from it."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

from .. import allan, io
from .._checks import collected, unit_problems
from .._gyrocore import SampleError
from .._extras import pyplot
from ..io.atomic import write_atomically, write_text_atomically
from ..window import Window
from ._common import (
    NAME,
    POSITIVE,
    WINDOW_HELP,
    add_command,
    add_overwrite_option,
    add_reading_options,
    named_path,
    print_json,
    reading_options,
    refuse_existing,
    require_suffix,
    warn_about,
)


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "allan",
        "Allan deviation of a gyro log (best recorded at rest) with ARW, bias instability and RRW",
        "gyrocore allan sample_drive --window +0 +60 --json",
        run,
    )
    p.add_argument("input", type=NAME, help="log folder (gyro.csv) or a file with time and rate columns")
    p.add_argument("--json", action="store_true", help="print the curve and parameters as JSON")
    p.add_argument("--taus", choices=("octave", "decade", "log", "all"), default="octave",
                   help="averaging times (default octave: 1, 2, 4, ... samples)")
    p.add_argument("--non-overlapping", action="store_true", help="non-overlapping estimator")
    p.add_argument("--kind", choices=("allan", "modified", "hadamard"), default="allan",
                   help="which deviation: allan, modified Allan (always overlapping) or hadamard (blind to a "
                   "linear rate drift) (default allan)")
    p.add_argument("--window", nargs=2, metavar=("T0", "T1"),
                   help=f"analyse only this span, e.g. the rest: {WINDOW_HELP}")
    p.add_argument("--plot", type=named_path, metavar="FILE", help="write a log-log plot (PNG) to this file")
    p.add_argument("--kalibr", type=named_path, metavar="FILE", help="write a Kalibr-style IMU noise YAML to this file")
    p.add_argument("--rrw", type=POSITIVE, default=None,
                   help="rate random walk K [rad/s^2/sqrt(Hz)] for --kalibr when the record is too short to show it")
    add_overwrite_option(p)
    add_reading_options(p, "--window")


def run(args: argparse.Namespace) -> int:
    src = Path(args.input)
    window = None if args.window is None else Window.parse(args.window, "--window")
    if args.rrw is not None and args.kalibr is None:
        raise ValueError("--rrw is the rate random walk written by --kalibr: give --kalibr FILE too, or leave --rrw out")
    if args.kind == "modified" and args.non_overlapping:  # the option has no meaning there: refused, not ignored
        raise ValueError("--non-overlapping: the modified Allan deviation is always overlapping; leave the option out, "
                         "or give --kind allan or hadamard for a non-overlapping estimate")
    if args.kalibr is not None and args.kind != "allan":  # before the work, not once its report is printed
        raise ValueError(f"--kalibr needs --kind allan (the noise parameters are read off the Allan deviation), "
                         f"not --kind {args.kind}")
    outputs = [out for out in (args.plot, args.kalibr) if out is not None]
    if len(outputs) == 2 and os.path.abspath(outputs[0]) == os.path.abspath(outputs[1]):
        # the YAML would replace the plot just written
        raise ValueError(f"--plot {args.plot} and --kalibr {args.kalibr} are one file; give each its own")
    for out in outputs:
        io.check_not_input(out, [src])
    if args.plot is not None:
        require_suffix(args.plot, "--plot", "a PNG image", (".png",))
    if args.kalibr is not None:
        require_suffix(args.kalibr, "--kalibr", "Kalibr's YAML", (".yaml", ".yml"))
    refuse_existing(outputs, args.overwrite)
    plt = None if args.plot is None else pyplot("--plot")  # before the work
    # A record for the Allan deviation is taken at rest: small rates are no sign of a unit mistake.
    log = io.read_log(src, static=True, use_fixes=False, **reading_options(args))
    t, rate = log.t, log.rate
    inside = np.arange(len(t))
    if window is not None:
        inside = window.samples(t, minimum=3, within=True)  # 0 .. 1000 s of a minute's record was cut to it
        t, rate = t[inside], rate[inside]
    raised: list[str] = []
    try:
        with collected(raised):  # its warning of a moving gyro names the log, as a reader's would
            result = allan.deviation_from_timestamps(
                t, rate, taus=args.taus, overlapping=not args.non_overlapping, kind=args.kind
            )
    except SampleError as e:  # a NaN, times out of order: named with the file and its line, as process does
        source = io.open_source(src, **reading_options(args))
        raise ValueError(f"{e} ({source.data_path}, {source.where(int(inside[e.index]))})") from None
    except ValueError as e:  # a gap, too few samples: which log
        raise ValueError(f"{src}: {e}") from None
    # the reader judged the units already, with the file's options: its warnings said them
    said = set(unit_problems(t, rate))
    warn_about(src, [note for note in raised if note not in said])
    try:
        params = allan.noise_parameters(result) if args.kind == "allan" else None
    except ValueError as e:  # too short a record (or --window) for the curve's slopes
        short = window is not None and len(result.taus) < 3  # not for a record with no noise
        raise ValueError(f"{src}: {e}" + (" (give a longer --window)" if short else "")) from None
    kalibr = None  # made before anything is printed or written: a record too short to show the rate
    if args.kalibr is not None:  # random walk failed once the plot was written, and a run again with --rrw was refused for it
        assert params is not None  # --kind allan, checked before the work
        kalibr = params.kalibr_yaml(rrw=args.rrw)
    if args.json:
        out = {"input": str(src), "allan": result.as_dict(), "noise": None if params is None else params.as_dict()}
        print_json(out)
    else:
        print(f"{log.name}: {result}")
        print(f"{'tau [s]':>12} {'dev [rad/s]':>12} {'low':>11} {'high':>11} {'terms':>9}")
        for tau, d, lo, hi, n in zip(result.taus, result.adev, result.adev_low, result.adev_high, result.n):
            print(f"{tau:12.5g} {d:12.5g} {lo:11.4g} {hi:11.4g} {n:9d}")
        if params is not None:
            print(params)
    if plt is not None:
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
        allan.plot(result, parameters=params, ax=ax)
        ax.set_title(f"{log.name}: {result.kind} deviation")
        fig.tight_layout()  # room for the axis labels: the default margins clip the y label
        write_atomically(args.plot, lambda tmp: fig.savefig(tmp, format="png", dpi=120), replace=args.overwrite)
        plt.close(fig)
    if kalibr is not None:
        write_text_atomically(args.kalibr, kalibr, replace=args.overwrite)
    return 0

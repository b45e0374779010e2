"""``gyrocore simulate``: a simulated gyro log with its truth, written to CSV."""

from __future__ import annotations

import argparse
import functools
import math
from pathlib import Path
from typing import Callable

import numpy as np

from .. import motion, sim
from ..io.atomic import write_atomically
from ._common import NAME, COUNT, POSITIVE, SEED, add_command, add_overwrite_option, refuse_existing

#: Column order of the CSV: what a log has (t, gyro_z, temperature), then the truth.
COLUMNS = ("t", "gyro_z", "temperature", "rate_true", "heading_true", "x", "y", "speed", "drift")
#: The unit of each column, said by ``--help`` (the names alone left degrees or radians a guess).
UNITS = ("s", "rad/s", "degC", "rad/s", "rad", "m", "m", "m/s", "rad/s")


#: The defaults of the options that apply to some profiles only.
DURATION, MIX, RUNS = 600.0, "mixed", 10

#: The profiles made of ``--runs`` repetitions of one run.
_REPEATED: dict[str, Callable[..., motion.Motion]] = {"square": motion.square_path, "rotary": motion.rotary_table}


def _profiles(args: argparse.Namespace) -> dict[str, Callable[[], motion.Motion]]:
    """The motions of the profiles other than ``car`` (:func:`gyrocore.sim.car_drive` builds its own)."""
    return {
        "hdr-figure3": lambda: motion.hdr_figure3(),
        "robot": lambda: motion.robot_run(),
        **{name: functools.partial(build, runs=args.runs) for name, build in _REPEATED.items()},
    }


def _options_of_the_profile(args: argparse.Namespace) -> None:
    """Refuses an option the profile does not take (it would be ignored without a word), and sets
    the defaults of those it takes."""
    takes = {"--duration": args.profile == "car", "--mix": args.profile == "car", "--runs": args.profile in _REPEATED}
    given = {"--duration": args.duration, "--mix": args.mix, "--runs": args.runs}
    for option, value in given.items():
        if value is not None and not takes[option]:
            which = "the car profile" if option != "--runs" else "the square and rotary profiles"
            raise ValueError(f"{option} applies to {which} only, not to --profile {args.profile}")
    args.duration = DURATION if args.duration is None else args.duration
    args.mix = MIX if args.mix is None else args.mix
    args.runs = RUNS if args.runs is None else args.runs


def checked_sensor(name: str, rate_hz: float) -> sim.GyroSpec:
    """The simulated gyro ``name`` at ``--rate-hz``; a name or rate it refuses is named by its option
    (``tune`` takes ``--sensor`` as text: an unknown name was blamed on ``--rate-hz``)."""
    try:
        sim.sensor(name)
    except ValueError as e:
        raise ValueError(f"--sensor {name}: {e}") from None
    try:
        return sim.sensor(name, rate_hz=rate_hz)  # a spec is checked by the core as it is made
    except ValueError as e:  # "gyro model: invalid parameter rate_hz = ...": the option by its name
        raise ValueError(f"--rate-hz {rate_hz:g}: {e}") from None


def check_car_drive(spec: sim.GyroSpec, duration: float, option: str) -> None:
    """Refuse a car drive of ``duration`` seconds that is no longer than its rest, or that asks for
    more samples than the simulator makes, naming the ``option`` that asks for it (``--duration
    600``; the simulator's words named no option)."""
    if duration <= sim.CAR_REST:
        raise ValueError(f"{option}: a car drive begins with a {sim.CAR_REST:g} s rest "
                         "(its static bias test); give a longer drive")
    try:
        sim.check_span(spec, 0.0, duration)
    except ValueError as e:
        raise ValueError(f"{option} at --rate-hz {spec.rate_hz:g}: {e}") from None


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "simulate",
        "write a simulated gyro log (t, gyro_z, temperature) and its truth to CSV",
        "gyrocore simulate --profile car --sensor crs03 --duration 1200 --out drive.csv",
        run,
    )
    columns = ", ".join(f"{c} [{u}]" for c, u in zip(COLUMNS, UNITS))
    p.add_argument("-o", "--out", required=True, type=NAME,
                   help=f"output CSV; columns {columns} (drift: the slow part of the gyro's bias, beyond its static bias)")
    p.add_argument(
        "--profile",
        choices=("car", "hdr-figure3", "robot", "square", "rotary"),
        default="car",
        help="motion: a car drive (--duration, --mix), the HDR Figure 3 drive, the Hong & Park robot run, "
        "the FOG square path or rotary table (--runs) (default car)",
    )
    p.add_argument("--sensor", choices=sorted(sim.SENSORS), default="crs03", help="simulated gyro (default crs03)")
    p.add_argument("--rate-hz", type=POSITIVE, help="sample rate [Hz] (default: the sensor's)")
    p.add_argument("--duration", type=POSITIVE, help=f"car drive length [s] (default {DURATION:g})")
    p.add_argument("--mix", choices=sorted(motion.ROAD_MIXES), help=f"car road mix (default {MIX})")
    p.add_argument("--runs", type=COUNT, help=f"runs of the square path or rotary table (default {RUNS})")
    p.add_argument("--seed", type=SEED, default=0, help="random seed (default 0)")
    add_overwrite_option(p)


def run(args: argparse.Namespace) -> int:
    out = Path(args.out)
    if out.suffix.lower() != ".csv":
        raise ValueError(f"{out}: output must end in .csv")
    refuse_existing([out], args.overwrite)
    _options_of_the_profile(args)
    rate_hz = sim.sensor(args.sensor).rate_hz if args.rate_hz is None else args.rate_hz
    spec = checked_sensor(args.sensor, rate_hz)
    if args.profile == "car":  # car_drive refuses a drive of too many samples before building its route
        check_car_drive(spec, args.duration, f"--duration {args.duration:g}")
        drive = sim.car_drive(args.duration, rate_hz, seed=args.seed, mix=args.mix, sensor_name=args.sensor)
    else:
        if args.profile in _REPEATED:
            # the simulator's sample limit, asked for all the runs before they are built one by one
            # (a billion runs would take hours to build before the limit said no)
            seconds = float(_REPEATED[args.profile](runs=1).knots[-1]) * args.runs
            try:
                sim.check_span(spec, 0.0, seconds)
            except ValueError as e:
                raise ValueError(f"--runs {args.runs} of the {args.profile} profile: {e}") from None
        drive = sim.simulate(_profiles(args)[args.profile](), args.sensor, seed=args.seed, rate_hz=args.rate_hz)
    route = drive.motion
    table = np.column_stack(
        [drive.t, drive.rate_measured, drive.temperature, drive.rate_true, drive.heading_true,
         drive.x, drive.y, drive.speed, drive.drift]
    )
    write_atomically(
        out,
        lambda tmp: np.savetxt(tmp, table, delimiter=",", header=",".join(COLUMNS), comments="", fmt="%.10g"),
        replace=args.overwrite,  # refused above if it existed; one written meanwhile is kept
    )
    rest = "none" if drive.stationary is None else f"{drive.stationary[0]:g} .. {drive.stationary[1]:g} s"
    print(
        f"{len(drive)} samples of {route.name!r} ({drive.duration:.1f} s) from {drive.sensor.name} at "
        f"{drive.sensor.rate_hz:g} Hz, seed {args.seed}; rest window {rest}; static bias "
        f"{math.degrees(drive.bias):.4f} deg/s -> {out}"
    )
    return 0

"""``gyrocore tune``: fit a method's parameters over training drives and write a parameter file."""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
from pathlib import Path
from typing import Any, Sequence

from .. import motion, sim, tune
from .._extras import require
from ..io import check_not_input, read_log
from ..pipeline import parameters
from .simulate import check_car_drive, checked_sensor
from ._common import (
    COUNT,
    NAME,
    NON_NEGATIVE,
    POSITIVE,
    SEED,
    add_command,
    add_overwrite_option,
    add_reading_options,
    once_each,
    parse_value,
    print_json,
    reading_options,
    refuse_existing,
    require_suffix,
)

_TABLES = {"II": motion.TABLE_II_DRIVES, "IV": motion.TABLE_IV_DRIVES}
#: Seeds of the simulated test drives start here, away from the training drives' seeds.
_TEST_SEED = 500
#: Seeds of the held-out do-no-harm drives.
_HARM_TEST_SEED = 2000
#: Seeds of the --sim-drive training drives.
_DRIVE_SEED = 300
#: Length of the do-no-harm drives at --time-scale 1 [min].
_HARM_MINUTES = 20.0


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "tune",
        "fit a method's parameters to minimise the mean NE_psi over training drives (HDR section 5.3)",
        "gyrocore tune --preset hdr --sim-table II --test-sim-table IV --out hdr_tuned.json",
        run,
    )
    add = p.add_argument
    # a file with its truth trains as in evaluate; "real log folders" kept it unsaid
    add("logs", nargs="*", type=NAME, metavar="LOGDIR", help="log folders to train on (with a reference), or CSV or Parquet "
        "files with a heading_true column [rad] (what gyrocore simulate writes)")
    add("--preset", default="hdr", metavar="NAME", help="base preset (default hdr)")
    add(
        "--param",
        action="append",
        metavar="NAME[=LOW:HIGH]",
        help="parameter to fit, optionally with SI bounds (repeatable; default: HDR's five, and the "
        "threshold where the preset has one)",
    )
    add("--sim-table", action="append", choices=sorted(_TABLES),
        help="train on simulated drives like HDR Table II or IV")
    add("--sim-drive", action="append", metavar="MIX:MINUTES[:COUNT]",
        help="train also on COUNT (default 1) simulated drives of a road mix (gyrocore.motion.ROAD_MIXES)")
    add("--set", action="append", metavar="NAME=VALUE",
        help="hold a parameter at an SI value, a switch at true or false (repeatable)")
    add("--test-sim-table", action="append", choices=sorted(_TABLES), help="simulated test drives (other seeds)")
    add("--test", action="append", default=[], type=NAME, metavar="LOGDIR",
        help="log folder (or file with a heading_true column) to test on (not trained on)")
    add("--time-scale", type=POSITIVE, default=1.0, metavar="F", help="scale the simulated drives' durations (default 1)")
    add("--rate-hz", type=POSITIVE, default=10.0, metavar="HZ",
        help="sample rate of the simulated drives [Hz] (default 10)")
    add("--sensor", default="crs03", metavar="NAME", help="simulated gyro (gyrocore.sim.SENSORS; default crs03)")
    add("--harm-mix", action="append", metavar="MIX", help="road mixes of the do-no-harm drives "
        f"(default {', '.join(tune.HARM_MIXES)})")
    add("--harm-per-mix", type=COUNT, default=2, metavar="N", help="do-no-harm drives per road mix and gyro (default 2)")
    add("--harm-noisy", action="store_true",
        help="also unbiased gyros with noise, against static bias removal (see gyrocore.tune)")
    add("--no-harm", action="store_true", help="no do-no-harm constraint")
    add("--harm-limit", type=NON_NEGATIVE, default=0.5, metavar="DEG",
        help="allowed E_psi above the baseline on a do-no-harm drive [deg] (default 0.5)")
    add("--objective", choices=tune.OBJECTIVES, default="ne_psi",
        help="minimise the mean NE_psi (HDR section 5.3; default) or the mean log ratio of E_psi to "
        "static-bias removal's (scale-free: for real logs of 0.4-116 deg)")
    add("--causal", action="store_true",
        help="run the logs as a streaming pipeline would (default: whole mode, as gyrocore evaluate)")
    add("--no-speed", action="store_true",
        help="whole mode: find the logs' rests from the rate alone, not where the speed is zero (as evaluate "
        "--no-speed)")
    add("--bias-duration", type=POSITIVE, metavar="S", help="static bias of logs without a rest window: first S seconds")
    add("--leave-one-out", action="store_true", help="also report the leave-one-out score (one fit per drive)")
    add("--max-evals", type=COUNT, default=2000, metavar="N", help="objective evaluations per fit (default 2000)")
    add("--seed", type=SEED, default=0, metavar="N", help="optimiser seed (default 0)")
    add("--optimiser", choices=tune.OPTIMISERS, default="differential_evolution",
        help="differential_evolution (global; the start is part of its first population; default) or nelder-mead "
        "(local, from the start)")
    add("--name", help="name of the parameter set (default <preset>_tuned)")
    add("-o", "--out", type=NAME, metavar="FILE",
        help="write the parameter file (JSON) here, for evaluate --params and process --params")
    add("--json", action="store_true",
        help="print the result as JSON (a report of the fit, not a parameter file: that is --out's)")
    add_overwrite_option(p)
    add_reading_options(p, "--bias-duration")


def _refuse_twice(option: str, specs: Sequence[str]) -> None:
    """Refuse a parameter given twice to ``option`` (``--param hdr_c1=1:2 --param hdr_c1=0.1:0.2``):
    the last was taken without a word."""
    names = [spec.partition("=")[0] for spec in specs]
    twice = next((n for i, n in enumerate(names) if n in names[:i]), None)
    if twice is not None:
        raise ValueError(f"{option} {twice} is given twice; give it once")


def _parse_params(specs: Sequence[str]) -> tuple[list[str], dict[str, tuple[float, float]]]:
    _refuse_twice("--param", specs)
    names: list[str] = []
    bounds: dict[str, tuple[float, float]] = {}
    for spec in specs:
        name, _, rng = spec.partition("=")
        if not name.strip():  # it was "unknown parameter(s) ; the pipeline's are ..."
            raise ValueError(f"--param {spec!r}: give a parameter's name, NAME or NAME=LOW:HIGH (SI bounds)")
        names.append(name)
        if rng:
            bounds[name] = _bounds(spec, rng)
    return names, bounds


def _bounds(spec: str, text: str) -> tuple[float, float]:
    """The bounds ``LOW:HIGH`` of ``--param spec``: finite numbers, LOW below HIGH."""
    low, _, high = text.partition(":")
    try:
        lo, hi = float(low), float(high)
    except ValueError:
        lo = hi = math.nan
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"--param {spec}: bounds must read LOW:HIGH, finite SI numbers with LOW < HIGH")
    return lo, hi


def _parse_drives(specs: Sequence[str]) -> list[motion.DriveSpec]:
    drives = []
    for spec in specs:
        parts = spec.split(":")
        try:
            mix, minutes, count = parts[0], float(parts[1]), int(parts[2]) if len(parts) > 2 else 1
        except (IndexError, ValueError):
            raise ValueError(f"--sim-drive {spec}: must read MIX:MINUTES[:COUNT]") from None
        if mix not in motion.ROAD_MIXES or len(parts) > 3 or not 0 < minutes < math.inf or count < 1:
            raise ValueError(f"--sim-drive {spec}: need a road mix of {', '.join(motion.ROAD_MIXES)}, "
                             "minutes > 0 and a count >= 1")
        drives += [motion.DriveSpec(f"{mix} {minutes:g} min", minutes, mix, "--sim-drive")] * count
    return drives


def _parse_fixed(specs: Sequence[str]) -> dict[str, float]:
    """The values of ``--set NAME=VALUE``; the names are :func:`gyrocore.tune.search_box`'s to
    check, which suggests one for a typo and takes the ``*_dps`` / ``*_deg`` spellings."""
    _refuse_twice("--set", specs)
    fixed: dict[str, Any] = {}
    switches = [n for n, what in parameters().items() if what.endswith("[bool]")]
    for spec in specs:
        name, sep, value = spec.partition("=")
        if not sep or not name:
            raise ValueError(f"--set {spec}: must read NAME=VALUE with a parameter name")
        if name in switches and value.lower() in ("true", "false"):  # as --param takes a switch
            fixed[name] = parse_value(value)
            continue
        try:
            fixed[name] = float(value)
        except ValueError:
            fixed[name] = math.nan
        if not math.isfinite(fixed[name]):
            switch = f" ({name} is a switch: true or false)" if name in switches else ""
            raise ValueError(f"--set {spec}: the value must be a finite number (SI){switch}")
    return fixed


def _check_simulated(args: argparse.Namespace) -> None:
    """Refuse, before any drive is built, a simulated drive (training, test or do-no-harm, which
    are always built for the held-out check) that --time-scale or --sim-drive makes no longer than
    its rest, or a --rate-hz that leaves too few samples in its rest, naming the option: the car
    model said only "the rest (20.0 s) must be shorter than the drive (18.0 s)", and a rate of
    0.01 Hz failed in the scoring with "reference: 1 sample(s)"."""
    spec = checked_sensor(args.sensor, args.rate_hz)
    tables = {*(args.sim_table or []), *(args.test_sim_table or [])}
    minutes = {f"--sim-table {t}": min(d.minutes for d in _TABLES[t]) for t in sorted(tables)}
    minutes |= {f"--sim-drive {d.mix}:{d.minutes:g}": d.minutes for d in _parse_drives(args.sim_drive or [])}
    minutes["the do-no-harm drives"] = _HARM_MINUTES
    for what, m in minutes.items():
        check_car_drive(spec, m * 60.0 * args.time_scale, f"{what} ({m:g} min at --time-scale {args.time_scale:g})")
    # every simulated drive begins with the same rest, the samples of which the simulator counts
    t = sim.sample_times(spec, 0.0, 2 * sim.CAR_REST, seed=0)
    sim.refuse_too_few_samples(t, (0.0, sim.CAR_REST), spec.rate_hz)


def run(args: argparse.Namespace) -> int:
    if args.name is not None:  # the set's own check names no option, and came after the drives were built
        if not args.name.strip():
            raise ValueError(f"--name {args.name!r}: give the parameter set a name that is not blank (or leave --name "
                             f"out: {args.preset}_tuned)")
        try:
            tune.ParameterSet(args.name, args.preset, {})  # a line break split evaluate's rows of the set
        except ValueError as e:
            raise ValueError(f"--name: {e}") from None
    if args.out is not None:  # before the fit, which takes minutes
        check_not_input(Path(args.out), [Path(p) for p in args.logs + args.test])
        require_suffix(args.out, "--out", "a JSON parameter file", (".json",))
        refuse_existing([Path(args.out)], args.overwrite)
    require("scipy.optimize", "tuning")  # before the drives are built
    names, bounds = _parse_params(args.param or [])
    fixed = _parse_fixed(args.set or [])
    box = tune.search_box(args.preset, names or None, bounds, fixed)  # before the drives are built
    try:
        tune.start_point(args.preset, box, fixed)
    except ValueError as e:  # the core's words are the Python API's: tune fixes a parameter with --set
        raise ValueError(re.sub(r"\bpass (\w+)=True\b", r"give --set \1=true", str(e))) from None
    _check_simulated(args)
    progress = (lambda msg: print(msg, file=sys.stderr)) if not args.json else None
    sim_options = {"rate_hz": args.rate_hz, "sensor_name": args.sensor, "time_scale": args.time_scale}
    reading = reading_options(args)
    mode = "causal" if args.causal else "whole"

    def log_cases(paths: Sequence[str]) -> list[tune.Case]:
        return [tune.Case.from_log(read_log(p, use_fixes=False, **reading), bias_duration=args.bias_duration, mode=mode,
                                   use_speed=not args.no_speed) for p in paths]

    twice = "a log given twice weighed twice in the mean over the drives"
    args.logs, args.test = once_each(args.logs, "a training log", twice), once_each(args.test, "a --test log", twice)
    both = set(map(os.path.realpath, args.logs)) & set(map(os.path.realpath, args.test))
    if both:  # its test score would be no held-out score
        raise ValueError(f"{', '.join(p for p in args.test if os.path.realpath(p) in both)}: both a training log and a "
                         "--test log; a test log is scored with parameters fitted without it: give it as one of them")
    cases = log_cases(args.logs)
    for table in args.sim_table or []:
        cases += tune.simulated_cases(_TABLES[table], **sim_options)
    if args.sim_drive:
        cases += tune.simulated_cases(_parse_drives(args.sim_drive), first_seed=_DRIVE_SEED, **sim_options)
    if not cases:
        raise ValueError("no training drive: give log folders, --sim-table and/or --sim-drive")
    if args.leave_one_out:  # before the main fit, not after it
        tune.check_leave_one_out(cases)
    tests = log_cases(args.test)
    for table in args.test_sim_table or []:
        tests += tune.simulated_cases(_TABLES[table], first_seed=_TEST_SEED, **sim_options)
    harm_options: dict[str, Any] = {
        "minutes": _HARM_MINUTES * args.time_scale, "rate_hz": args.rate_hz, "mixes": args.harm_mix or tune.HARM_MIXES,
        "per_mix": args.harm_per_mix,
    }
    gyros = (False, True) if args.harm_noisy else (False,)

    def harm_drives(**seed: Any) -> list[tune.Case]:
        return [c for noisy in gyros for c in tune.harm_cases(**harm_options, **seed, noisy=noisy)]

    harm = [] if args.no_harm else harm_drives()
    # The same roads with other seeds: does the constraint hold on drives it was not fitted to?
    harm_test = harm_drives(first_seed=_HARM_TEST_SEED)
    options: dict[str, Any] = {
        "preset": args.preset, "names": names or None, "bounds": bounds, "harm": harm,
        "harm_limit_deg": args.harm_limit, "fixed": fixed,
        "max_evaluations": args.max_evals, "seed": args.seed,
        "optimiser": args.optimiser, "objective": args.objective,
    }
    if progress:
        progress(f"tuning {args.preset} on {len(cases)} drive(s), {len(harm)} do-no-harm drive(s), "
                 f"up to {args.max_evals} evaluations")
    result = tune.tune(cases, name=args.name, **options)
    try:
        loo = tune.leave_one_out(cases, progress=progress, **options) if args.leave_one_out else ()
    except tune.TuningInterrupted as e:  # the fit on all drives had ended: what the file would have held
        raise tune.TuningInterrupted(
            f"the fit on all {len(cases)} drive(s) had ended ({result.evaluations} evaluations, objective "
            f"{result.objective:.6g}); the {e.what}; the fit on all drives found",
            {n: result.params.overrides[n] for n in result.bounds},
        ) from None
    test = tune.score_cases(tests, args.preset, result.params.overrides)
    test_start = tune.score_cases(tests, args.preset, result.start)
    held = (
        tune.score_cases(harm_test, args.preset, result.start),
        tune.score_cases(harm_test, args.preset, result.params.overrides),
    )
    extra = dict(result.params.tuning)
    # how the real logs were run: the file's scores are evaluate's only when it runs them alike
    extra["mode"] = mode
    extra["bias_duration_s"] = args.bias_duration
    extra["use_speed"] = not args.no_speed
    extra["harm_held_out_deg"] = {s.case: s.harm_deg for s in held[1]}
    if loo:
        extra["leave_one_out_ne_psi_deg_per_min"] = tune.mean_ne_psi(loo)
        extra["leave_one_out_log_ratio"] = tune.mean_log_ratio(loo)
    if test:
        extra["test"] = {t.case: t.ne_psi_deg_per_min for t in test}
        extra["test_score_ne_psi_deg_per_min"] = tune.mean_ne_psi(test)
    params = tune.ParameterSet(result.params.name, result.params.preset, result.params.overrides, extra)
    if args.out:
        params.write(args.out, overwrite=args.overwrite)  # refused before the fit if it existed
    if args.json:
        out = result.as_dict()
        out["leave_one_out"] = [s.as_dict() for s in loo]
        out["test"] = [s.as_dict() for s in test]
        out["test_start"] = [s.as_dict() for s in test_start]
        out["harm_test_start"] = [s.as_dict() for s in held[0]]
        out["harm_test"] = [s.as_dict() for s in held[1]]
        print_json(out)
    else:
        _print_report(result, loo, test, test_start)
        _print_harm("held-out drives", *held, result.harm_limit_deg)
    if args.out:
        # process's --bias-duration replaces a log's rest window, evaluate's does not: left out there
        run_as = " --causal" * args.causal + " --no-speed" * args.no_speed
        again = run_as + (f" --bias-duration {args.bias_duration:g}" if args.bias_duration else "")
        print(f"wrote {args.out} (score it: gyrocore evaluate LOGDIR --params {args.out}{again}; run it: gyrocore "
              f"process IN --params {args.out}{run_as} -o OUT)", file=sys.stderr if args.json else sys.stdout)
    return 0


_RATES = ("hdr_increment", "hdr_turn_threshold", "threshold")


def _print_report(
    result: tune.TuningResult,
    loo: Sequence[tune.CaseScore],
    test: Sequence[tune.CaseScore],
    test_start: Sequence[tune.CaseScore],
) -> None:
    units = parameters()
    print(f"{result.params.preset}: {result.optimiser}, seed {result.seed}, {result.evaluations} evaluations")
    print(f"{'parameter':<20} {'start':>12} {'tuned':>12}  unit")
    for name, value in result.params.overrides.items():
        deg = f"  ({math.degrees(result.start[name]):.4g} -> {math.degrees(value):.4g} deg/s)" if name in _RATES else ""
        print(f"{name:<20} {result.start[name]:>12.5g} {value:>12.5g}  {units.get(name, '')}{deg}")
    _print_scores("training", result.train_start, result.train)
    if test:
        _print_scores("test", test_start, test)
    if loo:
        _print_held_out(loo)
        print(f"leave-one-out mean NE_psi: {tune.mean_ne_psi(loo):.4f} deg/min (training {result.train_score:.4f}); "
              f"mean log(E_psi / static_bias's): {tune.mean_log_ratio(loo):+.4f} (training {tune.mean_log_ratio(result.train):+.4f})")
    if result.harm:
        _print_harm("the fit's drives", result.harm_start, result.harm, result.harm_limit_deg)


def _print_harm(label: str, start: Sequence[tune.CaseScore], tuned: Sequence[tune.CaseScore], limit: float) -> None:
    print(f"do no harm on {label} (E_psi above the baseline, limit {limit} deg):")
    for before, after in zip(start, tuned):
        flag = "ok" if after.harm_deg <= limit else "EXCEEDED"
        print(f"  {after.case:<60} start {before.harm_deg:+8.3f}  tuned {after.harm_deg:+8.3f} deg  {flag}")


def _print_scores(label: str, start: Sequence[tune.CaseScore], tuned: Sequence[tune.CaseScore]) -> None:
    print(f"{label + ' drive':<44} {'raw E_psi':>10} {'start E_psi':>12} {'tuned E_psi':>12} {'tuned NE_psi':>13}")
    print(f"{'':<44} {'[deg]':>10} {'[deg]':>12} {'[deg]':>12} {'[deg/min]':>13}")  # as evaluate's table
    for a, b in zip(start, tuned):
        print(f"{b.case:<44} {b.raw_e_psi_deg:>10.2f} {a.e_psi_deg:>12.3f} {b.e_psi_deg:>12.3f} "
              f"{b.ne_psi_deg_per_min:>13.4f}")
    # on a line of its own: under the E_psi columns the means read as degrees
    print(f"mean NE_psi: start {tune.mean_ne_psi(start):.4f}, tuned {tune.mean_ne_psi(tuned):.4f} deg/min")


def _print_held_out(loo: Sequence[tune.CaseScore]) -> None:
    """Each drive scored with the parameters fitted without it, beside static-bias removal."""
    print(f"{'held-out drive (leave-one-out)':<44} {'raw E_psi':>10} {'static_bias':>12} {'tuned E_psi':>12}")
    print(f"{'':<44} {'[deg]':>10} {'[deg]':>12} {'[deg]':>12}")
    for s in loo:
        print(f"{s.case:<44} {s.raw_e_psi_deg:>10.2f} {s.static_bias_e_psi_deg:>12.3f} {s.e_psi_deg:>12.3f}")

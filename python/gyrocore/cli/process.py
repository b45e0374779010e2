"""``gyrocore process``: the heading of logs, streamed to CSV or Parquet; one file or a fleet."""

from __future__ import annotations

import argparse
import os
import re
import warnings
from pathlib import Path
from typing import Any

from .. import io
from .._checks import InputWarning, collected
from ..batch import (
    check_out_dir,
    check_outside_inputs,
    check_unreached,
    complete_output,
    expand_inputs,
    output_paths,
    process_file,
    process_many,
)
from ..tune import ParameterSet
from ._fixes import add_fix_options, any_fixes_csv, note_unused_gnss
from ._common import (
    BIAS_DPS,
    COUNT,
    NAME,
    POSITIVE,
    POSITIVE_OR_INF,
    WINDOW_HELP,
    add_command,
    add_overwrite_option,
    add_override_options,
    add_reading_options,
    named,
    pipeline_overrides,
    print_json,
    progress_bar,
    reading_options,
    refuse_existing,
    warn_about,
)

_EPILOG = """
IN is a CSV (or tab-separated .tsv), Parquet, .npy or .npz file, a ROS 1 .bag or ROS 2 bag
folder, a log folder, a folder of those, or a glob; give several. OUT ending in .csv or .parquet
is one output file (one input); otherwise a folder (a name without another file suffix, or
ending in /) that receives <name>.csv (or --format parquet) per input, processed in parallel (--jobs, or a Dask cluster with --scheduler). An
output that exists already is refused before any work unless --overwrite is given, or, in an
output folder, --skip-existing (which skips its input: outputs are written whole or not at all).
Exit code 0: all done; 1: some files failed (listed with their reason); 2: bad usage or input
(one line); 130: interrupted.
"""


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_command(
        sub,
        "process",
        "compute the heading of logs (CSV, Parquet, NumPy, ROS bags, log folders) into CSV or Parquet",
        "gyrocore process sample_drive --out heading.csv --preset recommended",
        run,
    )
    p.epilog = f"{p.epilog}\n{_EPILOG}"
    p.formatter_class = argparse.RawDescriptionHelpFormatter
    p.add_argument("inputs", nargs="+", type=NAME, metavar="IN", help="input files, folders or glob patterns")
    p.add_argument("-o", "--out", required=True, type=named("a .csv or .parquet file, or a folder for several inputs"), help="output .csv/.parquet file, or a folder for several inputs")
    p.add_argument("--preset", help="preset name (default recommended; with --params, the file's base preset)")
    p.add_argument("--params", type=NAME, metavar="FILE",
                   help="parameter file written by gyrocore tune: its base preset and its parameters (the static "
                   "bias still comes from each log or the bias options)")

    add_reading_options(p, "--bias-window or --bias-duration")

    bias = p.add_argument_group(
        "static bias (default: the rest window of a log folder's meta.json, else every rest found in the log, "
        "applied from the first sample; finding rests reads the log's times and rates into memory, 16 bytes a sample)"
    )
    bias.add_argument(
        "--causal",
        action="store_true",
        help="what a streaming pipeline gives: a rest corrects only what follows it, no rest search (one pass)",
    )
    bias.add_argument(
        "--no-speed",
        action="store_true",
        help="find rests from the rate alone, not where the speed is zero (a log folder's odometry.csv, "
        "a file's speed column [m/s])",
    )
    group = bias.add_mutually_exclusive_group()
    group.add_argument("--bias-window", nargs=2, metavar=("T0", "T1"), help=f"rest window: {WINDOW_HELP}")
    group.add_argument("--bias-duration", type=POSITIVE, metavar="S", help="rest during the first S seconds")
    group.add_argument("--bias-dps", type=BIAS_DPS, metavar="B", help="known bias [deg/s] (what the gyro reads at rest)")

    pipe = p.add_argument_group("pipeline")
    pipe.add_argument("--nonfinite", choices=("error", "hold", "skip"), help="NaN/inf readings (default error)")
    pipe.add_argument("--gap-limit", type=POSITIVE_OR_INF, metavar="S", help="longest interval that is not a gap [s] (default 2)")
    pipe.add_argument("--gap-action", choices=("bridge", "reset"), help="at a gap (default bridge)")
    add_override_options(pipe)

    out = p.add_argument_group("output")
    out.add_argument(
        "--heading",
        choices=io.HEADING_CONVENTIONS,
        default="enu",
        help="enu: yaw CCW from east (default); compass: CW from north; either in radians and continuous (not "
        "wrapped to a turn), the yaw starting at initial_heading (--param; default 0: east)",
    )
    out.add_argument(
        "--format", choices=("csv", "parquet"), help="file format in an output folder (default csv)"
    )
    out.add_argument(
        "--columns",
        metavar="LIST",
        help=f"the columns to write, comma-separated, e.g. t,heading (default {','.join(io.OUTPUT_COLUMNS)}: "
        "t [s], heading [rad], rate and drift [rad/s]); rate and drift are computed only when written",
    )
    out.add_argument("--jobs", type=COUNT, help="parallel files (default: all cores)")
    out.add_argument("--scheduler", metavar="ADDRESS", help="run on this Dask scheduler (tcp://host:8786)")
    out.add_argument(
        "--chunk-rows",
        type=COUNT,
        default=io.DEFAULT_CHUNK_ROWS,
        help=f"samples per chunk (default {io.DEFAULT_CHUNK_ROWS})",
    )
    out.add_argument("--json", action="store_true", help="print the report as JSON")
    existing = out.add_mutually_exclusive_group()
    add_overwrite_option(existing)
    existing.add_argument(
        "--skip-existing",
        action="store_true",
        help="in an output folder, skip each input whose output exists already (named and counted in the "
        "report): an interrupted batch goes on where it stopped (an output appears only once complete)",
    )
    add_fix_options(p, evaluate=False)


def options(args: argparse.Namespace, tuned: dict[str, Any]) -> dict[str, Any]:
    """Reader options and pipeline overrides from the command line, with the parameters ``tuned``
    of a --params file (:func:`_tuned`)."""
    named = {
        "bias_window": args.bias_window,
        "bias_duration": args.bias_duration,
        "bias_dps": args.bias_dps,
        "nonfinite": args.nonfinite,
        "gap_limit": args.gap_limit,
        "gap_action": args.gap_action,
    }
    out = {**reading_options(args), **pipeline_overrides(args, named)}
    twice = sorted(set(tuned) & set(out))
    if twice:  # as evaluate --params: which of two values was meant is not for the command to guess
        raise ValueError(f"--params {args.params} sets {', '.join(twice)}, which the command line gives too")
    return {**out, **tuned}


def _tuned(args: argparse.Namespace) -> dict[str, Any]:
    """The parameters of the --params file ({} without one), read once and before any work (a bad
    file fails at once), and ``args.preset`` set to the preset to run: --preset, else the file's
    base preset, else recommended. A tuned file's parameters belong to its own preset: another one
    given with it is refused."""
    if args.params is None:
        args.preset = args.preset or "recommended"
        return {}
    params = ParameterSet.read(args.params)
    if args.preset is not None and args.preset != params.preset:
        raise ValueError(f"--preset {args.preset}: --params {args.params} was tuned for the preset {params.preset}; "
                         "leave --preset out")
    args.preset = params.preset
    return dict(params.overrides)


def columns(args: argparse.Namespace) -> tuple[str, ...] | None:
    """The output columns of ``--columns``; None (not given): all, with the heading's sigma for a
    log with heading fixes."""
    if args.columns is None:
        return None
    return io.check_columns([c.strip() for c in args.columns.split(",")], "--columns")


def run(args: argparse.Namespace) -> int:
    if args.out == "-":  # the Unix spelling of standard output became a folder named "-"
        raise ValueError("--out -: the headings go to a file (the report goes to standard output): give a .csv "
                         "or .parquet file, or a folder for several inputs")
    tuned = _tuned(args)
    inputs = expand_inputs(args.inputs)
    out = Path(args.out)
    # the files that options name are inputs too: none may become the output (said before that the
    # output exists; an input that cannot be read fails later with its reason)
    named = [Path(p) for p in (args.fixes, args.calibration, args.params) if p is not None]
    io.check_not_input(out, [*(p for p in inputs if p.exists()), *named])
    check_outside_inputs(args.inputs, out, inputs)
    run_options = options(args, tuned)
    kwargs = {**run_options, "columns": columns(args)}
    one_file = out.suffix.lower() in (".csv", ".parquet", ".pq")
    if args.skip_existing and one_file:
        raise ValueError(f"--skip-existing is for a batch into an output folder, and --out {out} is one file: "
                         "leave the option out (an output that exists is refused unless --overwrite is given)")
    if one_file and args.format not in (None, io.output_format(out)):  # it was left unused without a word
        raise ValueError(f"--format {args.format}: --out {out} is one file, whose suffix says its format "
                         f"({io.output_format(out)}); --format is the format of an output folder's files: leave it "
                         "out, or give the file the suffix of the format meant")
    unused = [f"{o} {v}" for o, v in (("--jobs", args.jobs), ("--scheduler", args.scheduler)) if v is not None]
    if not one_file and len(unused) == 2:  # the cluster's workers ran the files, --jobs left unused without a word
        raise ValueError(f"{' '.join(unused)}: --jobs is the number of files processed at once here, and "
                         "--scheduler runs them on the Dask cluster's workers (as many as it has): give one of them")
    if one_file and unused and len(inputs) == 1:  # the one file was processed here, on one thread, without a word
        raise ValueError(f"{' '.join(unused)}: --out {out} is one file, processed here from one input; "
                         f"{'they run' if len(unused) > 1 else 'it runs'} the files of a batch into an output folder "
                         f"(--out DIR): leave {'them' if len(unused) > 1 else 'it'} out")
    args.format = args.format or "csv"
    if not one_file:
        _refuse_file_like_folder(args.out)
        check_out_dir(out)
    outputs = [out] if one_file else output_paths(inputs, out, args.format, named)
    check_unreached(args.inputs, [out, *outputs])
    # a complete output that --skip-existing keeps is not refused; anything else there is
    refuse_existing([p for p in outputs if not (args.skip_existing and complete_output(p))], args.overwrite,
                    folders_exist=one_file)  # an output folder is made
    try:
        with warnings.catch_warnings():
            # every file's report carries these; print them once, with the file's name
            warnings.simplefilter("ignore", InputWarning)
            if args.fixes is not None:  # a log folder's own fixes.csv is fused by its job, also in a batch
                if len(inputs) != 1:
                    raise ValueError(f"--fixes {args.fixes} is for one input, got {len(inputs)}")
                if not one_file:
                    raise ValueError(f"--out {out}: with --fixes the output is one .csv or .parquet file")
                kwargs["fixes"] = args.fixes
            elif "heading_sigma" in (kwargs["columns"] or ()) and not any_fixes_csv(args, inputs):
                raise ValueError("--columns heading_sigma: it comes with heading fixes (--fixes FILE, or log "
                                 "folders with fixes.csv)")
            note_unused_gnss(args, [p for p in inputs if p.is_dir()],
                             "" if one_file else "in a run of FOLDER alone, into one .csv or .parquet file")
            if one_file:
                return _one(inputs, out, args, kwargs)
            return _many(out, args, kwargs)
    except ImportError as e:  # an optional dependency the input needs: the user can install it
        raise ValueError(str(e)) from None


def _one(inputs: list[Path], out: Path, args: argparse.Namespace, kwargs: dict[str, Any]) -> int:
    if len(inputs) != 1:
        raise ValueError(f"--out {out} is one file but there are {len(inputs)} inputs; give a folder")
    raised: list[str] = []
    try:
        # a file that fails has no report to carry its warnings: they are collected here (as
        # warnings they are ignored, see run)
        with progress_bar(inputs[0].name) as bar, collected(raised):
            report = process_file(inputs[0], out, progress=bar, overwrite=args.overwrite, **_run_options(args),
                                  **kwargs)
    except Exception:
        # what looked wrong before the error often says why (float32 times that cannot increase);
        # the error follows, in one line
        warn_about(inputs[0], raised)
        raise
    warn_about(inputs[0], report.warnings)
    if args.json:
        print_json(report.as_dict())
    else:
        print(report)
    return 0


def _refuse_file_like_folder(given: str) -> None:
    """Refuse an output named like a file of another kind (``heading.tsv``, ``h.txt``, ``h.npy``),
    which became a folder holding ``<input>.csv``: the user asked for a file. A folder that exists,
    or a name ending in ``/``, is taken as the folder it names (a file that exists is refused as
    no folder, by :func:`check_out_dir`)."""
    out = Path(given)
    if re.fullmatch(r"\.[A-Za-z]{1,5}", out.suffix) and not out.exists() and not given.endswith(("/", os.sep)):
        raise ValueError(f"--out {given}: gyrocore writes the headings to a .csv or .parquet file, not {out.suffix}; "
                         f"give one of those, or a folder for the outputs (a folder named {out.name}: "
                         f"--out {given}/)")


def _run_options(args: argparse.Namespace) -> dict[str, Any]:
    """What one file and a batch are run with alike."""
    return {"preset": args.preset, "heading": args.heading, "chunk_rows": args.chunk_rows,
            "mode": "causal" if args.causal else "whole", "use_speed": not args.no_speed, "use_fixes": not args.no_fixes}


def _many(out: Path, args: argparse.Namespace, kwargs: dict[str, Any]) -> int:
    summary = process_many(
        args.inputs,  # as given: the folders among them are where no output may go
        out_dir=out,
        client=args.scheduler,
        jobs=args.jobs,
        fmt=args.format,
        progress=True,
        skip_existing=args.skip_existing,
        # an output another run writes meanwhile is kept unless --overwrite (checked before the
        # work, it appeared since)
        overwrite=args.overwrite,
        **_run_options(args),
        **kwargs,
    )
    for report in summary.files:
        warn_about(report.input, report.warnings)
    if args.json:
        print_json(summary.as_dict())
    else:
        print(summary)
    return 0 if not summary.failed else 1

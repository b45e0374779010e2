"""The ``gyrocore`` command line."""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import evaluate, io, sim
from .pipeline import preset_names, process, recommended_preset, uses_static_bias

EXAMPLES = {
    "demo": "gyrocore demo --duration 900 --seed 3",
    "process": "gyrocore process ../shared/data/real/f110_ds3 --out heading.csv --preset recommended",
    "presets": "gyrocore presets --json",
}


def _demo(args: argparse.Namespace) -> int:
    drive = sim.car_drive(duration=args.duration, rate_hz=args.rate_hz, seed=args.seed)
    rows: list[dict[str, Any]] = []
    results = {}
    for preset in preset_names():
        bias = {"bias_window": drive.stationary} if uses_static_bias(preset) else {}
        result = process(drive.t, drive.rate_measured, preset, **bias)
        results[preset] = result
        errors = evaluate.heading_errors(drive.t, result.heading, drive.t, drive.heading_true)
        rows.append({"preset": preset, **errors.as_dict()})
    raw_e = rows[0]["e_psi_deg"]
    if args.json:
        print(json.dumps(rows, indent=2))
    else:
        print(
            f"Simulated drive: {args.duration:.0f} s at {args.rate_hz:g} Hz (seed {args.seed}), "
            f"static bias {np.degrees(drive.bias):.3f} deg/s, drift up to "
            f"{np.degrees(np.abs(drive.drift).max()):.3f} deg/s"
        )
        print(f"{'preset':<12} {'E_psi [deg]':>12} {'NE_psi [deg/min]':>17} {'final [deg]':>12} {'vs raw':>8}")
        for r in rows:
            gain = raw_e / r["e_psi_deg"] if r["e_psi_deg"] > 0 else float("inf")
            print(
                f"{r['preset']:<12} {r['e_psi_deg']:>12.3f} {r['ne_psi_deg_per_min']:>17.4f} "
                f"{r['final_error_deg']:>12.3f} {gain:>7.1f}x"
            )
        print(f"recommended = {recommended_preset()}")
    if args.plot:
        _plot_demo(Path(args.plot), drive, results)
    return 0


def _plot_demo(path: Path, drive: sim.Drive, results: dict[str, Any]) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(no plot: install matplotlib, e.g. pip install 'gyrocore[plot]')", file=sys.stderr)
        return
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(9, 6))
    ax1.plot(drive.t, np.degrees(drive.heading_true), "k", lw=2, label="true")
    for name, r in results.items():
        ax1.plot(r.t, r.heading_deg, lw=1, label=name)
        ax2.plot(r.t, r.heading_deg - np.degrees(drive.heading_true), lw=1, label=name)
    ax1.set_ylabel("heading [deg]")
    ax2.set_ylabel("error [deg]")
    ax2.set_xlabel("t [s]")
    ax1.legend(fontsize=8)
    fig.tight_layout()
    _write_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=100))
    plt.close(fig)
    print(f"wrote {path}")


def _write_atomically(path: Path, write: Any) -> None:
    """Write through a temporary file in the same folder and rename: no half-written output."""
    fd, tmp = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def _read_input(path: Path, time_col: str, rate_col: str) -> tuple[np.ndarray, np.ndarray, tuple[float, float] | None]:
    if path.is_dir():
        log = io.read_log(path)
        return log.t, log.rate, log.stationary
    cols = io.read_csv_columns(path, (time_col, rate_col))
    return cols[time_col], cols[rate_col], None


def _process(args: argparse.Namespace) -> int:
    src, out = Path(args.input), Path(args.out)
    if out.resolve() == src.resolve() or (src.is_dir() and src.resolve() in out.resolve().parents):
        raise ValueError(f"refusing to write {out} inside or over the input {src}")
    if out.suffix.lower() != ".csv":
        raise ValueError(f"{out}: output must end in .csv")
    t, rate, window = _read_input(src, args.time_col, args.rate_col)
    if args.rate_unit == "deg/s":
        rate = np.radians(rate)
    overrides: dict[str, Any] = {}
    if args.bias_dps is not None:
        overrides["bias_dps"] = args.bias_dps
    elif uses_static_bias(args.preset) and window is not None:
        overrides["bias_window"] = window
    result = process(t, rate, args.preset, **overrides)
    table = np.column_stack([result.t, result.heading, result.rate, result.drift])
    _write_atomically(
        out,
        lambda tmp: np.savetxt(tmp, table, delimiter=",", header="t,heading,rate,drift", comments="", fmt="%.10g"),
    )
    print(f"{len(t)} samples in, {len(result)} out -> {out}")
    return 0


def _presets(args: argparse.Namespace) -> int:
    from .pipeline import preset_params

    params = {name: preset_params(name) for name in preset_names()}
    if args.json:
        print(json.dumps({"recommended": recommended_preset(), "presets": params}, indent=2))
    else:
        for name, p in params.items():
            mark = " (recommended)" if name == recommended_preset() else ""
            print(f"{name}{mark}: " + ", ".join(f"{k}={v}" for k, v in p.items()))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="gyrocore", description="Drift-free heading from a yaw-rate gyro.")
    sub = parser.add_subparsers(dest="command", required=True)

    def add(name: str, help_text: str) -> argparse.ArgumentParser:
        return sub.add_parser(
            name, help=help_text, description=help_text, epilog=f"example: {EXAMPLES[name]}"
        )

    demo = add("demo", "simulate a drive, run every preset, print the errors and plot the headings")
    demo.add_argument("--duration", type=float, default=600.0, help="drive length [s] (default 600)")
    demo.add_argument("--rate-hz", type=float, default=100.0, help="gyro sample rate [Hz] (default 100)")
    demo.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    demo.add_argument("--plot", default="gyrocore_demo.png", help="PNG to write ('' for none)")
    demo.add_argument("--json", action="store_true", help="print the table as JSON")
    demo.set_defaults(func=_demo)

    proc = add("process", "compute the heading of a log folder or CSV file")
    proc.add_argument("input", help="log folder (gyro.csv, meta.json) or CSV file")
    proc.add_argument("--out", required=True, help="output CSV with columns t, heading, rate, drift")
    proc.add_argument("--preset", default="recommended", help="preset name (default recommended)")
    proc.add_argument("--time-col", default="t", help="time column of a CSV input [s]")
    proc.add_argument("--rate-col", default="gyro_z", help="rate column of a CSV input")
    proc.add_argument("--rate-unit", choices=("rad/s", "deg/s"), default="rad/s")
    proc.add_argument("--bias-dps", type=float, help="static bias [deg/s] instead of the rest window")
    proc.set_defaults(func=_process)

    pre = add("presets", "list the presets and their parameters")
    pre.add_argument("--json", action="store_true")
    pre.set_defaults(func=_presets)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except (ValueError, TypeError, OSError) as e:
        print(f"gyrocore: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

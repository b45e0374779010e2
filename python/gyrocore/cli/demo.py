"""``gyrocore demo``: simulate drives, run every preset, print the errors, plot the headings.

One simulated drive says little about a method (the table below differs a lot from seed to
seed), so the table averages several drives of the same roads and counts on how many each preset
beats static-bias removal; the plot shows the first.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from .. import evaluate, motion, sim, tune
from .._extras import MissingExtra, pyplot
from ..io.atomic import write_atomically
from ..pipeline import HeadingResult, preset_names, recommended_preset
from ._common import (
    COUNT, POSITIVE, SEED, add_command, add_overwrite_option, print_json, refuse_existing, require_suffix,
)
from .simulate import check_car_drive, checked_sensor


#: The demo's own plot: each run replaces the previous run's (a file named with --plot is the user's).
PLOT = "gyrocore_demo.png"
#: What the demo's plot says of itself (a PNG ``tEXt`` chunk), so that a run replaces only a plot it
#: wrote: a file of that name from anywhere else is the user's, refused unless --overwrite.
_SOFTWARE = "gyrocore demo"


def _written_by_demo(path: Path) -> bool:
    """Whether ``path`` is missing or a PNG the demo wrote (its ``Software`` text chunk, read
    chunk by chunk up to the image data)."""
    if not os.path.lexists(path):
        return True
    try:
        with open(path, "rb") as f:
            if f.read(8) != b"\x89PNG\r\n\x1a\n":
                return False
            while header := f.read(8):
                size, kind = int.from_bytes(header[:4], "big"), header[4:]
                if kind == b"IDAT" or len(header) < 8:
                    return False
                data = f.read(size)
                f.seek(4, os.SEEK_CUR)  # the chunk's CRC
                if kind == b"tEXt" and data == b"Software\0" + _SOFTWARE.encode():
                    return True
    except OSError:  # a folder, a file that cannot be read: not the demo's to replace
        return False
    return False


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "demo",
        "simulate drives, run every preset, print the errors and plot the headings",
        "gyrocore demo --duration 900 --seed 3 --drives 10",
        run,
    )
    p.add_argument("--duration", type=POSITIVE, default=600.0, help="drive length [s] (default 600)")
    p.add_argument("--rate-hz", type=POSITIVE, default=100.0, help="gyro sample rate [Hz] (default 100)")
    p.add_argument("--seed", type=SEED, default=0, help="random seed of the first drive (default 0)")
    p.add_argument("--drives", type=COUNT, default=5, help="drives to average, seeds from --seed (default 5)")
    p.add_argument("--sensor", choices=sorted(sim.SENSORS), default="crs03",
                   help="simulated gyro (default crs03, the HDR paper's)")
    p.add_argument("--mix", choices=sorted(motion.ROAD_MIXES), default="mixed",
                   help="road mix of the drive (default mixed, the HDR paper's Mixed Drive)")
    p.add_argument("--plot", default=PLOT, help=f"PNG to write ('' for none; default {PLOT}, which each run "
                   "replaces if the demo wrote it; any other file that exists is refused unless --overwrite)")
    add_overwrite_option(p)
    p.add_argument("--json", action="store_true", help="print the table as JSON")


def run(args: argparse.Namespace) -> int:
    if args.plot and Path(args.plot) != Path(PLOT):
        require_suffix(args.plot, "--plot", "a PNG image", (".png",))
        refuse_existing([Path(args.plot)], args.overwrite)
    elif args.plot and not args.overwrite and not _written_by_demo(Path(PLOT)):
        raise FileExistsError(f"{PLOT} already exists and is not a plot gyrocore demo wrote; pass --overwrite to "
                              "replace it, or --plot FILE to write elsewhere (nothing was written)")
    check_car_drive(checked_sensor(args.sensor, args.rate_hz), args.duration, f"--duration {args.duration:g}")
    drives = [
        sim.car_drive(duration=args.duration, rate_hz=args.rate_hz, seed=args.seed + k, mix=args.mix,
                      sensor_name=args.sensor)
        for k in range(args.drives)
    ]
    errors: dict[str, list[evaluate.HeadingErrors]] = {p: [] for p in preset_names()}
    first: dict[str, HeadingResult] = {}
    for k, drive in enumerate(drives):
        case = tune.Case.from_drive(f"seed {args.seed + k}", drive)
        for preset in errors:
            result = case.heading(preset, {})
            errors[preset].append(case.reference.errors(result.t, result.heading))
            if k == 0:
                first[preset] = result
    static = [e.e_psi_deg for e in errors["static_bias"]]
    rows: list[dict[str, Any]] = []
    for preset, errs in errors.items():
        e_psi = [e.e_psi_deg for e in errs]
        rows.append({
            "preset": preset,
            "e_psi_deg": float(np.mean(e_psi)),
            "ne_psi_deg_per_min": float(np.mean([e.ne_psi_deg_per_min for e in errs])),
            "abs_final_error_deg": float(np.mean([abs(e.final_error_deg) for e in errs])),
            "beats_static_bias": sum(a < b for a, b in zip(e_psi, static)),
            "e_psi_deg_per_drive": e_psi,
        })
    if args.json:
        print_json(rows)
    else:
        d = drives[0]
        print(
            f"{args.drives} simulated drive(s): {args.duration:.0f} s of '{args.mix}' roads, {d.sensor.name} at "
            f"{args.rate_hz:g} Hz (seeds {args.seed}-{args.seed + args.drives - 1}); the first has a static "
            f"bias of {np.degrees(d.bias):.3f} deg/s and a drift up to {np.degrees(np.abs(d.drift).max()):.3f} deg/s"
        )
        print(f"{'preset':<12} {'E_psi [deg]':>12} {'NE_psi [deg/min]':>17} {'|final| [deg]':>14} "
              f"{'vs raw':>8} {'beats static_bias':>18}")
        raw_e = rows[0]["e_psi_deg"]
        for r in rows:
            gain = raw_e / r["e_psi_deg"] if r["e_psi_deg"] > 0 else float("inf")
            beats = "" if r["preset"] == "static_bias" else f"{r['beats_static_bias']} of {args.drives}"
            print(f"{r['preset']:<12} {r['e_psi_deg']:>12.3f} {r['ne_psi_deg_per_min']:>17.4f} "
                  f"{r['abs_final_error_deg']:>14.3f} {gain:>7.1f}x {beats:>18}")
        print(f"(means over the drives) recommended = {recommended_preset()}")
        print(_why_recommended(rows))
    if args.plot:
        title = (f"simulated car drive: {args.duration:.0f} s of '{args.mix}' roads (seed {args.seed}); "
                 f"gyro {drives[0].sensor.name} at {args.rate_hz:g} Hz")
        _plot_demo(Path(args.plot), drives[0], first, title, overwrite=args.overwrite)
    return 0


def _why_recommended(rows: list[dict[str, Any]]) -> str:
    """Why the recommended preset is not the lowest error of the table, when it is not."""
    corrected = [r for r in rows if r["preset"] != "raw"]
    best = min(corrected, key=lambda r: r["e_psi_deg"])
    if best["preset"] == recommended_preset():
        return f"{recommended_preset()} has the lowest E_psi here"
    return (
        f"{recommended_preset()} is not the lowest E_psi here ({best['preset']} is): it was chosen to do no harm "
        "(within 0.5 deg of its baseline on a gyro without bias) and chosen on real logs, so it corrects "
        "less on strongly drifting gyros like these (docs/results.md)"
    )


def _plot_demo(path: Path, drive: sim.Drive, results: dict[str, HeadingResult], title: str, *,
               overwrite: bool) -> None:
    try:
        plt = pyplot("the demo's plot")
    except MissingExtra as e:
        print(f"(no plot: {e})", file=sys.stderr)
        return
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(9, 6))
    truth = np.degrees(drive.heading_true)
    ax1.plot(drive.t, truth, "k", lw=2, label="true")
    for name, r in results.items():
        # Raw integration runs off by hundreds of degrees: it would flatten every other curve.
        if name != "raw":
            ax1.plot(r.t, r.heading_deg, lw=1, label=name)
            ax2.plot(r.t, r.heading_deg - truth, lw=1, label=name)
    ax1.set_ylabel("heading [deg]")
    ax2.set_ylabel("error [deg]")
    ax2.set_title("heading error (raw integration left out: see the table)", fontsize=9)
    ax2.set_xlabel("t [s]")
    ax1.legend(fontsize=8)
    ax1.set_title(title)
    fig.tight_layout()
    # the demo's own earlier plot is replaced; any other file, also one another run wrote
    # meanwhile, only with --overwrite
    own = path == Path(PLOT) and os.path.lexists(path) and _written_by_demo(path)
    write_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=100, metadata={"Software": _SOFTWARE}),
                     replace=overwrite or own)
    plt.close(fig)
    print(f"wrote {path}")

"""``gyrocore process``: the heading of a log folder or CSV file, written to CSV."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from .. import io
from ..pipeline import process, uses_static_bias
from ._common import add_command, write_atomically


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "process",
        "compute the heading of a log folder or CSV file",
        "gyrocore process ../shared/data/real/f110_ds3 --out heading.csv --preset recommended",
        run,
    )
    p.add_argument("input", help="log folder (gyro.csv, meta.json) or CSV file")
    p.add_argument("--out", required=True, help="output CSV with columns t, heading, rate, drift")
    p.add_argument("--preset", default="recommended", help="preset name (default recommended)")
    p.add_argument("--time-col", default="t", help="time column of a CSV input [s]")
    p.add_argument("--rate-col", default="gyro_z", help="rate column of a CSV input")
    p.add_argument("--rate-unit", choices=("rad/s", "deg/s"), default="rad/s")
    p.add_argument("--bias-dps", type=float, help="static bias [deg/s] instead of the rest window")


def _read_input(path: Path, time_col: str, rate_col: str) -> tuple[np.ndarray, np.ndarray, tuple[float, float] | None]:
    if path.is_dir():
        log = io.read_log(path)
        return log.t, log.rate, log.stationary
    cols = io.read_csv_columns(path, (time_col, rate_col))
    return cols[time_col], cols[rate_col], None


def run(args: argparse.Namespace) -> int:
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
    write_atomically(
        out,
        lambda tmp: np.savetxt(tmp, table, delimiter=",", header="t,heading,rate,drift", comments="", fmt="%.10g"),
    )
    print(f"{len(t)} samples in, {len(result)} out -> {out}")
    return 0

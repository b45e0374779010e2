"""Batch throughput on 1 and 2 (or --jobs) threads: a fleet of CSV logs through
`gyrocore.batch.process_many`, best of --repeats runs, interleaved.

    python benches/batch_scaling.py --files 8 --rows 1000000
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv

from gyrocore.batch import process_many


def write_fleet(folder: Path, files: int, rows: int) -> list[Path]:
    paths = []
    for k in range(files):
        rng = np.random.default_rng(k)
        t = np.arange(rows) * 0.01
        rate = 0.01 + 0.2 * np.sin(t / 30.0) + rng.normal(0.0, 0.005, rows)
        path = folder / f"log{k}.csv"
        pacsv.write_csv(pa.table({"t": t, "gyro_z": rate}), path)
        paths.append(path)
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--files", type=int, default=8)
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--format", choices=("csv", "parquet"), default="parquet")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        paths = write_fleet(folder, args.files, args.rows)
        best = {jobs: float("inf") for jobs in args.jobs}
        for _ in range(args.repeats):
            for jobs in args.jobs:
                out = folder / "out"
                shutil.rmtree(out, ignore_errors=True)
                start = time.perf_counter()
                report = process_many(paths, out_dir=out, jobs=jobs, fmt=args.format, bias_duration=20.0)
                best[jobs] = min(best[jobs], time.perf_counter() - start)
                assert not report.failed and report.rows_out == args.files * args.rows
        total = args.files * args.rows / 1e6
        for jobs in args.jobs:
            print(f"jobs={jobs}: best {best[jobs]:.2f} s = {total / best[jobs]:.2f} M rows/s "
                  f"({best[args.jobs[0]] / best[jobs]:.2f}x of jobs={args.jobs[0]})")


if __name__ == "__main__":
    main()

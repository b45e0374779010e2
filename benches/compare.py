"""Side-by-side benchmark on one 10^7-sample log: gyrocore's `combined` pipeline against the same
algorithm as a pure-Python loop and compiled with Numba (benches/reference.py, one source), against
`numpy.cumsum` over the same array (a memory-bound one-pass scan: the practical floor), and against
imufusion's gyroscope bias stage (FusionBias, formerly FusionOffset) (a peer library's per-sample gyro filter).

Prints ns/sample (median of --repeats runs; the pure-Python and imufusion loops run once, on a
prefix, and say so) and the ratios, and checks that the implementations agree: the reference must
give the same heading as gyrocore to 1e-9 rad. Exit status 1 if they do not.

    pip install ".[bench]" && python benches/compare.py            # 10^7 samples
    python benches/compare.py --samples 1000000 --json             # quicker, machine-readable
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path
from typing import Callable

import numpy as np

import gyrocore

sys.path.insert(0, str(Path(__file__).resolve().parent))
import reference  # noqa: E402

BIAS = 0.0087


def synthetic_log(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A 100 Hz drive: turns and curves on a drifting, noisy gyro (vectorised, any length)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    turns = 0.25 * np.sin(2 * np.pi * t / 97.0) * (np.sin(2 * np.pi * t / 413.0) > 0.6)
    drift = np.radians(0.05) * np.sin(2 * np.pi * t / 3600.0)
    return t, turns + BIAS + drift + rng.normal(0.0, np.radians(0.4), n)


def median_seconds(run: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def reference_args() -> tuple[float, ...]:
    p = gyrocore.preset_params("combined")
    return (
        BIAS, p["scale"], p["offset"], p["threshold"], p["lowpass_tau"], p["hdr_increment"],
        p["hdr_turn_threshold"], p["hdr_c1"], p["hdr_c2"], p["hdr_interval"],
    )


def run_reference(impl: Callable[..., None], t: np.ndarray, rate: np.ndarray) -> np.ndarray:
    heading, out_rate, drift = (np.empty(len(t)) for _ in range(3))
    impl(t, rate, heading, out_rate, drift, *reference_args())
    return heading


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=10_000_000)
    ap.add_argument("--repeats", type=int, default=7, help="runs per fast implementation (median)")
    ap.add_argument("--slow-samples", type=int, default=1_000_000, help="prefix for the per-sample Python loops")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()

    t, rate = synthetic_log(args.samples)
    n = len(t)
    rows: list[dict[str, object]] = []

    def add(name: str, seconds: float, samples: int, note: str = "") -> None:
        rows.append({"implementation": name, "ns_per_sample": seconds / samples * 1e9, "samples": samples, "note": note})

    gyro = gyrocore.process(t, rate, "combined", bias=BIAS)
    add("gyrocore combined (gyrocore.process)", median_seconds(lambda: gyrocore.process(t, rate, "combined", bias=BIAS), args.repeats), n)
    add("numpy.cumsum (floor)", median_seconds(lambda: np.cumsum(rate), args.repeats), n)

    failures = []
    try:
        import numba

        jitted = numba.njit(cache=False)(reference.combined)
        numba_heading = run_reference(jitted, t, rate)  # compiles; not timed
        add("Numba (same algorithm)", median_seconds(lambda: run_reference(jitted, t, rate), args.repeats), n)
        # The loop alone: outputs allocated and faulted in once, outside the timing (criterion
        # times gyrocore's Rust loop the same way).
        reused = [np.empty(n) for _ in range(3)]
        add("Numba, into reused arrays (the loop alone)",
            median_seconds(lambda: jitted(t, rate, *reused, *reference_args()), args.repeats), n)
        if not np.allclose(numba_heading, gyro.heading, rtol=0, atol=1e-9):
            failures.append(f"Numba differs from gyrocore by {np.abs(numba_heading - gyro.heading).max():.3g} rad")
    except ImportError:
        print("(numba not installed: pip install '.[bench]')", file=sys.stderr)

    m = min(args.slow_samples, n)
    start = time.perf_counter()
    py_heading = run_reference(reference.combined, t[:m], rate[:m])
    add("pure Python loop (same algorithm)", time.perf_counter() - start, m, f"one run on the first {m} samples")
    prefix = gyrocore.process(t[:m], rate[:m], "combined", bias=BIAS)
    if not np.allclose(py_heading, prefix.heading, rtol=0, atol=1e-9):
        failures.append(f"pure Python differs from gyrocore by {np.abs(py_heading - prefix.heading).max():.3g} rad")

    try:
        import imufusion

        def fusion_offset() -> None:
            bias = imufusion.Bias()
            settings = imufusion.BiasSettings()
            settings.sample_rate = 100.0
            bias.set_settings(settings)
            sample = np.zeros(3)
            for r in np.degrees(rate[:m]):
                sample[2] = r
                bias.update(sample)

        start = time.perf_counter()
        fusion_offset()
        add("imufusion Bias.update (peer, Python loop)", time.perf_counter() - start, m, f"one run on the first {m} samples")
    except ImportError:
        print("(imufusion not installed: pip install '.[bench]')", file=sys.stderr)

    floor = next(r["ns_per_sample"] for r in rows if str(r["implementation"]).startswith("numpy.cumsum"))
    ours = rows[0]["ns_per_sample"]
    for r in rows:
        r["x_cumsum"] = r["ns_per_sample"] / floor  # type: ignore[operator]
        r["x_gyrocore"] = r["ns_per_sample"] / ours  # type: ignore[operator]
    machine = {
        "cpu": platform.processor() or platform.machine(),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "gyrocore": gyrocore.__version__,
        "samples": n,
        "repeats": args.repeats,
    }
    if args.json:
        print(json.dumps({"machine": machine, "rows": rows, "agree": not failures, "failures": failures}, indent=2))
    else:
        print(f"{n} samples, median of {args.repeats} runs; {machine}")
        print(f"{'implementation':<46} {'ns/sample':>10} {'x cumsum':>9} {'x gyrocore':>11}  note")
        for r in rows:
            print(
                f"{r['implementation']:<46} {r['ns_per_sample']:>10.2f} {r['x_cumsum']:>9.2f} "
                f"{r['x_gyrocore']:>11.2f}  {r['note']}"
            )
        print("outputs agree" if not failures else "DISAGREE: " + "; ".join(failures))
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())

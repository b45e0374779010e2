"""The cost of watching the core's long calls for Ctrl-C: the calls that go through the core piece by
piece (and, from 2^20 samples, on a second thread while this one runs the signal handlers), timed
at sizes below and above that threshold.

Two builds of the extension are loaded side by side in one process, and each call runs once on
each in turn, --rounds times: the machine's load moves single runs, and it moves both of a round
alike. Prints the CPU model and, for each call and size, the median time of each build in ms and
the median of the per-round ratios (second / first) as JSON lines:

    python benches/watched_calls.py OLD/_gyrocore.abi3.so python/gyrocore/_gyrocore.abi3.so
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import platform
import statistics
import time
from collections.abc import Callable
from types import ModuleType
from typing import Any

import numpy as np

from gyrocore import sim


def cpu_model() -> str:
    """The CPU's model name (Linux), or what the platform says."""
    try:
        with open("/proc/cpuinfo") as f:
            return next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        return platform.processor() or "unknown"


def build(label: str, path: str) -> ModuleType:
    """The extension module at `path`, loaded under a package name of its own."""
    spec = importlib.util.spec_from_file_location(f"{label}._gyrocore", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"{path}: not an extension module")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def calls(n: int) -> dict[str, Callable[[Any], object]]:
    """The watched calls on an n-sample log, each of a build's module."""
    t = np.arange(n) * 0.01
    rate = 0.001 + 0.001 * np.random.default_rng(0).standard_normal(n)
    spec = sim.sensor("xv3500").si()
    factors = [m for m in (1, 16, 256, 4096, 65536) if 4 * m < n]
    return {
        "integrate": lambda g: g.integrate(t, rate),
        "downsample": lambda g: g.downsample(t, rate, 1.0),
        "check_samples": lambda g: g.check_samples(t, rate),
        "project_up": lambda g: g.project_up(rate, rate, rate, [0.0, 0.0, 1.0]),
        "static_bias_test": lambda g: g.static_bias_test(t, rate, 0.0, t[-1]),
        "gyro_measure": lambda g: g.gyro_measure(spec, 1, t, rate),
        "format_csv_rows": lambda g: g.format_csv_rows([t[: n // 10], rate[: n // 10]]),
        "modified_allan": lambda g: g.allan_variances(rate, 0.01, factors, "modified_allan", True),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("first", help="the extension module (.so) of one build")
    parser.add_argument("second", help="the extension module of the other build")
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 1_000_000, 10_000_000])
    parser.add_argument("--rounds", type=int, default=21)
    args = parser.parse_args()
    builds = [build("first", args.first), build("second", args.second)]
    print(json.dumps({"cpu": cpu_model()}))
    for n in args.sizes:
        for name, call in calls(n).items():
            for g in builds:
                call(g)  # the first run faults in the pages of the inputs
            times: list[list[float]] = [[], []]
            for _ in range(args.rounds):
                for g, spent in zip(builds, times):
                    start = time.perf_counter()
                    call(g)
                    spent.append(time.perf_counter() - start)
            ratio = statistics.median(b / a for a, b in zip(*times))
            ms = [round(1e3 * statistics.median(t), 3) for t in times]
            print(json.dumps({"call": name, "n": n, "ms": ms, "ratio": round(ratio, 3)}), flush=True)


if __name__ == "__main__":
    main()

"""The cost of one call of a stream: `Pipeline.process` given a chunk of 1, 10 or 100 samples at a
time, as a robot's loop gives its gyro's latest readings, for `recommended` with a fixed bias and
for `tracked` with a speed per sample (its rest tracker's own work on top).

Each round runs every case once, in turn (--calls calls each, on a stream that goes on where the
last round left it); prints the CPU model and, per case, the median over --rounds rounds of the
time of one call [us], as JSON lines:

    python benches/stream_calls.py --rounds 9 --calls 2000
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
import warnings
from collections.abc import Callable

import numpy as np
from compare import cpu_model

import gyrocore


def _stream(preset: str, size: int, speed: bool, calls: int, rounds: int) -> Callable[[], float]:
    """A function that gives the next `calls` chunks of `size` samples to one stream and returns
    the time of one call [s]."""
    n = size * calls * rounds
    t = np.arange(n) * 0.01
    rate = 0.001 + 0.2 * np.sin(t / 7.0) * (np.sin(t / 31.0) > 0) + 1e-3 * np.random.default_rng(0).standard_normal(n)
    moving = np.where(np.sin(t / 31.0) > 0, 5.0, 0.0)
    options = {"track_rests": True} if speed else {}
    pipeline = gyrocore.Pipeline(preset, bias=0.001, **options)
    cursor = 0

    def run() -> float:
        nonlocal cursor
        start = time.perf_counter()
        for _ in range(calls):
            chunk = slice(cursor, cursor + size)
            if speed:
                pipeline.process(t[chunk], rate[chunk], speed=moving[chunk])
            else:
                pipeline.process(t[chunk], rate[chunk])
            cursor += size
        return (time.perf_counter() - start) / calls

    return run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--calls", type=int, default=2000)
    args = ap.parse_args()
    warnings.simplefilter("ignore")  # a tracked stream's advice, said once: not what is timed
    cases = {(preset, size, speed): _stream(preset, size, speed, args.calls, args.rounds)
             for preset, speed in (("recommended", False), ("tracked", True)) for size in (1, 10, 100)}
    times: dict[tuple[str, int, bool], list[float]] = {case: [] for case in cases}
    for _ in range(args.rounds):
        for case, run in cases.items():
            times[case].append(run())
    print(json.dumps({"cpu": cpu_model(), "rounds": args.rounds, "calls": args.calls}))
    for (preset, size, speed), seconds in times.items():
        print(json.dumps({"preset": preset, "chunk": size, "speed": speed,
                          "us_per_call": round(statistics.median(seconds) * 1e6, 1)}))


if __name__ == "__main__":
    main()

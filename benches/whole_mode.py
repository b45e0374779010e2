"""Whole mode on a long log with many rests: `gyrocore.process(t, rate, preset, outputs=("heading",),
out=h, mode="whole")` over 10^7 samples at 100 Hz (28 hours) of a gyro with a bias of 0.003 rad/s
and noise of 0.002 rad/s that turns (0.2 sin(0.05 t) rad/s) except for the first 20 s of every
230 s (435 rests found), the heading into an array allocated once. With ``--log swinging``, a gyro
that never stops, its rate swinging slowly (0.02 sin(2 pi t / 600 s) rad/s, the same bias and
noise): the rate's quiet stretches pass for rests (7,010 in 10^7 samples), and the outlier test
refuses 2,211 of them, one at a time, each round filtering the rests forward and backward.

Prints the CPU model and, per preset, the median, lowest and highest of --repeats calls [s], by
wall time and by the calling thread's CPU time (which leaves out the time it waits for a core on a
busy machine); the presets run in turn, one call each per round. `static_bias` has no HDR bound;
`recommended` has one (`hdr_bound_sigmas`), which takes the smoothed bias's standard error at
every sample.

    python benches/whole_mode.py                                 # 10^7 samples, 5 calls
    python benches/whole_mode.py --samples 1000000 --presets static_bias hdr
    python benches/whole_mode.py --log swinging --repeats 3
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import gyrocore

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare import cpu_model  # noqa: E402


def stopping_log(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``n`` samples at 100 Hz: bias 0.003 rad/s, white noise 0.002 rad/s, and a turn rate of
    0.2 sin(0.05 t) rad/s except in the first 20 s of every 230 s."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    rate = rng.normal(0.0, 0.002, n) + 0.003
    rate += np.where(t % 230 > 20, 0.2 * np.sin(0.05 * t), 0.0)
    return t, rate


def swinging_log(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``n`` samples at 100 Hz of a gyro that never stops: bias 0.003 rad/s, white noise 0.002
    rad/s, and a turn rate of 0.02 sin(2 pi t / 600 s) rad/s."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    return t, rng.normal(0.0, 0.002, n) + 0.003 + 0.02 * np.sin(2 * np.pi * t / 600.0)


LOGS = {"stopping": stopping_log, "swinging": swinging_log}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=10_000_000)
    ap.add_argument("--repeats", type=int, default=5, help="calls per preset (median)")
    ap.add_argument("--presets", nargs="+", default=["static_bias", "recommended"])
    ap.add_argument("--log", choices=LOGS, default="stopping", help="the drive (see above)")
    args = ap.parse_args()

    t, rate = LOGS[args.log](args.samples)
    heading = np.empty_like(t)
    clocks = {"wall": time.perf_counter, "thread CPU": time.thread_time}
    seconds: dict[tuple[str, str], list[float]] = {(p, clock): [] for p in args.presets for clock in clocks}
    for _ in range(args.repeats):
        for preset in args.presets:
            start = {clock: read() for clock, read in clocks.items()}
            gyrocore.process(t, rate, preset, outputs=("heading",), out=heading, mode="whole")
            for clock, read in clocks.items():
                seconds[preset, clock].append(read() - start[clock])
    print(f"CPU: {cpu_model()}; {args.log} log, {args.samples} samples, {args.repeats} calls per preset")
    for (preset, clock), s in seconds.items():
        print(f"{preset:>12} {clock:>10}: median {statistics.median(s):.3f} s "
              f"(lowest {min(s):.3f}, highest {max(s):.3f})")


if __name__ == "__main__":
    main()

"""Whole mode on a long log with many rests: `gyrocore.process(t, rate, preset, outputs=("heading",),
out=h, mode="whole")` over 10^7 samples at 100 Hz (28 hours) of a gyro with a bias of 0.003 rad/s
and noise of 0.002 rad/s that turns (0.2 sin(0.05 t) rad/s) except for the first 20 s of every
230 s (435 rests found), the heading into an array allocated once. With ``--log swinging``, a gyro
that never stops, its rate swinging slowly (0.02 sin(2 pi t / 600 s) rad/s, the same bias and
noise): the rate's quiet stretches pass for rests (7,010 in 10^7 samples), and the outlier test
refuses 2,211 of them, one at a time, each round filtering the rests forward and backward. With
``--log refused``, a car that stops for 2 s every 6 s (its speed given: 13,334 stops in 8*10^6
samples), a fifth of its stops reading 4 to 25 standard errors off (a bias that jumps there): the
outlier test refuses them one at a time, the worst first.

Prints the CPU model and, per preset, the median, lowest and highest of --repeats calls [s], by
wall time and by the calling thread's CPU time (which leaves out the time it waits for a core on a
busy machine); the presets run in turn, one call each per round. `static_bias` has no HDR bound;
`recommended` has one (`hdr_bound_sigmas`), which takes the smoothed bias's standard error at
every sample.

    python benches/whole_mode.py                                 # 10^7 samples, 5 calls
    python benches/whole_mode.py --samples 1000000 --presets static_bias hdr
    python benches/whole_mode.py --log swinging --repeats 3
    python benches/whole_mode.py --log refused --samples 8000000 --repeats 3
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


Drive = tuple[np.ndarray, np.ndarray, "np.ndarray | None"]  # t, rate, speed


def stopping_log(n: int, seed: int = 0) -> Drive:
    """``n`` samples at 100 Hz: bias 0.003 rad/s, white noise 0.002 rad/s, and a turn rate of
    0.2 sin(0.05 t) rad/s except in the first 20 s of every 230 s."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    rate = rng.normal(0.0, 0.002, n) + 0.003
    rate += np.where(t % 230 > 20, 0.2 * np.sin(0.05 * t), 0.0)
    return t, rate, None


def swinging_log(n: int, seed: int = 0) -> Drive:
    """``n`` samples at 100 Hz of a gyro that never stops: bias 0.003 rad/s, white noise 0.002
    rad/s, and a turn rate of 0.02 sin(2 pi t / 600 s) rad/s."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    return t, rng.normal(0.0, 0.002, n) + 0.003 + 0.02 * np.sin(2 * np.pi * t / 600.0), None


def refused_log(n: int, seed: int = 0) -> Drive:
    """``n`` samples at 100 Hz: bias 0.003 rad/s, white noise 0.002 rad/s, a turn rate of 0.2
    sin(0.05 t) rad/s while moving; stopped (speed 0, else 10 m/s) for 2 s of every 6 s, and at a
    fifth of the stops the rate off by 4 to 25 times a stop's standard error (0.002 / sqrt(200))."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    stop = np.floor(t / 6.0).astype(np.int64)
    stopped = t % 6.0 < 2.0
    rate = rng.normal(0.0, 0.002, n) + 0.003 + np.where(stopped, 0.0, 0.2 * np.sin(0.05 * t))
    stops = int(stop[-1]) + 1
    off = np.where(rng.random(stops) < 0.2, rng.choice([-1.0, 1.0], stops) * rng.uniform(4, 25, stops), 0.0)
    rate += np.where(stopped, off[stop] * 0.002 / np.sqrt(200), 0.0)
    return t, rate, np.where(stopped, 0.0, 10.0)


LOGS = {"stopping": stopping_log, "swinging": swinging_log, "refused": refused_log}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=10_000_000)
    ap.add_argument("--repeats", type=int, default=5, help="calls per preset (median)")
    ap.add_argument("--presets", nargs="+", default=["static_bias", "recommended"])
    ap.add_argument("--log", choices=LOGS, default="stopping", help="the drive (see above)")
    args = ap.parse_args()

    t, rate, speed = LOGS[args.log](args.samples)
    heading = np.empty_like(t)
    clocks = {"wall": time.perf_counter, "thread CPU": time.thread_time}
    seconds: dict[tuple[str, str], list[float]] = {(p, clock): [] for p in args.presets for clock in clocks}
    for _ in range(args.repeats):
        for preset in args.presets:
            start = {clock: read() for clock, read in clocks.items()}
            result = gyrocore.process(t, rate, preset, outputs=("heading",), out=heading, mode="whole", speed=speed)
            for clock, read in clocks.items():
                seconds[preset, clock].append(read() - start[clock])
    refused = sum(not r.accepted for r in result.rests)
    print(f"CPU: {cpu_model()}; {args.log} log, {args.samples} samples, {args.repeats} calls per preset; "
          f"{len(result.rests)} rests found, {refused} refused")
    for (preset, clock), s in seconds.items():
        print(f"{preset:>12} {clock:>10}: median {statistics.median(s):.3f} s "
              f"(lowest {min(s):.3f}, highest {max(s):.3f})")


if __name__ == "__main__":
    main()

"""Allan deviation of a long rate log: overlapping and non-overlapping, octave taus, median (and
fastest) of --repeats runs, with a breakdown of where the time goes.

    python benches/allan_speed.py --samples 100000000 --repeats 5

The rate is white noise on a bias, ``default_rng(0).standard_normal(n) * 0.01 + 0.05`` at
dt = 1 ms. The breakdown splits one overlapping call by timing the extension on its own:

- ``variances``: the sums alone, on a phase integrated beforehand
  (``_gyrocore.allan_variances(phase, ..., is_rate=False)``);
- ``phase``: what the rate route adds to that (``is_rate=True``): allocating the phase buffer
  and integrating the rate into it;
- ``python``: what ``allan.deviation`` adds to the extension call (tau list, degrees of
  freedom, confidence intervals).

Each part is the median of its own runs, so on a busy machine the parts need not add up.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np

from gyrocore import _gyrocore, allan

DT = 1e-3


def wall_times(run: Callable[[], object], repeats: int) -> list[float]:
    """Wall times of ``repeats`` calls [s]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return times


def median_time(run: Callable[[], object], repeats: int) -> float:
    """Median wall time of ``repeats`` calls [s]."""
    return statistics.median(wall_times(run, repeats))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=10**8)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--no-breakdown", action="store_true", help="time only the two public calls")
    args = ap.parse_args()
    rate = np.random.default_rng(0).standard_normal(args.samples) * 0.01 + 0.05
    curve = allan.deviation(rate, DT)
    print(f"{args.samples} samples, {len(curve.taus)} octave taus, median of {args.repeats}")
    times = wall_times(lambda: allan.deviation(rate, DT), args.repeats)
    plain = wall_times(lambda: allan.deviation(rate, DT, overlapping=False), args.repeats)
    overlapping = statistics.median(times)
    print(f"overlapping     {overlapping:7.3f} s (min {min(times):.3f})")
    print(f"non-overlapping {statistics.median(plain):7.3f} s (min {min(plain):.3f})")
    print(f"numpy.cumsum    {median_time(lambda: np.cumsum(rate), args.repeats):7.3f} s (for scale)")
    if args.no_breakdown:
        return
    factors = np.rint(curve.taus / DT).astype(np.int64).tolist()
    phase = np.concatenate(([0.0], np.cumsum((rate - rate.mean()) * DT)))
    passes = median_time(
        lambda: _gyrocore.allan_variances(phase, DT, factors, "overlapping_allan", False), args.repeats
    )
    from_rate = median_time(
        lambda: _gyrocore.allan_variances(rate, DT, factors, "overlapping_allan", True), args.repeats
    )
    print("breakdown of the overlapping call:")
    print(f"  variances {passes:7.3f} s ({passes / len(factors) * 1e3:.1f} ms per tau)")
    print(f"  phase     {from_rate - passes:7.3f} s")
    print(f"  python    {overlapping - from_rate:7.3f} s")


if __name__ == "__main__":
    main()

"""The gate's lock-out and re-admission (``readmit_after``) on the 12 KITTI logs: heading fixes
with what goes wrong with real ones (sigmas stated too small, clocks apart, a bearing given as a
heading) and lasting wrong courses (bursts of one offset, reversing), fused with ``fuse`` with the
gate alone (``readmit_after=inf``) and with the default re-admission. E_psi [deg], absolute,
median and largest over the 12 logs, causal / smoothed; and the fixes re-admitted in all.
Prints the table of docs/fixes_model.md "The gate's lock-out, and re-admission".

    python examples/fixes_lockout.py [DATA_DIR]     # default ../shared/data/real; a few seconds

The fixes are SIMULATED from each log's reference (``gyrocore.sim.gnss_fixes``, 1 Hz, 1 deg,
seed 1), then spoilt as each row says (seeded).
"""

import math
import sys
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

import gyrocore
from gyrocore.evaluate_metrics import Reference
from gyrocore.fixes import Fixes, from_gnss, from_positions, fuse

Spoil = Callable[[gyrocore.Log, Fixes, np.random.Generator], Fixes]


def _sigma(factor: float) -> Spoil:
    return lambda log, f, rng: Fixes(f.t, f.heading, f.sigma * factor)


def _shifted(seconds: float) -> Spoil:
    return lambda log, f, rng: Fixes(f.t + seconds, f.heading, f.sigma)


def _burst(count: int, offset_deg: float | None) -> Spoil:
    """``count`` fixes from the middle on, ``offset_deg`` off (None: each 30-90 deg either way)."""
    def spoil(log: gyrocore.Log, f: Fixes, rng: np.random.Generator) -> Fixes:
        h, mid = f.heading.copy(), len(f) // 2
        if offset_deg is None:
            h[mid:mid + count] += np.radians(rng.uniform(30, 90, count) * rng.choice([-1, 1], count))
        else:
            h[mid:mid + count] += math.radians(offset_deg)
        return Fixes(f.t, h, f.sigma)
    return spoil


def _track(log: gyrocore.Log) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The reference track at 1 Hz (every 10th sample): t, x, y."""
    assert log.t_ref is not None and log.x_ref is not None and log.y_ref is not None
    return log.t_ref[::10], log.x_ref[::10], log.y_ref[::10]


def _positions(noise: float, stated: float) -> Spoil:
    def spoil(log: gyrocore.Log, f: Fixes, rng: np.random.Generator) -> Fixes:
        t, x, y = _track(log)
        return from_positions(t, x + rng.normal(0, noise, len(t)), y + rng.normal(0, noise, len(t)),
                              position_sigma=stated)
    return spoil


def _velocities(log: gyrocore.Log, f: Fixes, rng: np.random.Generator) -> Fixes:
    """Course over ground from velocities with 0.5 m/s noise, ``speed_sigma`` 0.2 stated."""
    assert log.t_ref is not None and log.x_ref is not None and log.y_ref is not None
    vx, vy = (np.gradient(a, log.t_ref)[::10] + rng.normal(0, 0.5, len(log.t_ref[::10])) for a in (log.x_ref, log.y_ref))
    return from_gnss(log.t_ref[::10], np.degrees(np.arctan2(vx, vy)), np.hypot(vx, vy), speed_sigma=0.2)


ROWS: tuple[tuple[str, Spoil], ...] = (
    ("honest", lambda log, f, rng: f),
    ("honest, 0.3 deg", lambda log, f, rng: gyrocore.sim.gnss_fixes(*log.reference(), seed=1, sigma_deg=0.3)),
    ("honest, 0.1 deg", lambda log, f, rng: gyrocore.sim.gnss_fixes(*log.reference(), seed=1, sigma_deg=0.1)),
    ("sigma stated 2 times too small", _sigma(1 / 2)),
    ("sigma stated 3 times too small", _sigma(1 / 3)),
    ("sigma stated 10 times too small", _sigma(1 / 10)),
    ("from positions with 1.5 m noise, 1 m stated", _positions(1.5, 1.0)),
    ("from positions with 3 m noise, 1 m stated", _positions(3.0, 1.0)),
    ("from GNSS velocities with 0.5 m/s noise, 0.2 stated", _velocities),
    ("stamped 0.3 s late", _shifted(0.3)),
    ("stamped 1 s late", _shifted(1.0)),
    ("a bearing clockwise from north as the heading", lambda log, f, rng: Fixes(f.t, math.pi / 2 - f.heading, f.sigma)),
    ("10 fixes 30-90 deg off (multipath)", _burst(10, None)),
    ("30 fixes 45 deg off", _burst(30, 45.0)),
    ("60 fixes 45 deg off", _burst(60, 45.0)),
    ("20 fixes half a turn off (reversing)", _burst(20, 180.0)),
    ("30 fixes 10 deg off", _burst(30, 10.0)),
    ("60 fixes 20 deg off", _burst(60, 20.0)),
)


def _runs(logs: list[gyrocore.Log], spoil: Spoil) -> Iterator[tuple[float, list[float], int]]:
    """Per log and setting of ``readmit_after`` (inf, default): causal and smoothed E_psi, re-admitted."""
    for log in logs:
        reference = Reference(*log.reference())
        honest = gyrocore.sim.gnss_fixes(*log.reference(), seed=1)
        fixes = spoil(log, honest, np.random.default_rng(1))
        for readmit in (math.inf, None):
            settings = {} if readmit is None else {"readmit_after": readmit}
            e, readmitted = [], 0
            for mode in ("causal", "smoothed"):
                r = fuse(log.t, log.rate, fixes, mode=mode, **settings)
                e.append(reference.e_psi(log.t, r.heading, absolute=True))
                readmitted = r.counts["readmitted"]
            yield readmit or 0.0, e, readmitted


def main(data: Path) -> None:
    logs = [gyrocore.read_log(p) for p in sorted(data.glob("kitti_*")) if (p / "gyro.csv").is_file()]
    print("| fixes | gate alone: causal / smoothed, median (largest) | re-admitted: causal / smoothed, median (largest) | fixes re-admitted |")
    print("|---|---|---|---|")
    for label, spoil in ROWS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gyrocore.InputWarning)  # the checks' warnings: the point of the rows
            runs = list(_runs(logs, spoil))
        cells = []
        for gate_alone in (True, False):
            e = np.array([r[1] for r in runs if (r[0] == math.inf) == gate_alone])
            med, top = np.median(e, axis=0), e.max(axis=0)
            cells.append(f"{med[0]:.2f} ({top[0]:.1f}) / {med[1]:.2f} ({top[1]:.1f})")
        readmitted = sum(r[2] for r in runs if r[0] != math.inf)
        print(f"| {label} | {cells[0]} | {cells[1]} | {readmitted} |")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "../shared/data/real")

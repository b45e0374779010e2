"""Rest tracking on the real logs: per-log E_psi of static-bias removal, the recommended preset and
rest-tracking variants (causal), with the tracker's settings chosen by leave-one-log-out.

Usage: python examples/rest_tracking_eval.py [DATA_DIR] [--json OUT]

For each log, the tracker's settings are the grid point with the lowest mean E_psi ratio (to
static-bias removal on the same log) over the other 17 logs; the table reports E_psi on the held-out
log with those settings. The speed is the log folder's odometry.csv where it has one.
"""

from __future__ import annotations

import itertools
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from gyrocore.evaluate import Reference, log_bias
from gyrocore.io import Log, read_log
from gyrocore.pipeline import process, recommended_preset

#: The grid the leave-one-log-out choice searches.
GRID: dict[str, list[Any]] = {
    "rest_block, rest_min_duration": [(0.25, 0.5), (0.5, 1.0), (0.5, 2.0), (1.0, 2.0), (1.0, 3.0)],
    "rest_bias_walk": [1e-9, 1e-8, 1e-7, 1e-6],
    "rest_gate_sigmas": [3.0, float("inf")],
    "rest_speed_threshold": [0.05, 0.2],
    "rest_change_sigmas": [4.0, float("inf")],
    "rest_noise_ratio": [1.5, 3.0],
}


def settings(point: dict[str, Any]) -> dict[str, Any]:
    """A grid point as pipeline parameters (a joint key such as "a, b" names two)."""
    out: dict[str, Any] = {}
    for key, value in point.items():
        out.update(zip(key.split(", "), value) if ", " in key else [(key, value)])
    return out


def e_psi(log: Log, ref: Reference, preset: str, track: dict[str, Any] | None) -> tuple[float, int]:
    """E_psi [deg] of ``preset`` on ``log`` (with rest tracking under ``track``) and the rests used."""
    bias, _ = log_bias(log)
    extra: dict[str, Any] = {}
    if track is not None:
        extra = {"track_rests": True, **settings(track)}
        if log.speed is not None:
            extra.update(speed=log.speed, speed_t=log.t_odometry)
    r = process(log.t, log.rate, preset, mode="causal", outputs=("heading",), **bias, **extra)
    return ref.errors(r.t, r.heading).e_psi_deg, sum(x.accepted for x in r.tracked_rests)


def main(argv: list[str]) -> None:
    data = Path(argv[0]) if argv and not argv[0].startswith("--") else Path("../shared/data/real")
    logs = [read_log(p) for p in sorted(data.iterdir()) if p.is_dir()]
    refs = [Reference(log.t_ref, log.heading_ref) for log in logs]
    tuned = recommended_preset()
    base = {name: [e_psi(log, ref, name, None)[0] for log, ref in zip(logs, refs)]
            for name in ("static_bias", tuned)}
    points = [dict(zip(GRID, values)) for values in itertools.product(*GRID.values())]
    # ratio[preset][point][log]: E_psi of the tracked preset over static-bias removal's.
    scores: dict[str, list[list[tuple[float, int]]]] = {
        name: [[e_psi(log, ref, name, p) for log, ref in zip(logs, refs)] for p in points]
        for name in ("static_bias", tuned)
    }
    rows = []
    for i, log in enumerate(logs):
        row: dict[str, Any] = {"log": log.name, "static_bias": base["static_bias"][i], tuned: base[tuned][i]}
        for name in ("static_bias", tuned):
            ratio = np.array([[s[0] for s in per_point] for per_point in scores[name]]) / np.array(base["static_bias"])
            others = np.delete(ratio, i, axis=1).mean(axis=1)
            best = int(np.argmin(others))
            row[f"{name}+track"] = scores[name][best][i][0]
            row[f"{name}+track rests"] = scores[name][best][i][1]
            row[f"{name}+track point"] = points[best]
        rows.append(row)
    print(f"| log | static_bias | {tuned} | static_bias+track (rests) | {tuned}+track (rests) |")
    print("| --- | --- | --- | --- | --- |")
    for row in rows:
        print(f"| {row['log']} | {row['static_bias']:.2f} | {row[tuned]:.2f} | "
              f"{row['static_bias+track']:.2f} ({row['static_bias+track rests']}) | "
              f"{row[tuned + '+track']:.2f} ({row[tuned + '+track rests']}) |")
    for key in ("static_bias", tuned, "static_bias+track", f"{tuned}+track"):
        print(f"mean E_psi {key}: {np.mean([r[key] for r in rows]):.3f} deg")
    full = {name: points[int(np.argmin(np.mean([[s[0] for s in pp] for pp in scores[name]]
                                                / np.array(base['static_bias']), axis=1)))]
            for name in ("static_bias", tuned)}
    print("chosen on all 18 logs:", full)
    if "--json" in argv:
        Path(argv[argv.index("--json") + 1]).write_text(json.dumps({"rows": rows, "all": full}, indent=1))


if __name__ == "__main__":
    main(sys.argv[1:])

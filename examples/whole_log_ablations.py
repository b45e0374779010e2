"""Whole mode's choices changed one at a time, and a given window against the log's other rests:
E_psi [deg] of ``static_bias`` (and ``recommended``) in whole mode on the real logs. Prints the
tables of docs/whole_log.md "Ablations" and "A given window and the log's other rests".

    python examples/whole_log_ablations.py [DATA_DIR]     # default ../shared/data/real; a few seconds
"""

import dataclasses
import math
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import gyrocore

#: The ablations: (the row's label in docs/whole_log.md, the keywords of Log.process).
SETTINGS: list[tuple[str, dict[str, Any]]] = [
    ("defaults", {}),
    ("no significance test (`bias_sigmas` 0)", {"bias_sigmas": 0.0}),
    ("interpolation-like (`bias_walk` 1)", {"bias_walk": 1.0}),
    ("constant bias (`bias_walk` 0)", {"bias_walk": 0.0}),
    ("the previous default walk (`bias_walk` 1e-3)", {"bias_walk": 1e-3}),
    ("`min_rest` 2 s", {"min_rest": 2.0}),
    ("rate only (`use_speed=False`)", {"use_speed": False}),
    ("rate only, `bias_walk` 1e-3", {"use_speed": False, "bias_walk": 1e-3}),
]
#: The logs the ablation table shows (the other ten are equal in every row) and their short names.
SHOWN = {"f110_ds1": "f110_ds1", "f110_ds5": "f110_ds5", "kitti_2011_09_30_0018": "k0018",
         "kitti_2011_09_30_0018_mems": "k0018_mems", "kitti_2011_09_30_0027": "k0027",
         "kitti_2011_09_30_0027_mems": "k0027_mems", "kitti_2011_09_30_0034": "k0034",
         "kitti_2011_09_30_0034_mems": "k0034_mems"}
#: The logs with a window at the start that also rest later.
WINDOWED = ("broad_10", "broad_11", "f110_ds3")


def e_psi(log: gyrocore.Log, preset: str, **options: Any) -> float:
    result = log.process(preset, mode="whole", **options)
    return gyrocore.heading_errors(result.t, result.heading, *log.reference()).e_psi_deg


def main(data: Path) -> None:
    logs = [gyrocore.read_log(p) for p in sorted(data.iterdir()) if (p / "gyro.csv").is_file()]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # logs without a rest say so
        print(f"| setting | mean log E_psi ({len(logs)} logs) | " + " | ".join(SHOWN.values()) + " |")
        print("|---|---|" + "---|" * len(SHOWN))
        for label, options in SETTINGS:
            scores = {log.name: e_psi(log, "static_bias", **options) for log in logs}
            mean_log = float(np.mean([math.log(e) for e in scores.values()]))
            print(f"| {label} | {mean_log:.3f} | " + " | ".join(f"{scores[name]:.2f}" for name in SHOWN) + " |")
        print()
        print("| log | rests used | static_bias, window | static_bias, every rest | recommended, window | "
              "recommended, every rest | every rest from the rate alone: static_bias, recommended |")
        print("|---|---|---|---|---|---|---|")
        for log in (log for log in logs if log.name in WINDOWED):
            every = dataclasses.replace(log, stationary=None)
            rests = [r for r in every.process("static_bias").rests if r.accepted]
            used = ", ".join(f"{math.degrees(r.bias):.4f}" for r in rests)
            if all(r.found_by == "speed" for r in rests):
                used += " (speed)"
            cells = [e_psi(log, "static_bias"), e_psi(every, "static_bias"), e_psi(log, "recommended"),
                     e_psi(every, "recommended")]
            alone = [e_psi(every, p, use_speed=False) for p in ("static_bias", "recommended")]
            print(f"| {log.name} | {used} | " + " | ".join(f"{e:.3f}" for e in cells)
                  + " | " + ", ".join(f"{e:.3f}" for e in alone) + " |")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "../shared/data/real")

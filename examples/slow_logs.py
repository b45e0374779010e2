"""Whole mode on the real logs taken at a lower rate: every k-th reading (k = 1 to 5), with
neither speed nor rest window (what a slower logger without odometry gives), E_psi [deg] of raw
integration and of ``static_bias`` and ``recommended`` in whole mode, and the rests each used.
Prints the figures of docs/whole_log.md "Slower logs".

    python examples/slow_logs.py [DATA_DIR]     # default ../shared/data/real; a few seconds
"""

import sys
import warnings
from pathlib import Path

import gyrocore

STEPS = (1, 2, 3, 4, 5)
PRESETS = ("static_bias", "recommended")


def main(data: Path) -> None:
    logs = [gyrocore.read_log(p) for p in sorted(data.iterdir()) if (p / "gyro.csv").is_file()]
    print("| log | k | rate [Hz] | raw | " + " | ".join(f"{p} whole | its rests used" for p in PRESETS) + " |")
    print("|---|---|---|---|" + "---|---|" * len(PRESETS))
    for log in logs:
        for k in STEPS:
            t, rate = log.t[::k], log.rate[::k]

            def e_psi(preset: str, mode: str) -> tuple[float, int]:
                result = gyrocore.process(t, rate, preset, mode=mode)
                used = sum(r.accepted for r in result.rests)
                return gyrocore.heading_errors(result.t, result.heading, *log.reference()).e_psi_deg, used

            with warnings.catch_warnings():
                warnings.simplefilter("ignore", gyrocore.InputWarning)  # rests refused, or none found
                raw = e_psi("raw", "causal")[0]
                cells = [f"{e:.2f} | {n}" for e, n in (e_psi(p, "whole") for p in PRESETS)]
            hz = (len(t) - 1) / (t[-1] - t[0])
            print(f"| {log.name} | {k} | {hz:.1f} | {raw:.2f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "../shared/data/real")

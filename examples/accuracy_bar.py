"""The accuracy bar of the recommended preset (docs/results.md): E_psi on the
real logs beside static-bias removal, and do-no-harm checks on gyros without bias.

- real logs: E_psi [deg] against each log's reference in whole mode, the static bias from its rest window
  (comma_seg40 has none: its first 10 s of straight driving);
- perfect gyro: the worst E_psi above plain integration over 18 simulated 20-minute drives with
  long gentle curves (gyrocore.tune.harm_cases, seeds not used in tuning);
- reference rate: the same on each real log's own reference, differentiated (a gyro without bias);
- noisy gyro: the CRS03's noise without bias or drift on the same roads, E_psi above static-bias
  removal, mean and worst (not part of the bar; see docs/results.md).

    python examples/accuracy_bar.py [DATA_DIR]     # default ../shared/data/real
"""

import sys
from pathlib import Path

import numpy as np

import gyrocore
from gyrocore import tune

PRESETS = ("static_bias", "hong_park", "combined", "recommended", "tracked")
LOGS = ("f110_ds3", "broad_10", "comma_seg40")
HELD_OUT_SEED = 2000


def main(data: Path) -> None:
    logs = [gyrocore.read_log(data / name) for name in LOGS]
    real = [tune.Case.from_log(log, bias_duration=10.0) for log in logs]
    reference = [tune.Case.from_reference_rate(log) for log in logs]
    perfect = tune.harm_cases(per_mix=6, first_seed=HELD_OUT_SEED)
    noisy = tune.harm_cases(per_mix=6, first_seed=HELD_OUT_SEED, noisy=True)
    header = [*LOGS, "perfect gyro", "reference rate", "noisy: mean", "noisy: worst"]
    print(f"{'preset':<12} " + " ".join(f"{h:>14}" for h in header))
    for preset in PRESETS:
        noisy_harm = [c.harm_deg(preset, {}) for c in noisy]
        cells = [c.score(preset, {}).e_psi_deg for c in real]
        cells += [max(c.harm_deg(preset, {}) for c in perfect), max(c.harm_deg(preset, {}) for c in reference)]
        cells += [float(np.mean(noisy_harm)), max(noisy_harm)]
        print(f"{preset:<12} " + " ".join(f"{v:>14.3f}" for v in cells))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "real")

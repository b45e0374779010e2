"""E_psi [deg] of raw integration, static-bias removal and the recommended preset on every real
log, causal (what a streaming pipeline gives: a rest corrects only what follows it; a log
without a rest window gets no bias) and whole-log (the bias smoothed from every rest, known from
the first sample), with whole mode's choices (``bias_walk``, ``min_rest``, ``bias_sigmas``) made
by leave-one-log-out: each log is scored with the choice that is best on the other logs (lowest
mean log E_psi of static_bias, each log counted twice: with its speed, and from the rate alone as
a log without odometry is processed), never with one fitted to it. Prints the table of
docs/results.md (Markdown) with the choice each log was scored with and without its "held out"
column (that one is docs/recommended.md's leave-one-out fit), the choice on all logs (beside the default
a new log gets), and the rests each log used. The last column is no method a user can run: one constant scale and bias fitted to
the log's own reference (Hong eq 4-7), the floor of any constant calibration on that log.

    python examples/whole_log_table.py [DATA_DIR]     # default ../shared/data/real; about 10 s
"""

import itertools
import math
import sys
import warnings
from pathlib import Path

import numpy as np

import gyrocore
from gyrocore import calibration, evaluate
from gyrocore.wholelog_options import Options

PRESETS = ("static_bias", "recommended")
#: The grid whole mode's choices (bias_walk [rad/s/sqrt(s)], min_rest [s], bias_sigmas) are made
#: on, each axis from the most cautious choice (the least change to the readings) to the least:
#: :func:`min` keeps the first of equally good choices, so a tie goes to caution.
WALKS = (0.0, 1e-5, 1e-4, 1e-3)
MIN_RESTS = (2.0, 1.0, 0.5)
SIGMAS = (5.0, 4.0, 3.0, 2.0, 0.0)
GRID = list(itertools.product(WALKS, MIN_RESTS, SIGMAS))


def e_psi(log: gyrocore.Log, result: gyrocore.HeadingResult) -> float:
    return evaluate.heading_errors(result.t, result.heading, *log.reference()).e_psi_deg


#: A log's whole-mode E_psi per (preset, use_speed, bias_walk, min_rest, bias_sigmas).
Grid = dict[tuple[str, bool, float, float, float], float]
#: Whole mode with the log's speed, and from the rate alone (``use_speed=False``).
SPEED_CASES = (True, False)


def score_log(log: gyrocore.Log) -> tuple[dict[str, float], Grid, str]:
    """Causal scores, whole-mode scores on the grid, and the rests at the default choice."""
    fixed = {"raw": e_psi(log, log.process("raw", mode="causal"))}
    fit = calibration.heading_reference(log.t, log.rate, *log.reference()[:2])
    fixed["floor"] = e_psi(log, log.process("raw", mode="causal", **fit.overrides(include_bias=True)))
    for preset in PRESETS:
        fixed[f"{preset} causal"] = e_psi(log, evaluate.Method.from_preset(preset).run(log, mode="causal")[0])
    grid = {}
    for preset, use_speed, choice in itertools.product(PRESETS, SPEED_CASES, GRID):
        options = dict(zip(("bias_walk", "min_rest", "bias_sigmas"), choice))
        method = evaluate.Method(preset, evaluate.Method.from_preset(preset).preset, options)
        grid[(preset, use_speed, *choice)] = e_psi(log, method.run(log, mode="whole", use_speed=use_speed)[0])
    result = log.process("static_bias", mode="whole")
    lines = [f"  {log.name:<28} {result.bias_source}"]
    lines += gyrocore.wholelog.rest_lines(result.bias_source, result.rests, " " * 33)
    return fixed, grid, "\n".join(lines)


def best(grids: list[Grid]) -> tuple[float, float, float]:
    """The choice with the lowest mean log E_psi of static_bias over ``grids``, with and without speed."""
    return min(GRID, key=lambda c: float(np.mean([math.log(g["static_bias", u, *c]) for g in grids for u in SPEED_CASES])))


def main(data: Path) -> None:
    logs = [gyrocore.read_log(p) for p in sorted(data.iterdir()) if (p / "gyro.csv").is_file()]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # the bias sources are printed below
        scored = [score_log(log) for log in logs]
    grids = [g for _, g, _ in scored]
    print("| log | raw | static_bias causal | static_bias whole | recommended causal | recommended whole | "
          "static_bias whole, rate only | recommended whole, rate only | choice (walk, min_rest, sigmas) | "
          "constant calibration fitted to the reference |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    worse, harmed = [], []
    for i, (log, (fixed, _, _)) in enumerate(zip(logs, scored)):
        choice = best(grids[:i] + grids[i + 1 :])  # leave this log out
        sb, rec = grids[i]["static_bias", True, *choice], grids[i]["recommended", True, *choice]
        sb_rate, rec_rate = grids[i]["static_bias", False, *choice], grids[i]["recommended", False, *choice]
        cells = [fixed["raw"], fixed["static_bias causal"], sb, fixed["recommended causal"], rec, sb_rate, rec_rate]
        print(f"| {log.name} | " + " | ".join(f"{v:.2f}" for v in cells) + f" | {choice[0]:g}, {choice[1]:g}, {choice[2]:g} | {fixed['floor']:.2f} |")
        if rec > sb - 0.005:  # a tie at the table's precision counts
            worse.append(f"{log.name} ({rec:.2f} >= {sb:.2f})")
        if max(sb, rec, sb_rate, rec_rate) > fixed["raw"] + 0.5:
            harmed.append(f"{log.name} (raw {fixed['raw']:.2f}, static_bias {sb:.2f} / {sb_rate:.2f} rate only, "
                          f"recommended {rec:.2f} / {rec_rate:.2f})")
    print(f"\nrecommended does not beat static_bias (whole, leave-one-log-out) on {len(worse)} logs: {', '.join(worse) or 'none'}")
    print(f"whole mode (with speed or from the rate alone) more than 0.5 deg above raw on {len(harmed)} logs: {', '.join(harmed) or 'none'}")
    walk, min_rest, sigmas = best(grids)
    defaults = Options()
    print(
        f"\nchoice on all {len(logs)} logs: bias_walk {walk:g} rad/s/sqrt(s), min_rest {min_rest:g} s, bias_sigmas "
        f"{sigmas:g}; the defaults: {defaults.bias_walk:g}, {defaults.min_rest:g} s, {defaults.bias_sigmas:g} "
        "(docs/whole_log.md says why the walk differs)"
    )
    print("\nwhole-log bias of static_bias at the defaults:")
    print("\n".join(text for _, _, text in scored))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "real")

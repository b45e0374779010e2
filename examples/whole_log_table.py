"""E_psi of raw integration, static-bias removal and the recommended preset on every real log, in
whole-log mode (the bias from every rest in the log, known from the first sample) and in causal
mode (what a streaming pipeline gives: a rest corrects only what follows it; a log without a rest
window gets no bias). The same runs as ``gyrocore evaluate`` and ``gyrocore evaluate --causal``
(:func:`gyrocore.evaluate.compare`). Prints the README's table (Markdown) and where the whole-log
bias came from.

    python examples/whole_log_table.py [DATA_DIR]     # default ../shared/data/real; about 20 s
"""

import sys
import warnings
from pathlib import Path

import gyrocore
from gyrocore import evaluate

PRESETS = ("raw", "static_bias", "recommended")


def rests_text(score: evaluate.Score) -> str:
    """The rests a method used, short: '1 (rate+speed)', '2 (rate, rate)', or how else."""
    if not score.rests:
        return "given window" if score.bias_source.startswith("rest window") else "none"
    return f"{len(score.rests)} ({', '.join(r.found_by for r in score.rests)})"


def main(data: Path) -> None:
    logs = sorted(p for p in data.iterdir() if (p / "gyro.csv").is_file())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # the bias sources are printed below
        whole = evaluate.compare(logs, PRESETS, mode="whole")
        causal = evaluate.compare(logs, PRESETS, mode="causal")
    by = {(m, s.log, s.method.name): s for m, rows in (("whole", whole), ("causal", causal)) for s in rows}
    print("| log | rests (whole) | raw | static_bias causal | static_bias whole | recommended causal | recommended whole |")
    print("|---|---|---|---|---|---|---|")
    worse = []
    for log in dict.fromkeys(s.log for s in whole):
        e = {(m, p): by[m, log, p].errors.e_psi_deg for m in ("whole", "causal") for p in PRESETS}
        cells = [e["whole", "raw"], e["causal", "static_bias"], e["whole", "static_bias"],
                 e["causal", "recommended"], e["whole", "recommended"]]
        print(f"| {log} | {rests_text(by['whole', log, 'static_bias'])} | " + " | ".join(f"{v:.2f}" for v in cells) + " |")
        if e["whole", "recommended"] > e["whole", "static_bias"] - 0.005:  # a tie at the table's precision counts
            worse.append(f"{log} ({e['whole', 'recommended']:.2f} >= {e['whole', 'static_bias']:.2f})")
    print(f"\nrecommended does not beat static_bias (whole mode, by 0.005 deg) on {len(worse)} logs: {', '.join(worse) or 'none'}")
    print("\nwhole-log bias of static_bias:")
    for s in whole:
        if s.method.name == "static_bias":
            print(f"  {s.log:<28} {s.bias_source}")
            for r in s.rests if len(s.rests) > 1 else ():
                print(f"  {'':<28}   rest {r}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "real")

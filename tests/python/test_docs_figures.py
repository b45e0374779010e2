"""The tables and figures of the docs that a command or script prints are what it prints now:
each is run as the page says and compared with the page, to the places the page shows
(test_results_page.py does the same for docs/results.md's whole-log table), and figures counted
from a table that takes too long to rerun here are counted from it."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.cli import main

from .conftest import DATA

ROOT = Path(__file__).resolve().parents[2]
REAL = DATA / "real"
NUMBER = re.compile(r"-?\d+(?:\.\d+)?")


@pytest.fixture(autouse=True)
def _real_logs() -> None:
    if not REAL.is_dir():
        pytest.skip(f"shared data not found at {REAL}")


def table(page: str, header_start: str) -> list[list[str]]:
    """The rows of the Markdown table of ``docs/page`` whose header starts with ``header_start``,
    each a list of its cells."""
    lines = (ROOT / "docs" / page).read_text(encoding="utf-8").splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith(header_start))
    rows = []
    for line in lines[at + 2 :]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows


def script_rows(script: str) -> list[list[str]]:
    """The Markdown table rows ``python examples/SCRIPT REAL`` prints, without their headers (a
    row, a list of its cells)."""
    done = subprocess.run([sys.executable, str(ROOT / "examples" / script), str(REAL)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    lines = done.stdout.splitlines()
    return [[c.strip() for c in line.strip().strip("|").split("|")] for line, after in zip(lines, [*lines[1:], ""])
            if line.startswith("| ") and not after.startswith("|---")]  # its rows, not their headers


def shown_as(printed: float, shown: str, printed_places: int = 9) -> bool:
    """Whether ``shown`` is ``printed`` (itself printed to ``printed_places``) rounded to the places it shows."""
    places = len(shown.split(".")[1]) if "." in shown else 0
    return abs(printed - float(shown)) <= 0.5 * 10.0**-places + 0.5 * 10.0**-printed_places + 1e-9


def test_the_accuracy_bar_table_is_what_its_script_prints() -> None:
    # docs/results.md: `python examples/accuracy_bar.py`
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "accuracy_bar.py"), str(REAL)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    printed = {line.split()[0]: [float(v) for v in line.split()[1:]] for line in done.stdout.splitlines()[1:] if line}
    rows = table("results.md", "| preset | f110_ds3 | broad_10 | comma_seg40 | perfect gyro")
    names = {"static_bias": "static_bias", "hong_park": "hong_park", "combined": "combined",
             "tuned": "recommended", "tracked": "tracked"}
    assert len(rows) == len(names)
    for row in rows:
        preset = names[row[0].split("`")[1]]
        values = printed[preset]
        cells = [c.replace("*", "") for c in row[1:]]
        for value, cell in zip(values[:5], cells[:5]):
            assert shown_as(value, cell, 3), (preset, cell, value)
        if cells[5].startswith("0 (the baseline)"):
            assert values[5] == values[6] == 0.0, (preset, values)
        else:
            mean, worst = NUMBER.findall(cells[5])
            assert shown_as(values[5], mean, 3) and shown_as(values[6], worst, 3), (preset, cells[5], values[5:])


def test_the_causal_table_of_the_results_page_is_what_evaluate_prints(capsys: pytest.CaptureFixture[str]) -> None:
    # docs/results.md's first table: gyrocore evaluate f110_ds3 broad_10 comma_seg40 --bias-duration 10 --causal
    logs = ["f110_ds3", "broad_10", "comma_seg40"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        assert main(["evaluate", *(str(REAL / n) for n in logs), "--bias-duration", "10", "--causal", "--json"]) == 0
    scores = {(Path(r["path"]).name, r["preset"]): r["e_psi_deg"] for r in json.loads(capsys.readouterr().out)}
    header = "| log | raw | static_bias | hong_park | hdr | combined | tuned (= recommended) | tracked |"
    presets = ["raw", "static_bias", "hong_park", "hdr", "combined", "tuned", "tracked"]
    rows = table("results.md", header)
    assert [row[0].split()[0] for row in rows] == logs
    for row in rows:
        for preset, cell in zip(presets, row[1:], strict=True):
            assert shown_as(scores[(row[0].split()[0], preset)], cell), (row[0], preset, cell)


def test_the_slower_logs_table_is_what_its_script_prints() -> None:
    # docs/whole_log.md "Slower logs": `python examples/slow_logs.py`; the "after" columns
    printed = {(r[0], int(r[1])): r for r in script_rows("slow_logs.py")}
    rows = table("whole_log.md", "| log, every k-th reading (rate) |")
    assert rows
    for row in rows:
        log, k = re.fullmatch(r"(\w+), k = (\d) \(.*\)", row[0]).groups()  # type: ignore[union-attr]
        run = printed[(log, int(k))]
        assert [row[1], row[3], row[5]] == [run[3], run[4], run[6]], (row, run)


def test_the_ablation_tables_are_what_their_script_prints() -> None:
    # docs/whole_log.md "Ablations" and "A given window and the log's other rests":
    # `python examples/whole_log_ablations.py`
    printed = {r[0]: r for r in script_rows("whole_log_ablations.py")}
    ablations = table("whole_log.md", "| setting | mean log E_psi (18 logs) |")
    rerun = [row for row in ablations  # the two rows of the build before rests from the rate had to be rests
             if "before rests from the rate" not in row[0] and not row[0].startswith("the same")]
    assert len(rerun) == 8
    for row in rerun:
        assert row == printed[row[0]], (row, printed[row[0]])
    windows = table("whole_log.md", "| log | rests used | static_bias, window |")
    assert [row[0] for row in windows] == ["broad_10", "broad_11", "f110_ds3"]
    for row in windows:
        run = printed[row[0]]
        assert NUMBER.findall(row[1]) == NUMBER.findall(run[1]), (row, run)
        assert row[2:] == run[2:6], (row, run)


def test_the_time_offset_table_is_what_its_script_prints() -> None:
    # docs/calibration.md "A gyro's time offset": `python examples/time_offsets.py`
    rows = table("calibration.md", "| log | offset [s] | its standard error [ms] |")
    assert len(rows) == 18  # every real log has a reference
    assert rows == script_rows("time_offsets.py")
    text = " ".join((ROOT / "docs" / "calibration.md").read_text(encoding="utf-8").split())
    kitti = {r[0]: r for r in rows}["kitti_2011_09_30_0034"]  # what the page's example prints and scores
    assert f"offset = {kitti[1]}" in text and f"{kitti[4]} deg, not {kitti[3]}" in text


def test_the_lock_out_table_is_what_its_script_prints() -> None:
    # docs/fixes_model.md "The gate's lock-out, and re-admission": `python examples/fixes_lockout.py`
    rows = table("fixes_model.md", "| fixes | gate alone: causal / smoothed")
    assert len(rows) == 18
    assert rows == script_rows("fixes_lockout.py")


def test_the_fixes_results_table_is_what_its_script_prints() -> None:
    # docs/fixes_results.md "Results": `python examples/fixes_acceptance.py`, its first table (the
    # page leaves out the settings column, and the "(-)" of a true bias or scale not known)
    run = script_rows("fixes_acceptance.py")
    printed = {r[0]: [c.replace(" (-)", "") for c in r[:9]] for r in run if len(r) == 10}
    rows = table("fixes_results.md", "| log | raw | raw from 1st fix | fixes throughout")
    assert len(rows) == len(printed) == 12
    for row in rows:
        assert row == printed[row[0]], (row, printed[row[0]])
    # the summary on docs/fixes.md, the user's page: each group's range of those figures
    grade = {r[0]: r[6].split(" / ") for r in run if len(r) == 7}
    summary = {row[0]: row[1:] for row in table("fixes.md", "| logs | raw integration | fixes throughout")}

    def span(values: list[str], places: int = 2) -> str:
        numbers = sorted(float(v) for v in values)
        return f"{numbers[0]:.{places}f}-{numbers[-1]:.{places}f}"

    for label, group in (("6 KITTI MEMS twins", [r for n, r in printed.items() if n.endswith("_mems")]),
                         ("6 KITTI true-rate drives", [r for n, r in printed.items() if not n.endswith("_mems")])):
        causal, smoothed = zip(*(r[3].split(" / ") for r in group))
        assert summary[label] == [span([r[1] for r in group], 1), f"{span(list(causal))} / {span(list(smoothed))}",
                                  f"{span([r[5] for r in group])} / {span([r[6] for r in group])}"], label
    label = "the same, with the OXTS's data-sheet grade as priors (causal)"
    assert summary[label][1:] == [span([g[0] for g in grade.values()]), span([g[1] for g in grade.values()])]


def test_the_held_out_counts_are_those_of_the_held_out_table() -> None:
    # The README and docs/results.md count the logs on which `tuned`, held out, beats static-bias
    # removal, from docs/recommended.md's held-out table (its `gyrocore tune ... --leave-one-out`
    # takes 12 minutes); results.md said "by 2.5 % to 59 %" where kitti_0018_mems gains 60 %.
    text = (ROOT / "docs" / "recommended.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\w+) \| [\d.]+ \| ([\d.]+) \| ([\d.]+) \|$", text, re.M)
    assert len(rows) == 18
    change = {name: float(tuned) / float(static) - 1.0 for name, static, tuned in rows}
    better = sorted(-c for c in change.values() if c <= -0.005)
    within = [c for c in change.values() if -0.005 < c <= 0.004]
    worse = [c for c in change.values() if c > 0.004]
    mean_log = sum(math.log1p(c) for c in change.values()) / len(change)
    readme = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    results = " ".join((ROOT / "docs" / "results.md").read_text(encoding="utf-8").split())
    assert (len(better), len(within), len(worse)) == (6, 7, 5)
    assert f"0.5 % or more on {len(better)} of the 18 logs" in readme
    assert f"is within 0.4 % on {len(within)} and worse on {len(worse)}" in readme
    assert f"a mean log ratio of {mean_log:.3f}" in readme
    assert f"by 0.5 % or more on {len(better)} of the 18 logs" in results
    assert f"by {100 * better[0]:.1f} % to {100 * better[-1]:.0f} %" in results
    assert f"log ratio to static-bias removal is {mean_log:.3f} held out" in results


@pytest.mark.parametrize("causal", [False, True])
def test_the_simulated_fixes_table_is_what_evaluate_prints(causal: bool, capsys: pytest.CaptureFixture[str]) -> None:
    # docs/fixes_results.md "Fixes in the normal entry points": gyrocore evaluate kitti_2011_09_30_00{18,20,27,33,34}
    # kitti_2011_10_03_0042 --preset raw --sim-fixes rate=1,sigma_deg=1,outage=30:50,seed=1 [--causal]
    rows = table("fixes_results.md", "| log | smoothed | causal | raw |")
    assert len(rows) == 6
    args = ["evaluate", *(str(REAL / row[0]) for row in rows), "--preset", "raw",
            "--sim-fixes", "rate=1,sigma_deg=1,outage=30:50,seed=1", "--json", *(["--causal"] if causal else [])]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        assert main(args) == 0
    scores = {Path(r["path"]).name: r for r in json.loads(capsys.readouterr().out)}
    for row in rows:
        r = scores[row[0]]
        assert row[2 if causal else 1] == f"{r['e_psi_deg']:.2f} / {r['outage_e_psi_deg']:.2f}", row
        assert row[3] == f"{r['raw_e_psi_deg']:.2f} / {r['raw_outage_e_psi_deg']:.2f}", row


def test_the_gyros_without_bias_table_is_what_its_expression_gives() -> None:
    # docs/whole_log.md "Gyros without bias, from the rate alone": the "after" column, from the
    # expression the page gives under the table
    from gyrocore import tune

    rows = table("whole_log.md", "| drives (seeds), whole mode, no window, no speed |")
    assert len(rows) == 3
    for row in rows:
        count, hz, minutes, first, last, preset = re.fullmatch(  # type: ignore[union-attr]
            r"(\d+) at (\d+) Hz, (\d+) min \((\d+)-(\d+)(?:, perfect and noisy)?\), `(\w+)`", row[0]).groups()
        per_mix = (int(last) - int(first) + 1) // 3  # the three road mixes of tune.harm_cases
        cases = [case for noisy in (False, True) for case in tune.harm_cases(
            per_mix=per_mix, first_seed=int(first), noisy=noisy, rate_hz=float(hz), minutes=float(minutes))]
        assert len(cases) == int(count), row
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gyrocore.InputWarning)  # no rest used: it says so
            worst = max(case.reference.errors(case.t, gyrocore.process(case.t, case.rate, preset).heading).e_psi_deg
                        - case.raw.e_psi_deg for case in cases)
        assert f"{worst:.2f}" == row[2], (row, worst)


def test_the_held_out_column_and_the_readme_quote_the_held_out_table() -> None:
    # docs/results.md's "recommended whole, held out" column and the README's held-out pairs are
    # docs/recommended.md's held-out table, rounded (its fit takes 12 minutes: not rerun here)
    text = (ROOT / "docs" / "recommended.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\w+) \| [\d.]+ \| ([\d.]+) \| ([\d.]+) \|$", text, re.M)
    held = {name: (float(static), float(tuned)) for name, static, tuned in rows}
    header = ("| log | raw | static_bias causal | static_bias whole | recommended causal | recommended whole | "
              "recommended whole, held out |")
    lines = (ROOT / "docs" / "results.md").read_text(encoding="utf-8").splitlines()
    names = [c.strip() for c in next(line for line in lines if line.startswith(header)).strip("|").split("|")]
    column = names.index("recommended whole, held out")
    rows = table("results.md", header)
    assert sorted(row[0] for row in rows) == sorted(held)
    for row in rows:
        assert row[column] == f"{held[row[0]][1]:.2f}", row
    readme = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    for name, short in (("kitti_2011_09_30_0018_mems", "kitti_0018_mems"), ("f110_ds5", "f110_ds5"),
                        ("kitti_2011_09_30_0034", "kitti_0034")):
        static, tuned = held[name]
        assert f"{short}: {static:.2f} to {tuned:.2f}" in readme, name


def test_the_calibration_pages_spreads_and_moving_shares_are_the_real_logs() -> None:
    # docs/calibration.md: the share of moving half-seconds of the 18 real drives, how far their
    # rests' readings spread beyond their white noise, and their first 5 s
    from gyrocore import _motion

    text = " ".join((ROOT / "docs" / "calibration.md").read_text(encoding="utf-8").split())
    logs = [gyrocore.read_log(p) for p in sorted(REAL.iterdir()) if (p / "gyro.csv").is_file()]
    assert len(logs) == 18
    shares = sorted((_motion.moving_share(log.rate, float(np.median(np.diff(log.t)))) or 0.0, log.name) for log in logs)
    low, high = re.search(r"([\d.]+) \(comma_seg40, often stopped\) to ([\d.]+) \(f110_ds1\) on the 18 real drives",
                          text).groups()  # type: ignore[union-attr]
    assert (shares[0][1], shares[-1][1]) == ("comma_seg40", "f110_ds1")
    assert shown_as(shares[0][0], low) and shown_as(shares[-1][0], high), shares
    at_rest, first = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        for log in logs:
            for use_speed in (True, False):
                for rest in log.process("static_bias", use_speed=use_speed).rests:
                    at_rest.append(_motion.spread(log.rate[(log.t >= rest.start) & (log.t <= rest.end)]))
            if not log.name.startswith("broad"):  # the hand-held logs rest at their start
                first.append(_motion.spread(log.rate[log.t <= log.t[0] + 5.0]))
    ratio, beyond = [s[0] for s in at_rest if s], [math.degrees(s[1]) for s in at_rest if s]
    assert (f"{min(ratio):.2f} to {max(ratio):.2f} times, at most {max(beyond):.2f} deg/s beyond") in text
    ratio, beyond = [s[0] for s in first if s], [math.degrees(s[1]) for s in first if s]
    assert (f"first 5 s spread {min(ratio):.1f} (a car still stopped) to {max(ratio):.0f} times and "
            f"{min(beyond):.1f} to {max(beyond):.0f} deg/s beyond") in text


def test_the_simulated_drive_figures_of_the_whole_log_page_are_what_evaluate_prints(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # docs/whole_log.md quoted 4.74 deg as the largest error with the speed, where evaluate printed 4.31
    drive = tmp_path / "drive.csv"
    assert main(["simulate", "--out", str(drive)]) == 0
    largest = {}
    for speed in (True, False):
        capsys.readouterr()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gyrocore.InputWarning)
            assert main(["evaluate", str(drive), "--preset", "recommended", "--json",
                         *([] if speed else ["--no-speed"])]) == 0
        largest[speed] = json.loads(capsys.readouterr().out)[0]["max_error_deg"]
    text = " ".join((ROOT / "docs" / "whole_log.md").read_text(encoding="utf-8").split())
    assert (f"`gyrocore simulate`'s default drive: {largest[True]:.2f} deg with the speed; with `--no-speed` "
            f"35.9 deg before rests from the rate alone had to be rests, {largest[False]:.1f} deg since") in text


def test_the_sample_logs_rest_figures_are_what_the_calibration_gives() -> None:
    # docs/rest_tracking.md "The sample log's rest" gave 0.02437 rad/s for the reference fit's bias,
    # which is 0.0243647
    from gyrocore import calibration, datasets

    sample = datasets.sample_drive()
    found = calibration.static_bias(sample.t, sample.rate)
    early = calibration.static_bias(sample.t, sample.rate, (0.0, 8.5))
    fit = calibration.heading_reference(sample.t, sample.rate, *sample.reference())
    text = " ".join((ROOT / "docs" / "rest_tracking.md").read_text(encoding="utf-8").split())
    assert (f"The sample's rest is found as 0-{found.window[1]:.1f} s (its first 5.5 s of straight road read the "
            f"same to a gyro), and the bias from it, {found.bias:.5f} rad/s, against {early.bias:.5f} from 0-8.5 s "
            f"and {fit.bias:.5f} from the reference fit") in text

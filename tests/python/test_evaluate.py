"""Heading metrics (HDR eq 15-16, Hong Table 1, FOG section 4.1) against closed forms and the
papers' numbers, and the method comparison on the real logs of ../shared/data/real."""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import evaluate
from gyrocore.cli import main

from .conftest import REAL_LOGS, gyrocore_cli, real_log_path


def irregular_times(duration: float, mean_dt: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.concatenate(([0.0], np.cumsum(rng.uniform(0.2, 1.8, int(duration / mean_dt) + 10) * mean_dt)))
    return t[t <= duration]


def wrap(angle: np.ndarray) -> np.ndarray:
    """To (-pi, pi], as the logs store the reference."""
    return np.angle(np.exp(1j * angle))


# Both sides turn at W rad/s (several whole turns); the estimate drifts at B rad/s on top.
W, B = 0.4, math.radians(0.05)


def drifting(t: np.ndarray) -> np.ndarray:
    return W * t + B * t


def test_linear_drift_gives_the_closed_form_metrics_on_irregular_times() -> None:
    t_est = irregular_times(300.0, 0.01, seed=1)
    t_ref = irregular_times(300.0, 0.2, seed=2) + 0.05
    e = gyrocore.heading_errors(t_est, drifting(t_est), t_ref, wrap(W * t_ref))
    inside = t_ref[t_ref <= t_est[-1]]
    expected = np.degrees(B * (inside - inside[0]))  # aligned at the first compared time
    assert e.n == len(inside)
    assert e.e_psi_deg == pytest.approx(expected.mean(), rel=1e-9)
    assert e.std_error_deg == pytest.approx(expected.std(), rel=1e-9)
    assert e.final_error_deg == pytest.approx(expected[-1], rel=1e-9)
    assert e.max_error_deg == pytest.approx(expected[-1], rel=1e-9)
    assert e.ne_psi_deg_per_min == pytest.approx(expected.mean() / ((inside[-1] - inside[0]) / 60), rel=1e-9)
    assert e.gaps == 0


def test_time_weighting_averages_over_time_not_samples() -> None:
    # A faster reference early on (10 Hz, then 4 Hz): the sample mean leans to small errors, the
    # time mean of a linear error is exactly half the final one.
    t_ref = np.concatenate((np.arange(0.0, 10.0, 0.1), np.linspace(10.0, 100.0, 361)))
    t_est = np.linspace(0.0, 100.0, 2001)
    timed = gyrocore.heading_errors(t_est, drifting(t_est), t_ref, wrap(W * t_ref), time_weighted=True)
    plain = gyrocore.heading_errors(t_est, drifting(t_est), t_ref, wrap(W * t_ref))
    assert timed.e_psi_deg == pytest.approx(np.degrees(B * 100.0) / 2, rel=1e-9)
    assert plain.e_psi_deg == pytest.approx(np.degrees(B * t_ref).mean(), rel=1e-9)
    assert plain.e_psi_deg < 0.9 * timed.e_psi_deg


def test_reference_gap_is_skipped_and_its_turns_recovered() -> None:
    # 30 s without reference while turning 12 rad (almost two turns): unwrapping across the gap
    # would lose whole turns; the error must stay the drift's closed form.
    t_est = np.arange(0.0, 200.0, 0.01)
    t_ref = np.arange(0.0, 200.0, 0.1)
    t_ref = t_ref[(t_ref < 80.0) | (t_ref > 110.0)]
    e = gyrocore.heading_errors(t_est, drifting(t_est), t_ref, wrap(W * t_ref))
    inside = t_ref[t_ref <= t_est[-1]]
    assert e.gaps == 1
    assert e.e_psi_deg == pytest.approx(np.degrees(B * inside).mean(), rel=1e-9)
    naive = np.unwrap(wrap(W * t_ref))
    assert abs(naive[-1] - W * t_ref[-1]) > 1.0  # plain unwrapping gets the turns wrong here


def test_reference_samples_inside_a_gap_of_the_estimate_are_not_scored() -> None:
    t_est = np.arange(0.0, 100.0, 0.01)
    t_est = t_est[(t_est < 40.0) | (t_est > 60.0)]
    t_ref = np.arange(0.0, 100.0, 0.1)
    # The estimate is wrong inside its gap only as a straight line can be: score must ignore it.
    e = gyrocore.heading_errors(t_est, drifting(t_est), t_ref, wrap(W * t_ref))
    kept = t_ref[((t_ref <= t_est[t_est < 50][-1]) | (t_ref >= t_est[t_est > 50][0])) & (t_ref <= t_est[-1])]
    assert e.n == len(kept)
    assert e.gaps == 1
    assert e.e_psi_deg == pytest.approx(np.degrees(B * kept).mean(), rel=1e-9)


def test_bad_reference_names_the_index() -> None:
    t = np.arange(10.0)
    with pytest.raises(ValueError, match=r"reference: t must strictly increase: t\[3\] = 2.0 follows 2.0"):
        gyrocore.heading_errors(t, t * 0, [0.0, 1.0, 2.0, 2.0, 4.0], np.zeros(5))
    with pytest.raises(ValueError, match=r"reference: heading\[2\] is nan: samples must be finite"):
        gyrocore.heading_errors(t, t * 0, [0.0, 1.0, 2.0], [0.0, 0.0, math.nan])
    with pytest.raises(ValueError, match="fewer than two samples inside"):
        gyrocore.heading_errors(t, t * 0, [20.0, 21.0], [0.0, 0.0])


# HDR Table II: E_psi without and with HDR [deg], the improvement it reports, duration [min] and
# NE_psi with HDR [deg/min]. The paper's E values are rounded, hence the tolerances.
TABLE_II = [
    ("City 1", 17, 3.1, 5.4, 19.4, 0.16),
    ("Suburbs", 35, 10.4, 3.4, 24.3, 0.43),
    ("Mixed", 44, 4.7, 9.4, 20.0, 0.24),
    ("Highway 1", 184, 6.4, 29, 52.1, 0.12),
    ("City 2", 74, 11.3, 6.7, 21.6, 0.52),
]


@pytest.mark.parametrize("name,raw,hdr,factor,minutes,ne", TABLE_II)
def test_improvement_and_ne_psi_reproduce_table_ii(
    name: str, raw: float, hdr: float, factor: float, minutes: float, ne: float
) -> None:
    # A heading that is off by a constant hdr degrees after the start scores E_psi = hdr.
    t = np.linspace(0.0, minutes * 60.0, 2001)
    ref = np.zeros_like(t)
    with_hdr = gyrocore.heading_errors(t, np.where(t > 0, math.radians(hdr), 0.0), t, ref)
    without = gyrocore.heading_errors(t, np.where(t > 0, math.radians(raw), 0.0), t, ref)
    assert with_hdr.ne_psi_deg_per_min == pytest.approx(ne, abs=0.006)
    assert evaluate.improvement(without, with_hdr) == pytest.approx(factor, rel=0.03)


def test_return_orientation_error_of_a_square_lap_with_a_scale_error() -> None:
    # FOG section 4.1: a lap with four 90-degree turns; a gyro reading 1 % high measures 363.6 deg.
    t = np.linspace(0.0, 64.0, 641)
    true = np.clip(np.floor(t / 16.0), 0, 4) * (math.pi / 2)
    measured = 1.01 * true
    assert math.degrees(evaluate.return_orientation_error(t, measured)) == pytest.approx(3.6, rel=1e-9)
    assert math.degrees(evaluate.return_orientation_error(t, -measured)) == pytest.approx(-3.6, rel=1e-9)
    explicit = evaluate.return_orientation_error(t, measured, t_start=10.0, t_end=40.0, rotation=math.pi)
    assert math.degrees(explicit) == pytest.approx(1.8, rel=1e-9)


def test_compare_scores_every_method_on_every_real_log(tmp_path: Path) -> None:
    logs = [real_log_path(n) for n in REAL_LOGS]
    rows = evaluate.compare(logs, ["raw", "static_bias", "recommended"], bias_duration=10.0, plot_dir=tmp_path)
    assert [(r.log, r.method.name) for r in rows] == [
        (n, p) for n in REAL_LOGS for p in ("raw", "static_bias", "recommended")
    ]
    by = {(r.log, r.method.name): r for r in rows}
    # The data README's independent figures (static bias from the rest window).
    assert by["f110_ds3", "static_bias"].errors.e_psi_deg == pytest.approx(3.7, abs=0.05)
    assert by["broad_10", "static_bias"].errors.e_psi_deg == pytest.approx(1.3, abs=0.05)
    assert by["f110_ds3", "static_bias"].improvement == pytest.approx(20.4 / 3.7, rel=0.03)
    assert by["f110_ds3", "recommended"].method.preset == gyrocore.recommended_preset()
    # comma_seg40 has no rest: a 10 s leading window while driving straight is the documented way.
    comma = by["comma_seg40", "static_bias"]
    assert comma.bias_source.startswith("first 10 s") and comma.errors.e_psi_deg < 10.0
    # Both f110_ds3 (out and back, 0.7 m apart) and broad_10 (back to rest) end where they started.
    assert by["f110_ds3", "raw"].return_error_deg is not None and by["comma_seg40", "raw"].return_error_deg is None
    assert by["f110_ds3", "static_bias"].position is not None and by["broad_10", "raw"].position is None
    for name in REAL_LOGS:
        assert (tmp_path / f"{name}.png").read_bytes()[:4] == b"\x89PNG"


def test_without_a_bias_option_a_log_without_rest_gets_no_bias() -> None:
    with pytest.warns(gyrocore.InputWarning, match="no rest was found"):  # comma_seg40 never stops
        rows = evaluate.compare([real_log_path("comma_seg40")], ["raw", "static_bias"])
    assert rows[1].bias_source.startswith("none")
    assert rows[1].errors.e_psi_deg == pytest.approx(rows[0].errors.e_psi_deg, rel=1e-9)


KEYS = {"path", "name", "preset", "e_psi_deg", "ne_psi_deg_per_min", "final_error_deg", "max_error_deg"}


def test_cli_json_has_one_object_per_log_and_preset(capsys: pytest.CaptureFixture[str]) -> None:
    logs = [str(real_log_path(n)) for n in ("f110_ds3", "comma_seg40")]
    assert main(["evaluate", *logs, "--preset", "static_bias", "--preset", "recommended",
                 "--bias-duration", "10", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [(r["path"], r["name"], r["preset"]) for r in rows] == [
        (logs[0], "f110_ds3", "static_bias"), (logs[0], "f110_ds3", "recommended"),
        (logs[1], "comma_seg40", "static_bias"), (logs[1], "comma_seg40", "recommended"),
    ]
    assert all(KEYS <= set(r) for r in rows)
    assert rows[0]["e_psi_deg"] == pytest.approx(3.7, abs=0.05)


def test_cli_table_and_errors(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    assert main(["evaluate", str(real_log_path("broad_10")), "--preset", "raw", "--preset", "hdr"]) == 0
    out = capsys.readouterr().out
    assert "E_psi" in out and f"\n{real_log_path('broad_10')} hdr " in out
    assert main(["evaluate", str(tmp_path), "--preset", "raw"]) == 2
    assert main(["evaluate", str(real_log_path("broad_10")), "--preset", "nonsense"]) == 2
    assert main(["evaluate", str(real_log_path("broad_10")), "--param", "bias_duration=-1"]) == 2
    err = capsys.readouterr().err
    assert err.count("gyrocore: error:") == 3


def test_a_log_without_reference_is_refused_by_name(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # A bare gyro file: samples, no reference.csv. Evaluating, tuning or dead-reckoning against it
    # is an error that names the log and what is missing, raised before any work.
    drive = gyrocore.sim.car_drive(duration=60.0, seed=2)
    src = tmp_path / "bare.npz"
    np.savez(src, t=drive.t, gyro_z=drive.rate_measured)
    log = gyrocore.read_log(src)
    assert not log.has_track
    for attempt in (log.reference, log.track):
        with pytest.raises(ValueError, match="log bare: no reference"):
            attempt()
    with pytest.raises(ValueError, match=f"^{src}: no reference heading"):  # named by its path, once
        evaluate.compare([log], ["raw"])
    with pytest.raises(ValueError, match="log bare: no reference heading"):
        gyrocore.tune.Case.from_log(log)
    folder = tmp_path / "no_reference"
    folder.mkdir()
    np.savetxt(folder / "gyro.csv", np.column_stack([drive.t, drive.rate_measured]), delimiter=",",
               header="t,gyro_z", comments="")
    assert main(["evaluate", str(folder), "--preset", "raw"]) == 2
    assert f"{folder}: no reference heading to score against (a log folder's reference.csv" in capsys.readouterr().err
    # A log folder has both: the reference and the positions come back as read.
    real = gyrocore.read_log(real_log_path("f110_ds3"))
    t_ref, heading_ref = real.reference()
    assert real.has_track and real.track()[0] is t_ref and heading_ref is real.heading_ref


def test_an_odometry_in_relative_time_warns_in_process_and_evaluate_alike(tmp_path: Path) -> None:
    folder = gyrocore.datasets.write_sample(tmp_path / "rel")
    odometry = np.loadtxt(folder / "odometry.csv", delimiter=",", skiprows=1)
    odometry[:, 0] += 1000.0  # another clock: none of it overlaps the gyro's
    np.savetxt(folder / "odometry.csv", odometry, delimiter=",", header="t,speed", comments="", fmt="%.17g")
    meta = json.loads((folder / "meta.json").read_text())
    (folder / "meta.json").write_text(json.dumps({**meta, "stationary": None}))  # rests found, with the speed
    processed = gyrocore_cli("process", folder, "--out", tmp_path / "h.csv", code=0)
    evaluated = gyrocore_cli("evaluate", folder, code=0)
    for proc in (processed, evaluated):
        assert "odometry.csv: its times" in proc.stderr or "odometry speed: its times" in proc.stderr, proc.stderr
        assert "cover 0 % of the gyro's" in proc.stderr
    assert "0 odometry sample(s) (times 1000 .. " in evaluated.stderr and "no dead reckoning" in evaluated.stderr


def broken_copy(tmp_path: Path, name: str, file: str, edit: Callable[[list[str]], list[str] | None]) -> Path:
    """A copy of f110_ds3 in ``tmp_path/name`` whose ``file`` has its lines edited (None: removed)."""
    folder = tmp_path / name
    shutil.copytree(real_log_path("f110_ds3"), folder)
    for path in folder.iterdir():
        path.chmod(0o644)
    lines = edit((folder / file).read_text().splitlines())
    if lines is None:
        (folder / file).unlink()
    else:
        (folder / file).write_text("\n".join(lines) + "\n")
    return folder


def with_line(number: int, text: Callable[[str], str]) -> Callable[[list[str]], list[str]]:
    """An edit that rewrites line ``number`` (1 is the header)."""
    return lambda lines: [text(line) if k == number else line for k, line in enumerate(lines, start=1)]


def cells(line: str, **values: str) -> str:
    """A reference.csv line (t,heading,x,y) with some of its cells replaced."""
    row = dict(zip(("t", "heading", "x", "y"), line.split(",")))
    return ",".join({**row, **values}.values())


def test_a_fleet_run_reports_every_log_and_fails_the_bad_ones_alone(tmp_path: Path) -> None:
    good = real_log_path("f110_ds3")
    bad = {
        "malformed gyro": (broken_copy(tmp_path, "malformed", "gyro.csv", with_line(50, lambda s: s.split(",")[0])),
                           "gyro.csv: line 50: 1 field, but the header has 2"),
        "no reference": (broken_copy(tmp_path, "noref", "reference.csv", lambda lines: None),
                         "noref: no reference heading to score against"),
        "empty reference": (broken_copy(tmp_path, "emptyref", "reference.csv", lambda lines: lines[:1]),
                            "emptyref: reference: 0 sample(s)"),
        "other clock": (broken_copy(tmp_path, "clock", "reference.csv", lambda lines: lines[:1] + [
                            cells(s, t=str(float(s.split(",")[0]) - 1e6)) for s in lines[1:]]),
                        "clock: the reference has fewer than two samples inside the heading's time span"),
    }
    folders = [str(folder) for folder, _ in bad.values()]
    proc = gyrocore_cli("evaluate", good, *folders, "--preset", "raw", "--preset", "static_bias", code=1)
    lines = proc.stdout.splitlines()
    assert sum(line.startswith(f"{good} ") for line in lines) == 2  # its two methods scored
    failed = [line for line in lines if line.startswith("FAILED ")]
    assert len(failed) == len(bad)
    for line, (folder, message) in zip(failed, bad.values()):
        assert line.startswith(f"FAILED {folder}") and message in line
        assert line.count(str(folder)) == 1  # named once
    assert f"1 of {1 + len(bad)} logs scored, {len(bad)} failed" in proc.stdout
    rows = json.loads(gyrocore_cli("evaluate", good, *folders, "--preset", "raw", "--json", code=1).stdout)
    assert [r["path"] for r in rows] == [str(good), *folders]
    assert rows[0]["name"] == "f110_ds3" and "error" not in rows[0]
    assert [message in r["error"] for r, (_, message) in zip(rows[1:], bad.values())] == [True] * len(bad)
    twice = gyrocore_cli("evaluate", good, good, "--preset", "raw", code=0).stdout  # scored once
    assert twice.count(f"\n{good} ") == 1 and f"  {good} raw: none" in twice


def test_a_single_log_that_cannot_be_scored_is_a_one_line_error(tmp_path: Path) -> None:
    folder = broken_copy(tmp_path, "clock", "reference.csv", lambda lines: lines[:1] + [
        cells(s, t=str(float(s.split(",")[0]) - 1e6)) for s in lines[1:]])
    proc = gyrocore_cli("evaluate", folder, "--preset", "raw", code=2)
    assert proc.stdout == ""
    (line,) = proc.stderr.splitlines()
    # both time spans, so that another clock shows
    assert line.startswith(f"gyrocore: error: {folder}: the reference has fewer than two samples inside")
    assert "the reference runs from t = 1650541251.826 to 1650541378.813 s" in line
    assert "the heading from t = 1651541251.831 to 1651541378.824 s" in line


def test_logs_of_the_same_name_are_told_apart_by_their_path(tmp_path: Path) -> None:
    first, second = (tmp_path / "a" / "drive", tmp_path / "b" / "drive")
    for folder in (first, second):
        shutil.copytree(real_log_path("f110_ds3"), folder)
    proc = gyrocore_cli("evaluate", first, second, "--preset", "raw", "--preset", "static_bias", code=0)
    for folder in (first, second):
        assert proc.stdout.count(f"\n{folder} ") == 2  # a row per method
        assert f"  {folder} static_bias: rest [1651541251.831, " in proc.stdout  # its own bias-source line
    rows = json.loads(gyrocore_cli("evaluate", first, second, "--preset", "raw", "--json", code=0).stdout)
    assert [(r["path"], r["name"]) for r in rows] == [(str(first), "f110_ds3"), (str(second), "f110_ds3")]


def test_a_nan_reference_heading_is_named_by_its_line(tmp_path: Path) -> None:
    folder = broken_copy(tmp_path, "nan", "reference.csv", with_line(102, lambda s: cells(s, heading="nan")))
    proc = gyrocore_cli("evaluate", folder, "--preset", "raw", code=2)
    assert f"{folder}/reference.csv: line 102, column 2 (heading): nan" in proc.stderr


def test_an_empty_position_drops_the_positions_and_the_heading_is_scored(tmp_path: Path) -> None:
    folder = broken_copy(tmp_path, "nopos", "reference.csv", with_line(102, lambda s: cells(s, y="")))
    with pytest.warns(gyrocore.InputWarning, match=r"reference.csv: line 102, column 4 \(y\): empty"):
        log = gyrocore.read_log(folder)
    assert not log.has_track and log.heading_ref is not None
    (row,) = evaluate.compare([log], ["static_bias"])
    assert row.errors.e_psi_deg == pytest.approx(3.7, abs=0.05) and row.position is None
    assert row.return_error_deg is None


def test_a_fleet_run_with_simulated_fixes_fails_the_bad_logs_alone(tmp_path: Path) -> None:
    good = real_log_path("f110_ds3")
    bad = broken_copy(tmp_path, "noref", "reference.csv", lambda lines: None)
    args = ("evaluate", good, bad, good, "--preset", "hdr", "--sim-fixes", "rate=1")
    proc = gyrocore_cli(*args, code=1)
    assert proc.stdout.count(f"\n{good} ") == 1  # given twice, scored once
    assert f"\nFAILED {bad}: no reference heading to score against" in proc.stdout
    rows = json.loads(gyrocore_cli(*args, "--json", code=1).stdout)
    assert [r["path"] for r in rows] == [str(good), str(bad)]
    assert rows[0]["name"] == "f110_ds3" and "no reference heading" in rows[1]["error"]
    late = gyrocore_cli("evaluate", good, bad, "--preset", "hdr", "--sim-fixes", "outage=200:10", code=1)
    assert f"FAILED {good}: the outage starts 200 s after the first sample" in late.stdout


def test_a_nan_heading_true_is_named_by_its_file_and_line(tmp_path: Path) -> None:
    # it was "reference: heading[9] is nan", an index into the log, not a line of the file
    rows = [f"{i * 0.01:.2f},0.01,{i * 1e-4!r}" for i in range(500)]
    rows[9] = "0.09,0.01,nan"
    drive = tmp_path / "drive.csv"
    drive.write_text("t,gyro_z,heading_true\n" + "\n".join(rows) + "\n")
    proc = gyrocore_cli("evaluate", drive, "--preset", "raw", code=2)
    assert f"{drive}: line 11, column heading_true: empty or nan; a reference's t and heading must be finite" in proc.stderr


def test_a_bias_duration_names_its_rest_once(capsys: pytest.CaptureFixture[str]) -> None:
    # "first 10 s: rest [...] ..." was followed by a line that named the same rest again
    assert main(["evaluate", str(real_log_path("comma_seg40")), "--preset", "static_bias", "--bias-duration", "10"]) == 0
    sources = capsys.readouterr().out.split("bias source:")[1]
    assert sources.count("rest [") == 1 and "first 10 s: rest [" in sources


def test_a_nan_reading_is_named_by_its_line_with_the_option_that_takes_it(tmp_path: Path) -> None:
    # it said "LOG: rate[498] is NaN: ... (drop or fill them first)", and --param nonfinite=hold,
    # which every method took, still failed: the raw baseline refused the NaN
    from gyrocore import datasets

    log = datasets.write_sample(tmp_path / "drive")
    lines = (log / "gyro.csv").read_text().splitlines()
    lines[499] = lines[499].split(",")[0] + ","
    (log / "gyro.csv").write_text("\n".join(lines) + "\n")
    error = gyrocore_cli("evaluate", log, "--preset", "static_bias", code=2).stderr
    assert f"rate[498] is NaN: samples must be finite (drop or fill them first) ({log / 'gyro.csv'}, line 500); " in error
    assert "--param nonfinite=hold uses the last usable reading there" in error
    rows = json.loads(gyrocore_cli("evaluate", log, "--preset", "static_bias", "--param", "nonfinite=hold", "--json",
                                   code=0).stdout)
    assert rows[0]["e_psi_deg"] < 10


def test_plot_dir_names_the_plots_it_wrote(tmp_path: Path) -> None:
    # it said "plots in DIR", naming no file
    pytest.importorskip("matplotlib")
    from gyrocore import datasets

    log = datasets.write_sample(tmp_path / "drive")
    out = gyrocore_cli("evaluate", log, "--preset", "raw", "--plot-dir", tmp_path / "plots", code=0).stdout
    assert out.splitlines()[-1] == f"wrote {tmp_path / 'plots' / 'sample_drive.png'}"
    assert (tmp_path / "plots" / "sample_drive.png").is_file()


def test_the_evaluation_page_says_json_is_one_list(tmp_path: Path) -> None:
    # it said "one JSON object per (log, method)", read as JSON lines; the output is one list
    from gyrocore import datasets

    page = (Path(__file__).resolve().parents[2] / "docs" / "evaluation.md").read_text(encoding="utf-8")
    assert "--json   # one JSON list, an object per (log, method)" in page
    out = gyrocore_cli("evaluate", datasets.write_sample(tmp_path / "d"), "--preset", "raw", "--json", code=0).stdout
    assert isinstance(json.loads(out), list)


def test_every_json_field_is_named_with_its_unit_in_the_docs(capsys: pytest.CaptureFixture[str]) -> None:
    # a rest's bias in the JSON is rad/s while the text beside it says deg/s; no field was listed
    docs = (Path(__file__).parents[2] / "docs" / "evaluation.md").read_text(encoding="utf-8")
    log = str(real_log_path("f110_ds3"))
    assert main(["evaluate", log, "--preset", "static_bias", "--param", "lowpass_tau=0.5", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)[0]
    assert main(["evaluate", log, "--preset", "raw", "--sim-fixes", "rate=1,outage=10:20", "--json"]) == 0
    fixed = json.loads(capsys.readouterr().out)[0]
    keys = {*row, *row["rests"][0], *fixed}
    assert row["position_n"] > 0 and "overrides" in row
    assert sorted(k for k in keys if f"`{k}`" not in docs) == []
    assert "`noise` **[rad/s]**" in docs


def test_the_table_says_when_a_log_had_gaps_skipped(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # the JSON's "gaps" had no place in the table: the score of a log with an outage read as a whole one
    t = np.arange(0.0, 200.0, 0.1)
    t = t[(t < 100.0) | (t > 130.0)]
    rate = 0.02 * np.sin(t / 10)
    heading = wrap(-0.2 * np.cos(t / 10))
    path = tmp_path / "outage.csv"
    np.savetxt(path, np.column_stack((t, rate, heading)), delimiter=",", header="t,gyro_z,heading_true", comments="")
    assert main(["evaluate", str(path), "--preset", "raw"]) == 0
    out = capsys.readouterr().out
    assert f"{path}: 1 gap(s) of the gyro or the reference skipped" in out


def test_the_recommended_method_is_named_so_in_what_the_pipeline_says() -> None:
    # `evaluate --preset recommended` warned of preset 'tuned', the preset it stands for, which the
    # user never named; it runs the same pipeline, bit for bit
    t = np.arange(0.0, 60.0, 0.01)
    rate = 0.2 * np.sin(t / 3) + 0.01
    log = gyrocore.Log("turns", t, rate, t_ref=t, heading_ref=np.cumsum(rate) * 0.01)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        named, _ = evaluate.Method.from_preset("recommended").run(log)
    said = " | ".join(str(w.message) for w in caught)
    assert "preset 'recommended' removes a static bias" in said and "'tuned'" not in said
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        base, _ = evaluate.Method.from_preset(gyrocore.recommended_preset()).run(log)
    assert np.array_equal(named.heading, base.heading)


def test_a_log_without_reference_is_told_how_to_give_it_one_from_a_file(tmp_path: Path) -> None:
    # it named only where a log's own reference would be (reference.csv, heading_true), not how to add one apart
    drive = gyrocore.sim.car_drive(duration=60.0, seed=2)
    src, truth = tmp_path / "bare.npz", tmp_path / "truth.csv"
    np.savez(src, t=drive.t, gyro_z=drive.rate_measured)
    np.savetxt(truth, np.column_stack([drive.t, drive.heading_true]), delimiter=",", header="t,heading", comments="")
    log = gyrocore.read_log(src)
    with pytest.raises(ValueError, match=r"one apart: dataclasses\.replace\(log, t_ref=\.\.\., heading_ref=\.\.\.\), e\.g\. "
                       r"the t and heading of gyrocore\.io\.read_reference_file\)$"):
        log.reference()
    ref = gyrocore.io.read_reference_file(truth)  # as told: it scores
    scored = evaluate.compare([dataclasses.replace(log, t_ref=ref["t"], heading_ref=ref["heading"])], ["raw"])
    assert scored[0].errors.e_psi_deg > 0

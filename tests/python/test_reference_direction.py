"""A reference that turns clockwise (a compass bearing), is timed in ms against a gyro in seconds or
runs on an offset clock was scored without a word (f110_ds3 with static_bias: E_psi 397, 110 and 91
deg against 3.65): heading_errors and the evaluation warn, never on the real logs as they are."""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import sim

from .conftest import DATA, gyrocore_cli, real_log_path

LOGS = sorted(p.name for p in (DATA / "real").iterdir()) if (DATA / "real").is_dir() else ["f110_ds3"]


def said(run: object, words: str) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run()  # type: ignore[operator]
    return [str(w.message) for w in caught if words in str(w.message)]


def clockwise(run: object) -> list[str]:
    return said(run, "turns clockwise")


def test_a_compass_bearing_as_reference_is_warned_about_and_its_conversion_scores_right() -> None:
    d = sim.car_drive(300.0, 100.0, seed=1, mix="city")
    r = gyrocore.process(d.t, d.rate_measured, "static_bias", bias_window=d.stationary)
    t_ref = d.t[::10]
    bearing = np.mod(90.0 - np.degrees(d.heading_true[::10]), 360.0)  # clockwise from north
    right = gyrocore.heading_errors(r.t, r.heading, t_ref, d.heading_true[::10])
    wrong = clockwise(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, np.radians(bearing)))
    assert len(wrong) == 1, wrong
    assert wrong[0].startswith("the reference heading turns clockwise where the estimate turns counter-clockwise: ")
    assert f"deg as given, {right.e_psi_deg:.4g} deg with the reference negated" in wrong[0]
    assert "heading = pi/2 - radians(bearing)" in wrong[0]
    # the conversion the warning gives: the right score, and nothing said
    converted = np.pi / 2 - np.radians(bearing)
    assert not clockwise(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, converted))
    assert gyrocore.heading_errors(r.t, r.heading, t_ref, converted).e_psi_deg == pytest.approx(right.e_psi_deg)


def test_a_clockwise_reference_is_warned_about_where_a_drift_makes_it_score_better() -> None:
    # raw integration of a 50-minute highway drive: the drift outweighs the turns, and the reference
    # negated scored 15.98 deg against 16.51: a lower E_psi is no sign of the right direction
    d = sim.car_drive(3000.0, 10.0, seed=2, mix="highway")
    r = gyrocore.process(d.t, d.rate_measured, "raw")
    right = gyrocore.heading_errors(r.t, r.heading, d.t, d.heading_true).e_psi_deg
    wrong = clockwise(lambda: gyrocore.heading_errors(r.t, r.heading, d.t, -d.heading_true))
    assert len(wrong) == 1 and f"as given, {right:.4g} deg with the reference negated" in wrong[0], wrong


@pytest.mark.parametrize("name", LOGS)
def test_the_real_logs_are_never_said_to_turn_clockwise_and_are_with_their_reference_negated(name: str) -> None:
    log = gyrocore.read_log(real_log_path(name))
    t_ref, h_ref = log.reference()
    for preset in ("raw", "static_bias", "recommended"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = log.process(preset)
        assert not clockwise(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, h_ref)), preset
        assert clockwise(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, -h_ref)), preset


def test_a_reference_timed_in_ms_is_warned_about() -> None:
    t = np.arange(0.0, 300.0, 0.01)
    h = 0.5 * np.sin(t / 20.0)
    t_ref = t[::10]
    assert not said(lambda: gyrocore.heading_errors(t, h, t_ref, h[::10]), "the reference spans")
    # from 0 in ms, it overlapped the heading's first 0.3 s: E_psi of 3 samples, without a word
    msg = said(lambda: gyrocore.heading_errors(t, h, t_ref * 1000.0, h[::10]), "the reference spans")
    assert msg == ["the reference spans 299900 s, 1e+03 times the heading's 299.99 s: only 3 of its 3000 samples "
                   "fall inside the heading's span and are scored; if the reference's times are in ms, us or ns, "
                   "convert them to seconds"]


def test_evaluate_warns_of_a_log_folders_clockwise_reference(tmp_path: Path) -> None:
    folder = tmp_path / "drive"
    shutil.copytree(real_log_path("f110_ds3"), folder)
    reference = folder / "reference.csv"
    reference.chmod(0o644)
    table = np.genfromtxt(reference, delimiter=",", names=True)
    table["heading"] = -table["heading"]
    np.savetxt(reference, table, delimiter=",", header=",".join(table.dtype.names or ()), comments="", fmt="%.9f")
    proc = gyrocore_cli("evaluate", folder, "--preset", "static_bias", code=0)
    assert f"gyrocore: warning: {folder}: the reference heading turns clockwise where the estimate turns " \
           "counter-clockwise: E_psi " in proc.stderr, proc.stderr


def offset(run: object) -> list[str]:
    return said(run, "its clock looks offset from the gyro's")


@pytest.mark.parametrize("name", LOGS)
def test_a_reference_on_an_offset_clock_is_warned_about_and_the_real_logs_as_they_are_never(name: str) -> None:
    # f110_ds3 with its reference 18 s late (GPS time against UTC) scored 91.3 deg against 3.65
    log = gyrocore.read_log(real_log_path(name))
    t_ref, h_ref = log.reference()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = log.process("static_bias")
    assert not offset(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, h_ref))
    msg = offset(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref + 2.0, h_ref))
    assert len(msg) == 1 and msg[0].startswith("the reference's turns follow the estimate's "), msg
    lag = float(msg[0].split("follow the estimate's ")[1].split(" s later")[0])
    assert lag == pytest.approx(2.0, abs=0.5)  # one 10 Hz step off on KITTI, 0.5 s on kitti_0042's turns


def test_an_offset_clock_names_the_score_with_the_times_put_right() -> None:
    d = sim.car_drive(600.0, 100.0, seed=0, mix="city")
    r = gyrocore.process(d.t, d.rate_measured, "static_bias", bias_window=d.stationary)
    right = gyrocore.heading_errors(r.t, r.heading, d.t, d.heading_true)
    msg = offset(lambda: gyrocore.heading_errors(r.t, r.heading, d.t + 18.0, d.heading_true))
    assert len(msg) == 1 and "follow the estimate's 18 s later" in msg[0], msg
    assert "deg with the reference's times less 18 s" in msg[0] and f"as given, {right.e_psi_deg:.4g} deg" in msg[0]

"""The file ``gyrocore simulate`` writes is a whole log. Its ``speed`` column [m/s] marks rests in
whole mode, as a log folder's odometry.csv does: the simulated drive (a rest, then a car at
10 Hz whose gentle curves the rate alone takes for rests) gets its bias from where the car stood.
Its ``heading_true`` column is the reference ``gyrocore evaluate`` scores against."""

from __future__ import annotations

import json
from functools import partial
from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import gyrocore_cli, real_log_path

pa_csv = pytest.importorskip("pyarrow.csv")
pq = pytest.importorskip("pyarrow.parquet")


run_cli = partial(gyrocore_cli, code=0)


@pytest.fixture(scope="module")
def drive(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("speed") / "drive.csv"
    run_cli("simulate", "--out", str(path))  # car, 600 s at 10 Hz, rest window 0..20 s, seed 0
    return path


def heading_error(written: Path, drive: Path) -> float:
    truth = pa_csv.read_csv(drive)["heading_true"].to_numpy()
    return float(np.degrees(np.abs(pa_csv.read_csv(written)["heading"].to_numpy() - truth).max()))


def test_process_takes_the_rests_from_a_files_speed_column(drive: Path, tmp_path: Path) -> None:
    with_speed = run_cli("process", str(drive), "--out", str(tmp_path / "s.csv"), "--preset", "static_bias")
    rate_only = run_cli("process", str(drive), "--out", str(tmp_path / "r.csv"), "--preset", "static_bias", "--no-speed")
    assert "(speed)" in with_speed.stdout and "(speed)" not in rate_only.stdout
    # the simulated rest window, 0..20 s, less the trim at its ends
    assert "rest [0.500, 19.500] s (speed)" in with_speed.stdout
    # the rate alone takes 1.1 s of a gentle curve for the rest: a bias 0.24 deg/s off
    assert heading_error(tmp_path / "s.csv", drive) < heading_error(tmp_path / "r.csv", drive) / 3
    table = pa_csv.read_csv(drive)
    t, rate, speed = (table[c].to_numpy() for c in ("t", "gyro_z", "speed"))
    expected = gyrocore.process(t, rate, "static_bias", speed=speed).heading
    written = pa_csv.read_csv(tmp_path / "s.csv")["heading"].to_numpy()
    np.testing.assert_allclose(written, expected, rtol=0, atol=1e-12)


def test_a_parquet_files_speed_column_counts_as_a_csvs(drive: Path, tmp_path: Path) -> None:
    parquet = tmp_path / "drive.parquet"
    pq.write_table(pa_csv.read_csv(drive), parquet)
    run_cli("process", str(drive), "--out", str(tmp_path / "c.csv"), "--preset", "recommended")
    out = run_cli("process", str(parquet), "--out", str(tmp_path / "p.csv"), "--preset", "recommended")
    assert "(speed)" in out.stdout
    np.testing.assert_array_equal(
        pa_csv.read_csv(tmp_path / "p.csv")["heading"].to_numpy(), pa_csv.read_csv(tmp_path / "c.csv")["heading"].to_numpy()
    )


def test_read_log_gives_the_speed_column_as_the_logs_speed(drive: Path, tmp_path: Path) -> None:
    log = gyrocore.read_log(drive)
    speed = pa_csv.read_csv(drive)["speed"].to_numpy()
    assert log.speed is not None and log.t_odometry is not None
    np.testing.assert_array_equal(log.speed, speed)
    np.testing.assert_array_equal(log.t_odometry, log.t)
    assert any(r.found_by == "speed" for r in log.process("static_bias").rests)
    without = tmp_path / "no_speed.csv"
    pa_csv.write_csv(pa_csv.read_csv(drive).drop_columns(["speed"]), without)
    assert gyrocore.read_log(without).speed is None


def test_evaluate_scores_a_simulated_file_against_its_truth(drive: Path, tmp_path: Path) -> None:
    proc = run_cli("evaluate", str(drive), "--preset", "raw", "--preset", "static_bias", "--json")
    rows = {r["preset"]: r for r in json.loads(proc.stdout)}
    table = pa_csv.read_csv(drive)
    t, rate, truth = (table[c].to_numpy() for c in ("t", "gyro_z", "heading_true"))
    for preset, heading in (
        ("raw", gyrocore.integrate(t, rate)),
        ("static_bias", gyrocore.process(t, rate, "static_bias", speed=table["speed"].to_numpy()).heading),
    ):
        expected = gyrocore.evaluate.heading_errors(t, heading, t, truth).e_psi_deg
        assert rows[preset]["e_psi_deg"] == pytest.approx(expected, rel=1e-12)
    assert rows["static_bias"]["e_psi_deg"] < rows["raw"]["e_psi_deg"] / 10


def test_evaluate_names_a_file_without_a_reference(drive: Path, tmp_path: Path) -> None:
    bare = tmp_path / "bare.csv"
    pa_csv.write_csv(pa_csv.read_csv(drive).drop_columns(["heading_true"]), bare)
    proc = gyrocore_cli("evaluate", bare, code=2)
    assert proc.stderr.startswith(f"gyrocore: error: {bare}: no reference heading to score against"), proc.stderr
    assert gyrocore.read_log(bare).heading_ref is None


def calibrate_json(path: Path) -> dict[str, object]:
    return dict(json.loads(run_cli("calibrate", str(path), "--json").stdout))


def test_calibrate_takes_the_first_rest_the_speed_or_the_rate_shows(drive: Path) -> None:
    # The simulated rest, 0..20 s (trimmed): the rate alone found 1.1 s of a curve at 27.7 s.
    out = calibrate_json(drive)
    assert out["rest_found_by"] == "speed"
    assert out["static_bias"]["window"] == [0.5, 19.5]  # type: ignore[index]
    # A real stop where the rate finds no rest (a MEMS twin of KITTI at 10 Hz): the bias whole
    # mode measures over the same stop.
    twin = real_log_path("kitti_2011_09_30_0027_mems")
    out = calibrate_json(twin)
    assert out["rest_found_by"] == "speed"
    log = gyrocore.read_log(twin)
    first = gyrocore.process(log.t, log.rate, "static_bias", speed=log.speed_on_gyro_times()).rests[0]
    start, end = out["static_bias"]["window"]  # type: ignore[index]
    # its first and last sample inside the stop (the stop's bounds lie between samples)
    assert first.start <= start < first.start + 0.11 and first.end - 0.11 < end <= first.end
    assert out["static_bias"]["bias"] == pytest.approx(first.bias, rel=1e-9)  # type: ignore[index]
    # The rate's rest comes first on f110_ds3 (its first stop is too short to measure): kept.
    out = calibrate_json(real_log_path("f110_ds3"))
    assert out["rest_found_by"] == "rate"


def test_an_infinite_speed_is_named_in_whole_mode_as_in_causal_mode(drive: Path, tmp_path: Path) -> None:
    # whole mode took an infinite speed for an unknown one; the causal tracker refuses it
    table = pa_csv.read_csv(drive)
    t, rate, speed = (table[c].to_numpy() for c in ("t", "gyro_z", "speed"))
    speed = speed.copy()
    speed[100] = np.inf
    with pytest.raises(ValueError, match=r"^speed\[100\] is inf: give a finite speed \[m/s\], or NaN where it is unknown"):
        gyrocore.process(t, rate, "static_bias", speed=speed)
    bad = tmp_path / "inf_speed.csv"
    pa_csv.write_csv(table.set_column(table.column_names.index("speed"), "speed", [speed]), bad)
    proc = gyrocore_cli("process", bad, "--out", tmp_path / "h.csv", code=2)
    assert f"{bad}: line 102, column speed: inf is not a finite speed [m/s]" in proc.stderr, proc.stderr
    assert not (tmp_path / "h.csv").exists()
    # --no-speed reads the file without the column
    run_cli("process", str(bad), "--out", str(tmp_path / "h.csv"), "--no-speed")

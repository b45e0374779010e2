"""The sample log (gyrocore.datasets): simulated, always the same, written as a log folder that every
command that reads a log accepts through the real command line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import datasets


def gyrocore_cli(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gyrocore.cli", *map(str, args)], cwd=cwd, capture_output=True,
                          text=True, timeout=300)


def ok(done: subprocess.CompletedProcess[str]) -> str:
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    return done.stdout


def test_the_sample_is_the_same_every_time_and_says_it_is_simulated() -> None:
    a, b = datasets.sample_drive(), datasets.sample_drive()
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.rate, b.rate)
    assert a.meta["simulated"] is True and "simulated" in a.meta["platform"]
    drive = gyrocore.sim.car_drive(**datasets.SAMPLE)
    np.testing.assert_array_equal(a.rate, drive.rate_measured)
    assert a.stationary == drive.stationary == (0.0, datasets.SAMPLE["rest"])
    assert a.t_ref is not None and len(a.t_ref) == len(a.t) // datasets.REFERENCE_EVERY


def test_the_written_folder_reads_back_as_the_sample_exactly(tmp_path: Path) -> None:
    folder = datasets.write_sample(tmp_path / "new" / "sample")
    assert sorted(p.name for p in folder.iterdir()) == sorted(datasets.FILES)
    log, sample = gyrocore.read_log(folder), datasets.sample_drive()
    for name in ("t", "rate", "t_ref", "heading_ref", "x_ref", "y_ref", "t_odometry", "speed"):
        np.testing.assert_array_equal(getattr(log, name), getattr(sample, name), err_msg=name)
    assert log.stationary == sample.stationary
    assert log.meta == json.loads(json.dumps(sample.meta))


def test_nothing_in_the_folder_is_overwritten(tmp_path: Path) -> None:
    (tmp_path / "reference.csv").write_text("mine\n")
    with pytest.raises(FileExistsError, match="reference.csv"):
        datasets.write_sample(tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["reference.csv"]
    assert (tmp_path / "reference.csv").read_text() == "mine\n"
    with pytest.raises(NotADirectoryError, match="not a folder"):
        datasets.write_sample(tmp_path / "reference.csv")


def test_an_interrupted_write_leaves_no_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    real = datasets.write_text_atomically

    def interrupted_at_the_third(path: Path, text: str) -> None:
        if path.name == datasets.FILES[2]:
            raise KeyboardInterrupt
        real(path, text)

    monkeypatch.setattr(datasets, "write_text_atomically", interrupted_at_the_third)
    with pytest.raises(KeyboardInterrupt):
        datasets.write_sample(tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_python_m_gyrocore_datasets_writes_the_folder_once(tmp_path: Path) -> None:
    run = [sys.executable, "-m", "gyrocore.datasets", "s"]
    first = subprocess.run(run, cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert first.returncode == 0, first.stderr
    assert "simulated" in first.stdout and "gyrocore process s --out heading.csv" in first.stdout
    again = subprocess.run(run, cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert again.returncode == 2 and "Traceback" not in again.stderr
    assert again.stderr.startswith("gyrocore.datasets: error: s: already holds gyro.csv")
    assert "replace them (--overwrite" in again.stderr
    (tmp_path / "s" / "gyro.csv").write_text("t,gyro_z\n")  # a sample spoiled by hand
    (tmp_path / "s" / "notes.txt").write_text("mine")
    replaced = subprocess.run([*run, "--overwrite"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert replaced.returncode == 0, replaced.stderr
    assert (tmp_path / "s" / "gyro.csv").read_text().count("\n") > 1000  # whole again
    assert (tmp_path / "s" / "notes.txt").read_text() == "mine"  # nothing else touched


@pytest.fixture(scope="module")
def sample(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return datasets.write_sample(tmp_path_factory.mktemp("datasets") / "sample")


def test_process_on_the_folder_gives_the_python_apis_heading(sample: Path, tmp_path: Path) -> None:
    ok(gyrocore_cli("process", sample, "--out", "heading.csv", cwd=tmp_path))
    out = np.genfromtxt(tmp_path / "heading.csv", delimiter=",", names=True)
    expected = datasets.sample_drive().process()  # the rest window of meta.json, as the command
    np.testing.assert_array_equal(out["t"], expected.t)
    np.testing.assert_array_equal(out["heading"], expected.heading)


def test_evaluate_scores_every_preset_on_the_sample(sample: Path, tmp_path: Path) -> None:
    rows = json.loads(ok(gyrocore_cli("evaluate", sample, "--json", cwd=tmp_path)))
    e_psi = {r["preset"]: r["e_psi_deg"] for r in rows}
    assert set(gyrocore.preset_names()) <= set(e_psi)
    assert e_psi["static_bias"] < e_psi["raw"] / 10  # the simulated gyro's large bias (crs03) is removed


def test_calibrate_finds_the_simulated_bias_and_scale(sample: Path, tmp_path: Path) -> None:
    result = json.loads(ok(gyrocore_cli("calibrate", sample, "--json", cwd=tmp_path)))
    drive = gyrocore.sim.car_drive(**datasets.SAMPLE)
    static = result["static_bias"]
    t0, t1 = static["window"]
    inside = (drive.t >= t0) & (drive.t <= t1)
    truth = float(np.mean(drive.bias + drive.drift[inside]))  # the gyro's bias over the window it used
    assert abs(static["bias"] - truth) < 4 * static["bias_stderr"]
    fit = result["heading_reference"]
    # within two points of scale error (its stderr is optimistic: calibration.heading_reference)
    assert abs(fit["scale_error"] - float(np.mean(drive.scale))) < 0.02


def test_calibrate_ends_the_rates_rest_where_the_speed_shows_motion(sample: Path, tmp_path: Path) -> None:
    # the rate alone ran the sample's 60 s rest on 5.5 s into the drive, which pulls off straight
    assert "(found from the rate, ended where the speed shows motion)" in ok(gyrocore_cli("calibrate", sample,
                                                                                          cwd=tmp_path))
    result = json.loads(ok(gyrocore_cli("calibrate", sample, "--json", cwd=tmp_path)))
    t0, t1 = result["static_bias"]["window"]
    log = datasets.sample_drive()
    speed = log.speed_on_gyro_times()
    assert speed is not None and result["rest_found_by"] == "rate"
    assert t0 == log.t[0] and 59.0 < t1 < 61.0
    assert np.all(speed[(log.t >= t0) & (log.t <= t1)] <= 0.05)


def test_allan_runs_on_the_samples_rest(sample: Path, tmp_path: Path) -> None:
    out = json.loads(ok(gyrocore_cli("allan", sample, "--window", "+0", "+60", "--json", cwd=tmp_path)))
    taus = out["allan"]["taus"]
    assert taus[0] == pytest.approx(0.01, rel=0.05) and 10 < taus[-1] < 60


def test_the_docs_sample_commands_run(tmp_path: Path) -> None:
    readme = (Path(__file__).resolve().parents[2] / "docs" / "index.md").read_text(encoding="utf-8")
    commands = [line.split() for line in readme.splitlines()
                if "sample_drive" in line and line.startswith(("gyrocore ", "python -m gyrocore.datasets"))]
    assert [c[:2] for c in commands] == [["python", "-m"], ["gyrocore", "process"], ["gyrocore", "evaluate"],
                                         ["gyrocore", "calibrate"], ["gyrocore", "allan"]]
    for command in commands:
        argv = command[2:] if command[0] == "python" else ["gyrocore.cli", *command[1:]]
        done = subprocess.run([sys.executable, "-m", *argv], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        ok(done)
    assert (tmp_path / "heading.csv").is_file()


def test_a_mistyped_option_is_named_with_the_one_meant(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # `python -m gyrocore.datasets s --overwite` said "unrecognized arguments: --overwite", where the
    # gyrocore command says which option a typo is likely of
    with pytest.raises(SystemExit) as stopped:
        datasets.main([str(tmp_path / "s"), "--overwite"])
    assert stopped.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == (
        "python -m gyrocore.datasets: error: unrecognized arguments: --overwite (did you mean '--overwrite'?)")
    assert list(tmp_path.iterdir()) == []

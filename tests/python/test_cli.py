"""The gyrocore command: demo (the README's main command), process, presets, error exits."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from gyrocore import InputWarning
from gyrocore.cli import main
from gyrocore.pipeline import recommended_preset

from .conftest import gyrocore_cli, real_log_path


def test_demo_prints_every_preset_and_writes_a_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plot = tmp_path / "demo.png"
    assert main(["demo", "--duration", "300", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    for preset in ("raw", "static_bias", "hong_park", "hdr", "combined"):
        assert f"\n{preset} " in out
    assert plot.read_bytes()[:4] == b"\x89PNG"


def test_demo_json_rows_beat_raw(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--duration", "300", "--drives", "3", "--plot", "", "--json"]) == 0
    rows = {r["preset"]: r for r in json.loads(capsys.readouterr().out)}
    assert rows["static_bias"]["e_psi_deg"] < rows["raw"]["e_psi_deg"]
    # The table's figures are the means of the per-drive ones.
    assert rows["hdr"]["e_psi_deg"] == pytest.approx(np.mean(rows["hdr"]["e_psi_deg_per_drive"]))
    assert len(rows["hdr"]["e_psi_deg_per_drive"]) == 3 and 0 <= rows["hdr"]["beats_static_bias"] <= 3
    with pytest.raises(SystemExit) as info:  # refused as the command line is read
        main(["demo", "--drives", "0"])
    assert info.value.code == 2


def test_process_writes_csv_with_one_row_per_sample(tmp_path: Path) -> None:
    log = real_log_path("f110_ds3")
    out = tmp_path / "heading.csv"
    assert main(["process", str(log), "--out", str(out), "--preset", "hdr"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert out.read_text().splitlines()[0] == "t,heading,rate,drift"
    assert data.shape == (2736, 4)
    assert not list(tmp_path.glob(".*tmp")), "no temporary file may be left behind"


def test_out_has_the_short_form_o(tmp_path: Path) -> None:
    # -o is --out for every command that writes one file or folder, as most command lines spell it
    drive, heading = tmp_path / "drive.csv", tmp_path / "heading.csv"
    assert main(["simulate", "-o", str(drive), "--duration", "30"]) == 0
    assert main(["process", str(drive), "-o", str(heading), "--preset", "raw"]) == 0
    assert heading.read_text().splitlines()[0] == "t,heading,rate,drift"
    assert len(heading.read_text().splitlines()) == len(drive.read_text().splitlines())


def test_process_refuses_to_write_into_the_input(tmp_path: Path) -> None:
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0\n1,0\n")
    before = src.read_bytes()
    assert main(["process", str(src), "--out", str(src)]) == 2
    assert src.read_bytes() == before


def test_user_errors_exit_2_with_one_line_and_no_traceback(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("t,gyro_z\n0,0\n0,1\n")
    proc = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "process", str(bad), "--out", str(tmp_path / "o.csv"), "--preset", "raw"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert proc.stderr.startswith("gyrocore: error: timestamps must strictly increase: t[1]")
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


def test_every_subcommand_help_shows_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    for cmd in ("demo", "process", "presets"):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        assert "example: gyrocore " + cmd in capsys.readouterr().out


def test_top_level_help_lists_an_example_for_every_subcommand(capsys: pytest.CaptureFixture[str]) -> None:
    from gyrocore.cli import COMMANDS

    with pytest.raises(SystemExit):
        main(["--help"])
    out = " ".join(capsys.readouterr().out.split())  # argparse wraps lines
    for command in COMMANDS:
        name = command.__name__.rsplit(".", 1)[-1]
        assert f"(example: gyrocore {name}" in out, name


def test_process_a_folder_of_logs_in_parallel_with_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data = real_log_path("f110_ds3").parent
    out = tmp_path / "headings"
    assert main(["process", str(data), "--out", str(out), "--format", "parquet", "--jobs", "2", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    # Counted from the folder itself, so that a log added to it is counted too.
    logs = sorted(p for p in data.iterdir() if (p / "gyro.csv").is_file())
    with_header = [len((p / "gyro.csv").read_text(encoding="utf-8").splitlines()) for p in logs]
    assert summary["failed"] == 0 and summary["rows_in"] == summary["rows_out"] == sum(with_header) - len(logs)
    assert sorted(p.name for p in out.iterdir()) == [f"{p.name}.parquet" for p in logs]
    comma = next(f for f in summary["files"] if f["input"].endswith("comma_seg40"))
    assert any("no rest window" in w for w in comma["warnings"])  # no rest in meta.json: said, not hidden


def test_process_batch_with_a_bad_file_exits_1_and_names_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "good.csv").write_text("t,gyro_z\n0,0\n1,0.5\n")
    (tmp_path / "bad.csv").write_text("t,gyro_z\n0,0\n1,half\n")
    assert main(["process", str(tmp_path / "*.csv"), "--out", str(tmp_path / "out"), "--preset", "raw"]) == 1
    out = capsys.readouterr().out
    assert f"FAILED {tmp_path / 'bad.csv'}: line 3, column 2 (gyro_z): 'half' is not a number" in out
    assert f"ok     {tmp_path / 'good.csv'}: 2 rows in, 2 out" in out
    assert "1 of 2 files processed, 1 failed" in out


def test_process_units_columns_and_compass_heading(tmp_path: Path) -> None:
    # a quarter turn counter-clockwise in 10 s, in ms and deg/s: from east (compass 90) to north (0)
    rows = "".join(f"{k * 100},{9.0}\n" for k in range(101))
    (tmp_path / "turn.csv").write_text("time_ms,wz\n" + rows)
    out = tmp_path / "h.csv"
    args = ["process", str(tmp_path / "turn.csv"), "--out", str(out), "--preset", "raw", "--time-col", "time_ms"]
    args += ["--rate-col", "wz", "--time-unit", "ms", "--rate-unit", "deg/s", "--heading", "compass"]
    assert main(args) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data[0, 0] == 0.0 and data[-1, 0] == 10.0
    assert data[0, 1] == pytest.approx(np.pi / 2) and data[-1, 1] == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(data[:, 2], -np.radians(9.0))


def test_process_malformed_file_exits_2_naming_file_line_and_column(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("t,gyro_z\n0,0\n1,0\n2,0;1\n")
    assert main(["process", str(bad), "--out", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert err == f"gyrocore: error: {bad}: line 4, column 2 (gyro_z): '0;1' is not a number\n"
    assert not (tmp_path / "o.csv").exists()


def test_process_warns_about_units_on_one_line_and_draws_no_bar_off_a_terminal(tmp_path: Path) -> None:
    log = real_log_path("f110_ds3")
    out = tmp_path / "h.csv"
    proc = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "process", str(log), "--out", str(out), "--rate-unit", "deg/s"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0
    lines = proc.stderr.splitlines()  # only the warning: no progress bar, no Python warning text
    assert len(lines) == 1 and lines[0].startswith(f"gyrocore: warning: {log}: rates look like rad/s, not deg/s")


def test_process_params_reach_the_pipeline(tmp_path: Path) -> None:
    src = tmp_path / "nan.csv"
    src.write_text("t,gyro_z\n0,0.1\n1,nan\n2,0.1\n")
    base = ["process", str(src), "--preset", "raw", "--out"]
    assert main([*base, str(tmp_path / "a.csv")]) == 2
    assert main([*base, str(tmp_path / "a.csv"), "--nonfinite", "hold"]) == 0
    held = np.loadtxt(tmp_path / "a.csv", delimiter=",", skiprows=1)
    assert held[-1, 1] == pytest.approx(0.2)
    assert main([*base, str(tmp_path / "b.csv"), "--param", "nonfinite=skip", "--param", "initial_heading_deg=90"]) == 0
    skipped = np.loadtxt(tmp_path / "b.csv", delimiter=",", skiprows=1)
    assert np.isnan(skipped[1, 2]) and skipped[0, 1] == pytest.approx(np.pi / 2)
    assert main([*base, str(tmp_path / "c.csv"), "--param", "hdr_c2"]) == 2


def test_allan_reads_the_simulated_arw_and_writes_plot_and_kalibr(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # A static gyro with white noise only (2.5 deg/sqrt(h), no bandwidth limit), 2000 s at 100 Hz.
    from gyrocore import sim

    spec = sim.GyroSpec(rate_hz=100.0, arw_deg_per_sqrt_h=2.5)
    t = np.arange(200_000) / spec.rate_hz
    rate = sim.measure(spec, t, np.zeros_like(t), seed=7).rate
    src = tmp_path / "static.csv"
    np.savetxt(src, np.column_stack([t, np.degrees(rate)]), delimiter=",", header="t,gyro_z", comments="")
    plot, kalibr = tmp_path / "adev.png", tmp_path / "imu.yaml"
    args = ["allan", str(src), "--rate-unit", "deg/s", "--json", "--plot", str(plot), "--kalibr", str(kalibr),
            "--rrw", "1e-5"]
    with warnings.catch_warnings():
        # A record at rest in deg/s: its small rates are no sign of a log in rad/s.
        warnings.simplefilter("error", InputWarning)
        assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["noise"]["arw"]["value_deg"] == pytest.approx(2.5, rel=0.05)
    assert plot.read_bytes()[:4] == b"\x89PNG"
    density = float(kalibr.read_text().split("gyroscope_noise_density:")[1].split()[0])
    assert density == pytest.approx(out["noise"]["arw"]["value"], rel=1e-5)
    # The noise parameters come from the Allan deviation only; another kind cannot give a YAML.
    assert main(["allan", str(src), "--rate-unit", "deg/s", "--kind", "modified", "--kalibr", str(tmp_path / "b.yaml")]) == 2
    assert "--kalibr needs --kind allan" in capsys.readouterr().err
    assert not (tmp_path / "b.yaml").exists()


def test_reproduce_prints_paper_beside_ours_and_writes_figures(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "figures"
    assert main(["reproduce", "hong-calibration", "fog-square-path", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "1.111" in printed and "return orientation error on the 4x4 m" in printed
    assert sorted(p.name for p in out.iterdir()) == ["fog_square_path.png", "hong_calibration.png"]
    assert main(["reproduce", "hong-calibration", "--no-figures", "--out", str(tmp_path / "none")]) == 0
    assert "1.111" in capsys.readouterr().out and not (tmp_path / "none").exists()
    # A misspelt name stops it before anything runs.
    assert main(["reproduce", "hong-calibration", "hong-tabel-1", "--out", str(tmp_path / "typo")]) == 2
    captured = capsys.readouterr()
    assert "unknown experiment 'hong-tabel-1'" in captured.err and "1.111" not in captured.out
    assert not (tmp_path / "typo").exists()
    # A name given twice runs once.
    assert main(["reproduce", "hong-calibration", "hong-calibration", "--no-figures"]) == 0
    twice = capsys.readouterr().out
    assert main(["reproduce", "hong-calibration", "--no-figures"]) == 0
    assert twice == capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("calibrate", "{log}", "--min-duration", "nan"), "argument --min-duration: must be a finite number > 0, got 'nan'"),
        (("calibrate", "{log}", "--max-rate-dps", "-1"), "argument --max-rate-dps: must be a finite number > 0, got '-1'"),
        (("allan", "{log}", "--kalibr", "{tmp}/k.yaml", "--rrw", "inf"),
         "argument --rrw: must be a finite number > 0, got 'inf'"),
        (("tune", "{log}", "--harm-limit", "-1"), "argument --harm-limit: must be a finite number >= 0, got '-1'"),
        (("tune", "{log}", "--bias-duration", "-1"), "argument --bias-duration: must be a finite number > 0, got '-1'"),
        (("tune", "{log}", "--max-evals", "0"), "argument --max-evals: must be an integer >= 1, got '0'"),
        (("tune", "{log}", "--set", "hdr_c2=nan"), "--set hdr_c2=nan: the value must be a finite number (SI)"),
        (("tune", "{log}", "--param", "hdr_c2=1:nan"), "--param hdr_c2=1:nan: bounds must read LOW:HIGH, finite"),
        (("tune", "--sim-drive", "mixed:nan"), "--sim-drive mixed:nan: need a road mix of"),
        (("simulate", "--out", "{tmp}/s.csv", "--duration", "nan"), "argument --duration: must be a finite number > 0, got 'nan'"),
        (("simulate", "--out", "{tmp}/s.csv", "--rate-hz", "-1"), "argument --rate-hz: must be a finite number > 0, got '-1'"),
        (("simulate", "--out", "{tmp}/s.csv", "--profile", "square", "--runs", "0"), "argument --runs: must be an integer >= 1"),
        (("simulate", "--out", "{tmp}/s.csv", "--seed", "1.5"), "argument --seed: must be an integer >= 0, got '1.5'"),
        (("process", "{log}", "--out", "{tmp}/h.csv", "--bias-duration", "0"),
         "argument --bias-duration: must be a finite number > 0, got '0'"),
        (("process", "{log}", "--out", "{tmp}/h.csv", "--bias-duration", "nan"),
         "argument --bias-duration: must be a finite number > 0, got 'nan'"),
        (("process", "{log}", "--out", "{tmp}/h.csv", "--bias-dps", "inf"), "argument --bias-dps: must be a finite number, got 'inf'"),
        (("process", "{log}", "--out", "{tmp}/h.csv", "--gap-limit", "-1"),
         "argument --gap-limit: must be a finite number > 0 (or inf), got '-1'"),
        (("process", "{log}", "--out", "{tmp}/h.csv", "--jobs", "0"), "argument --jobs: must be an integer >= 1, got '0'"),
        (("process", "{log}", "--out", "{tmp}/h.csv", "--chunk-rows", "-5"),
         "argument --chunk-rows: must be an integer >= 1, got '-5'"),
        (("evaluate", "{log}", "--bias-duration", "-1"), "argument --bias-duration: must be a finite number > 0, got '-1'"),
        (("evaluate", "{log}", "--bias-dps", "nan"), "argument --bias-dps: must be a finite number, got 'nan'"),
        (("demo", "--duration", "nan", "--plot", "{tmp}/d.png"), "argument --duration: must be a finite number > 0, got 'nan'"),
        (("demo", "--rate-hz", "0", "--plot", "{tmp}/d.png"), "argument --rate-hz: must be a finite number > 0, got '0'"),
        (("demo", "--duration", "10", "--plot", "{tmp}/d.png"), "--duration 10: a car drive begins with a 20 s rest"),
        # a log whose rest window cannot give its bias is not written
        (("simulate", "--out", "{tmp}/s.csv", "--rate-hz", "1e-6"),
         "rate_hz 1e-06 puts 1 sample(s) in the drive's rest window [0, 20] s, and its bias needs at least 3"),
    ],
)
def test_numeric_options_are_checked_before_any_work(tmp_path: Path, args: tuple[str, ...], message: str) -> None:
    log = real_log_path("broad_10")
    proc = gyrocore_cli(*(a.format(log=log, tmp=tmp_path) for a in args), code=2, timeout=60)
    assert message in proc.stderr.splitlines()[-1], proc.stderr
    assert not list(tmp_path.iterdir())


def test_a_reader_that_closes_the_pipe_ends_the_command_quietly(tmp_path: Path) -> None:
    # `gyrocore process ... | head -0`: the output is written in full; only its report has no
    # reader. That is no usage error (exit 2 with "[Errno 32] Broken pipe"): the shell's SIGPIPE
    # code, and nothing on stderr.
    out = tmp_path / "h.csv"
    proc = subprocess.Popen([sys.executable, "-m", "gyrocore.cli", "process", str(real_log_path("f110_ds3")),
                             "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()
    assert proc.wait(timeout=120) == 141
    assert proc.stderr.read() == b""
    assert len(out.read_text().splitlines()) == 2737  # a header and every sample


def test_process_of_one_file_that_fails_prints_the_warnings_before_its_error(tmp_path: Path) -> None:
    # float32 epoch times cannot increase: the warning that says why comes first, the error stays one line
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    path = tmp_path / "f32.parquet"
    t = (1.7e9 + np.arange(200) * 0.01).astype(np.float32)
    pq.write_table(pa.table({"t": pa.array(t, pa.float32()), "gyro_z": np.zeros(len(t))}), path)
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2)
    warned, error = proc.stderr.splitlines()
    assert warned.startswith(f"gyrocore: warning: {path}: the times are float32, which at their size resolve only 128 s")
    assert error.startswith("gyrocore: error: ") and "must strictly increase" in error
    assert not (tmp_path / "h.csv").exists()


def test_python_dash_m_gyrocore_is_the_command() -> None:
    proc = subprocess.run([sys.executable, "-m", "gyrocore", "presets", "--json"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["recommended"] == recommended_preset()


def test_every_option_of_every_command_says_what_it_does() -> None:
    # allan's --kind had no help: its --help listed the choices and nothing of what they are
    import argparse

    from gyrocore.cli import build_parser

    parser = build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    for name, command in commands.items():
        for action in command._actions:
            if action.option_strings:
                assert action.help, f"gyrocore {name} {action.option_strings[-1]} has no help"


@pytest.mark.parametrize(("command", "said"), [
    ("simulate", "columns t [s], gyro_z [rad/s], temperature [degC], rate_true [rad/s], heading_true [rad], x [m]"),
    ("process", "t [s], heading [rad], rate and drift [rad/s]"),
    ("process", "either in radians and continuous"),
    ("process", "any pipeline parameter, in SI units (gyrocore presets lists them, with their units)"),
])
def test_help_gives_the_units_of_what_a_command_writes_and_takes(command: str, said: str) -> None:
    # the column names alone left degrees or radians a guess
    assert said in " ".join(gyrocore_cli(command, "--help", code=0).stdout.split())


def test_presets_say_what_each_parameter_means_and_its_unit() -> None:
    # `--param` pointed to `gyrocore presets --json`, which gave values with neither meaning nor unit
    out = gyrocore_cli("presets", code=0).stdout
    assert "\nparameters (SI units; change one with --param NAME=VALUE;" in out
    assert "  hdr_increment " in out and "i_c [rad/s per step]" in out
    meanings = json.loads(gyrocore_cli("presets", "--json", code=0).stdout)["parameters"]
    assert meanings["threshold"].startswith("dead band") and "[rad/s]" in meanings["threshold"]


def test_version_is_printed() -> None:
    # what a bug report asks for first; it was "the following arguments are required: command"
    import gyrocore

    assert gyrocore_cli("--version", code=0).stdout == f"gyrocore {gyrocore.__version__}\n"

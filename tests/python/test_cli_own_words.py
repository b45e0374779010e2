"""What the command line says of its own arguments and of what it did: an empty name is refused
as one, a message states only what is so of the file, and a value is named as the user wrote it."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import gyrocore
from gyrocore.cli import main

from .conftest import real_log_path
from .test_batch import synthetic_csv
from .test_errors_named import run_cli

_BLANK = "no name (an empty shell variable?)"


@pytest.mark.parametrize("args, option", [
    (("process", "", "-o", "OUT/"), "IN"),
    (("process", "LOG", "-o", "h.csv", "--calibration", ""), "--calibration"),
    (("process", "LOG", "-o", "h.csv", "--fixes", ""), "--fixes"),
    (("process", "LOG", "-o", "h.csv", "--params", " "), "--params"),
    (("allan", ""), "input"),
    (("allan", "LOG", "--plot", ""), "--plot"),
    (("calibrate", "LOG", "--save", ""), "--save"),
    (("calibrate", "LOG", "--reference", ""), "--reference"),
    (("evaluate", "", "--preset", "raw"), "LOGDIR"),
    (("evaluate", "LOG", "--preset", "raw", "--plot-dir", ""), "--plot-dir"),
    (("simulate", "-o", ""), "-o/--out"),
    (("tune", "LOG", "-o", ""), "-o/--out"),
    (("reproduce", "-o", ""), "-o/--out"),
])
def test_an_empty_name_is_refused_for_every_path(tmp_path: Path, args: tuple[str, ...], option: str,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    # "" (an unset shell variable) was the current folder: every log in it processed, a plot written there
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    monkeypatch.chdir(tmp_path)
    proc = run_cli(*(str(log) if a == "LOG" else a for a in args))
    assert proc.returncode == 2
    blank = next(a for a in args if not a.strip())
    assert proc.stderr.splitlines()[-1].endswith(f"error: argument {option}: {blank!r}: {_BLANK}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]


def test_an_out_of_range_reading_is_named_as_the_file_has_it(tmp_path: Path) -> None:
    # whole mode subtracts a bias that varies over the log before the pipeline meets the reading:
    # it was named "rate[500] = 10000000.006588526", a value the file does not hold
    lines = (real_log_path("f110_ds3") / "gyro.csv").read_text().splitlines()
    lines[501] = f"{lines[501].split(',')[0]},1e7"
    src = tmp_path / "big.csv"
    src.write_text("\n".join(lines) + "\n")
    proc = run_cli("process", src, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: rate[500] = 10000000 rad/s is beyond +-1048576 rad/s: no gyro "
                                  f"reads that fast: check the unit and the column ({src}, line 502)")
    log = gyrocore.read_log(src)
    with pytest.raises(gyrocore.SampleError, match=r"^rate\[500\] = 10000000 rad/s is beyond"):
        gyrocore.process(log.t, log.rate)


@pytest.mark.parametrize("command", ["process", "evaluate"])
def test_a_bias_beyond_a_reading_is_named_as_given(tmp_path: Path, command: str) -> None:
    # it was "invalid parameter bias = 1.7453292519943295e306: must be finite and at most 2^20": a
    # name and a unit (rad/s) the user never gave
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    out = ("--out", tmp_path / "h.csv") if command == "process" else ("--preset", "raw")
    proc = run_cli(command, log, *out, "--bias-dps=-1e308")
    assert proc.returncode == 2
    assert proc.stderr.splitlines()[-1] == (f"gyrocore {command}: error: argument --bias-dps: must be at most "
                                            "6.007898e+07 deg/s in magnitude (2^20 rad/s, the limit of a reading), "
                                            "got '-1e308'")


def test_the_modified_deviation_refuses_a_non_overlapping_estimate(tmp_path: Path) -> None:
    # it ran overlapping without a word, although --help says modified is always overlapping
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli("allan", log, "--kind", "modified", "--non-overlapping")
    assert (proc.returncode, proc.stdout) == (2, "")
    assert proc.stderr == ("gyrocore: error: --non-overlapping: the modified Allan deviation is always overlapping; "
                           "leave the option out, or give --kind allan or hadamard for a non-overlapping estimate\n")


def test_a_method_given_twice_is_scored_once_with_a_warning() -> None:
    # as a log given twice: its rows were printed twice
    proc = run_cli("evaluate", real_log_path("f110_ds3"), "--preset", "raw", "--preset", "raw", "--json")
    assert proc.returncode == 0, proc.stderr
    assert [row["preset"] for row in json.loads(proc.stdout)] == ["raw"]
    assert ("gyrocore: warning: raw: given more than once as a method (--preset); each is used once (its rows would "
            "be printed twice)") in proc.stderr.splitlines()
    # recommended and the preset it stands for are one method too
    proc = run_cli("evaluate", real_log_path("f110_ds3"), "--preset", "recommended", "--preset",
                   gyrocore.recommended_preset(), "--json")
    assert proc.returncode == 0, proc.stderr
    assert [row["preset"] for row in json.loads(proc.stdout)] == ["recommended"]


@pytest.mark.parametrize("chunk_rows", ["1000", "65536"])
def test_a_gap_says_the_heading_change_made_up_across_it(tmp_path: Path, chunk_rows: str) -> None:
    # a gap is integrated across, as documented: "1 gap(s), the longest 1000 s" alone hid a turn
    # made up from the readings at its ends (52 rad across a parked car's 1000 s)
    lines = synthetic_csv(tmp_path / "log.csv", 3000).read_text().splitlines()
    shifted = [f"{float(x.split(',')[0]) + 1000:.6f},{x.split(',')[1]}" for x in lines[1001:]]
    src = tmp_path / "gap.csv"
    src.write_text("\n".join([*lines[:1001], *shifted]) + "\n")
    out = tmp_path / "h.csv"
    proc = run_cli("process", src, "--out", out, "--chunk-rows", chunk_rows)
    assert proc.returncode == 0, proc.stderr
    rows = [line.split(",") for line in out.read_text().splitlines()[1000:1002]]
    turn = abs(float(rows[1][1]) - float(rows[0][1]))
    assert turn > 1.0  # made up: the gap's ends read 0.3 rad/s or so
    said = (f"gyrocore: warning: {src}: 1 gap(s), the longest {float(rows[1][0]) - float(rows[0][0]):.6g} s, across "
            f"which the heading changes by {turn:.4f} rad ({math.degrees(turn):.2f} deg)")
    assert said in proc.stderr.splitlines()


@pytest.mark.parametrize("window", [("0", "5"), ("+0", "+5")])
@pytest.mark.parametrize("mode", [(), ("--causal",)])
def test_a_bias_window_beside_another_bias_source_is_refused(tmp_path: Path, window: tuple[str, str],
                                                             mode: tuple[str, ...]) -> None:
    # --bias-window dropped --param bias_duration=3 without a word, where the window as a --param
    # beside --bias-duration, and gyrocore.process with both, are refused
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    out = tmp_path / "h.csv"
    proc = run_cli("process", log, "--out", out, "--bias-window", *window, "--param", "bias_duration=3", *mode)
    assert proc.returncode == 2
    assert proc.stderr == ("gyrocore: error: give at most one of bias, bias_window, bias_duration (got bias_window, "
                           "bias_duration)\n")
    assert not out.exists()


@pytest.mark.parametrize(("option", "value"), [("--time-col", ""), ("--rate-col", " ")])
@pytest.mark.parametrize("command", ["process", "evaluate", "allan"])
def test_a_blank_column_name_is_refused(tmp_path: Path, option: str, value: str, command: str) -> None:
    # it read the default column without a word, where a blank --gyro-cols is refused
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    extra = {"process": ("--out", tmp_path / "h.csv"), "evaluate": ("--preset", "raw"), "allan": ()}[command]
    proc = run_cli(command, log, *extra, option, value)
    assert proc.returncode == 2
    name = option.removeprefix("--").replace("-", "_")
    assert proc.stderr.splitlines()[-1] == (f"gyrocore: error: {name} ({option}) {value!r}: no column name; give one, "
                                            "or leave the option out for the default column")
    with pytest.raises(ValueError, match=f"^{name} "):
        gyrocore.read_log(log, **{name: value})


def test_presets_json_is_json_that_strict_readers_take() -> None:
    # hdr_max_correction = inf (no bound) was written Infinity, which JSON has not (JSON.parse refused it)
    proc = run_cli("presets", "--json")
    assert proc.returncode == 0, proc.stderr

    def refuse(constant: str) -> None:
        raise AssertionError(f"{constant} is no JSON")

    presets = json.loads(proc.stdout, parse_constant=refuse)["presets"]
    assert presets["hdr"]["hdr_max_correction"] is None


@pytest.mark.parametrize("param, switch", [("hdr_increment_dps=0.05", "hdr"), ("rest_block=0.5", "track_rests")])
def test_a_switch_left_off_is_named_as_the_command_line_sets_it(tmp_path: Path, param: str, switch: str,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    # the core's words are the Python API's ("pass hdr=True"), which no option of the command takes
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    assert main(["process", str(log), "-o", str(tmp_path / "h.csv"), "--preset", "raw",
                 "--param", param]) == 2
    err = capsys.readouterr().err
    assert f"give --param {switch}=true to enable it" in err and "=True" not in err

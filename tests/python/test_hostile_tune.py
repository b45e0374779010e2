"""Hostile command lines for ``gyrocore tune``: one line naming the option and what to do, exit 2,
before the drives are built or the fit runs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import gyrocore
from gyrocore import tune

from .test_errors_named import run_cli


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # the car model said only "the rest (20.0 s) must be shorter than the drive (18.0 s)"
        (("--sim-drive", "city:0.3"), "--sim-drive city:0.3 (0.3 min at --time-scale 1): a car drive begins with a "
                                      "20 s rest (its static bias test); give a longer drive"),
        (("--sim-table", "II", "--time-scale", "0.01"), "--sim-table II (12.9 min at --time-scale 0.01): a car drive "
                                                        "begins with a 20 s rest"),
        (("--sim-drive", "city:30", "--time-scale", "0.015"), "the do-no-harm drives (20 min at --time-scale 0.015): a car "
                                                           "drive begins with a 20 s rest"),
        # it failed in the scoring: "reference: 1 sample(s); a heading error needs at least two ..."
        (("--sim-drive", "city:1", "--rate-hz", "0.01"),
         "rate_hz 0.01 puts 1 sample(s) in the drive's rest window [0, 20] s, and its bias needs at least 3"),
        # the last was taken without a word
        (("--sim-drive", "city:1", "--param", "hdr_c1=1:2", "--param", "hdr_c1=0.1:0.2"),
         "--param hdr_c1 is given twice; give it once"),
        (("--sim-drive", "city:1", "--set", "hdr_c2=1", "--set", "hdr_c2=2"), "--set hdr_c2 is given twice; give it once"),
        # it failed at the first evaluation, after "tuning", in the Python API's words (pass hdr=True)
        (("--sim-drive", "city:1", "--set", "hdr=false"),
         "hdr_increment is set but HDR is off; give --set hdr=true to enable it"),
        # it failed only after the whole fit
        (("--sim-drive", "city:1", "--leave-one-out"),
         "leave-one-out needs at least two training drives, got 1: it fits once without each drive"),
    ],
)
def test_a_tuning_that_cannot_run_is_refused_before_the_fit(tmp_path: Path, args: tuple[str, ...], message: str) -> None:
    out = tmp_path / "p.json"
    proc = run_cli("tune", *args, "--no-harm", "--out", out)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("gyrocore: error: ") and message in proc.stderr, proc.stderr
    assert "tuning hdr on" not in proc.stderr  # no fit began
    assert not out.exists()


def test_a_fixed_parameter_in_degrees_is_checked_and_saved_by_its_si_name(tmp_path: Path) -> None:
    # --set refused hdr_increment_dps, which fixed= takes; fixed= took it beside a fitted hdr_increment,
    # and every evaluation failed: "hdr_increment is given twice (as hdr_increment and in degrees)"
    with pytest.raises(ValueError, match="^hdr_increment cannot be both fitted and fixed: hdr's fit takes hdr_increment, "):
        tune.search_box("hdr", fixed={"hdr_increment_dps": 0.01})
    proc = run_cli("tune", "--sim-drive", "city:1", "--set", "hdr_incremnt=1", "--no-harm")
    assert proc.returncode == 2 and "unknown parameter(s) hdr_incremnt (did you mean 'hdr_increment'?)" in proc.stderr
    out = tmp_path / "p.json"
    proc = run_cli("tune", "--sim-drive", "city:1", "--set", "hdr_increment_dps=0.01", "--param", "hdr_c1",
                   "--no-harm", "--max-evals", "2", "--out", out)
    assert proc.returncode == 0, proc.stderr
    saved = tune.ParameterSet.read(out)  # what evaluate --params reads
    assert saved.overrides["hdr_increment"] == pytest.approx(math.radians(0.01)) and "hdr_increment_dps" not in saved.overrides
    assert json.loads(out.read_text())["units"]["hdr_increment"] == gyrocore.parameters()["hdr_increment"]


def test_a_name_the_parameter_file_cannot_hold_is_refused_before_the_fit(tmp_path: Path) -> None:
    # the set was written with the name " ", and evaluate --params refused the file: "name" must not be empty
    out = tmp_path / "p.json"
    proc = run_cli("tune", "--sim-drive", "city:1", "--name", " ", "--no-harm", "--out", out)
    assert proc.returncode == 2 and proc.stderr.endswith(
        "gyrocore: error: --name ' ': give the parameter set a name that is not blank (or leave --name out: "
        "hdr_tuned)\n"), proc.stderr
    assert not out.exists()
    with pytest.raises(ValueError, match='^"name" must be a string, got 5$'):
        tune.ParameterSet(5, "hdr", {})  # type: ignore[arg-type]


def test_a_name_with_a_line_break_is_refused_before_any_drive_is_built(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    # refused only by tune.tune, after the training, test and do-no-harm drives were built
    from gyrocore.cli import main

    def built(*args: object, **kwargs: object) -> list[tune.Case]:
        raise AssertionError("a drive was built")

    monkeypatch.setattr(tune, "simulated_cases", built)
    monkeypatch.setattr(tune, "harm_cases", built)
    assert main(["tune", "--sim-table", "II", "--name", "a\nb"]) == 2
    assert capsys.readouterr().err == ('gyrocore: error: --name: "name" must be one line of text without control '
                                       "characters, got 'a\\nb'\n")


def test_a_log_both_trained_on_and_tested_on_is_refused_before_the_fit() -> None:
    from .conftest import real_log_path

    log = str(real_log_path("f110_ds1"))
    proc = run_cli("tune", log, "--test", log, "--no-harm")
    assert proc.returncode == 2 and proc.stderr.endswith(
        f"gyrocore: error: {log}: both a training log and a --test log; a test log is scored with parameters "
        "fitted without it: give it as one of them\n"), proc.stderr


def test_a_log_given_twice_is_fitted_on_once() -> None:
    from .conftest import real_log_path

    log = str(real_log_path("f110_ds1"))
    proc = run_cli("tune", log, f"{log}/", "--no-harm", "--max-evals", "1", "--preset", "static_bias", "--param",
                   "threshold=1e-4:1e-2")
    assert proc.returncode == 0, proc.stderr
    assert f"{log}/: given more than once as a training log; each is used once" in proc.stderr
    assert "on 1 drive(s)" in proc.stderr


@pytest.mark.parametrize(
    ("options", "error", "message"),
    [
        # a misspelt start was ignored: the fit started from the preset's value
        ({"start": {"hdr_incremnt": 1e-4}}, ValueError,
         "unknown start value(s) hdr_incremnt (did you mean 'hdr_increment'?); the parameters fitted are hdr_increment"),
        ({"start": {"hdr_c1": 1.0}}, ValueError, "unknown start value(s) hdr_c1; the parameters fitted are hdr_increment"),
        # clipped into the bounds without a word
        ({"start": {"hdr_increment": 1.0}}, ValueError,
         "start['hdr_increment'] must be finite and >= 1e-05 and at most 0.01 (its search bounds), got 1.0"),
        ({"start": {"hdr_increment": "1e-4"}}, TypeError, "start['hdr_increment'] must be a number"),
        # '5' failed as "'<' not supported between instances of 'str' and 'int'"; 5.5 and True passed
        ({"max_evaluations": "5"}, ValueError, "max_evaluations must be a whole number >= 1, got '5'"),
        ({"max_evaluations": 5.5}, ValueError, "max_evaluations must be a whole number >= 1, got 5.5"),
        ({"max_evaluations": True}, ValueError, "max_evaluations must be a whole number >= 1, got True"),
        # numpy's "Seed must be between 0 and 2**32 - 1", from inside the optimiser
        ({"seed": -1}, ValueError, "seed must be an integer in [0, 2**32), got -1"),
        ({"seed": 2**32}, ValueError, "seed must be an integer in [0, 2**32)"),
        ({"harm_limit_deg": -1.0}, ValueError, "harm_limit_deg must be finite and >= 0 [deg], got -1.0"),
    ],
)
def test_tunes_arguments_are_refused_by_name_before_the_fit(options: dict[str, object], error: type, message: str) -> None:
    case = tune.Case.from_drive("d", gyrocore.sim.car_drive(duration=30.0, seed=2))
    with pytest.raises(error) as raised:
        tune.tune([case], preset="hdr", names=["hdr_increment"], bounds={"hdr_increment": (1e-5, 1e-2)},
                  **{"max_evaluations": 2, **options})  # type: ignore[arg-type]
    assert message in str(raised.value)


@pytest.mark.parametrize("where", ["cases", "harm"])
def test_a_single_case_is_refused_with_the_list_to_give(where: str) -> None:
    case = tune.Case.from_drive("d", gyrocore.sim.car_drive(duration=30.0, seed=2))
    given = {"cases": case, "harm": ()} if where == "cases" else {"cases": [case], "harm": case}
    with pytest.raises(TypeError, match=rf"^{where}: give a list of cases, not one Case \(\[case\]\)$"):
        tune.tune(given.pop("cases"), max_evaluations=2, **given)  # type: ignore[arg-type]

"""Ctrl-C during ``gyrocore tune``: nothing is written, and the best parameters found until then
are said (minutes of fitting were lost without a word)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from gyrocore import motion, tune
from gyrocore.cli import main

DRIVES = [motion.DriveSpec(f"short {mix}", 1.0, mix, "test") for mix in ("city", "suburbs")]
NAMES = ("hdr_increment", "hdr_turn_threshold")


def interrupt_at(monkeypatch: pytest.MonkeyPatch, stop: Any) -> None:
    """A Ctrl-C in the scoring of the drives, at the first call for which ``stop(calls, cases)`` holds."""
    score, calls = tune.score_cases, [0]

    def scoring(cases: Any, *args: Any) -> Any:
        calls[0] += 1
        if stop(calls[0], cases):
            raise KeyboardInterrupt
        return score(cases, *args)

    monkeypatch.setattr(tune, "score_cases", scoring)


def test_an_interrupted_fit_says_the_best_it_had_found(monkeypatch: pytest.MonkeyPatch) -> None:
    cases = tune.simulated_cases(DRIVES, rate_hz=10.0, first_seed=7)
    # the budget the interrupt left: the same evaluations, in the same order
    whole = tune.tune(cases, names=NAMES, max_evaluations=29)
    interrupt_at(monkeypatch, lambda calls, _: calls == 30)  # one call per evaluation (no harm drives)
    with pytest.raises(tune.TuningInterrupted) as info:
        tune.tune(cases, names=NAMES, max_evaluations=200)
    assert isinstance(info.value, KeyboardInterrupt)
    assert info.value.best == {n: whole.params.overrides[n] for n in NAMES}
    assert str(info.value).startswith(f"the fit had run 29 of 200 evaluations; the best found (objective "
                                      f"{whole.objective:.6g}, the start's {whole.start_objective:.6g}): hdr_increment=")
    assert f"hdr_turn_threshold={whole.params.overrides['hdr_turn_threshold']!r}" in str(info.value)


def test_an_interrupted_leave_one_out_keeps_the_fit_on_all_drives(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "t.json"
    args = ["tune", "--sim-drive", "city:1:2", "--param", "hdr_increment", "--no-harm", "--max-evals", "12", "--json"]
    assert main([*args, "--out", str(out)]) == 0
    fitted = tune.ParameterSet.read(out).overrides["hdr_increment"]
    capsys.readouterr()
    out.unlink()
    interrupt_at(monkeypatch, lambda _, cases: len(cases) == 1)  # a fold fits on one of the two drives
    assert main([*args, "--leave-one-out", "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert ("gyrocore: interrupted; no partial output was left; the fit on all 2 drive(s) had ended (12 evaluations, "
            "objective ") in err
    assert (f"the leave-one-out had scored 0 of 2 drive(s), and was fitting without city 1 min (sim city, seed 300); "
            f"the fit on all drives found: hdr_increment={fitted!r}\n") in err
    assert not out.exists()

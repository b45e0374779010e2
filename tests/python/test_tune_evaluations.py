"""What one evaluation of a tuning run does: the preset's parameters are built once per run, and
each evaluation lays its fitted values over them."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import gyrocore
import gyrocore.tune as tune_module
from gyrocore import tune, wholelog_bias_plan

from .conftest import real_log_path


def test_a_tuning_run_builds_the_presets_parameters_once_not_per_evaluation(monkeypatch: pytest.MonkeyPatch) -> None:
    # Whole-mode cases with rests (a given window, one found by the speed): their dead band and
    # HDR bound scale with the preset's parameters in every evaluation.
    cases = [tune.Case.from_log(gyrocore.read_log(real_log_path(name))) for name in ("f110_ds3", "f110_ds5")]
    assert all(c.plan is not None and c.plan.used for c in cases)
    tune.score_cases(cases, "tuned", {})  # the comparisons every score is set against, computed once per case
    calls: list[str] = []

    def counting(module: Any) -> Callable[..., dict[str, Any]]:
        build = module.preset_params

        def spy(preset: str = "hdr", **overrides: Any) -> dict[str, Any]:
            calls.append(preset)
            return build(preset, **overrides)  # type: ignore[no-any-return]

        return spy

    for module in (wholelog_bias_plan, tune_module):  # the plan's scaled dead band and HDR bound, and tune's
        monkeypatch.setattr(module, "preset_params", counting(module))
    runs = []
    for evaluations in (4, 16):
        calls.clear()
        result = tune.tune(cases, preset="tuned", names=("hdr_bound_sigmas",), max_evaluations=evaluations,
                           optimiser="nelder-mead", fixed={"hdr_c1": 0.2})
        runs.append((result.evaluations, len(calls)))
    (few, calls_few), (many, calls_many) = runs
    assert many > few  # the longer run evaluated more ...
    assert calls_many == calls_few  # ... and built the parameters no more often


@pytest.mark.parametrize("preset", ["hdr", "tuned", "combined", "hong_park", "recommended"])
def test_fitted_values_over_the_presets_parameters_are_what_the_core_builds(preset: str) -> None:
    # What each evaluation relies on (gyrocore.tune.tune's objective): the preset's parameters
    # with the fixed ones, the fitted values laid over them, equal the set the core builds.
    base = gyrocore.preset_params(preset)
    names = [n for n in tune.BOUNDS if n in base]
    rng = np.random.default_rng(7)
    for fixed in ({}, {"delag": False}, {"scale": 1.01, "c_cw": 0.99}):
        for _ in range(5):
            fitted = {n: float(np.exp(rng.uniform(*np.log(tune.BOUNDS[n])))) for n in names}
            laid = {**gyrocore.preset_params(preset, **fixed), **fitted}
            assert laid == gyrocore.preset_params(preset, **fixed, **fitted), (fixed, fitted)


def test_a_reference_whose_clock_jumps_is_refused_before_a_grid_over_the_jump() -> None:
    from gyrocore.io import Log
    from gyrocore.tune_cases import Case

    t = np.r_[np.arange(0.0, 10.0, 0.1), 1e9 + np.arange(0.0, 10.0, 0.1)]
    log = Log(name="jump", t=t, rate=np.zeros(len(t)), t_ref=t, heading_ref=np.zeros(len(t)))
    with pytest.raises(ValueError, match="log jump: the reference spans 1e\\+09 s.*a gap or a jump of its clock"):
        Case.from_reference_rate(log)

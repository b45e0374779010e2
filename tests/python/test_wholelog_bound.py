"""Whole mode's HDR bound from found rests: the bias's standard error over every sample, computed
only for a configuration that bounds HDR by it (``hdr_bound_sigmas``), and unchanged where one does."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np
import pytest

import gyrocore
from gyrocore import tune, wholelog
from gyrocore._smoother import SmoothedBias, smooth
from gyrocore.evaluate import Reference

from .conftest import real_log_path
from .test_wholelog import drive

#: Every preset, and presets given a bound or a dead band scaled by the rests.
CONFIGURATIONS = [(preset, {}) for preset in (*gyrocore.preset_names(), "recommended")] + [
    ("hdr", {"hdr_bound_sigmas": 2.0}),
    ("combined", {"hdr_bound_sigmas": 0.5, "threshold_sigmas": 1.0}),
    ("hong_park", {"threshold_sigmas": 2.0}),
    ("tuned", {"hdr_bound_sigmas": 3.0, "hdr_bound_walk": 1e-4}),
]

Log = tuple[np.ndarray, np.ndarray, np.ndarray | None]


def wandering() -> Log:
    """Three rests on a bias that wanders: smoothed between them."""
    t, rate, _ = drive(300.0, [(0.0, 12.0), (120.0, 135.0), (280.0, 295.0)], bias=lambda t: 0.01 + 2e-5 * (t - t[0]))
    return t, rate, None


def bias_free() -> Log:
    """Two rests that read no bias: the bias stays 0, the bound comes from them all the same."""
    t, rate, _ = drive(200.0, [(0.0, 12.0), (150.0, 165.0)], bias=0.0, seed=3)
    return t, rate, None


def real(name: str) -> Callable[[], Log]:
    """A real log without a given rest window: its stops found by its odometry's speed."""

    def read() -> Log:
        log = gyrocore.read_log(real_log_path(name))
        assert log.stationary is None
        return log.t, log.rate, log.speed_on_gyro_times()

    return read


LOGS = {"wandering": wandering, "bias_free": bias_free, "f110_ds5": real("f110_ds5"),
        "kitti_2011_09_30_0027_mems": real("kitti_2011_09_30_0027_mems")}


@pytest.fixture
def variance_calls(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The number of times in each evaluation of a smoothed bias's variance."""
    calls: list[int] = []
    variance_at = SmoothedBias.variance_at

    def spy(self: SmoothedBias, t: np.ndarray) -> np.ndarray:
        calls.append(np.size(t))
        return variance_at(self, t)

    monkeypatch.setattr(SmoothedBias, "variance_at", spy)
    return calls


@pytest.mark.parametrize("log", LOGS)
@pytest.mark.parametrize(("preset", "overrides"), CONFIGURATIONS)
def test_the_bound_is_computed_only_where_the_configuration_has_one(
    log: str, preset: str, overrides: dict[str, float], variance_calls: list[int]
) -> None:
    t, rate, speed = LOGS[log]()
    result = gyrocore.process(t, rate, preset, speed=speed, **overrides)
    si = dict(overrides)
    options = wholelog.Options.pop(si)
    sigmas = gyrocore.preset_params(preset, **si).get("hdr_bound_sigmas")
    assert variance_calls == ([] if sigmas is None else [len(t)])  # over every sample, once
    if sigmas is None:
        return
    # the bound as it always was: the rests smoothed with the bound's walk, their standard error's
    # root mean square over every sample, times hdr_bound_sigmas
    used = [r for r in result.rests if r.refused is None]
    bound = smooth([r.middle for r in used], [r.bias for r in used], [r.bias_std_error for r in used], options.hdr_bound_walk)
    plan = wholelog.plan_arrays(preset, si, t, rate, speed, options)
    assert plan.overrides["hdr_max_correction"] == sigmas * math.sqrt(float(np.mean(bound.variance_at(t))))
    expected = gyrocore.process(t, rate - plan.bias(t), preset, **plan.overrides)
    np.testing.assert_array_equal(result.heading.view(np.uint64), expected.heading.view(np.uint64))


def test_a_tuning_case_computes_the_bound_once_for_the_first_evaluation_with_one(variance_calls: list[int]) -> None:
    # A tuning run plans a log once for a preset without a bound, then lays each evaluation's
    # parameters over the preset's: the bound is there from the first evaluation that has one on.
    t, rate, true = drive(300.0, [(0.0, 12.0), (120.0, 135.0), (280.0, 295.0)], bias=lambda t: 0.01 + 2e-5 * (t - t[0]))
    evaluations = [("static_bias", {}), ("hdr", {}), ("hdr", {"hdr_bound_sigmas": 2.0}), ("tuned", {}),
                   ("tuned", {"hdr_bound_sigmas": 0.3, "hdr_increment": 1e-4})]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        whole = [gyrocore.process(t, rate, preset, **overrides).heading for preset, overrides in evaluations]
    variance_calls.clear()
    plan = wholelog.plan_arrays("static_bias", {}, t, rate, None, wholelog.Options())
    case = tune.Case("wandering", t, rate, Reference(t, gyrocore.integrate(t, true)), {"bias": 0.0}, plan=plan)
    for i, ((preset, overrides), heading) in enumerate(zip(evaluations, whole)):
        assert variance_calls == ([] if i <= 2 else [len(t)])  # none before the first bounded evaluation
        np.testing.assert_array_equal(case.heading(preset, overrides).heading.view(np.uint64), heading.view(np.uint64))
    assert variance_calls == [len(t)]  # and none after it


@pytest.mark.parametrize("preset", ["static_bias", "recommended"])
def test_a_streamed_plan_keeps_no_copy_of_the_log_times(preset: str) -> None:
    # gyrocore process plans a file (its rests found over the whole log), then streams it: the
    # bound is scaled by then, and the times would only hold 8 bytes a sample through that pass.
    t, rate, _ = wandering()
    chunks = lambda: iter([(t, rate)])  # noqa: E731 - the stream of one chunk
    plan = wholelog.plan_stream(preset, {}, chunks, lambda: (t, rate, None))
    assert plan.times is None and plan.used
    in_memory = wholelog.plan_arrays(preset, {}, t, rate, None, wholelog.Options())
    assert plan.overrides == in_memory.overrides and plan.source == in_memory.source


def test_a_rest_of_exactly_constant_readings_gives_a_bound_of_0_and_no_correction() -> None:
    """A rest whose readings do not change (a quantised gyro, a synthetic log) measures its bias
    with a standard error of 0: the bound hdr_bound_sigmas times it was 0, which the core refused
    ("invalid parameter hdr_max_correction = 0", a parameter nobody gave). HDR then corrects
    nothing, as the causal pipeline's measured bound of 0 does."""
    t = np.arange(0.0, 120.0, 0.01)
    rate = np.where(t < 20.0, 0.125, 0.125 + 0.2 * np.sin(0.1 * t))
    result = gyrocore.process(t, rate, "recommended", bias_window=(0.0, 19.0))
    assert "+- 0 deg/s" in result.bias_source
    static = gyrocore.process(t, rate, "static_bias", bias_window=(0.0, 19.0))
    np.testing.assert_array_equal(result.heading, static.heading)

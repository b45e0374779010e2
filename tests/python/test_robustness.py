"""Bad input and state: the input policy, unit checks, a panic that must not abort, and property
tests (hypothesis) of the streaming invariants."""

from __future__ import annotations

import math
import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrocore
from gyrocore import _gyrocore

from .conftest import gyrocore_cli


@st.composite
def logs(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    n = draw(st.integers(1, 300))
    steps = draw(st.lists(st.floats(1e-3, 0.5), min_size=n, max_size=n))
    rates = draw(st.lists(st.floats(-3.0, 3.0), min_size=n, max_size=n))
    return 1.6e9 + np.cumsum(steps), np.array(rates)


PRESETS = ["raw", "static_bias", "hong_park", "hdr", "combined"]


def _run(preset: str, t: np.ndarray, r: np.ndarray, **kw: object) -> gyrocore.HeadingResult:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        return gyrocore.Pipeline(preset, bias=0.01, **kw).process(t, r)


@settings(max_examples=40, deadline=None)
@given(logs(), st.lists(st.integers(0, 300), max_size=5), st.sampled_from(PRESETS))
def test_any_chunking_is_bit_identical(log: tuple[np.ndarray, np.ndarray], cuts: list[int], preset: str) -> None:
    t, r = log
    whole = _run(preset, t, r)
    p = gyrocore.Pipeline(preset, bias=0.01)
    bounds = sorted({min(c, len(t)) for c in cuts} | {0, len(t)})
    parts = [p.process(t[a:b], r[a:b]) for a, b in zip(bounds, bounds[1:])]
    joined = np.concatenate([x.heading for x in parts]) if parts else np.array([])
    assert joined.tobytes() == whole.heading.tobytes()
    assert len(whole.heading) == len(t)


@settings(max_examples=30, deadline=None)
@given(logs(), st.integers(0, 300), st.sampled_from(PRESETS))
def test_pickle_snapshot_continues_and_reset_equals_fresh(log: tuple[np.ndarray, np.ndarray], at: int, preset: str) -> None:
    t, r = log
    at = min(at, len(t))
    a = gyrocore.Pipeline(preset, bias=0.01)
    a.process(t[:at], r[:at])
    b = pickle.loads(pickle.dumps(a))
    assert a.process(t[at:], r[at:]).heading.tobytes() == b.process(t[at:], r[at:]).heading.tobytes()
    a.reset()
    assert a.process(t, r).heading.tobytes() == _run(preset, t, r).heading.tobytes()


@settings(max_examples=30, deadline=None)
@given(logs(), st.sampled_from(PRESETS), st.floats(-0.5, 0.5))
def test_finite_in_finite_out_and_a_known_bias_is_removed_exactly(
    log: tuple[np.ndarray, np.ndarray], preset: str, bias: float
) -> None:
    t, r = log
    out = _run(preset, t, r)
    assert all(np.isfinite(a).all() for a in (out.heading, out.rate, out.drift))
    if preset != "raw":
        flat = gyrocore.process(t, np.full_like(t, bias), preset, bias=bias)
        assert np.all(flat.heading == 0.0)
    still = gyrocore.process(t, np.zeros_like(t), preset, bias=0.0, initial_heading=0.7)
    assert np.all(still.heading == 0.7)


def test_nan_policies_and_their_warnings() -> None:
    t = np.arange(0.0, 20.0, 0.01)
    r = np.full_like(t, 0.1)
    r[[500, 501, 900]] = np.nan
    with pytest.raises(ValueError, match=r"rate\[500\] is NaN"):
        gyrocore.process(t, r, "hdr", bias=0.0)
    with pytest.warns(gyrocore.InputWarning, match=r"3 reading\(s\) not finite or beyond \+-1048576 replaced by the last usable reading \(first at index 500"):
        held = gyrocore.process(t, r, "raw", nonfinite="hold")
    assert held.heading[-1] == pytest.approx(0.1 * t[-1])
    p = gyrocore.Pipeline("raw", nonfinite="skip")
    with pytest.warns(gyrocore.InputWarning, match=r"3 reading\(s\) not finite or beyond \+-1048576 skipped"):
        skipped = p.process(t, r)
    assert np.isnan(skipped.rate[[500, 501, 900]]).all() and np.isfinite(skipped.heading).all()
    assert p.report["skipped"] == 3
    with pytest.raises(ValueError, match="unknown nonfinite 'drop'"):
        gyrocore.Pipeline("raw", nonfinite="drop")


@pytest.mark.parametrize("mode", ["causal", "whole"])
@pytest.mark.parametrize("nonfinite", ["hold", "skip"])
@pytest.mark.parametrize("value", [5e6, 1e300])
def test_a_reading_beyond_the_limit_is_repaired_with_a_warning(mode: str, nonfinite: str, value: float) -> None:
    t = np.arange(0.0, 60.0, 0.01)
    r = 0.01 + 0.1 * np.sin(t)
    r[7] = value
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gyrocore.process(t, r, "recommended", nonfinite=nonfinite, mode=mode, bias=0.0 if mode == "causal" else None)
    messages = [f"{w.category.__name__}: {w.message}" for w in caught]
    assert not [m for m in messages if not m.startswith("InputWarning")], messages  # no numpy overflow leaks
    assert any(
        f"1 reading(s) not finite or beyond +-1048576 {'replaced by the last usable reading' if nonfinite == 'hold' else 'skipped'} "
        f"(first at index 7, t = 0.07: rate {value} rad/s)" in m
        for m in messages
    ), messages


def test_a_temperature_beyond_the_limit_is_named_when_held() -> None:
    t = np.arange(0.0, 10.0, 0.01)
    temperature = np.full_like(t, 20.0)
    temperature[3] = -1e12
    with pytest.warns(gyrocore.InputWarning, match=r"first at index 3, t = 0.03: temperature -1000000000000.0 degC"):
        gyrocore.process(t, np.zeros_like(t), "hdr", bias=0.0, nonfinite="hold", mode="causal", temperature=temperature,
                         temp_slope=1e-4)


def test_the_limit_of_a_reading_is_the_cores() -> None:
    from gyrocore._checks import MAX_READING, usable

    edge = np.array([np.nextafter(MAX_READING, 0.0), MAX_READING])
    assert usable(edge).tolist() == [True, False]
    gyrocore.integrate([0.0, 1.0], [edge[0], -edge[0]])
    with pytest.raises(gyrocore.SampleError, match=r"rate\[1\] = 1048576 rad/s is beyond"):
        gyrocore.integrate([0.0, 1.0], [0.0, MAX_READING])


def test_gaps_are_reported_and_reset_on_request() -> None:
    t = np.r_[np.arange(0.0, 30.0, 0.1), np.arange(90.0, 120.0, 0.1)]
    r = np.full_like(t, 0.004)
    with pytest.warns(gyrocore.InputWarning, match=r"1 gap\(s\) longer than 2.0 s .*60.1"):
        bridged = gyrocore.process(t, r, "hdr", bias=0.0)
    with pytest.warns(gyrocore.InputWarning, match="gap_action='reset'"):
        reset = gyrocore.process(t, r, "hdr", bias=0.0, gap_action="reset")
    k = len(np.arange(0.0, 30.0, 0.1))
    assert bridged.drift[k] != 0.0 and reset.drift[k] == 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gyrocore.process(t, r, "hdr", bias=0.0, gap_limit=math.inf)


def test_rates_and_times_in_the_wrong_unit_warn() -> None:
    t = np.arange(0.0, 60.0, 0.01)
    deg = 30.0 * np.sin(t)
    with pytest.warns(gyrocore.InputWarning, match="rates look like deg/s"):
        gyrocore.process(t, deg, "raw")
    with pytest.warns(gyrocore.InputWarning, match="timestamps look like ms"):
        gyrocore.process(t * 1000.0, np.radians(deg), "raw", gap_limit=math.inf)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gyrocore.process(t, np.radians(deg), "raw")


def test_a_panic_in_rust_is_a_python_exception_not_an_abort() -> None:
    with pytest.raises(BaseException, match="forced panic") as info:
        _gyrocore._panic_for_test()
    assert type(info.value).__name__ == "PanicException"
    # The interpreter and the extension still work afterwards.
    assert gyrocore.integrate([0.0, 1.0], [1.0, 1.0])[-1] == 1.0


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"lowpass_tau": -1.0}, "lowpass_tau = -1: must be >= 0 and at most 2\\^40 s"),
        ({"hdr_c2": -0.5}, "hdr_c2 = -0.5: must be finite and > 0"),
        ({"threshold": -0.1}, "threshold = -0.1: must be finite and >= 0"),
        ({"hdr_interval": 0.0}, "hdr_interval = 0: must be > 0 and at most 2\\^40 s"),
        ({"gap_limit": -1.0}, "gap_limit = -1: must be >= 1e-12 s"),
        ({"scale": float("nan")}, "scale = NaN: must be > 0 and at most 2\\^20"),
        ({"bias_window": (5.0, 1.0)}, "bias_window.end = 1: must be finite and >= start"),
        # beyond the core's limits (issue: 1e308 was accepted, and a rate of 1e308 overflowed)
        ({"lowpass_tau": 1e308}, "lowpass_tau = 1e308: must be >= 0 and at most 2\\^40 s"),
        ({"scale": 2.0**21}, "scale = 2097152: must be > 0 and at most 2\\^20"),
        ({"bias": 1e7}, "bias = 10000000: must be finite and at most 2\\^20"),
    ],
)
def test_invalid_parameters_name_the_parameter_and_range(overrides: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        gyrocore.Pipeline("hdr", **({"bias": 0.0} | overrides if "bias_window" not in overrides else overrides))


def test_sample_errors_carry_the_index_counted_from_the_offset() -> None:
    t = np.arange(10.0)
    r = np.zeros(10)
    r[4] = np.inf
    p = gyrocore.Pipeline("raw")
    with pytest.raises(gyrocore.SampleError, match=r"rate\[1004\] is inf") as info:
        p.process(t, r, index_offset=1000)
    assert (info.value.index, info.value.what) == (1004, "rate")
    assert isinstance(info.value, ValueError)
    t[6] = t[5]
    with pytest.raises(gyrocore.SampleError) as info:
        p.process(t, np.zeros(10))
    assert (info.value.index, info.value.what) == (6, "t")


@pytest.mark.parametrize("n", [100, 101, 1000, 9999, 10_000, 50_000])
def test_the_rate_unit_check_agrees_with_the_99th_percentile(n: int) -> None:
    from gyrocore._checks import RATE_LIMIT, unit_problems

    rng = np.random.default_rng(n)
    t = np.arange(n) * 0.01
    for share in (0.0, 0.005, 0.009, 0.0101, 0.011, 0.02, 0.5):
        rate = rng.normal(0.0, 0.1, n)
        big = rng.choice(n, int(round(share * n)), replace=False)
        rate[big] = RATE_LIMIT * rng.uniform(1.01, 3.0, len(big))
        subset = rate[:: max(1, n // 10_000)]
        expected = np.percentile(np.abs(subset), 99) > RATE_LIMIT
        warned = any(p.startswith("rates look like deg/s") for p in unit_problems(t, rate))
        assert warned == expected, (n, share)


@pytest.mark.parametrize("mode", ["causal", "whole"])
def test_one_gap_does_not_make_the_timestamps_look_like_ms(mode: str) -> None:
    t = np.r_[np.arange(0.0, 30.0, 0.01), 1e5 + np.arange(0.0, 30.0, 0.01)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gyrocore.process(t, 0.01 * np.sin(t), "hdr", bias=0.0, mode=mode)
    messages = [str(w.message) for w in caught]
    assert not [m for m in messages if "look like" in m] and any("1 gap(s)" in m for m in messages), messages
    with pytest.warns(gyrocore.InputWarning, match="timestamps look like ms, us or ns, not seconds: the median interval is 10 "):
        gyrocore.process(t * 1000.0, np.zeros_like(t), "raw", gap_limit=math.inf, mode=mode)


def test_a_file_with_one_gap_is_read_in_seconds(tmp_path: Path) -> None:
    src = tmp_path / "gap.csv"
    t = np.r_[np.arange(0.0, 30.0, 0.01), 1e5 + np.arange(0.0, 30.0, 0.01)]
    np.savetxt(src, np.c_[t, np.zeros_like(t)], delimiter=",", header="t,gyro_z", comments="", fmt="%.10g")
    proc = gyrocore_cli("process", src, "--out", tmp_path / "h.csv", "--causal", "--bias-dps", "0", code=0)
    assert proc.stderr == (f"gyrocore: warning: {src}: 1 gap(s), the longest 99970 s, across which the heading "
                           "changes by 0.0000 rad (0.00 deg)\n")


@pytest.mark.parametrize("bad", ["t_repeat", "t_nan", "rate_nan", "rate_huge", "temperature_inf", "lengths", "none"])
def test_the_sample_check_says_what_a_pipeline_says(bad: str) -> None:
    # _checks.require_readings and the Python checks of Allan and calibration inputs name a bad
    # sample with the core's own check: the same error, word for word, as a pipeline's block
    t, rate, temperature = np.arange(20) * 0.01, np.full(20, 0.1), np.full(20, 25.0)
    if bad == "t_repeat":
        t[7] = t[6]
    elif bad == "t_nan":
        t[3] = np.nan
    elif bad == "rate_nan":
        rate[5] = np.nan
    elif bad == "rate_huge":
        rate[9] = 5e6
    elif bad == "temperature_inf":
        temperature[2] = np.inf
    elif bad == "lengths":
        rate = rate[:-1]
    errors = []
    for check in (lambda: _gyrocore.check_samples(t, rate, temperature),
                  lambda: _gyrocore.Pipeline("raw", {}).process(t, rate, temperature)):
        try:
            check()
            errors.append(None)
        except ValueError as e:
            errors.append((type(e), str(e), getattr(e, "index", None), getattr(e, "what", None)))
    assert errors[0] == errors[1]
    assert (errors[0] is None) == (bad == "none")


@pytest.mark.parametrize("fixes", [False, True])
def test_a_pickled_pipeline_edited_out_of_range_is_refused_with_its_reason(fixes: bool) -> None:
    """A damaged state (a low-pass time constant made negative) was refused in the words of the
    other shape of state ("invalid type: map, expected a tuple"), or taken (NaN headings after)."""
    p = gyrocore.Pipeline("hdr", bias=0.0)
    if fixes:
        p.process(np.arange(10) * 0.01, np.zeros(10), fixes=([0.05], [0.0], [0.01]))
    state = p.__getstate__()
    assert '"tau":0.75' in state["state"]
    edited = {**state, "state": state["state"].replace('"tau":0.75', '"tau":-1.0', 1)}
    with pytest.raises(ValueError, match=r"^not a gyrocore pipeline state: invalid parameter lowpass_tau = -1: must be >= 0"):
        gyrocore.Pipeline.__new__(gyrocore.Pipeline).__setstate__(edited)


@pytest.mark.parametrize("nonfinite", ["hold", "skip"])
def test_a_stream_says_its_repairs_once_and_counts_them_all(nonfinite: str) -> None:
    # nonfinite="hold" warned once per chunk: 100 chunks with a NaN each, 100 warnings
    t = np.arange(0.0, 100.0, 0.01)
    r = np.full_like(t, 0.1)
    r[5::100] = np.nan  # one in each chunk of 100
    p = gyrocore.Pipeline("raw", nonfinite=nonfinite)
    key = "held" if nonfinite == "hold" else "skipped"

    def repairs(pipeline: gyrocore.Pipeline, first: int, last: int) -> list[str]:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            for start in range(first, last, 100):
                pipeline.process(t[start:start + 100], r[start:start + 100])
        return [str(w.message) for w in caught if "not finite" in str(w.message)]

    said = repairs(p, 0, 5000)
    assert said == [f"1 reading(s) not finite or beyond +-1048576 "
                    f"{'replaced by the last usable reading' if nonfinite == 'hold' else 'skipped'} "
                    f"(first at index 5, t = 0.05: rate nan rad/s); said once per pipeline: its report['{key}'] "
                    "counts those of later chunks too"]
    resumed = pickle.loads(pickle.dumps(p))  # the same stream, elsewhere: said already
    assert repairs(resumed, 5000, 10_000) == [] and resumed.report[key] == 100
    assert repairs(p, 5000, 10_000) == [] and p.report[key] == 100
    p.reset()  # a new stream: said again
    assert len(repairs(p, 0, 1000)) == 1


def test_a_stream_says_its_gaps_once_and_counts_them_all() -> None:
    # a gap in each of 50 chunks warned 50 times
    t = np.concatenate([np.arange(0.0, 1.0, 0.01) + 10.0 * k for k in range(100)])
    r = np.full_like(t, 0.1)
    p = gyrocore.Pipeline("raw", bias=0.0, gap_limit=2.0)

    def gaps(first: int, last: int) -> list[str]:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            for start in range(first, last, 200):
                p.process(t[start:start + 200], r[start:start + 200])
        return [str(w.message) for w in caught if "gap(s) longer" in str(w.message)]

    said = gaps(0, 5000)
    assert said == ["1 gap(s) longer than 2.0 s (longest so far 9.01 s); gap_action='bridge'; said once per "
                    "pipeline: its report['gaps'] and report['longest_gap'] count those of later chunks too"]
    assert gaps(5000, 10_000) == [] and p.report["gaps"] == 99
    p.reset()
    assert len(gaps(0, 1000)) == 1

"""The public Python API once more under odd but valid use: a pipeline reset for a new log,
results compared with ``==``, a public module's names listed by ``dir()``, odd numbers for the
Allan helpers, an improvement over a perfect integration, a compass result with heading fixes,
the arguments of a fit, a score as JSON."""

from __future__ import annotations

import importlib
import json
import pickle
import warnings

import numpy as np
import pytest

import gyrocore

T = np.arange(0.0, 60.0, 0.01)
RATE = 0.002 + 0.1 * np.sin(T)


def _said(run: object) -> list[str]:
    """The warnings a call gives, each as text."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run()  # type: ignore[operator]
    return [str(w.message) for w in caught]


@pytest.mark.parametrize("pickled", [False, True])
def test_a_reset_pipeline_warns_of_a_new_log_as_a_new_pipeline_does(pickled: bool) -> None:
    """``reset()`` returns to the state before the first sample: the unit check and the unmeasured
    bias are said again for the next log (a new log in ms was processed without a word)."""
    p = gyrocore.Pipeline("static_bias")
    p.process(T, RATE)
    if pickled:
        p = pickle.loads(pickle.dumps(p))
    p.reset()
    fresh = _said(lambda: gyrocore.Pipeline("static_bias").process(T * 1000, RATE))
    assert any("timestamps look like ms" in w for w in fresh) and any("removes a static bias" in w for w in fresh)
    assert _said(lambda: p.process(T * 1000, RATE)) == fresh


def test_results_holding_arrays_compare_and_hash_by_identity() -> None:
    """``==`` of two results holding arrays (a ``HeadingResult``, ``Log``, ``AllanResult``, ...)
    raised numpy's ``truth value of an array ... is ambiguous``, and ``hash`` of one ``unhashable
    type``: they compare by identity, as ``Fixes`` and ``sim.Drive`` do."""
    log = gyrocore.Log("x", T, RATE)
    results = [
        (gyrocore.process(T, RATE, "raw"), gyrocore.process(T, RATE, "raw")),
        (log, gyrocore.Log("x", T.copy(), RATE)),
        (gyrocore.allan.deviation(RATE, 0.01), gyrocore.allan.deviation(RATE, 0.01)),
        (_track(), _track()),
    ]
    for a, b in results:
        assert a == a and a != b and len({a, b}) == 2, type(a).__name__


def _track() -> object:
    """A dead-reckoned track at 1 m/s along the heading of ``RATE``."""
    return gyrocore.deadreckon.dead_reckon(T, np.ones_like(T), T, np.cumsum(RATE) * 0.01)


#: The public modules (docs/api.md, ``gyrocore.__all__``).
PUBLIC_MODULES = ("allan", "batch", "calibration", "datasets", "deadband", "deadreckon", "evaluate", "fixes",
                  "integration", "io", "motion", "paper", "pipeline", "rests", "sim", "tune", "wholelog", "window")


@pytest.mark.parametrize("name", PUBLIC_MODULES)
def test_a_public_module_lists_its_all_not_what_it_imports(name: str) -> None:
    """docs/python.md: each public module's tab completion offers its ``__all__``, not the names it
    imports (``np``, ``Any``); gyrocore.sim, rests, deadband, deadreckon, integration, window and
    datasets had no ``__all__`` and offered ``np``, ``Any``, ``asdict``, ``TYPE_CHECKING``."""
    module = importlib.import_module(f"gyrocore.{name}")
    public = [n for n in dir(module) if not n.startswith("_")]
    assert public == sorted(module.__all__) and all(hasattr(module, n) for n in public)


@pytest.mark.parametrize(("m", "n"), [(0, 100), (-1, 100), (2.5, 100), (True, 100), (1, 0), (1, 100.0)])
def test_an_edf_of_no_whole_averaging_factor_or_sample_count_is_refused(m: object, n: object) -> None:
    """``allan.equivalent_dof`` with m = 0 raised a bare ZeroDivisionError; m = -1 gave 102 and
    m = 2.5 a number, as if such an average existed."""
    with pytest.raises(ValueError, match=r"^[mn] must be a whole number >= 1, got "):
        gyrocore.allan.equivalent_dof(0, 2, m, n, overlapping=True, modified=False)  # type: ignore[arg-type]


def test_a_method_no_better_than_a_perfect_integration_improves_by_one() -> None:
    """``evaluate.improvement`` of two errors of 0 (a gyro that reads the truth, or a log at rest)
    was infinite, as if the method had removed an error; ``compare`` printed ``improvement inf``."""
    perfect = gyrocore.heading_errors(T, RATE, T, RATE)
    off = gyrocore.heading_errors(T, RATE + 0.01, T, RATE)
    assert gyrocore.evaluate.improvement(perfect, perfect) == 1.0
    assert gyrocore.evaluate.improvement(off, perfect) == np.inf and gyrocore.evaluate.improvement(perfect, off) == 0.0
    still = gyrocore.Log("still", T, np.zeros_like(T), t_ref=T, heading_ref=np.zeros_like(T))
    assert [s.improvement for s in gyrocore.evaluate.compare([still], ["raw", "hdr"], bias_duration=10.0)] == [1.0, 1.0]


def test_a_compass_result_gives_its_fix_stage_clockwise_too() -> None:
    """``io.convert_heading(result, "compass")`` turned the heading, rate and drift clockwise but
    left the fix stage's heading (the ENU yaw) and bias (counter-clockwise) as they were:
    ``columns()`` then held a clockwise ``rate`` beside a counter-clockwise ``fusion_bias``."""
    drive = gyrocore.sim.car_drive(120.0, seed=2)
    every = np.arange(0, len(drive.t), 100)
    fixes = gyrocore.fixes.Fixes.of(drive.t[every], drive.heading_true[every], 0.02)
    enu = gyrocore.process(drive.t, drive.rate_measured, "hdr", fixes=fixes, mode="causal", bias_duration=10.0)
    compass = gyrocore.io.convert_heading(enu, "compass")
    assert compass.fusion is not None and enu.fusion is not None and enu.fusion.bias is not None
    assert np.array_equal(compass.fusion.heading, compass.heading)
    assert np.array_equal(compass.columns()["fusion_bias"], -enu.fusion.bias)
    assert np.array_equal(compass.columns()["fusion_scale"], enu.columns()["fusion_scale"])


@pytest.mark.parametrize(
    ("bounds", "error", "words"),
    [({"hdr_incremnt": (1e-5, 1e-3)}, ValueError, r"bounds given for hdr_incremnt \(did you mean 'hdr_increment'\?\), "
                                                  r"which is not fitted; the parameters fitted are hdr_increment, "),
     ({"threshold": (1e-5, 1e-3)}, ValueError, "bounds given for threshold, which is not fitted"),
     ({"hdr_increment": 5}, TypeError, r"bounds of hdr_increment must be two numbers \(low, high\), got 5"),
     ({"hdr_increment": ("a", "b")}, TypeError, r"bounds of hdr_increment must be two numbers \(low, high\)")],
)
def test_tune_refuses_bounds_it_would_not_use_or_cannot_read(bounds: dict, error: type, words: str) -> None:
    """``tune.search_box`` (and ``tune``, before any drive is scored) ignored bounds of a parameter
    not fitted (a typo: the fit searched the default range without a word), and failed on bounds
    that are no pair in Python's words (``cannot unpack non-iterable int object``)."""
    with pytest.raises(error, match=f"^{words}"):
        gyrocore.tune.search_box("hdr", bounds=bounds)
    assert gyrocore.tune.search_box("hdr", bounds={"hdr_increment": [1e-5, 1e-3]})["hdr_increment"] == (1e-5, 1e-3)


@pytest.mark.parametrize(
    ("options", "words"),
    [({"names": "hdr_c1"}, r"names='hdr_c1': give a sequence of parameter names, e.g. \('hdr_c1',\), not str"),
     ({"names": 5}, "names=5: give a sequence of parameter names"),
     ({"fixed": ["hdr_c1"]}, r"fixed must be a dict of parameter names and values, got \['hdr_c1'\]"),
     ({"bounds": "hdr_c1=1:2"}, "bounds must be a dict of parameter names and values"),
     ({"start": [("hdr_c1", 1.0)]}, "start must be a dict of parameter names and values")],
)
def test_tune_names_its_arguments_of_the_wrong_kind(options: dict, words: str) -> None:
    """``tune(names="hdr_c1")`` took the name's letters as names (``unknown parameter(s) h, d, r,
    _, c, 1``); ``fixed``, ``bounds`` or ``start`` as a list failed in ``dict()``'s words."""
    case = gyrocore.tune.Case("still", T, RATE, gyrocore.evaluate.Reference(T, np.zeros_like(T)), {"bias": 0.002})
    with pytest.raises(TypeError, match=f"^{words}"):
        gyrocore.tune.tune([case], **options)


@pytest.mark.parametrize("limit", [np.nan, -1.0, "0.5"])
def test_a_harm_limit_that_is_no_number_at_least_0_is_refused(limit: object) -> None:
    """``tune.harm_excess(scores, nan)`` was 0 (no harm, whatever the drives' scores)."""
    score = gyrocore.tune.CaseScore("drive", 5.0, 1.0, 2.0, 2.0, 2.0)
    assert gyrocore.tune.harm_excess([score], 0.5) == pytest.approx(2.5)
    with pytest.raises((ValueError, TypeError), match="^limit_deg must be "):
        gyrocore.tune.harm_excess([score], limit)  # type: ignore[arg-type]


def test_a_reference_refuses_a_switch_given_as_text() -> None:
    """``evaluate.Reference(..., time_weighted="no")`` scored time-weighted, and
    ``Reference.errors(..., absolute="no")`` compared the wrapped difference, as
    ``heading_errors`` (which checked its switches itself) refused."""
    reference = gyrocore.evaluate.Reference(T, np.sin(T / 10))
    with pytest.raises(TypeError, match="^time_weighted must be True or False, got 'no'$"):
        gyrocore.evaluate.Reference(T, np.sin(T / 10), time_weighted="no")  # type: ignore[arg-type]
    for score in (reference.errors, reference.e_psi, reference.compared):
        with pytest.raises(TypeError, match="^absolute must be True or False, got 'no'$"):
            score(T, np.sin(T / 10), absolute="no")  # type: ignore[operator]
    with pytest.raises(TypeError, match="^absolute must be True or False, got 1$"):
        gyrocore.heading_errors(T, RATE, T, RATE, absolute=1)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("options", "error", "words"),
    [({"noisy": "no"}, TypeError, "noisy must be True or False, got 'no'"),
     ({"per_mix": -1}, ValueError, "per_mix must be a whole number >= 1, got -1"),
     ({"per_mix": 2.5}, ValueError, "per_mix must be a whole number >= 1, got 2.5"),
     ({"mixes": "highway"}, TypeError, r"mixes='highway': give a sequence of road mixes, e.g. \('highway',\)"),
     ({"minutes": "1"}, TypeError, "minutes must be a number, got '1'")],
)
def test_harm_drives_refuse_options_of_the_wrong_kind(options: dict, error: type, words: str) -> None:
    """``tune.harm_cases(noisy="no")`` built the noisy gyro's drives, ``per_mix=-1`` none at all
    without a word; ``mixes="highway"`` failed on the mix ``'h'``, ``per_mix=2.5`` and
    ``minutes="1"`` in Python's words."""
    with pytest.raises(error, match=f"^{words}"):
        gyrocore.tune.harm_cases(**options)


@pytest.mark.parametrize(
    ("call", "words"),
    [(lambda: gyrocore.calibration.detect_rest(T, RATE, max_rte=0.1),
      r"detect_rest: unknown rest option\(s\) 'max_rte' \(did you mean 'max_rate'\?\); it takes block, "),
     (lambda: gyrocore.calibration.static_bias(T, RATE, (0.0, 20.0), blok=0.5),
      r"static_bias: unknown rest option\(s\) 'blok' \(did you mean 'block'\?\)"),
     (lambda: gyrocore.calibration.rotary_table(T, RATE, min_duration=1.0),
      r"rotary_table \(its pauses' min_duration is min_pause\): unknown rest option")],
)
def test_a_rest_option_misspelt_is_named_with_the_function_called(call: object, words: str) -> None:
    """A rest option passed on to ``rest_windows`` and misspelt failed as
    ``rest_windows_of_checked() got an unexpected keyword argument 'max_rte'`` (a function the
    caller never called), was ignored beside a given window, or in ``rotary_table`` said
    ``got multiple values for keyword argument 'min_duration'``."""
    with pytest.raises(TypeError, match=f"^{words}"):
        call()  # type: ignore[operator]


@pytest.mark.parametrize(
    ("options", "words"),
    [({"outages": (5.0, 10.0)}, r"an outage must be \(start, end\) in seconds, got 5.0"),
     ({"outages": (("a", "b"),)}, r"an outage must be \(start, end\) in seconds, got \('a', 'b'\)"),
     ({"outages": ((1.0, 2.0, 3.0),)}, r"an outage must be \(start, end\) in seconds"),
     ({"sigma_deg": "1"}, r"sigma_deg must be in \[5.73e-11, 60\] deg \(beyond, the noise wraps at \+-180 deg and is no longer the sigma\), got '1'"),
     ({"sigma_deg": True}, r"sigma_deg must be in \[5.73e-11, 60\] deg \(beyond, the noise wraps at \+-180 deg and is no longer the sigma\), got True")],
)
def test_simulated_fixes_name_an_outage_or_noise_of_the_wrong_kind(options: dict, words: str) -> None:
    """``sim.gnss_fixes(..., outages=(5, 10))`` (one outage given alone) failed as ``cannot unpack
    non-iterable int object``, text as numpy's ``UFuncTypeError``; ``sigma_deg="1"`` as ``'<=' not
    supported``, and ``sigma_deg=True`` was a noise of 1 deg."""
    with pytest.raises(ValueError, match=f"^{words}"):
        gyrocore.sim.gnss_fixes(T, np.zeros_like(T), seed=0, **options)
    assert len(gyrocore.sim.gnss_fixes(T, np.zeros_like(T), seed=0, outages=[[2.0, 5.0]])) == len(T[::100]) - 3


def test_a_score_as_a_dict_is_json_even_where_a_method_has_no_error() -> None:
    """``Score.as_dict()`` (a "JSON-ready dict") held ``improvement = inf`` where the method had
    no error at all: ``json.dumps`` wrote ``Infinity``, which strict parsers refuse (the command
    line mended it in its own copy)."""
    still = gyrocore.Log("still", T, np.full_like(T, 0.25), t_ref=T, heading_ref=np.zeros_like(T),
                         stationary=(0.0, 10.0))
    rows = gyrocore.evaluate.compare([still], ["raw", "static_bias"])
    assert rows[1].improvement == np.inf
    text = json.dumps([r.as_dict() for r in rows], allow_nan=False)
    assert [r["improvement"] for r in json.loads(text)] == [1.0, None]


def test_dead_reckoning_on_another_clock_names_both_spans() -> None:
    """``deadreckon.dead_reckon`` with odometry on another clock (epoch seconds beside a heading
    from boot) said only ``fewer than two odometry samples lie inside the heading's time span``,
    with neither span, where the reference's check names both."""
    with pytest.raises(ValueError, match=r"^the odometry has fewer than two samples inside the heading's time span: "
                                         r"the odometry runs from t = 1700000000.000 to 1700000059.990 s, the heading "
                                         r"from t = 0.000 to 59.990 s; give both on the same clock$"):
        gyrocore.deadreckon.dead_reckon(T + 1.7e9, np.ones_like(T), T, RATE)


def test_the_api_page_documents_every_public_module() -> None:
    """docs/api.md, "the reference of the gyrocore package", left out gyrocore.fixes, rests and
    wholelog, whose Fusion, Rest and bias_walk the guide pages send a reader to."""
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "api.md").read_text(encoding="utf-8")
    documented = {line[len("::: gyrocore."):].strip() for line in page.splitlines() if line.startswith("::: gyrocore.")}
    modules = {n for n in gyrocore.__all__ if isinstance(getattr(gyrocore, n), type(gyrocore))}
    assert modules == set(PUBLIC_MODULES)
    assert set(PUBLIC_MODULES) <= documented, sorted(set(PUBLIC_MODULES) - documented)

"""Scoring and dead reckoning under hostile arguments (``gyrocore.evaluate``,
``gyrocore.deadreckon``): NaN positions, switches given as text, a path where a list of logs is
asked for; each refused naming the argument, never a NaN score or an answer to another question."""

from __future__ import annotations

import json
import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import deadreckon, evaluate

from .conftest import gyrocore_cli, real_log_path

T = np.arange(0.0, 60.0, 0.01)
HEADING = 0.01 * T
SPEED = np.full_like(T, 10.0)
TRACK = deadreckon.dead_reckon(T, SPEED, T, np.zeros_like(T))


def _nan_at(values: np.ndarray, i: int) -> np.ndarray:
    out = values.astype(np.float64, copy=True)
    out[i] = np.nan
    return out


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: evaluate.find_gaps(_nan_at(T, 3)), ValueError, "t[3] is nan: samples must be finite"),
        (lambda: evaluate.find_gaps(T[::-1]), ValueError, "t must strictly increase: t[1] = 59.98"),
        (lambda: evaluate.find_gaps(T, gap_factor=np.nan), ValueError, "gap_factor must be finite and > 1, got nan"),
        (lambda: evaluate.heading_errors(T, HEADING, T, HEADING, gap_factor="x"), TypeError,
         "gap_factor must be a number, got 'x'"),
        (lambda: evaluate.heading_errors(T, HEADING, T, HEADING, time_weighted="no"), TypeError,
         "time_weighted must be True or False, got 'no'"),
        (lambda: evaluate.heading_errors(T, HEADING, T, HEADING, absolute=1), TypeError,
         "absolute must be True or False, got 1"),
        (lambda: evaluate.is_closed_path([0.0, 1.0, 0.0], [0.0, 1.0]), ValueError, "y has 2 samples but x has 3"),
        (lambda: evaluate.is_closed_path([0.0, np.nan, 0.0], [0.0, 1.0, 0.0]), ValueError, "x[1] is nan"),
        (lambda: evaluate.is_closed_path([0.0, 1.0, 0.0], [0.0, 1.0, 0.0], fraction=np.nan), ValueError,
         "fraction must be finite and >= 0, got nan"),
        (lambda: evaluate.return_orientation_error([], []), ValueError,
         "a return orientation error needs at least two samples, got 0"),
        (lambda: evaluate.return_orientation_error(T, HEADING, rotation=np.nan), ValueError,
         "rotation must be finite [rad], got nan"),
        (lambda: evaluate.return_orientation_error(T, HEADING, rotation="a"), TypeError,
         "rotation must be a number [rad], got 'a'"),
        (lambda: deadreckon.dead_reckon(T, SPEED, T, HEADING, position=(np.nan, 0.0)), ValueError,
         "position[0] must be finite [m], got nan"),
        (lambda: deadreckon.dead_reckon(T, SPEED, T, HEADING, position="ab"), TypeError,  # type: ignore[arg-type]
         "position must be (x, y) in metres, got 'ab'"),
        (lambda: deadreckon.dead_reckon(T, SPEED, T, HEADING, position=(1.0, 2.0, 3.0)), ValueError,  # type: ignore[arg-type]
         "position must be (x, y) in metres, two numbers, got (1.0, 2.0, 3.0)"),
        (lambda: deadreckon.dead_reckon(T, SPEED, T, HEADING, heading_offset=np.nan), ValueError,
         "heading_offset must be finite [rad], got nan"),
        (lambda: deadreckon.dead_reckon(T, SPEED, T, HEADING, heading_offset="0"), TypeError,  # type: ignore[arg-type]
         "heading_offset must be a number [rad], got '0'"),
        (lambda: deadreckon.position_errors(TRACK, T, _nan_at(SPEED * T, 5), np.zeros_like(T)), ValueError,
         "reference: x_ref[5] is nan"),
        (lambda: deadreckon.position_errors(TRACK, T, SPEED * T, _nan_at(np.zeros_like(T), 7)), ValueError,
         "reference: y_ref[7] is nan"),
        (lambda: deadreckon.return_position_error(TRACK, displacement=(0.0, np.inf)), ValueError,
         "displacement[1] must be finite [m], got inf"),
    ],
)
def test_a_hostile_argument_of_scoring_or_dead_reckoning_is_named(
    call: Callable[[], object], error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match="^" + re.escape(message)):
        call()


def test_valid_arguments_score_as_before() -> None:
    assert not evaluate.find_gaps(T).any() and evaluate.find_gaps(np.r_[T, 100.0])[-1]
    assert evaluate.is_closed_path([0.0, 1.0, 0.0], [0.0, 1.0, 0.0])
    assert evaluate.return_orientation_error(T, HEADING, rotation=0.0) == pytest.approx(HEADING[-1])
    shifted = deadreckon.dead_reckon(T, SPEED, T, np.zeros_like(T), position=np.array([1.0, 2.0]))
    assert shifted.x[-1] - TRACK.x[-1] == pytest.approx(1.0) and shifted.y[-1] - TRACK.y[-1] == pytest.approx(2.0)
    assert deadreckon.return_position_error(TRACK, displacement=(TRACK.x[-1], 0.0)) == pytest.approx(0.0, abs=1e-9)


def test_compare_names_a_bad_method_before_reading_a_log_and_takes_one_log_or_preset_alone() -> None:
    path = real_log_path("f110_ds1")
    missing = "/nonexistent/log"  # never read: each argument is checked first
    with pytest.raises(ValueError, match=r"^unknown preset 'hdrr'"):  # it was blamed on the first log
        evaluate.compare([missing], ["hdrr"])
    with pytest.raises(TypeError, match=r"^preset must be the name of a preset"):
        evaluate.compare([missing], [None])  # type: ignore[list-item]
    with pytest.raises(ValueError, match=r"^bias_duration must be finite and > 0 \[s\], got nan"):
        evaluate.compare([missing], ["hdr"], bias_duration=np.nan)
    with pytest.raises(TypeError, match=r"^bias_duration must be a number \[s\], got '5'"):
        evaluate.compare([missing], ["hdr"], bias_duration="5")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"^use_speed must be True or False, got 'no'"):
        evaluate.compare([missing], ["hdr"], use_speed="no")  # type: ignore[arg-type]
    # two different methods of one name gave two rows labelled alike, and the plot kept one of them
    tuned = evaluate.Method("hdr", "hdr", {"hdr_increment": 1e-4})
    with pytest.raises(ValueError, match=r"^two methods are named 'hdr' \(hdr \{\} and hdr \{'hdr_increment': "
                       r"0\.0001\}\): .* give each its own name"):
        evaluate.compare([missing], ["hdr", tuned])
    # one path was read as one-letter logs ("/: not a log folder"), one preset as one-letter presets
    (alone,) = evaluate.compare(str(path), "hdr")  # type: ignore[arg-type]
    (listed,) = evaluate.compare([path], ["hdr"])
    assert alone.errors == listed.errors and alone.method == listed.method
    twice = evaluate.compare([path], ["hdr", "hdr"])  # the same method twice is scored twice, as asked
    assert [r.method.name for r in twice] == ["hdr", "hdr"] and twice[0].errors == twice[1].errors


def test_a_wrapped_estimate_warns_that_it_is_scored_as_continuous() -> None:
    # a heading wrapped to +-pi scored 267 deg against its own continuous self without a word
    t = np.arange(0.0, 100.0, 0.1)
    wrapped = np.angle(np.exp(1j * 0.1 * t))
    with pytest.warns(gyrocore.InputWarning, match=r"the heading jumps by -6\.27\d* rad from 3\.14\d* at t = 31\.4"
                      r"\d* to .* it looks wrapped, .* give the continuous heading \(numpy\.unwrap\)"):
        evaluate.heading_errors(t, wrapped, t, 0.1 * t)
    with warnings.catch_warnings():  # a continuous heading, and an absolute comparison, are scored as they are
        warnings.simplefilter("error")
        assert evaluate.heading_errors(t, np.unwrap(wrapped), t, 0.1 * t).e_psi_deg < 1e-9
        assert evaluate.heading_errors(t, wrapped, t, 0.1 * t, absolute=True).e_psi_deg < 1e-9


def test_dead_reckoning_refuses_a_heading_in_degrees_and_warns_of_a_wrapped_one() -> None:
    # each wrap was interpolated across, and its step's chord shrank to nothing: 0.93 m of a 9.9 m drive
    t = np.arange(0.0, 10.0, 0.1)
    speed = np.ones_like(t)
    wrapped = np.angle(np.exp(1j * t))
    with pytest.raises(ValueError, match=r"^the heading looks like degrees, not radians: it jumps by -354\.27"):
        deadreckon.dead_reckon(t, speed, t, np.degrees(wrapped))
    with pytest.warns(gyrocore.InputWarning, match=r"^the heading jumps by -6\.1\d* rad .* it looks wrapped"):
        deadreckon.dead_reckon(t, speed, t, wrapped)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert deadreckon.dead_reckon(t, speed, t, np.unwrap(wrapped)).distance == pytest.approx(9.9, rel=1e-3)


def test_the_command_scores_a_log_given_twice_once() -> None:
    # a log named twice (or through a trailing slash) was scored and printed twice
    log = str(real_log_path("f110_ds1"))
    proc = gyrocore_cli("evaluate", log, f"{log}/", log, "--preset", "static_bias", "--json", code=0)
    assert [r["path"] for r in json.loads(proc.stdout)] == [log]
    assert f"{log}, {log}/: given more than once as a log to score; each is used once" in proc.stderr



@pytest.mark.parametrize(
    ("preset", "overrides", "error", "message"),
    [
        # taken: Method(name='xx', preset='xx', overrides={}), refused only inside a comparison
        ("xx", {}, ValueError, "unknown preset 'xx'; choose one of raw, "),
        (None, {}, TypeError, "preset must be the name of a preset (raw, "),
        ("hdr", {"hdr_incremnt": 1e-4}, ValueError, "unknown parameter 'hdr_incremnt' (did you mean 'hdr_increment'?)"),
        ("hdr", {"hdr_increment": -1.0}, ValueError, "invalid parameter hdr_increment = -1: must be finite, >= 0"),
    ],
)
def test_a_method_is_checked_when_it_is_built_in_pipelines_words(
    preset: object, overrides: dict[str, float], error: type, message: str
) -> None:
    with pytest.raises(error) as raised:
        evaluate.Method("m", preset, overrides)  # type: ignore[arg-type]
    with pytest.raises(error) as pipeline:
        gyrocore.Pipeline(preset, **overrides)  # type: ignore[arg-type]
    assert str(raised.value).startswith(message) and str(raised.value) == str(pipeline.value)
    if isinstance(preset, str) and not overrides:
        with pytest.raises(error, match=f"^{re.escape(message)}"):
            evaluate.Method.from_preset(preset)


def test_a_methods_overrides_that_are_no_mapping_are_refused_when_it_is_built() -> None:
    # "cannot convert dictionary update sequence element #0 to a sequence", from inside compare
    with pytest.raises(TypeError, match=re.escape(
            "method 'm': overrides must be a mapping of parameter names to values (as Pipeline(preset, **overrides) "
            "takes them), not list")):
        evaluate.Method("m", "hdr", [("hdr", True)])  # type: ignore[arg-type]


def test_evaluate_causal_takes_no_speed_as_process_does(tmp_path: Path) -> None:
    # evaluate --causal --no-speed ran the rest tracker with the speed of a log without a rest window
    # (E_psi 25.7 deg here), where process --causal --no-speed and Log.process(use_speed=False) do not
    drive = tmp_path / "drive.csv"
    gyrocore_cli("simulate", "--duration", "600", "--mix", "city", "--out", drive, code=0)
    log = gyrocore.read_log(drive)
    for use_speed in (True, False):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gyrocore.InputWarning)
            result = log.process("tracked", mode="causal", use_speed=use_speed)
        expected = gyrocore.heading_errors(result.t, result.heading, *log.reference()).e_psi_deg
        proc = gyrocore_cli("evaluate", drive, "--preset", "tracked", "--causal", *["--no-speed"] * (not use_speed),
                            "--json", code=0)
        assert json.loads(proc.stdout)[0]["e_psi_deg"] == pytest.approx(expected, rel=1e-12)


def test_evaluate_bias_duration_replaces_a_calibrations_bias(tmp_path: Path) -> None:
    # --help: a calibration's bias is used "unless another bias option is given"; evaluate kept it
    # beside --bias-duration ("given by the method"), where process takes the duration
    drive, saved = tmp_path / "drive.csv", tmp_path / "cal.json"
    gyrocore_cli("simulate", "--duration", "60", "--out", drive, code=0)
    gyrocore_cli("calibrate", drive, "--save", saved, code=0)
    proc = gyrocore_cli("evaluate", drive, "--preset", "static_bias", "--calibration", saved, "--bias-duration", "5",
                        "--json", code=0)
    assert json.loads(proc.stdout)[0]["bias_source"].startswith("first 5 s: rest [0.000, 5.000] s (given)")


@pytest.mark.parametrize("param", ["bias_duration=3", "bias_window=0,5", "bias_dps=1"])
def test_evaluate_refuses_bias_duration_beside_a_bias_param(tmp_path: Path, param: str) -> None:
    # the method's own bias was used and --bias-duration dropped without a word, where process refuses both
    drive = tmp_path / "drive.csv"
    gyrocore_cli("simulate", "--duration", "60", "--out", drive, code=0)
    proc = gyrocore_cli("evaluate", drive, "--preset", "static_bias", "--bias-duration", "5", "--param", param, code=2)
    assert proc.stderr == (f"gyrocore: error: --bias-duration and --param {param.split('=')[0]} both give the static "
                           "bias: give one of them\n")

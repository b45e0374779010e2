"""Errors name the parameter, file or log, and the fix: parameters of the wrong type, a missing
output folder, a log in evaluate, Allan and calibration inputs, corrupt calibration files."""

from __future__ import annotations

import json
import re
import warnings
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan
from gyrocore.calibration import Calibration, static_bias
from gyrocore.evaluate import compare

from .conftest import gyrocore_cli

T = np.arange(0, 10, 0.01)
RATE = np.random.default_rng(0).normal(0.0, 0.01, len(T))


run_cli = partial(gyrocore_cli, timeout=120)


def test_a_window_may_be_a_list_or_an_array() -> None:
    expected = gyrocore.process(T, RATE, "hdr", bias_window=(0.0, 5.0))
    for window in ([0, 5], np.array([0.0, 5.0])):
        assert np.array_equal(gyrocore.process(T, RATE, "hdr", bias_window=window).heading, expected.heading)


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"hdr_c2": "abc"}, "invalid parameter hdr_c2 = 'abc': must be real number, not str; hdr_c2 is repetition"),
        ({"hdr": 1}, "invalid parameter hdr = 1: a switch takes True or False (on the command line true or false), "
                     "not int; hdr is run Heuristic"),
        ({"bias_window": (0, "a")}, "invalid parameter bias_window = (0, 'a'): must be real number, not str"),
    ],
)
def test_a_parameter_of_the_wrong_type_is_named(overrides: dict[str, object], message: str) -> None:
    with pytest.raises(TypeError) as e:
        gyrocore.Pipeline("hdr", bias=0.0, **overrides)
    assert str(e.value).startswith(message)
    with pytest.raises(TypeError, match="^" + re.escape(message.split(":")[0])):
        gyrocore.preset_params("hdr", **overrides)


def test_the_command_line_names_a_parameter_of_the_wrong_type(tmp_path: Path) -> None:
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0\n0.01,0\n")
    proc = run_cli("process", src, "--out", tmp_path / "h.csv", "--param", "hdr=1")
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1
    assert proc.stderr.startswith("gyrocore: error: invalid parameter hdr = 1: ")


def test_a_missing_output_folder_is_named_not_the_hidden_file(tmp_path: Path) -> None:
    src = tmp_path / "in.csv"
    src.write_text("t,gyro_z\n0,0\n0.01,0\n")
    out = tmp_path / "missing" / "h.csv"
    proc = run_cli("process", src, "--out", out, "--preset", "raw")
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {out}: the folder {out.parent} does not exist; create it or write elsewhere\n"


def test_evaluate_names_the_log_of_an_error() -> None:
    rate = RATE.copy()
    rate[3] = np.nan
    log = gyrocore.Log(name="drive", t=T, rate=rate, t_ref=T, heading_ref=np.zeros_like(T))
    with pytest.raises(ValueError, match=r"^log drive: rate\[3\] is NaN"):
        compare([log], ["raw"])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: allan.deviation(RATE, 0.01, taus=[np.nan]), r"taus\[0\] = nan: averaging times must be finite"),
        (lambda: allan.deviation_from_timestamps(T, RATE, dt=1e-9), r"dt = 1e-09 s would resample the 1000 samples"),
        (lambda: allan.deviation(RATE, 1e308), r"dt = 1e\+308 s: the angle, the sum of rate x dt, could overflow"),
        (lambda: static_bias(T, RATE, (5.0,)), r"the rest window must be \(start, end\) in seconds, got \(5\.0,\)"),
        (lambda: static_bias(T, RATE, (5.0, 1.0)), r"the rest window \(5\.0, 1\.0\) must be finite with end > start"),
    ],
)
def test_allan_and_calibration_inputs_are_named(call: Callable[[], object], message: str) -> None:
    with pytest.raises(ValueError, match="^" + message):
        call()


@pytest.mark.parametrize("field", ["bias", "method"])
def test_a_calibration_file_without_its_bias_or_method_is_named(tmp_path: Path, field: str) -> None:
    """Without its bias it was a calibration of bias 0, applied without a word; without its method
    Python's "Calibration.__init__() missing 1 required positional argument: 'method'"."""
    path = tmp_path / "cal.json"
    Calibration(method="static_bias", bias=0.01, window=(0.0, 1.0), samples=3).save(path)
    data = json.loads(path.read_text())
    del data["calibration"][field]
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=f"^{path}: not a valid calibration: missing calibration field\\(s\\): {field}$"):
        Calibration.load(path)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"bias": "abc"}, "bias must be a number, got 'abc'"),
        ({"bias": True}, "bias must be a number, got True"),
        ({"samples": 2.5}, "samples must be a whole number, got 2.5"),
        ({"window": [1]}, r"window must be \(start, end\) in seconds, got \[1\]"),
        ({"bias_table": "x"}, "bias_table must be an object of the lists temperatures, biases, stderr, counts, got 'x'"),
        # each was taken without a word, or failed later: 1/0 in s_bar, numpy's "fp and xp are not
        # of the same length", the bias of 30 degC read at 20 degC, notes of a letter each
        ({"method": "static-bias"}, "unknown calibration method 'static-bias' \\(did you mean 'static_bias'\\?\\); "
                                    "choose one of static_bias, rate_reference, heading_reference, rotary_table"),
        ({"bias": float("nan")}, "bias must be finite, got nan"),
        # null lost the bias without a word (bias 0), or was Python's "'>' not supported between
        # instances of 'NoneType' and 'int'"
        ({"bias": None}, "bias must be a number, got null"),
        ({"c_cw": None}, "c_cw must be a number, got null"),
        ({"scale_error": None}, "scale_error must be a number, got null"),
        ({"scale_error": -1}, r"scale_error must be > -1 \(s_bar = 1/\(1 \+ s\) > 0\), got -1"),
        ({"c_cw": 0}, "c_cw must be > 0, got 0"),
        ({"samples": -5}, "samples must be >= 0, got -5"),
        ({"temp_slope": 0.001}, "temp_slope and temp_offset make one temperature model: give both or neither"),
        ({"notes": "checked"}, "notes must be a list of text, got 'checked'"),
        ({"bias_table": {"temperatures": [30, 10, 20], "biases": [1, 2, 3], "stderr": [0, 0, 0], "counts": [5, 5, 5]}},
         "bias table temperatures\\[1\\] = 10 degC does not come after 30 degC: a table's temperatures must strictly increase"),
        ({"bias_table": {"temperatures": [10, 20], "biases": [1], "stderr": [0], "counts": [5]}},
         "a bias table needs one temperature, bias, stderr and count per entry and at least one entry, got 2 "
         "temperatures, 1 biases, 1 stderr, 1 counts"),
    ],
)
def test_a_corrupt_calibration_file_is_named(tmp_path: Path, change: dict[str, object], message: str) -> None:
    path = tmp_path / "cal.json"
    Calibration(method="static_bias", bias=0.01, window=(0.0, 1.0), samples=3).save(path)
    data = json.loads(path.read_text())
    data["calibration"].update(change)
    path.write_text(json.dumps(data))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=f"^{path}: not a valid calibration: {message}$"):
            Calibration.load(path)

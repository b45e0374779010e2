"""Inputs found by adversarial testing of the API and the command line: each was a bare Python
error, a misleading message or a silently wrong result, and is now refused in words that name
the argument and the problem."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan

from .conftest import gyrocore_cli

T = np.arange(0.0, 30.0, 0.01)
RATE = 0.01 + 0.1 * np.sin(T)
HUGE = 10**400  # an int no float64 holds: float() raised a bare OverflowError


@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize(
    ("key", "value"),
    [("bias_duration", HUGE), ("bias", -HUGE), ("hdr_c1", HUGE), ("bias_window", (0, HUGE)), ("bias_dps", HUGE),
     ("hdr_c1", 10**5000)],  # beyond the 4300 digits Python shows
    ids=["bias_duration", "bias", "hdr_c1", "bias_window", "bias_dps", "hdr_c1-5000-digits"],
)
def test_an_int_beyond_float64_as_a_parameter_is_named(mode: str, key: str, value: object) -> None:
    """It was ``OverflowError: int too large to convert to float``, naming no parameter."""
    with pytest.raises(ValueError, match=rf"^invalid parameter {key} = (10+|-10+|\(0, 10+|an int of \d+ bits)"):
        gyrocore.process(T, RATE, "hdr", mode=mode, **{key: value})


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: gyrocore.Pipeline("hdr", hdr_c1=HUGE), "invalid parameter hdr_c1 = 1000"),
        (lambda: gyrocore.preset_params("hdr", lowpass_tau=HUGE), "invalid parameter lowpass_tau = 1000"),
        (lambda: gyrocore.process(T, RATE, "hdr", bias_sigmas=HUGE), "invalid parameter bias_sigmas = 1000"),
        (lambda: gyrocore.process(T, RATE, "hdr", bias_walk=HUGE), "invalid parameter bias_walk = 1000"),
        (lambda: gyrocore.downsample(T, RATE, HUGE), "interval must be finite and > 0 [s], got 1000"),
        (lambda: allan.deviation(RATE, HUGE), "dt must be finite"),
        (lambda: gyrocore.process([0.0, 1.0, 2.0], [0, HUGE, 0], "raw"),
         "rate[1] is an int beyond the range of float64"),
        (lambda: gyrocore.integrate([0, 1, -HUGE], [0.0, 0.0, 0.0]), "t[2] is an int beyond the range of float64"),
    ],
)
def test_an_int_beyond_float64_is_named_wherever_a_number_goes(call: Callable[[], object], message: str) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(message)) as error:
        call()
    assert len(str(error.value)) < 400  # the 401 digits are shortened


def test_a_bias_window_that_is_no_pair_is_named_in_whole_mode_too() -> None:
    """A dict was indexed by whole mode's check of the window's range: a bare ``KeyError: 1``."""
    with pytest.raises(TypeError, match=r"^invalid parameter bias_window = \{0: 1\}: .*bias_window is \(start, end\)"):
        gyrocore.process(T, RATE, "hdr", bias_window={0: 1})


@pytest.mark.parametrize("window", [{"bias_window": (0.0, 1.0)}, {"bias_window": (29.0, 29.5)}, {"bias_duration": 1.0}])
def test_a_log_in_reverse_with_a_rest_window_names_the_time_going_back(window: dict[str, object]) -> None:
    """Whole mode said ``the bias window [0, 1] s holds no sample of the samples from t = 29.99 to
    29.99 s``: the core met the window at the first sample, before the time going back."""
    with pytest.raises(gyrocore.SampleError, match=r"^timestamps must strictly increase: t\[1\] = 29\.98 follows"):
        gyrocore.process(T[::-1].copy(), RATE, "static_bias", **window)


@pytest.mark.parametrize("option", [["--bias-duration", "1"], ["--bias-window", "+0", "+1"]])
def test_a_file_in_reverse_with_a_rest_window_names_the_time_going_back(tmp_path: Path, option: list[str]) -> None:
    """``gyrocore process`` said ``bias_duration = 1.0 s is longer than the log (the log runs from
    19.99 to 0 s (+0 .. +-19.99 s after its first sample ...``, a log that runs backwards."""
    path = tmp_path / "reverse.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{t!r},0.01\n" for t in T[:2000].tolist()[::-1]))
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", "--preset", "static_bias", *option, code=2)
    assert "timestamps must strictly increase: t[1] = 19.98 follows 19.99" in proc.stderr
    assert "reverse.csv, line 3)" in proc.stderr and "longer than the log" not in proc.stderr

"""Inputs found by adversarial testing of the API and the command line: each was a bare Python
error, a misleading message or a silently wrong result, and is now refused in words that name
the argument and the problem."""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrocore
from gyrocore import allan, batch, calibration, fixes

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


FIX = (np.array([1.0, 2.0]), np.array([0.0, 0.1]), np.array([0.1, 0.1]))


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        # a bare "must be real number, not str" from math.isfinite; a bool passed for 1 m
        (lambda: fixes.from_latlon([0.0, 1.0], [48.0, 48.001], [11.0, 11.0], position_sigma="1"), TypeError,
         "position_sigma must be a number, got '1'"),
        (lambda: fixes.from_positions([0.0, 1.0], [0.0, 9.0], [0.0, 0.0], min_speed=True), TypeError,
         "min_speed must be a number, got True"),
        (lambda: fixes.from_gnss([0.0, 1.0], [10.0, 10.0], [3.0, 5.0], speed_sigma="0.2"), TypeError,
         "speed_sigma must be a number, got '0.2'"),
        (lambda: fixes.from_gnss([0.0, 1.0], [10.0, 10.0], [3.0, 5.0], min_sigma_deg=HUGE), ValueError,
         "min_sigma_deg must be finite and > 0, got 1000"),
        # a numpy number reads as a number, not as numpy 2 writes it ("got np.float64(-1.0)")
        (lambda: fixes.from_gnss([0.0, 1.0], [10.0, 10.0], [3.0, 5.0], min_speed=np.float64(-1)), ValueError,
         "min_speed must be finite and > 0, got -1.0"),
        # "'str' object is not a mapping"
        (lambda: gyrocore.process(T, RATE, "hdr", bias=0.0, fixes=FIX, fusion="gate=3"), TypeError,
         "fusion must be a dict of the fix stage's settings (arw, "),
        (lambda: gyrocore.Pipeline("hdr", bias=0.0, fusion=[("gate", 3.0)]), TypeError,
         "fusion must be a dict of the fix stage's settings"),
        # "'list' object is not an instance of 'ndarray'", once the core had the fixes
        (lambda: gyrocore.process(T, RATE, "hdr", bias=0.0, fixes=fixes.Fixes(["1"], [0.0], [0.1])), TypeError,
         "fix t must hold real numbers, got dtype <U1"),
    ],
)
def test_fix_options_and_fixes_of_the_wrong_kind_are_named(
    call: Callable[[], object], error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match="^" + re.escape(message)):
        call()


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_fixes_built_from_lists_are_taken_as_arrays(mode: str) -> None:
    """``Fixes([1.0, 2.0], ...)`` was refused by the core (``'list' object is not an instance of
    'ndarray'``); it is what the arrays give."""
    lists = fixes.Fixes([1.0, 2.0], [0.0, 0.1], [0.1, 0.1])
    assert isinstance(lists.t, np.ndarray) and lists.t.dtype == np.float64
    given = gyrocore.process(T, RATE, "hdr", bias=0.0, mode=mode, fixes=lists)
    arrays = gyrocore.process(T, RATE, "hdr", bias=0.0, mode=mode, fixes=fixes.Fixes(*FIX))
    assert np.array_equal(given.heading, arrays.heading)


def test_a_fusion_setting_beyond_float64_is_no_overflow() -> None:
    """``gate=10**400`` was a bare OverflowError; it is the gate of inf (no gate) it stands for."""
    huge = fixes.fuse(T, RATE, FIX, gate=HUGE)
    assert np.array_equal(huge.heading, fixes.fuse(T, RATE, FIX, gate=math.inf).heading)
    with pytest.raises(ValueError, match=r"^invalid parameter arw = inf"):
        fixes.Fusion(arw=HUGE)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        # bare IndexErrors of ta[0]
        (lambda: calibration.heading_reference([], [], [0.0, 1.0, 2.0], [0.0, 0.1, 0.2]),
         "need at least 2 sample(s) of rate_measured, got 0"),
        (lambda: calibration.bias_temperature_table([], [], []), "need at least 1 sample(s) of rate, got 0"),
        # numpy's OverflowError converting the window
        (lambda: calibration.static_bias(T, RATE, (0, HUGE)), "the rest window must be (start, end) in seconds"),
    ],
)
def test_a_calibration_of_no_samples_or_a_window_beyond_float64_is_named(
    call: Callable[[], object], message: str
) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        call()


def test_an_unknown_reading_option_is_named_with_the_options() -> None:
    """It was ``ReadOptions.__init__() got an unexpected keyword argument 'time_colum'``: a class
    the caller never named, and no hint of the option meant."""
    with pytest.raises(ValueError, match=r"^unknown reading option 'time_colum' \(did you mean 'time_col'\?\); "
                                         r"choose one of time_col, rate_col, "):
        gyrocore.read_log(Path(__file__), time_colum="t")


_LAYOUTS = ("float64", "float32", "int32", "big-endian", "strided", "list", "read-only")


def _laid_out(values: np.ndarray, layout: str) -> object:
    """``values`` in another dtype or memory layout, as a caller may hold them."""
    if layout == "strided":
        doubled = np.repeat(values, 2)
        return doubled[::2]
    if layout == "list":
        return values.tolist()
    if layout == "read-only":
        frozen = values.copy()
        frozen.flags.writeable = False
        return frozen
    return values.astype({"float32": np.float32, "int32": np.int32, "big-endian": ">f8"}.get(layout, np.float64))


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    st.lists(st.tuples(st.floats(0.001, 5.0), st.floats(-50.0, 50.0)), min_size=0, max_size=40),
    st.sampled_from(_LAYOUTS),
    st.sampled_from(_LAYOUTS),
    st.sampled_from(["whole", "causal"]),
    st.floats(-1.0, 1.0),
)
def test_any_dtype_or_layout_gives_the_trapezoid_heading(
    steps: list[tuple[float, float]], t_layout: str, rate_layout: str, mode: str, bias: float
) -> None:
    """The heading of ``static_bias`` with a given bias, whatever the arrays' dtype and layout
    (int, float32, big-endian, strided, a list, read-only), in either mode, is the trapezoid
    integral of ``rate - bias`` over the times as float64 holds them: finite, and equal to the
    reference computation."""
    t = np.cumsum([dt for dt, _ in steps]).round(3) + 1.0  # whole milliseconds: int32 holds them exactly
    rate = np.array([r for _, r in steps]).round(2)
    if t_layout == "int32":
        t = np.round(t)  # whole seconds: the one conversion of times an int keeps
        t = np.unique(t)
        rate = rate[: len(t)]
    if rate_layout == "int32":
        rate = np.round(rate)
    if t_layout == "float32":
        t = t.astype(np.float32).astype(np.float64)
        t = t[np.concatenate(([True], np.diff(t) > 0))] if len(t) else t
        rate = rate[: len(t)]
    if rate_layout == "float32":
        rate = rate.astype(np.float32).astype(np.float64)
    expected = np.concatenate(([0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1] - 2 * bias) * np.diff(t))))[: len(t)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # rates beyond 20 rad/s look like deg/s
        result = gyrocore.process(_laid_out(t, t_layout), _laid_out(rate, rate_layout), "static_bias", mode=mode,
                                  bias=bias)
    assert result.heading.dtype == np.float64 and np.isfinite(result.heading).all()
    np.testing.assert_allclose(result.heading, expected, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize(("fmt", "out"), [("parquet", "h.csv"), ("csv", "h.parquet")])
def test_a_format_that_the_output_files_suffix_contradicts_is_refused(tmp_path: Path, fmt: str, out: str) -> None:
    """``--format parquet --out h.csv`` wrote CSV without a word (--format names the format of an
    output folder's files)."""
    path = tmp_path / "a.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{i / 100!r},0.01\n" for i in range(300)))
    proc = gyrocore_cli("process", path, "--out", tmp_path / out, "--preset", "raw", "--format", fmt, code=2)
    assert f"error: --format {fmt}: --out {tmp_path / out} is one file, whose suffix says its format" in proc.stderr
    assert not (tmp_path / out).exists()
    gyrocore_cli("process", path, "--out", tmp_path / "o.pq", "--preset", "raw", "--format", "parquet", code=0)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("demo", "--duration", "30", "--drives", "1", "--plot", "{victim}"),
         "--plot {victim}: gyrocore writes a PNG image there, so its name must end in .png"),
        (("allan", "{log}", "--plot", "{victim}"),
         "--plot {victim}: gyrocore writes a PNG image there, so its name must end in .png"),
        (("allan", "{log}", "--kalibr", "{victim}"),
         "--kalibr {victim}: gyrocore writes Kalibr's YAML there, so its name must end in .yaml or .yml"),
        (("tune", "--sim-drive", "city:1", "--no-harm", "--max-evals", "2", "--out", "{victim}"),
         "--out {victim}: gyrocore writes a JSON parameter file there, so its name must end in .json"),
    ],
    ids=["demo-plot", "allan-plot", "allan-kalibr", "tune-out"],
)
def test_an_output_named_like_another_kind_of_file_is_refused(
    tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    """``--plot drive.csv --overwrite`` replaced the user's log with a PNG image (``tune --out``
    with a parameter file in JSON), after the work; every plot was a PNG whatever its name."""
    log = tmp_path / "log.csv"
    log.write_text("t,gyro_z\n" + "".join(f"{i / 100!r},0.01\n" for i in range(3000)))
    victim = tmp_path / "drive.csv"
    victim.write_text("t,gyro_z\n0,0.1\n")
    filled = [a.format(log=log, victim=victim) for a in args]
    proc = gyrocore_cli(*filled, "--overwrite", code=2)
    assert proc.stderr == f"gyrocore: error: {message.format(victim=victim)}\n"
    assert victim.read_text() == "t,gyro_z\n0,0.1\n"


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"t_start": "1"}, TypeError, "t_start must be a number [s], got '1'"),  # numpy's UFuncTypeError
        ({"t_start": True}, TypeError, "t_start must be a number [s], got True"),  # the lap from t = 1 s
        ({"t_end": HUGE}, ValueError, "t_end must be finite [s], got 1000"),  # a bare OverflowError
    ],
)
def test_a_laps_bounds_that_are_no_times_are_named(kwargs: dict[str, object], error: type[Exception],
                                                  message: str) -> None:
    from gyrocore import evaluate

    with pytest.raises(error, match="^" + re.escape(message)):
        evaluate.return_orientation_error(T, 0.01 * T, **kwargs)


def test_a_wrapped_heading_given_for_a_return_orientation_error_warns() -> None:
    """A heading wrapped to +-pi counted each wrap as a turn: 0.69 rad off, without a word."""
    from gyrocore import evaluate

    continuous = 0.5 * T  # 15 rad over the lap
    with pytest.warns(gyrocore.InputWarning, match=r"more than three quarters of a turn between two samples: it looks "
                                                    r"wrapped"):
        evaluate.return_orientation_error(T, np.angle(np.exp(1j * continuous)), rotation=15.0)
    assert evaluate.return_orientation_error(T, continuous, rotation=15.0) == pytest.approx(-0.005, abs=1e-9)


def test_a_kalibr_rate_random_walk_of_any_real_type_is_taken_and_a_huge_one_named() -> None:
    """``kalibr_yaml(rrw=np.float32(1e-5))`` was refused as no number, ``rrw=10**400`` a bare
    OverflowError."""
    rate = np.random.default_rng(3).normal(0.0, 0.01, 20_000)
    params = allan.noise_parameters(allan.deviation(rate, 0.01))
    assert "gyroscope_random_walk: 1.000000e-05" in params.kalibr_yaml(rrw=np.float32(1e-5))
    with pytest.raises(ValueError, match=r"^rrw \(--rrw\) = 1000.*: give the rate random walk K"):
        params.kalibr_yaml(rrw=HUGE)


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        # a bare "'float' object cannot be interpreted as an integer"; True was a chunk of one row
        (lambda p, o: batch.process_file(p, o / "h.csv", preset="raw", chunk_rows=1.5), ValueError,
         "chunk_rows must be a whole number >= 1, got 1.5"),
        (lambda p, o: batch.process_file(p, o / "h.csv", preset="raw", chunk_rows=True), ValueError,
         "chunk_rows must be a whole number >= 1, got True"),
        # a switch given as text was read as True: "no" skipped the outputs that exist, used the speed
        (lambda p, o: batch.process_file(p, o / "h.csv", preset="raw", use_speed="no"), TypeError,
         "use_speed must be True or False, got 'no'"),
        (lambda p, o: batch.process_many([p], preset="raw", out_dir=o / "out", skip_existing="no"), TypeError,
         "skip_existing must be True or False, got 'no'"),
        (lambda p, o: batch.process_many([p], preset="raw", out_dir=o / "out", jobs=1.5), ValueError,
         "jobs must be a whole number >= 1, got 1.5"),
        # its letters were read as the columns: "unknown column ',', 'h', 'e', 'a', ..."
        (lambda p, o: batch.process_file(p, o / "h.csv", preset="raw", columns="t,heading"), TypeError,
         "columns 't,heading': give a sequence of column names, e.g. ('t', 'heading'), not one string"),
    ],
)
def test_a_batch_option_of_the_wrong_kind_is_named_before_any_work(
    tmp_path: Path, call: Callable[[Path, Path], object], error: type[Exception], message: str
) -> None:
    path = tmp_path / "a.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{i / 100!r},0.01\n" for i in range(300)))
    with pytest.raises(error, match="^" + re.escape(message)):
        call(path, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]


def test_a_reading_switch_given_as_text_and_a_deviation_of_no_sample_are_named() -> None:
    """``read_log(path, static="no")`` was read as True (and hid the warning of rates that look
    like another unit); ``phase_deviation([])`` said "-1 intervals"."""
    with pytest.raises(TypeError, match=r"^static must be True or False, got 'no'"):
        gyrocore.read_log(Path(__file__), static="no")
    with pytest.raises(ValueError, match=r"^too few samples for this deviation: 0 intervals"):
        allan.phase_deviation([], 0.01)


def test_every_averaging_time_of_a_long_record_is_refused_before_the_work() -> None:
    """``taus="all"`` sums n^2/4 terms: a day at 100 Hz (8.6e6 samples) asked for 1.9e13, hours of
    work with nothing shown; refused at once, with what to give instead."""
    with pytest.raises(ValueError, match=r"^taus='all' \(--taus all\) over 300000 intervals asks for 75000 averaging "
                                         r"times, 2\.3e\+10 terms to sum .*use taus='log'"):
        allan.deviation(np.zeros(300_000), 0.01, taus="all")  # without the check: 7 s, then no error
    assert len(allan.deviation(np.zeros(4000), 0.01, taus="all").taus) == 1000  # a short record: every one

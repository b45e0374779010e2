"""The pipeline's API (``gyrocore.process``, ``gyrocore.Pipeline``) under hostile arguments: a
bool for a number, a preset that is no name, ``outputs=None``, an ``index_offset`` past the core's
index."""

from __future__ import annotations

import pickle
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import datasets

T = np.arange(0.0, 60.0, 0.01)
RATE = np.full_like(T, 0.002)


@pytest.mark.parametrize(
    ("key", "value"), [("bias", True), ("bias_duration", True), ("bias_window", (False, True)), ("threshold_dps", True),
                       ("initial_heading", np.True_), ("nonfinite", True)]
)
@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_bool_for_a_parameter_that_is_no_switch_is_refused(key: str, value: object, mode: str) -> None:
    """The core reads True as 1: bias=True was a bias of 1 rad/s, bias_window=(False, True) 0 .. 1 s."""
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = {re.escape(repr(value))}: a bool, but {key} is .*"
                                        r"\(the switches, which take one, are delag, hdr, track_rests\)"):
        gyrocore.process(T, RATE, "hdr", mode=mode, **{key: value})
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = "):
        gyrocore.Pipeline("hdr", **{key: value})
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = "):
        gyrocore.preset_params("hdr", **{key: value})


@pytest.mark.parametrize(
    ("key", "value", "given"),
    [("bias", np.array([0.1]), "[0.1]: bias takes one value, got an array of shape (1,)"),
     ("bias", [0.1], "[0.1]: bias takes one value, got a list of 1"),
     ("threshold_dps", np.zeros((1, 2)), "[[0.0, 0.0]]: threshold_dps takes one value, got an array of shape (1, 2)")],
)
@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_an_array_for_a_parameter_of_one_value_is_named_as_given(key: str, value: object, given: str, mode: str) -> None:
    """A list or array is turned into the tuple a window is: bias=np.array([0.1]) was refused as the
    tuple (0.1,) the caller never gave."""
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = {re.escape(given)}; {key} is "):
        gyrocore.process(T, RATE, "hdr", mode=mode, **{key: value})
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = {re.escape(given)}; "):
        gyrocore.Pipeline("hdr", **{key: value})
    assert gyrocore.Pipeline("hdr", bias_window=np.array([0.0, 20.0])).params["bias_window"] == (0.0, 20.0)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_an_initial_heading_beyond_2_pow_20_rad_is_refused(mode: str) -> None:
    """At 1e300 rad every sample's increment was lost: the heading stayed 1e300 without a word."""
    with pytest.raises(ValueError, match=r"^invalid parameter initial_heading = 1e300: must be within \+-2\^20 rad"):
        gyrocore.process(T, RATE, "raw", mode=mode, initial_heading=1e300)
    turned = gyrocore.process(T, RATE, "raw", mode=mode, initial_heading=2.0**20)
    # at 2^20 rad a double resolves 2.3e-10 rad: each of the 6,000 steps rounds by at most that
    assert turned.heading[-1] - turned.heading[0] == pytest.approx(0.002 * (T[-1] - T[0]), abs=6000 * 2.4e-10)


def test_the_switches_take_bools_and_a_number_from_numpy_is_a_number() -> None:
    params = gyrocore.preset_params("hdr", delag=False, hdr=np.True_, track_rests=False, bias=np.array(0.002))
    assert params["delag"] is False and params["hdr"] is True and params["bias"] == 0.002
    as_number = gyrocore.process(T, RATE, "hdr", bias=np.array(0.002))  # 0-d: "'float' object is not iterable"
    assert np.array_equal(as_number.heading, gyrocore.process(T, RATE, "hdr", bias=0.002).heading)


@pytest.mark.parametrize("preset", [None, 3, ("hdr",)])
def test_a_preset_that_is_no_name_is_named(preset: object) -> None:
    message = rf"^preset must be the name of a preset \(raw, .*, recommended\), got {re.escape(repr(preset))}$"
    with pytest.raises(TypeError, match=message):
        gyrocore.process(T, RATE, preset)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=message):
        gyrocore.Pipeline(preset)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=message):
        gyrocore.preset_params(preset)  # type: ignore[arg-type]


@pytest.mark.parametrize("outputs", [None, 3, (o for o in ["heading"])])
def test_outputs_that_are_no_names_are_named(outputs: object) -> None:
    with pytest.raises(TypeError, match=r"^outputs=.*: give a tuple of names from heading, rate, drift"):
        gyrocore.process(T, RATE, "raw", outputs=outputs)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"^outputs=.*: give a tuple of names"):
        gyrocore.Pipeline("raw").process(T, RATE, outputs=outputs)  # type: ignore[arg-type]


@pytest.mark.parametrize("offset", [2**63, 2**64 - 1, 2**64, 2**70])
def test_an_index_offset_past_the_cores_index_is_refused(offset: int) -> None:
    """2^64 - 1 wrapped: a NaN at index 5 of the chunk was named rate[4]; 2^64 was a bare OverflowError."""
    rate = RATE[:10].copy()
    rate[5] = np.nan
    pipeline, fresh = gyrocore.Pipeline("hdr", bias=0.0), gyrocore.Pipeline("hdr", bias=0.0)
    with pytest.raises(ValueError, match=rf"^index_offset = {offset}: give the index of the chunk's first sample in the "
                                         r"whole log, an int >= 0 and below 2\^63$"):
        pipeline.process(T[:10], rate, index_offset=offset)
    assert np.array_equal(pipeline.process(T, RATE).heading, fresh.process(T, RATE).heading)  # nothing changed
    with pytest.raises(gyrocore.SampleError, match=rf"^rate\[{2**63 + 4}\] is NaN"):  # the largest offset taken
        gyrocore.Pipeline("hdr", bias=0.0).process(T[:10], rate, index_offset=2**63 - 1)


@pytest.mark.parametrize(("t", "overrides"), [([0.0], {"bias_window": (0.0, 0.0)}),
                                              ([0.0, 0.01], {"bias_window": (0.0, 0.01)}),
                                              ([0.0, 0.01], {"bias_duration": 0.01})])
def test_a_log_that_ends_at_its_rest_windows_end_needs_its_readings_in_either_mode(
    t: list[float], overrides: dict[str, object]
) -> None:
    """The window stayed open (no reading came after it), and causal mode took one reading as the
    bias, where whole mode refused it."""
    for mode in ("whole", "causal"):
        with pytest.raises(gyrocore.RestWindowError, match=rf"holds {len(t)} reading\(s\): the bias needs at least 3"):
            gyrocore.process(t, [0.1] * len(t), "hdr", mode=mode, **overrides)
    three = gyrocore.process([0.0, 0.01, 0.02], [0.1] * 3, "hdr", mode="causal", bias_window=(0.0, 0.02))
    assert np.array_equal(three.heading, np.zeros(3))  # enough readings: the bias is theirs


def test_an_output_of_no_name_is_named_as_such() -> None:
    result = gyrocore.process(T, RATE, "raw", outputs=("heading",))
    with pytest.raises(ValueError, match=r"^unknown output 'headings' \(did you mean 'heading'\?\); choose one of heading, rate, drift, heading_sigma$"):
        result.output("headings")
    with pytest.raises(ValueError, match=r"^the 'rate' output was not computed: ask for it in outputs="):
        result.output("rate")
    assert result.output("heading") is result.heading


def test_an_object_array_names_its_first_value_that_is_no_number_and_takes_numbers() -> None:
    """None among numbers (a pandas column with gaps) was "must hold real numbers, got dtype
    object", naming neither the value nor where it is."""
    for value in (None, "a", {}):
        rate = np.array([0.0, value, 1.0], dtype=object)
        with pytest.raises(TypeError, match=rf"^rate must hold real numbers, got dtype object: rate\[1\] is "
                                            rf"{re.escape(repr(value))} \(give numbers, NaN where a value is missing\)"):
            gyrocore.process([0.0, 1.0, 2.0], rate, "raw")
    numbers = np.array([0.0, 1, np.float32(2.0)], dtype=object)  # numbers of any type, stored as objects
    assert np.array_equal(gyrocore.process([0.0, 1.0, 2.0], numbers, "raw").heading,
                          gyrocore.process([0.0, 1.0, 2.0], [0.0, 1.0, 2.0], "raw").heading)


@pytest.mark.parametrize("switch", ["use_speed", "use_fixes"])
def test_a_log_switch_given_as_text_is_refused(switch: str) -> None:
    """``Log.process(use_speed="no")`` was read as True: the log's odometry found its rests."""
    log = datasets.sample_drive()
    with pytest.raises(TypeError, match=rf"^{switch} must be True or False, got 'no'$"):
        log.process("static_bias", **{switch: "no"})  # type: ignore[arg-type]
    assert len(log.process("static_bias", **{switch: False}).heading) == len(log.t)


def test_read_log_refuses_use_fixes_given_as_text(tmp_path: Path) -> None:
    folder = datasets.write_sample(tmp_path / "drive")
    with pytest.raises(TypeError, match=r"^use_fixes must be True or False, got 0$"):
        gyrocore.read_log(folder, use_fixes=0)  # type: ignore[arg-type]


def test_a_refused_chunk_in_the_rest_window_leaves_the_pipeline_as_it_was() -> None:
    """The readings of a chunk the core refused were kept for the rest window's turn check: sent
    again mended, the window was said to hold a turn it never had, and a pickle differed."""
    t = np.arange(0, 30, 0.01)
    rate = 0.002 + np.random.default_rng(0).normal(0, 0.001, len(t))
    corrupt = rate.copy()
    corrupt[200:400] += 0.5
    corrupt[450] = np.nan
    stream = gyrocore.Pipeline("static_bias", bias_duration=10.0)
    stream.process(t[:200], rate[:200])
    state = pickle.dumps(stream)
    with pytest.raises(gyrocore.SampleError, match=r"rate\[250\] is NaN"):
        stream.process(t[200:500], corrupt[200:500])
    assert pickle.dumps(stream) == state
    with warnings.catch_warnings():
        warnings.simplefilter("error", gyrocore.InputWarning)
        stream.process(t[200:], rate[200:])


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_bad_reading_names_the_policy_that_keeps_it(mode: str) -> None:
    # the core's words alone, "drop or fill them first", sent a notebook user to edit the data
    t = np.arange(0.0, 30.0, 0.01)
    rate = np.full_like(t, 0.01)
    rate[1000] = np.nan
    with pytest.raises(gyrocore.SampleError, match=r"^rate\[1000\] is NaN: .*\(drop or fill them first\); or keep them: "
                       r"nonfinite='hold' uses the last usable reading there, 'skip' leaves the sample out$"):
        gyrocore.process(t, rate, "static_bias", bias_duration=5.0, mode=mode)
    held = gyrocore.process(t, rate, "static_bias", bias_duration=5.0, mode=mode, nonfinite="hold")
    assert np.isfinite(held.heading).all()
    with pytest.raises(gyrocore.SampleError, match=r"^timestamps must strictly increase: t\[3\] = 2 follows 2 "
                       r"\(sort the log and drop duplicate timestamps\)$"):  # a time has no such policy
        gyrocore.process(np.array([0.0, 1.0, 2.0, 2.0]), np.zeros(4), "raw", mode=mode)

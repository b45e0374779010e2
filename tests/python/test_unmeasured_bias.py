"""The warning that a preset's static bias is unmeasured comes only for a run that goes on: a
call refused for its samples (a NaN reading, times out of order, lengths apart) says only why."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

import gyrocore
from gyrocore import datasets

from .conftest import real_log_path

T = np.arange(0.0, 60.0, 0.01)
RATE = np.full_like(T, 0.002)


def _bad_rate() -> np.ndarray:
    rate = RATE.copy()
    rate[5] = np.nan
    return rate


@pytest.mark.parametrize(
    ("mode", "args"),
    [
        ("causal", (T, _bad_rate())),  # the bad sample
        ("whole", (T, _bad_rate())),
        ("causal", (T[::-1], RATE)),  # times out of order
        ("whole", (T[::-1], RATE)),
        ("whole", (T, RATE[:-1])),  # lengths apart
        ("causal", (T, RATE[:-1])),
    ],
)
def test_a_run_that_is_refused_warns_of_no_unmeasured_bias(mode: str, args: tuple[np.ndarray, np.ndarray]) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(ValueError):
            gyrocore.process(*args, "recommended", mode=mode)
    assert [str(w.message) for w in caught] == []


def test_a_refused_temperature_in_whole_mode_warns_of_no_unmeasured_bias() -> None:
    rate = 0.5 * np.sin(2 * np.pi * T / 5.0)  # no rest in it: whole mode warns that none was found
    temperature = np.full_like(T, 20.0)
    temperature[7] = np.nan
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(gyrocore.SampleError, match=r"^temperature\[7\] is NaN"):
            gyrocore.process(T, rate, "static_bias", temperature=temperature, temp_slope=1e-3, temp_offset=20.0)
    assert [str(w.message) for w in caught] == []
    with pytest.warns(gyrocore.InputWarning, match="no rest was found in it: the bias is taken as 0"):
        gyrocore.process(T, rate, "static_bias", temperature=np.full_like(T, 20.0), temp_slope=1e-3, temp_offset=20.0)


def test_the_unmeasured_bias_is_said_once_as_the_first_samples_are_processed() -> None:
    pipeline = gyrocore.Pipeline("recommended")
    with pytest.raises(gyrocore.SampleError):
        pipeline.process(T[:100], _bad_rate()[:100])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pipeline.process(T[:0], RATE[:0])  # no sample: no run yet
        resumed = pickle.loads(pickle.dumps(pipeline))  # the warning still to come travels with the state
    for p in (pipeline, resumed):
        with pytest.warns(gyrocore.InputWarning, match=r"^preset 'recommended' removes a static bias, but no bias"):
            p.process(T[:100], RATE[:100])
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # once
            p.process(T[100:], RATE[100:])
    with pytest.warns(gyrocore.InputWarning, match="removes a static bias"):  # a run that goes on: said
        assert len(gyrocore.process(T, RATE, "recommended", mode="causal")) == len(T)


def _stop_in_deg_per_s() -> np.ndarray:
    """A drive with a stop from 20 to 40 s, a bias of 0.01 rad/s, written in deg/s: read as rad/s,
    its turns (11 "rad/s") pass the unit check, and its stop reads 0.57 "rad/s", no rest."""
    rng = np.random.default_rng(3)
    rate = 0.01 + np.where((T > 20) & (T < 40), 0.0, 0.2 * np.sin(T / 5)) + rng.normal(0, 0.002, len(T))
    return np.degrees(rate)


def test_no_rest_found_says_what_the_steadiest_stretch_reads_and_names_the_unit() -> None:
    # "no rest was found" alone left a rate in deg/s unsuspected
    hint = r"the steadiest stretch, 20.* s after the first sample, reads 0\.57.* rad/s .*--rate-unit deg/s"
    with pytest.warns(gyrocore.InputWarning, match="no rest was found in it.*" + hint):
        gyrocore.process(T, _stop_in_deg_per_s(), "static_bias")
    with pytest.raises(ValueError, match="no rest found.*" + hint):
        gyrocore.calibration.static_bias(T, _stop_in_deg_per_s())


def test_a_steady_level_far_beyond_any_deg_per_s_rest_does_not_name_the_unit() -> None:
    with pytest.warns(gyrocore.InputWarning) as caught:
        gyrocore.process(T, np.full_like(T, 12.0) + np.random.default_rng(4).normal(0, 0.002, len(T)), "static_bias")
    text = " ".join(str(w.message) for w in caught)  # 12 deg/s would be a bias beyond the 11.5 a gyro has
    assert "reads 12 rad/s" in text and "deg/s read as rad/s" not in text


def test_a_highway_drive_in_rad_per_s_with_a_large_bias_is_not_said_to_be_in_deg_per_s() -> None:
    # comma_seg40 drives straight with a bias of 0.068 rad/s: steady beyond 0.05 rad/s, turning little
    log = gyrocore.read_log(real_log_path("comma_seg40"))
    with pytest.warns(gyrocore.InputWarning) as caught:
        log.process("static_bias", use_speed=False)
    text = " ".join(str(w.message) for w in caught)
    assert "or a rest or straight drive with a bias that large" in text and "deg/s read as rad/s" not in text


def test_the_same_highway_drive_written_in_deg_per_s_names_the_unit() -> None:
    """comma_seg40 in deg/s, read as rad/s, drove a minute of straight highway as 37 turns: its bias,
    3.9 deg/s, lay beyond the 2.9 deg/s the clause allowed, and the unit went unsaid."""
    log = gyrocore.read_log(real_log_path("comma_seg40"))
    with pytest.warns(gyrocore.InputWarning) as caught:
        gyrocore.process(log.t, np.degrees(log.rate), "static_bias")
    text = " ".join(str(w.message) for w in caught)
    assert "reads -3.884 rad/s (-222.5 deg/s)" in text and "or a rate in deg/s read as rad/s" in text


def test_arrays_in_deg_per_s_are_told_a_remedy_that_process_takes() -> None:
    """The warning told a caller of gyrocore.process with arrays to "give rate_unit='deg/s'", which
    process refuses as an unknown parameter: rate_unit is the readers' option."""
    log = datasets.sample_drive()  # its rest is 60 s of 1.4 deg/s, read as 80 "rad/s"
    with pytest.warns(gyrocore.InputWarning) as caught:
        gyrocore.process(log.t, np.degrees(log.rate), "static_bias")
    text = " ".join(str(w.message) for w in caught)
    assert "or a rate in deg/s read as rad/s (convert arrays with numpy.radians, or read the file with " \
           "rate_unit='deg/s', --rate-unit deg/s)" in text
    with pytest.raises(ValueError, match="unknown parameter 'rate_unit'"):
        gyrocore.process(log.t, np.degrees(log.rate), "static_bias", rate_unit="deg/s")

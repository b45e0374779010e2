"""The warning that a preset's static bias is unmeasured comes only for a run that goes on: a
call refused for its samples (a NaN reading, times out of order, lengths apart) says only why."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

import gyrocore

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

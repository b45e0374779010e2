"""The whole-log bias smoother and the leave-one-out test that refuses outlying rests."""

from __future__ import annotations

import numpy as np
import pytest

from gyrocore._smoother import MIN_VARIANCE, leave_one_out, smooth


def _left_out(times: np.ndarray, values: np.ndarray, se: np.ndarray, walk: float) -> np.ndarray:
    """The definition: for each rest, a smoother over the others, asked at its time."""
    out = np.empty(len(times))
    for k in range(len(times)):
        others = np.arange(len(times)) != k
        mean, sd = smooth(times[others], values[others], se[others], walk).at(times[k : k + 1])
        out[k] = (values[k] - mean[0]) / np.sqrt(max(se[k] ** 2, MIN_VARIANCE) + sd[0] ** 2)
    return out


@pytest.mark.parametrize("walk", [0.0, 1e-5, 1e-3, 0.1])
def test_leave_one_out_equals_a_smoother_of_the_others_at_each_rest(walk: float) -> None:
    rng = np.random.default_rng(7)
    for _ in range(40):
        n = int(rng.integers(2, 25))
        times = np.cumsum(rng.uniform(0.5, 300.0, n))
        values, se = rng.normal(0.0, 0.01, n), rng.uniform(1e-5, 1e-2, n)
        np.testing.assert_allclose(leave_one_out(times, values, se, walk), _left_out(times, values, se, walk),
                                   rtol=1e-9, atol=1e-9)


def test_a_noiseless_rest_among_noisy_ones_gives_finite_numbers() -> None:
    """A quantized gyro reads one value through a rest (standard error 0): with no walk the
    smoother and the leave-one-out test stay finite, and the exact rest sets the bias."""
    times, values, se = np.array([0.0, 10.0, 20.0]), np.array([0.01, 0.0, 0.02]), np.array([1e-2, 0.0, 1e-2])
    smoothed = smooth(times, values, se, 0.0)
    assert np.all(np.isfinite(smoothed.mean)) and np.all(np.isfinite(smoothed.variance))
    np.testing.assert_allclose(smoothed.mean, 0.0, atol=1e-12)
    np.testing.assert_allclose(leave_one_out(times, values, se, 0.0), [1.0, -0.015 / np.sqrt(0.5e-4), 2.0], rtol=1e-9)


def test_leave_one_out_needs_two_rests() -> None:
    with pytest.raises(ValueError, match="at least two rests"):
        leave_one_out(np.array([1.0]), np.array([0.0]), np.array([1e-3]), 1e-3)

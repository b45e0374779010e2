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


def _textbook_filter(times: np.ndarray, values: np.ndarray, variances: np.ndarray, q: float) -> tuple[list[float], ...]:
    """The scalar Kalman filter of a random walk, a float at a time (the variance as P r / (P + r))."""
    mean, variance, predicted = [float(values[0])], [float(variances[0])], [np.inf]
    for k in range(1, len(times)):
        p = variance[-1] + q * abs(float(times[k]) - float(times[k - 1]))
        gain = p / (p + float(variances[k]))
        predicted.append(p)
        mean.append(mean[-1] + gain * (float(values[k]) - mean[-1]))
        variance.append(max(p * float(variances[k]) / (p + float(variances[k])), MIN_VARIANCE))
    return mean, variance, predicted


def test_the_cores_filter_is_the_textbook_filter_bit_for_bit_both_ways() -> None:
    # the filter over the rests that the core runs for whole mode is this one, to the last bit
    from gyrocore import _gyrocore

    rng = np.random.default_rng(3)
    n = 300
    times = np.cumsum(rng.uniform(0.5, 300.0, n))
    values, variances = rng.normal(0.0, 0.01, n), rng.uniform(1e-10, 1e-4, n) ** 2 + MIN_VARIANCE
    for q in (0.0, 1e-8, 1e-2):
        forward = _gyrocore.filter_rests(times, values, variances, q, MIN_VARIANCE, False)
        assert [a.tolist() for a in forward] == list(_textbook_filter(times, values, variances, q))
        backward = _gyrocore.filter_rests(times, values, variances, q, MIN_VARIANCE, True)
        expected = _textbook_filter(times[::-1], values[::-1], variances[::-1], q)
        assert [a.tolist() for a in backward] == [e[::-1] for e in expected]
    with pytest.raises(ValueError, match=r"timestamps must strictly increase: t\[1\]"):
        _gyrocore.filter_rests(np.array([1.0, 1.0]), np.zeros(2), np.ones(2), 0.0, MIN_VARIANCE, False)


@pytest.mark.parametrize("walk", [0.0, 1e-6, 1e-4, 0.1])
def test_rests_left_out_one_at_a_time_score_bit_for_bit_as_leave_one_out_of_those_kept(walk: float) -> None:
    from gyrocore._smoother import LeaveOneOut

    rng = np.random.default_rng(3)
    for n in (2, 3, 40, 3000):  # 3000: restarted filters that go past their first stretches
        times = np.cumsum(rng.uniform(0.5, 12.0, n))
        values, se = 0.003 + rng.normal(0.0, 1e-4, n), rng.uniform(5e-5, 2e-4, n)
        se[n // 2] = 0.0  # a noiseless rest, at the floor of the variances
        test, kept = LeaveOneOut(times, values, se, walk), list(range(n))
        while len(kept) > 2:
            assert np.array_equal(test.scores, leave_one_out(times[kept], values[kept], se[kept], walk))
            k = int(rng.choice([0, len(kept) - 1, int(rng.integers(len(kept)))]))  # the ends too
            test.remove(k)
            kept.pop(k)
            if n == 3000 and len(kept) < 2990:
                break
        assert np.array_equal(test.scores, leave_one_out(times[kept], values[kept], se[kept], walk))


def test_refusing_many_outlying_rests_filters_only_the_rests_near_each(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each refusal filtered every rest kept, forward and backward: 13,334 stops with a fifth of
    them off took most of whole mode's time. The verdicts are those of a full test per refusal."""
    from gyrocore import _rests, _smoother
    from gyrocore.rests import Rest

    rng = np.random.default_rng(0)
    n, sigma = 3000, 1e-4
    bias = 0.003 + rng.normal(0.0, sigma, n)
    off = rng.random(n) < 0.2
    bias[off] += rng.choice([-1.0, 1.0], int(off.sum())) * rng.uniform(4.0, 25.0, int(off.sum())) * sigma
    rests = [Rest(6.0 * k, 6.0 * k + 2.0, float(b), sigma, 0.002, 200, "speed") for k, b in enumerate(bias)]
    walk = 1e-5
    filtered: list[int] = []
    forward = _smoother._forward

    def counted(ts: np.ndarray, *args: object, **options: object) -> object:
        filtered.append(len(ts))
        return forward(ts, *args, **options)  # type: ignore[arg-type]

    monkeypatch.setattr(_smoother, "_forward", counted)
    out, _ = _rests._refuse_outliers(rests, walk)
    refused, steps = [k for k, r in enumerate(out) if r.refused is not None], sum(filtered)
    # the definition: the worst of a full leave-one-out refused, one at a time
    kept, expected = list(range(n)), []
    middle, error = np.array([r.middle for r in rests]), np.full(n, sigma)
    while True:
        z = leave_one_out(middle[kept], bias[kept], error[kept], walk)
        worst = int(np.argmax(np.abs(z)))
        if abs(z[worst]) <= _rests.OUTLIER_SIGMAS:
            break
        expected.append(kept.pop(worst))
    assert refused == sorted(expected) and len(refused) > 400
    assert steps < 0.1 * 2 * n * len(refused)  # a full pass each way per refusal was 2 n

"""The dead band's expected output (Hong eq 12 in Gaussian noise) against numerical integration
(scipy) and against the pipeline's own threshold on a simulated static gyro."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import norm

from gyrocore import deadband, process, sim


@pytest.mark.parametrize("bias", [-0.7, -0.05, 0.0, 0.02, 0.3, 1.0, 4.0])
@pytest.mark.parametrize("threshold", [0.0, 0.3, 1.0, 2.5])
def test_expected_output_is_the_integral_of_what_passes(bias: float, threshold: float) -> None:
    sigma = 0.8

    def passed(x: float) -> float:
        return x * norm.pdf(x, loc=bias, scale=sigma)

    lo, hi = bias - 12 * sigma, bias + 12 * sigma
    numeric = integrate.quad(passed, lo, min(-threshold, hi))[0] + integrate.quad(passed, max(threshold, lo), hi)[0]
    assert float(deadband.expected_output(bias, sigma, threshold)) == pytest.approx(numeric, abs=1e-9)


def test_bias_leak_is_the_slope_at_zero() -> None:
    for k in (0.0, 0.5, 1.0, 2.0, 3.0):
        h = 1e-6
        slope = float(np.diff(deadband.expected_output([-h, h], 1.0, k))[0]) / (2 * h)
        assert deadband.bias_leak(1.0, k) == pytest.approx(slope, rel=1e-6)
    assert deadband.bias_leak(1.0, 0.0) == 1.0
    assert deadband.bias_leak(0.31, 0.3) > 0.8 > deadband.bias_leak(0.1, 0.3) * 20


def test_the_pipelines_threshold_passes_what_the_formula_says() -> None:
    # A static XV3500 (white noise, 20 Hz bandwidth, so samples are correlated) with a residual
    # bias of 0.05 deg/s left after the pipeline's bias; the mean output of its threshold stage.
    residual_dps = 0.05
    spec = sim.sensor(
        "xv3500", bias_instability_deg_per_h=0.0, rrw_deg_per_h_per_sqrt_h=0.0, bias_dps=0.75, bias_dps_per_c=0.0,
        resolution_dps=0.0,
    )
    t = np.arange(1_000_000) / spec.rate_hz
    reading = sim.measure(spec, t, np.zeros_like(t), seed=3)
    for threshold_dps in (0.3, 0.6):
        out = process(
            t, reading.rate, "raw", bias=math.radians(0.75 - residual_dps), threshold=math.radians(threshold_dps)
        ).rate
        batches = np.degrees(out).reshape(200, -1).mean(axis=1)
        standard_error = batches.std(ddof=1) / math.sqrt(len(batches))
        expected = float(deadband.expected_output(residual_dps, spec.noise_rms_dps, threshold_dps))
        assert abs(batches.mean() - expected) < 4 * standard_error
        assert standard_error < 0.05 * expected


def test_noise_rms_is_what_the_simulated_gyro_gives() -> None:
    for bandwidth in (math.inf, 20.0, 2.0):
        spec = sim.sensor("xv3500", bias_instability_deg_per_h=0.0, rrw_deg_per_h_per_sqrt_h=0.0, bandwidth_hz=bandwidth)
        t = np.arange(400_000) / spec.rate_hz
        rms = np.degrees(sim.measure(spec, t, np.zeros_like(t), seed=5).rate).std()
        assert rms == pytest.approx(spec.noise_rms_dps, rel=0.02)


@pytest.mark.parametrize("noise_rms, threshold", [(0.0, 1.0), (-1.0, 1.0), (math.nan, 1.0), (1.0, -0.1), (1.0, math.inf)])
def test_bad_parameters_are_refused(noise_rms: float, threshold: float) -> None:
    with pytest.raises(ValueError, match="noise_rms|threshold"):
        deadband.bias_leak(noise_rms, threshold)


@pytest.mark.parametrize(
    ("rate", "message"),
    [
        ([0.1, math.nan, 0.2], r"rate\[1\] is nan: samples must be finite"),
        ([0.1, 0.2, -math.inf], r"rate\[2\] is -inf: samples must be finite"),
        ([[0.1, 0.2], [0.3, math.nan]], r"rate\[1, 1\] is nan: samples must be finite"),
        (math.nan, r"rate is nan: samples must be finite"),
    ],
)
def test_a_rate_that_is_not_finite_is_named(rate: object, message: str) -> None:
    # NaN came back as the expected output without a word
    with pytest.raises(ValueError, match=message):
        deadband.expected_output(rate, noise_rms=1.0, threshold=1.0)


def test_a_rate_of_text_is_named() -> None:
    # it was numpy's "could not convert string to float: 'a'"
    with pytest.raises(TypeError, match=r"^rate must hold real numbers, got dtype <U1"):
        deadband.expected_output([["a"]], noise_rms=1.0, threshold=1.0)


def test_a_threshold_infinitely_many_noises_wide_lets_no_bias_pass() -> None:
    # threshold / noise_rms overflowed to inf, and inf * phi(inf) gave NaN
    assert deadband.bias_leak(noise_rms=1e-300, threshold=1e300) == 0.0


def test_a_noise_far_below_the_rates_gives_the_dead_band_without_noise_and_no_warning() -> None:
    # (1 - 1e300) / 1e-300 overflows, as did its square: numpy's overflow warnings came with the
    # right answer, the noise-free dead band (0 inside, the rate outside, half of it on the edge)
    rate = np.array([1e300, -1e300, 0.5, 1.0, 2.0, -2.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = deadband.expected_output(rate, noise_rms=1e-300, threshold=1.0)
    np.testing.assert_array_equal(out, [1e300, -1e300, 0.0, 0.5, 2.0, -2.0])

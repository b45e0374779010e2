"""gyrocore's `combined` pipeline against benches/reference.py, an independent plain-Python
implementation written from the papers' equations (also the benchmark's pure-Python and Numba
versions)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import gyrocore

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benches"))
import reference  # noqa: E402


@pytest.mark.parametrize("lag_free", [False, True])
@pytest.mark.parametrize(("seed", "rate_hz", "bias"), [(0, 100.0, 0.0087), (1, 23.0, -0.002), (2, 1.0, 0.0)])
def test_combined_matches_the_reference_implementation(seed: int, rate_hz: float, bias: float, lag_free: bool) -> None:
    """Against the equations stage after stage, and against eq 7 and 13 in closed form (what the
    core computes): the two forms differ by rounding alone."""
    d = gyrocore.sim.car_drive(duration=600.0, rate_hz=rate_hz, seed=seed)
    rng = np.random.default_rng(seed)
    t = d.t + rng.uniform(0.0, 0.2 / rate_hz, len(d.t))  # irregular timestamps
    p = gyrocore.preset_params("combined")
    n = len(t)
    heading, rate, drift = np.empty(n), np.empty(n), np.empty(n)
    reference.combined(
        t, d.rate_measured, heading, rate, drift, bias, p["scale"], p["offset"], p["threshold"],
        p["lowpass_tau"], p["hdr_increment"], p["hdr_turn_threshold"], p["hdr_c1"], p["hdr_c2"], p["hdr_interval"],
        lag_free,
    )
    ours = gyrocore.process(t, d.rate_measured, "combined", bias=bias)
    assert np.any(ours.drift != 0.0), "HDR must act in this drive"
    # Same decisions (the attenuator's pow may differ in the last bit between libm and CPython).
    np.testing.assert_allclose(ours.drift, drift, rtol=1e-12, atol=1e-18)
    # The closed form is the core's operation order: only the attenuator's pow may differ.
    np.testing.assert_allclose(ours.heading, heading, rtol=0, atol=1e-12 if lag_free else 1e-9)
    np.testing.assert_allclose(ours.rate, rate, rtol=1e-9, atol=1e-12)


def test_heading_only_reference_matches_heading_only_gyrocore() -> None:
    """benches/compare.py's single-output comparison: both sides fill the heading alone."""
    d = gyrocore.sim.car_drive(duration=300.0, rate_hz=100.0, seed=3)
    p = gyrocore.preset_params("combined")
    heading = np.empty(len(d.t))
    reference.combined(
        d.t, d.rate_measured, heading, None, None, 0.0087, p["scale"], p["offset"], p["threshold"],
        p["lowpass_tau"], p["hdr_increment"], p["hdr_turn_threshold"], p["hdr_c1"], p["hdr_c2"], p["hdr_interval"],
    )
    ours = gyrocore.process(d.t, d.rate_measured, "combined", bias=0.0087, outputs=("heading",))
    assert ours.rate is None and ours.drift is None
    np.testing.assert_allclose(ours.heading, heading, rtol=0, atol=1e-9)

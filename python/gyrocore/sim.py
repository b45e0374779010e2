"""Simulated drives with a known true heading, for the demo, the tests and tuning.

The motion and the slow gyro drift are functions of continuous time (fixed by the seed), so the
same drive can be sampled at any rate; only the white noise depends on the sample interval
(``sigma = ARW / sqrt(dt)``), as it does for a real gyro.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._arrays import FloatArray

#: Segment kinds of a drive: straight (with a slight 0.1 Hz swerve), a long gentle curve,
#: a 90-degree turn, and a stop.
_KINDS = ("straight", "curve", "turn", "stop")


@dataclass(frozen=True)
class Drive:
    """A simulated drive: true motion, the gyro's reading and its (known) errors.

    Units: s, rad/s, rad; counter-clockwise positive.
    """

    t: FloatArray
    rate_true: FloatArray
    heading_true: FloatArray
    rate_measured: FloatArray
    drift: FloatArray
    """Slow error ``eps_d`` (HDR eq 1) at each sample, excluding the static bias [rad/s]."""
    bias: float
    """Static bias ``eps0`` [rad/s]."""
    stationary: tuple[float, float]
    """Rest window at the start [s]."""


def _segments(duration: float, rest: float, rng: np.random.Generator) -> list[tuple[float, float, float]]:
    """(start, end, rate) pieces of the true yaw rate; rates in rad/s, ramps added later."""
    pieces = [(0.0, rest, 0.0)]
    t = rest
    while t < duration:
        kind = rng.choice(_KINDS, p=(0.55, 0.2, 0.2, 0.05))
        if kind == "straight":
            length, rate = rng.uniform(20, 90), 0.0
        elif kind == "curve":
            length = rng.uniform(10, 30)
            rate = math.radians(rng.uniform(1.0, 3.0)) * rng.choice((-1, 1))
        elif kind == "turn":
            length = rng.uniform(5, 8)
            rate = math.radians(90.0) / length * rng.choice((-1, 1))
        else:
            length, rate = rng.uniform(5, 20), 0.0
        pieces.append((t, min(t + length, duration), rate))
        t += length
    return pieces


def _true_rate(t: FloatArray, pieces: list[tuple[float, float, float]], swerve: float) -> FloatArray:
    """Piecewise-constant rate with 1 s cosine ramps at the edges, plus a 0.1 Hz swerve while moving."""
    rate = np.zeros_like(t)
    for start, end, r in pieces:
        if r == 0.0:
            continue
        ramp = np.clip(np.minimum(t - start, end - t), 0.0, 1.0)
        inside = (t >= start) & (t <= end)
        rate[inside] += r * 0.5 * (1 - np.cos(math.pi * ramp[inside]))
    moving = t > pieces[0][1]
    rate[moving] += swerve * np.sin(2 * math.pi * 0.1 * t[moving])
    return rate


def car_drive(
    duration: float = 600.0,
    rate_hz: float = 100.0,
    *,
    seed: int = 0,
    rest: float = 20.0,
    bias_dps: float = 0.5,
    drift_dps: float = 0.05,
    arw_deg_per_sqrt_h: float = 2.5,
    swerve_dps: float = 0.3,
) -> Drive:
    """A car drive: a rest at the start, then straight stretches, gentle curves, 90-degree turns, stops.

    Args:
        duration: length [s]. rate_hz: gyro sample rate [Hz]. seed: fixes motion, drift and noise.
        rest: rest time at the start [s] (the static bias test).
        bias_dps: static bias [deg/s]. drift_dps: standard deviation of the slow drift [deg/s]
            (a first-order Gauss-Markov process with a 300 s correlation time, starting at 0).
        arw_deg_per_sqrt_h: angle random walk [deg/sqrt(h)]. swerve_dps: amplitude of the 0.1 Hz swerve.
    """
    if duration <= rest:
        raise ValueError(f"duration ({duration} s) must exceed the rest time ({rest} s)")
    if rate_hz <= 0:
        raise ValueError(f"rate_hz must be > 0, got {rate_hz}")
    rng = np.random.default_rng(seed)
    pieces = _segments(duration, rest, rng)
    # Drift on a 1 s grid, interpolated: a Gauss-Markov process independent of the sample rate.
    knots = np.arange(0.0, duration + 2.0)
    corr = 300.0
    phi = math.exp(-1.0 / corr)
    steps = rng.normal(0.0, math.radians(drift_dps) * math.sqrt(1 - phi**2), len(knots))
    drift_knots = np.zeros(len(knots))
    for k in range(1, len(knots)):
        drift_knots[k] = phi * drift_knots[k - 1] + steps[k]
    noise_rng = np.random.default_rng([seed, int(round(rate_hz * 1000))])
    t = np.arange(0.0, duration, 1.0 / rate_hz)
    rate_true = _true_rate(t, pieces, math.radians(swerve_dps))
    # True heading: the true rate integrated on a 1 ms grid (exact to well below a millidegree).
    fine = np.arange(0.0, duration + 0.001, 0.001)
    rate_fine = _true_rate(fine, pieces, math.radians(swerve_dps))
    heading_fine = np.concatenate(([0.0], np.cumsum(0.5 * (rate_fine[1:] + rate_fine[:-1]) * 0.001)))
    heading_true = np.interp(t, fine, heading_fine)
    drift = np.interp(t, knots, drift_knots)
    bias = math.radians(bias_dps)
    arw = math.radians(arw_deg_per_sqrt_h) / 60.0  # rad/sqrt(s)
    noise = noise_rng.normal(0.0, arw * math.sqrt(rate_hz), len(t))
    return Drive(
        t=t,
        rate_true=rate_true,
        heading_true=heading_true,
        rate_measured=rate_true + bias + drift + noise,
        drift=drift,
        bias=bias,
        stationary=(0.0, rest),
    )

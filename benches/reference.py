"""An independent, straightforward implementation of the `combined` pipeline (static bias, Hong
eq 3 calibration, Hong eq 12 threshold, HDR eq 7-13, trapezoid integration), written from the
equations stage after stage. With ``lag_free=True`` it computes the low-pass (eq 7) and the de-lag
(eq 13) in closed form as the Rust core does: eq 13 inverts eq 7, so the two leave the rate plus
the de-lag of HDR's steps (rust/src/lag_free.rs). Both agree with the core to 1e-9 rad.

It serves twice: run as plain Python it is the "pure-Python loop" of the benchmark and a
correctness oracle in the tests; compiled with ``numba.njit`` it is the Numba version.
Only floats, ints and float64 arrays are used, so Numba compiles it unchanged.
"""

from __future__ import annotations

import math

import numpy as np

def combined(
    t: np.ndarray,
    rate: np.ndarray,
    heading_out: np.ndarray,
    rate_out: np.ndarray | None,
    drift_out: np.ndarray | None,
    bias: float,
    scale: float,
    offset: float,
    threshold: float,
    tau: float,
    increment: float,
    turn_threshold: float,
    c1: float,
    c2: float,
    interval: float,
    lag_free: bool = False,
) -> None:
    """Fill the outputs for one whole log (fixed bias, no temperature, trapezoid rule); a None
    ``rate_out`` or ``drift_out`` is not filled (Numba compiles a version without it)."""
    last_t = 0.0
    lp_prev = 0.0  # per-sample low-pass (eq 7)
    dl_prev = 0.0  # de-lag input memory (eq 13)
    integ_prev = 0.0  # trapezoid memory
    heading = 0.0
    # HDR state: integrator I, the open step's sums, its decision low-pass, sign memory (eq 9).
    integ = 0.0
    step_sum = 0.0
    step_duration = 0.0
    elapsed = 0.0
    dec_prev = 0.0
    dec_started = False
    prev_sign = 2  # none yet
    reps = 0
    for i in range(len(t)):
        dt = 0.0 if i == 0 else t[i] - last_t
        last_t = t[i]
        r = scale * (rate[i] - bias) + offset  # HDR eq 2, Hong eq 3
        r = r * 1.0  # direction factors C_cw = C_ccw = 1 (FOG eq 3), as the core multiplies
        if abs(r) < threshold:  # Hong eq 12
            r = 0.0
        corrected = r
        if i == 0 or lag_free:
            lp = corrected
        else:
            inv = 1.0 / (dt + tau)
            lp = corrected * (dt * inv) + lp_prev * (tau * inv)  # eq 7
        lp_prev = lp
        applied = integ
        # HDR step accounting on the corrected rate (the core's BlockMean).
        step_sum += corrected * dt
        step_duration += dt
        elapsed += dt
        if step_duration > 0.0 and elapsed >= interval - 0.5 * dt:
            mean = step_sum / step_duration
            duration = step_duration
            carry = elapsed - interval
            step_sum = 0.0
            step_duration = 0.0
            elapsed = carry if abs(carry) < 0.5 * interval else 0.0
            if not dec_started:
                filtered = mean
                dec_started = True
            else:
                inv = 1.0 / (duration + tau)
                filtered = mean * (duration * inv) + dec_prev * (tau * inv)
            dec_prev = filtered
            w = filtered + integ
            s = 1 if w > 0.0 else (-1 if w < 0.0 else 0)
            reps = reps + 1 if s == prev_sign else 1  # eq 9
            prev_sign = s
            if abs(filtered) < turn_threshold:  # eq 8 as the text states it
                att = (1.0 + c1) / (1.0 + c1 * math.pow(float(reps), c2))  # eq 10
                integ -= float(s) * att * increment  # eq 11
        w = lp + applied  # eq 12
        if i == 0:
            out = w
        elif lag_free:
            out = w + tau / dt * (applied - dl_prev) if applied != dl_prev else w  # eq 7 then 13
        else:
            out = w + tau / dt * (w - dl_prev)  # eq 13
        dl_prev = applied if lag_free else w
        if i > 0:
            heading += 0.5 * (out + integ_prev) * dt
        integ_prev = out
        heading_out[i] = heading
        if rate_out is not None:
            rate_out[i] = out
        if drift_out is not None:
            drift_out[i] = -applied

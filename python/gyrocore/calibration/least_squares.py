"""Least-squares self-calibration of scale and bias against a rate or heading reference
(Hong eq 4-9)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._arrays import (
    READ_WITH_REFERENCE, READ_WITH_TRUE_RATES, FloatArray, as_float_array, as_window, no_path_for_arrays,
)
from .._checks import UnitError, require_radians, usable, warn
from ..evaluate import unwrap
from ..integration import angle_of
from .inputs import check_series
from .result import MAX_SCALE_ERROR, Calibration


def _solve(g: NDArray[np.float64], z: FloatArray) -> tuple[FloatArray, FloatArray, float, float]:
    """Least squares ``z = G q`` with equilibrated columns (SVD via lstsq): returns q, its
    covariance from the residuals, the residual RMS and the condition number of scaled G."""
    norms = np.linalg.norm(g, axis=0)
    if np.any(norms == 0):
        return np.full(2, np.nan), np.full((2, 2), np.nan), math.nan, math.inf
    scaled = g / norms
    q_scaled, _, rank, sv = np.linalg.lstsq(scaled, z, rcond=None)
    cond = float(sv[0] / sv[-1]) if rank == g.shape[1] and sv[-1] > 0 else math.inf
    q = q_scaled / norms
    resid = z - g @ q
    dof = max(len(z) - 2, 1)
    sigma2 = float(resid @ resid) / dof
    cov = sigma2 * np.linalg.pinv(scaled.T @ scaled) / np.outer(norms, norms)
    return q, cov, float(np.sqrt(np.mean(resid**2))), cond


#: A least-squares problem whose reference motion is worse conditioned than this cannot
#: separate scale from bias (Hong: "the robot should be changing rate during the calibration").
MAX_CONDITION = 1e6


#: A fitted ``s_bar`` within this factor of 180/pi: the reference is in degrees, the gyro in radians.
DEGREE_FACTOR = 2.0


def _check_units(method: str, s_bar: float, scale_error: float) -> None:
    """Refuse a fit whose reference is in degrees (it changes about 180/pi times as much as the
    gyro's rate or angle), and warn of a scale error no gyro has (a wrong unit of either)."""
    reference, unit = ("rate_reference", "rad/s") if method == "rate_reference" else ("heading_ref", "rad")
    if 1.0 / DEGREE_FACTOR < s_bar / math.degrees(1.0) < DEGREE_FACTOR:
        raise UnitError(
            f"{method}: the reference changes {s_bar:.4g} times as much as the gyro (s_bar), about 180/pi = 57.3: "
            f"{reference} looks like degrees; convert it to {unit} (numpy.radians)"
        )
    if abs(scale_error) > MAX_SCALE_ERROR:
        warn(
            f"{method}: the fitted scale error is {100 * scale_error:+.3g} %, beyond +-{100 * MAX_SCALE_ERROR:g} % "
            f"for any gyro: the units of the gyro's rate (rad/s) or of the reference ({unit}) look wrong"
        )


def check_gain(method: str, s_bar: float) -> float:
    """The scale error of a fit's ``s_bar`` (the reference's turn over the gyro's), checked: a
    ValueError where it is not positive (a reference of the other sign) or the reference looks like
    degrees, a warning where no gyro has it."""
    if not s_bar > 0:
        raise ValueError(
            f"the fit gives s_bar = {s_bar:.4g} <= 0 (the gyro would read against the motion): "
            "the rate must change during calibration, and the reference must match the gyro's axis and sign"
        )
    scale_error = 1.0 / s_bar - 1.0
    _check_units(method, s_bar, scale_error)
    return scale_error


def _calibration_from_q(
    method: str, q: FloatArray, cov: FloatArray, rms: float, cond: float, window: tuple[float, float] | None, n: int
) -> Calibration:
    """s and b from ``q = (s_bar, b_bar)`` (Hong eq 3 inverted), with first-order standard errors."""
    s_bar, b_bar = float(q[0]), float(q[1])
    scale_error = check_gain(method, s_bar)
    bias = -b_bar / s_bar
    # Jacobians of s = 1/s_bar - 1 and b = -b_bar/s_bar with respect to (s_bar, b_bar).
    js = np.array([-1.0 / s_bar**2, 0.0])
    jb = np.array([b_bar / s_bar**2, -1.0 / s_bar])
    return Calibration(
        method=method,
        bias=bias,
        scale_error=scale_error,
        bias_stderr=float(np.sqrt(max(jb @ cov @ jb, 0.0))),
        scale_error_stderr=float(np.sqrt(max(js @ cov @ js, 0.0))),
        residual_rms=rms,
        condition_number=cond,
        window=window,
        samples=n,
    )


#: :func:`heading_reference` fits the bias alone when the least-squares standard error of the scale
#: error exceeds this [1]. On the real logs that turn (f110, KITTI, broad: 1-21 rad) it is at most
#: 0.33 %; on comma_seg40, whose reference turns by 0.02 rad, 4.9 % (for a fitted scale error of
#: 56 %), and more on straight simulated drives (docs/rest_tracking.md): a typical gyro's scale
#: error is a percent or two, so a fit less certain than that cannot tell it.
MAX_SCALE_STDERR = 0.01


#: ... or when the gyro's angle, less its straight line in time (what a bias alone gives), spans
#: less than this [rad]: a window at rest, whose angle is its noise, fitted s_bar = 125 (a gain of
#: 0.008) with a first-order standard error of 0.25 %, which shrinks with the gain. Over the whole
#: log the real gyros turn so by 1.0 (broad_10) to 6.3 rad (kitti_0018_mems), comma_seg40's by 0.02.
MIN_SCALE_TURN = 0.1


def _turn(angle: FloatArray, time: FloatArray) -> float:
    """The span [rad] of ``angle`` less its least-squares line in ``time``: the gyro's turning, not
    its bias's drift."""
    line = np.polynomial.polynomial.polyfit(time, angle, 1)
    return float(np.ptp(angle - np.polynomial.polynomial.polyval(time, line)))


def _bias_only(g: NDArray[np.float64], z: FloatArray, window: tuple[float, float], n: int, note: str) -> Calibration:
    """Hong eq 5 with ``s_bar = 1``: the heading change less the gyro's angle is ``b_bar`` times the
    elapsed time; the bias ``b = -b_bar``."""
    angle, time = g[:, 0], g[:, 1]
    b_bar = float((z - angle) @ time) / float(time @ time)
    resid = z - angle - b_bar * time
    sigma2 = float(resid @ resid) / max(len(z) - 1, 1)
    return Calibration(
        method="heading_reference",
        bias=-b_bar,
        bias_stderr=math.sqrt(sigma2 / float(time @ time)),
        residual_rms=float(np.sqrt(np.mean(resid**2))),
        window=window,
        samples=n,
        notes=(note,),
    )


def _excited(reference_design: NDArray[np.float64], what: str) -> None:
    """Raise unless the reference motion excites the scale factor (columns not collinear)."""
    norms = np.linalg.norm(reference_design, axis=0)
    cond = math.inf
    if np.all(norms > 0):
        sv = np.linalg.svd(reference_design / norms, compute_uv=False)
        cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    if not cond < MAX_CONDITION:
        raise ValueError(
            f"the rate must change during calibration: {what} cannot separate the scale error "
            f"from the bias (condition number {cond:.3g}); calibrate over a motion with turns of "
            "different rates (Hong section 3.1)"
        )


@no_path_for_arrays("gyrocore.calibration.rate_reference", READ_WITH_TRUE_RATES)
def rate_reference(rate_measured: ArrayLike, rate_reference: ArrayLike) -> Calibration:
    """Least squares against a reference rate at the same instants (Hong eq 8-9).

    Minimises ``sum (r - s_bar r_m - b_bar)^2`` for ``q = (s_bar, b_bar)``. Hong eq 8 as printed
    has the columns of its matrix swapped (its first row reads ``sum r_m * s_bar + sum r_m^2 *
    b_bar = sum r r_m``); the normal equations of this fit are
    ``[[sum r_m^2, sum r_m], [sum r_m, n]] q = [sum r r_m, sum r]``, which is what is solved
    (by SVD on column-scaled data rather than by Cramer's rule, for conditioning).

    Args:
        rate_measured: gyro readings r_m [rad/s].
        rate_reference: true rates r at the same instants [rad/s].

    Raises:
        ValueError: unequal lengths, NaN or a rate beyond +-2^20 rad/s, fewer than 3 samples, or a
            reference rate that does not change ("the rate must change during calibration").
    """
    rm = as_float_array("rate_measured", rate_measured, unit="rad/s")
    r = as_float_array("rate_reference", rate_reference, unit="rad/s")
    if len(rm) != len(r):
        raise ValueError(f"rate_measured has {len(rm)} samples but rate_reference has {len(r)}")
    if len(rm) < 3:
        raise ValueError(f"need at least 3 samples to fit scale and bias, got {len(rm)}")
    for name, a in (("rate_measured", rm), ("rate_reference", r)):
        bad = np.flatnonzero(~usable(a))  # beyond a reading's limit, 1e300 overflowed into "constant readings"
        if len(bad):
            i = bad[0]
            if not np.isfinite(a[i]):
                raise ValueError(f"{name}[{i}] is {a[i]}: samples must be finite")
            raise ValueError(f"{name}[{i}] = {a[i]} rad/s is beyond +-2^20 rad/s (the limit of a reading): check the unit")
    ones = np.ones_like(r)
    _excited(np.column_stack([r, ones]), "a constant reference rate")
    q, cov, rms, cond = _solve(np.column_stack([rm, ones]), r)
    if not cond < MAX_CONDITION:
        raise ValueError(
            f"the rate must change during calibration: the gyro's readings are constant (condition number {cond:.3g})"
        )
    # no window: the readings come without times (their indices were printed and saved as seconds)
    return _calibration_from_q("rate_reference", q, cov, rms, cond, None, len(r))


def reference_rows(
    t: ArrayLike, rate_measured: ArrayLike, t_ref: ArrayLike, heading_ref: ArrayLike,
    window: tuple[float, float] | None, *, minimum: int,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
    """The checked gyro (``t``, ``rate_measured``) and reference (``t_ref``, ``heading_ref``), and the
    indices of the reference samples inside the gyro's span and ``window``: at least ``minimum``
    of them, else a ValueError (the checks every fit against a reference heading makes)."""
    ta, ra = check_series(t, rate_measured, rate_name="rate_measured", minimum=2)
    tr, hr = check_series(t_ref, heading_ref, t_name="t_ref", rate_name="heading_ref", readings=False)
    require_radians("heading_ref", tr, hr)
    lo, hi = ta[0], ta[-1]
    if window is not None:
        start, end = as_window("window", window)
        if end < lo or start > hi:  # the span between them read "200.0 .. 119.99 s"
            raise ValueError(f"the window [{start}, {end}] s lies outside the gyro's log ({lo} .. {hi} s); give it "
                             "in the log's own time base")
        lo, hi = max(lo, start), min(hi, end)
    inside = np.flatnonzero((tr >= lo) & (tr <= hi))
    if len(inside) < minimum:
        # a reference.csv of a header alone was asked about its time base
        why = "are both in the same time base?" if len(tr) >= minimum else f"the reference has {len(tr)} in all"
        raise ValueError(f"only {len(inside)} reference sample(s) fall inside the gyro's span {lo} .. {hi} s; need at "
                         f"least {minimum} ({why})")
    return ta, ra, tr, hr, inside


@no_path_for_arrays("gyrocore.calibration.heading_reference", READ_WITH_REFERENCE)
def heading_reference(
    t: ArrayLike,
    rate_measured: ArrayLike,
    t_ref: ArrayLike,
    heading_ref: ArrayLike,
    *,
    window: tuple[float, float] | None = None,
) -> Calibration:
    """Least squares against a reference heading (Hong eq 4-7), at the reference's own times.

    Hong eq 5 stacks ``psi(k+n) - psi(k) = s_bar h sum r_m + n h b_bar``: the heading change
    since the first reference sample equals ``s_bar`` times the gyro's integral plus ``b_bar``
    times the elapsed time. Here the gyro's integral (trapezoid over its actual intervals) is
    interpolated at each reference time, so the reference may come at another rate and at
    other instants (the paper: 20 Hz reference, 100 Hz gyro); rows are the reference samples
    inside the gyro's span (and ``window``). With a regular gyro and a reference at its sample
    times this is eq 6-7 with the trapezoid rule for eq 4's sum.

    Args:
        t, rate_measured: gyro timestamps [s] and readings [rad/s].
        t_ref, heading_ref: reference times [s, same time base] and heading [rad, may be
            wrapped to (-pi, pi]; it is unwrapped].
        window: ``(start, end)`` [s] to calibrate over (Hong used the first 20 s); None: all.

    The residuals of a heading fit are correlated (they are integrals), so ``bias_stderr`` and
    ``scale_error_stderr`` are optimistic; the residual RMS is in rad. A reference that turns too
    little to determine the scale (the scale's standard error over :data:`MAX_SCALE_STDERR`, which
    a barely turning drive reaches however little noise it has, or a gyro that turns by less than
    :data:`MIN_SCALE_TURN` besides its bias's drift) gets the bias alone: scale error
    0, no ``scale_error_stderr``, a note saying why, and an :class:`~gyrocore.InputWarning`.

    A scale error beyond :data:`MAX_SCALE_ERROR` (50 %) warns that a unit looks wrong.

    Raises:
        ValueError: bad samples, fewer than 3 reference samples inside the gyro's span, a
            motion that does not change rate ("the rate must change during calibration"), or a
            reference in degrees (a step of over 180 between two samples, or a fit that finds it
            changing about 180/pi times as much as the gyro's angle).
    """
    ta, ra, tr, hr, inside = reference_rows(t, rate_measured, t_ref, heading_ref, window, minimum=3)
    origin = ta[0]
    angle = angle_of(ta - origin, ra)  # its input warned of its units
    times = tr[inside] - origin
    psi = unwrap(hr)[inside]
    g1 = np.interp(times, ta - origin, angle)
    g = np.column_stack([g1 - g1[0], times - times[0]])
    z = psi - psi[0]
    _excited(
        np.column_stack([z, times - times[0]])[1:],
        "a reference heading that turns at one constant rate (or not at all)",
    )
    q, cov, rms, cond = _solve(g[1:], z[1:])
    span = (float(tr[inside[0]]), float(tr[inside[-1]]))
    # The scale error's standard error, to first order (for s_bar <= 0 too: a confident fit against
    # the motion, a reference of the other sign, still gets its error from _calibration_from_q).
    s_bar, stderr = float(q[0]), math.sqrt(max(float(cov[0, 0]), 0.0))
    stderr = stderr / s_bar**2 if s_bar != 0 else math.inf
    turn = _turn(g[:, 0], g[:, 1])
    if stderr <= MAX_SCALE_STDERR and turn >= MIN_SCALE_TURN:
        return _calibration_from_q("heading_reference", q, cov, rms, cond, span, len(inside))
    # which of the two turns too little is said: a gyro that does not follow a turning reference
    # (another axis, another column) is no reference that barely turns
    why = (f"the gyro turns by {turn:.3g} rad besides its steady drift, under {MIN_SCALE_TURN:g} rad, and the reference "
           f"by {np.ptp(z):.3g} rad" if turn < MIN_SCALE_TURN else
           f"the reference turns by {np.ptp(z):.3g} rad and the gyro by {turn:.3g} besides its steady drift; the "
           f"scale's standard error would be {100 * stderr:.3g} %, over {100 * MAX_SCALE_STDERR:g} %")
    note = (
        f"too little to determine the scale ({why}): the bias alone was fitted (scale error 0); calibrate over a "
        "drive with turns for the scale, with the gyro's axis and sign matching the reference's"
    )
    warn(f"heading_reference: {note}")
    return _bias_only(g[1:], z[1:], span, len(inside), note)

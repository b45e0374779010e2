"""The papers' heading metrics: the error of a heading against a reference (E_psi, HDR eq 15;
NE_psi, HDR eq 16; Hong Table 1's mean and standard deviation), the improvement factor over plain
integration (HDR Table II) and the return orientation error of a closed path (FOG section 4.1).
:mod:`gyrocore.evaluate` re-exports the public names.

Units: radians inside, degrees in the fields named ``*_deg``; times in seconds.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import READ_A_HEADING, READ_TO_SCORE, FloatArray, as_float_array, no_path_for_arrays, too_few_inside
from ._checks import (
    check_number, collected, require_finite, require_flag, require_increasing, require_radians, require_series, warn,
    warn_if_wrapped,
)

#: An interval longer than this many times the median interval is a gap (a logger or tracking
#: outage). Irregular ROS logging stays below about 5 times its median (f110_ds3: 4.1).
GAP_FACTOR = 10.0


@dataclass(frozen=True)
class HeadingErrors:
    """Heading error against a reference, in degrees (compared at the reference's times)."""

    e_psi_deg: float
    """Average absolute heading error E_psi (HDR eq 15)."""
    ne_psi_deg_per_min: float
    """E_psi per minute of duration, NE_psi (HDR eq 16)."""
    mean_error_deg: float
    """Mean absolute error (Hong Table 1's mean error; equal to E_psi)."""
    std_error_deg: float
    """Standard deviation of the absolute error (Hong Table 1)."""
    final_error_deg: float
    """Signed error (estimate - reference) at the last compared reference time."""
    max_error_deg: float
    """Largest absolute error."""
    duration_min: float
    """Compared duration T_d [min], from the first to the last compared reference time."""
    n: int
    """Number of reference samples compared."""
    gaps: int = 0
    """Gaps (of the reference or of the estimate) inside the compared span that were skipped."""

    def as_dict(self) -> dict[str, float]:
        """The metrics as a plain dict (for JSON)."""
        return asdict(self)


def unwrap(heading: ArrayLike) -> np.ndarray:
    """Continuous heading [rad] from one wrapped to (-pi, pi]."""
    return np.unwrap(as_float_array("heading", heading, unit="rad"))


def find_gaps(t: ArrayLike, *, gap_factor: float = GAP_FACTOR) -> np.ndarray:
    """Which intervals ``t[k] -> t[k+1]`` are gaps: longer than ``gap_factor`` times the median.

    Returns a boolean array of length ``len(t) - 1``.

    Raises:
        ValueError: a ``gap_factor`` that is not finite and > 1 (NaN found no gap), times that are
            not finite or not strictly increasing (a NaN time hid the gap around it), naming the first.
        TypeError: a ``gap_factor`` that is no number.
    """
    check_number("gap_factor", gap_factor, low=1.0)
    ta = as_float_array("t", t)
    require_finite("t", ta)
    require_increasing("t", ta)
    dt = np.diff(ta)
    if len(dt) == 0:
        return np.zeros(0, dtype=bool)
    return np.asarray(dt > gap_factor * float(np.median(dt)))


def _unwrapped_between(heading: FloatArray, gaps: np.ndarray) -> FloatArray:
    """``numpy.unwrap`` of each stretch of ``heading`` between ``gaps`` (:func:`find_gaps`), in one
    pass over all of them: a mask of each stretch over the whole reference took 21.8 s to score
    4*10^6 samples with a gap a second, and a call per stretch 0.64 s for 20,000 stretches."""
    step = np.diff(heading)
    # numpy.unwrap's correction of each step, none across a gap
    wrapped = np.mod(step + math.pi, 2 * math.pi) - math.pi
    wrapped[(wrapped == -math.pi) & (step > 0)] = math.pi
    correction = np.where((np.abs(step) < math.pi) | gaps, 0.0, wrapped - step)
    total = np.concatenate(([0.0], np.cumsum(correction)))
    # each sample less what the corrections came to at the start of its stretch
    index = np.arange(len(heading))
    start = np.maximum.accumulate(np.where(np.concatenate(([True], gaps)), index, 0))
    unwrapped: FloatArray = heading + (total - total[start])
    return unwrapped


class Reference:
    """A reference heading prepared once and scored against many estimates (tuning does thousands).

    The reference (rad, may be wrapped to (-pi, pi]) is unwrapped between its gaps. Across a gap
    its number of whole turns is unknown, so the turn count is chosen that makes the reference's
    change over the gap closest to the estimate's: the error stays continuous as long as the
    estimate does not drift by half a turn during the gap.

    Args:
        t_ref: reference times [s], strictly increasing, any rate.
        heading_ref: reference heading [rad], counter-clockwise positive.
        gap_factor: an interval longer than this many times the median interval is a gap, on the
            reference and on the estimate. Reference samples inside a gap of the estimate are not
            scored (the estimate there is only an interpolation).
        time_weighted: average the absolute error over time instead of over samples. HDR eq 15
            averages samples (its reference came at a regular 1 Hz); with a bursty reference the
            time average weighs each moment equally. Gap intervals get no weight.
    """

    def __init__(
        self,
        t_ref: ArrayLike,
        heading_ref: ArrayLike,
        *,
        gap_factor: float = GAP_FACTOR,
        time_weighted: bool = False,
    ) -> None:
        require_flag("time_weighted", time_weighted)  # "no" scored time-weighted
        # its own copies: the caller's arrays changed later (times out of order) were scored unchecked,
        # against the gaps and stretches found in them as they were
        t = as_float_array("t_ref", t_ref, copy=True)
        psi = as_float_array("heading_ref", heading_ref, copy=True, unit="rad")
        require_series("t", t, "heading", psi, context="reference")
        require_radians("the reference heading", t, psi)
        if len(t) < 2:
            raise ValueError(f"reference: {len(t)} sample(s); a heading error needs at least two reference samples")
        gaps = find_gaps(t, gap_factor=gap_factor)
        # Segment k starts after the k-th gap; unwrap within segments only.
        segment = np.concatenate(([0], np.cumsum(gaps)))
        unwrapped = _unwrapped_between(psi, gaps)
        self.given = psi
        """Reference heading [rad] as given (wrapped or not)."""
        self.t = t
        """Reference times [s]."""
        self.heading = unwrapped
        """Reference heading [rad], unwrapped within each stretch between gaps."""
        self.segment = segment
        """Index of the stretch between gaps that each sample belongs to."""
        self.gap_factor = gap_factor
        self.time_weighted = time_weighted

    def compared(
        self, t: ArrayLike, heading: ArrayLike, *, absolute: bool = False
    ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """The estimate's error at the compared reference times.

        Returns ``(t_compared, error [rad], gap_after)``: the error is estimate minus reference,
        both aligned to 0 at the first compared time (with ``absolute``, not aligned: wrapped to
        (-pi, pi], for a heading made absolute by fixes); ``gap_after[k]`` says whether the
        interval after sample ``k`` crosses a gap (of either side) and so is not scored.
        """
        require_flag("absolute", absolute)  # "no" compared the wrapped difference
        te = as_float_array("t", t)
        est_all = as_float_array("heading", heading, unit="rad")
        require_series("t", te, "heading", est_all, context="estimate")
        if len(te) < 2:
            raise ValueError("need at least two heading samples to compare")
        if not absolute:  # an absolute comparison wraps the difference, so a wrapped heading is fine there
            warn_if_wrapped(te, est_all, " (or compare with absolute=True)")
        inside = (self.t >= te[0]) & (self.t <= te[-1])
        est_gaps = find_gaps(te, gap_factor=self.gap_factor)
        if est_gaps.any():
            k = np.clip(np.searchsorted(te, self.t, side="right") - 1, 0, len(est_gaps) - 1)
            inside &= ~(est_gaps[k] & (self.t > te[k]) & (self.t < te[np.minimum(k + 1, len(te) - 1)]))
        idx = np.flatnonzero(inside)
        if len(idx) < 2:
            raise ValueError(too_few_inside("the reference", self.t, "the heading", te))
        tr, ref, seg = self.t[idx], self.heading[idx].copy(), self.segment[idx]
        est = np.interp(tr, te, est_all)
        # Consecutive compared samples not adjacent in the reference skipped an estimate gap.
        gap_after = (np.diff(idx) > 1) | (np.diff(seg) != 0)
        # Each crossing's whole turns, added to everything after it at once: added crossing by
        # crossing, they took a pass over the rest of the reference each.
        j = np.flatnonzero(np.diff(seg) != 0)
        if len(j):
            shift = np.zeros(len(ref))
            shift[j + 1] = 2 * math.pi * np.round(((est[j + 1] - est[j]) - (ref[j + 1] - ref[j])) / (2 * math.pi))
            ref += np.cumsum(shift)
        if absolute:
            return tr, np.angle(np.exp(1j * (est - ref))), gap_after
        return tr, (est - est[0]) - (ref - ref[0]), gap_after

    def _scored(self, t: ArrayLike, heading: ArrayLike, absolute: bool) -> tuple[FloatArray, FloatArray, np.ndarray,
                                                                             FloatArray | None]:
        """The compared times, the error [rad], which intervals cross a gap, and each sample's
        weight in E_psi (None: equal)."""
        tr, err_rad, gap_after = self.compared(t, heading, absolute=absolute)
        weights = None
        if self.time_weighted:
            # Each sample weighs half of each scored interval next to it (trapezoid rule).
            dt = np.where(gap_after, 0.0, np.diff(tr))
            weights = np.concatenate((dt, [0.0])) / 2 + np.concatenate(([0.0], dt)) / 2
            if weights.sum() == 0:
                weights = None
        return tr, err_rad, gap_after, weights

    def e_psi(self, t: ArrayLike, heading: ArrayLike, *, absolute: bool = False) -> float:
        """E_psi [deg] of an estimated heading against this reference (HDR eq 15), alone."""
        _, err_rad, _, weights = self._scored(t, heading, absolute)
        return float(np.average(np.degrees(np.abs(err_rad)), weights=weights))

    def errors(self, t: ArrayLike, heading: ArrayLike, *, absolute: bool = False) -> HeadingErrors:
        """Score an estimated heading (continuous, rad) against this reference (HDR eq 15-16;
        ``absolute``: see :meth:`compared`)."""
        tr, err_rad, gap_after, weights = self._scored(t, heading, absolute)
        abs_err = np.degrees(np.abs(err_rad))
        e_psi = float(np.average(abs_err, weights=weights))
        std = float(np.sqrt(np.average((abs_err - e_psi) ** 2, weights=weights)))
        duration_min = float(tr[-1] - tr[0]) / 60.0
        return HeadingErrors(
            e_psi_deg=e_psi,
            ne_psi_deg_per_min=e_psi / duration_min if duration_min > 0 else math.nan,
            mean_error_deg=e_psi,
            std_error_deg=std,
            final_error_deg=float(np.degrees(err_rad[-1])),
            max_error_deg=float(abs_err.max()),
            duration_min=duration_min,
            n=len(tr),
            gaps=int(gap_after.sum()),
        )


@no_path_for_arrays("gyrocore.heading_errors", READ_TO_SCORE)
def heading_errors(
    t: ArrayLike,
    heading: ArrayLike,
    t_ref: ArrayLike,
    heading_ref: ArrayLike,
    *,
    gap_factor: float = GAP_FACTOR,
    time_weighted: bool = False,
    absolute: bool = False,
) -> HeadingErrors:
    """Compare an estimated heading with a reference heading (HDR eq 15-16, Hong Table 1).

    The estimate (continuous, rad) is linearly interpolated at the reference's times inside its
    own time span; the reference (rad, may be wrapped) is unwrapped. Both are aligned at the first
    compared reference time (only relative heading is meaningful), and E_psi averages the absolute
    difference over the reference samples (HDR eq 15), NE_psi divides it by the duration in minutes
    (eq 16). Gaps are skipped as :class:`Reference` describes; both sides may have irregular rates.
    ``absolute``: no alignment, the wrapped difference (a heading made absolute by fixes).
    """
    reference = Reference(t_ref, heading_ref, gap_factor=gap_factor, time_weighted=time_weighted)
    errors = reference.errors(t, heading, absolute=absolute)
    warn_if_degrees(reference, t, heading, errors.e_psi_deg, absolute=absolute)
    warn_if_clockwise(reference, t, heading, errors.e_psi_deg, absolute=absolute)
    warn_if_longer(reference, t, errors.n)
    warn_if_offset(reference, t, heading, errors.e_psi_deg, absolute=absolute)
    return errors


#: Converting a side from degrees must make E_psi at least this many times smaller to say so: on the
#: 18 real logs (raw, static_bias, hdr, recommended, combined; whole and causal) a correct reference
#: converted made it at most 1.0 times smaller, one in degrees at least 16 times; an estimate 61 and
#: 57 times (comma_seg40, whose drift is no turn: see :func:`warn_if_degrees`).
DEGREES_GAIN = 10.0
#: A side in degrees turns about 57 times as far as the other: said only where it turns at least
#: this many times as far. On the real logs a reference in degrees turned at least 24 times as far
#: as the estimate (13 against broad_11's raw one, which drifts 19 deg where the drive turns 4.5:
#: not said), an estimate in degrees 39 times; comma_seg40's estimate in radians, drifting 116 deg
#: on a straight road, 11 times as far as its reference in degrees: the reference is to blame.
DEGREES_TURNING = 20.0


def warn_if_degrees(reference: Reference, t: ArrayLike, heading: ArrayLike, e_psi: float, *, absolute: bool) -> None:
    """Warn where the reference (else the estimate) looks like degrees, which :func:`require_radians`
    sees only where it wraps (a drive in [0, 360) that never crossed 0 scored 517 deg). Said where
    E_psi with that side converted from degrees is :data:`DEGREES_GAIN` times smaller than as given
    (``e_psi``) and smaller than the other side's own turning (its mean distance from its first
    heading, what a heading that stays put would score: else both barely turn, and comma_seg40's
    estimate, drifting on a straight road, scored 61 times smaller divided by 57), and where that
    side as given turns :data:`DEGREES_TURNING` times as far as the other."""
    te, est = as_float_array("t", t), as_float_array("heading", heading, unit="rad")
    start = max(te[0], reference.t[0])
    ref_turning = _turning(reference.t, reference.given, start)  # as given: unwrapping mangles degrees
    est_turning = _turning(te, est, start)
    # each side converted and scored against the other as given, with both sides' turning; the
    # turning first, which rules out nearly every call before a second scoring is paid for
    for side, turning, other in (("reference", ref_turning, est_turning), ("estimate", est_turning, ref_turning)):
        if not turning >= DEGREES_TURNING * other:
            continue
        given, against = ((reference.t, reference.given), (te, est)) if side == "reference" else (
            (te, est), (reference.t, reference.heading))
        if abs(_scale(*given, *against, start)) < DEGREES_SCALE:
            continue  # it turns as the other does, in radians: it drifts away (a gyro's bias over hours)
        with collected([]):  # the comparison as given said what it had to (a wrapped estimate)
            if side == "reference":
                converted = _rescored(reference, reference.t, np.radians(reference.given), te, est, absolute)
            else:
                converted = reference.e_psi(te, np.radians(est), absolute=absolute)
        if DEGREES_GAIN * converted <= e_psi and converted < other:
            warn(f"the {side} heading looks like degrees: E_psi {e_psi:.4g} deg as given, {converted:.4g} deg with "
                 f"the {side} in degrees; convert with numpy.radians")
            return


#: A side in degrees changes about 57 times as much as the other between two moments: said only
#: where it changes at least this many times as much (:func:`_scale`). Measured: on five real logs
#: (comma_seg40, broad_11, f110_ds1, kitti_0018_mems) and a simulated drive of 10^4 s, raw,
#: static_bias and recommended, 0.72 to 1.02 in radians, 41 to 58 with either side in degrees.
#: Without it, raw integration over a simulated drive of 10^4 s at 10 Hz was said to be in degrees
#: on 2 of 3 seeds (drifting 7000 deg, its drift divided by 57 came near the reference).
DEGREES_SCALE = 10.0


def _scale(t: FloatArray, heading: FloatArray, t_other: FloatArray, other: FloatArray, start: float) -> float:
    """How many times as much ``heading`` changes as ``other`` between the other's samples from
    ``start`` on (about 1000 steps): the least-squares slope of its changes on the other's, with a
    rate of its own beside it, so that a bias's drift (a change in proportion to the time) is not
    taken for a change in scale; negative where the two turn opposite ways. Infinite where there
    are too few steps to say."""
    grid = t_other[(t_other >= start) & (t_other <= t[-1])]
    grid = grid[:: max(1, len(grid) // 1000)]
    if len(grid) < 4:
        return math.inf
    changes, other_changes = np.diff(np.interp(grid, t, heading)), np.diff(np.interp(grid, t_other, other))
    return float(np.linalg.lstsq(np.column_stack((other_changes, np.diff(grid))), changes, rcond=None)[0][0])


#: The reference must turn against the estimate at least this much (the slope of its changes on the
#: estimate's, :func:`_scale`: -1 for a clockwise reference) to be called clockwise. Measured on the
#: 18 real logs (raw, static_bias, recommended; whole and causal): 0.75 to 1.00 as given, -1.00 to
#: -0.75 with the reference negated.
CLOCKWISE_SCALE = -0.5


def warn_if_clockwise(reference: Reference, t: ArrayLike, heading: ArrayLike, e_psi: float, *,
                      absolute: bool) -> None:
    """Warn where one side turns clockwise and the other counter-clockwise: a compass bearing given
    as the reference (clockwise from north), or a gyro mounted upside down. Each turn then adds twice
    its angle to the error (f110_ds3 with static_bias scored 397 deg against 3.65). Said where the
    reference turns against the estimate (:data:`CLOCKWISE_SCALE`), whatever E_psi: where a drift
    outweighs the turns, a clockwise reference may even score better (raw integration of a simulated
    50-minute highway drive: 15.98 deg against a clockwise reference, 16.51 against the right one)."""
    te, est = as_float_array("t", t), as_float_array("heading", heading, unit="rad")
    if not _scale(reference.t, reference.heading, te, est, max(te[0], reference.t[0])) <= CLOCKWISE_SCALE:
        return
    negated = _rescored(reference, reference.t, -reference.given, te, est, absolute)
    warn(f"the reference heading turns clockwise where the estimate turns counter-clockwise: E_psi {e_psi:.4g} "
         f"deg as given, {negated:.4g} deg with the reference negated. Headings are counter-clockwise: a "
         f"compass bearing (clockwise from north) is heading = pi/2 - radians(bearing); a gyro mounted upside "
         f"down needs its rate negated")


def _rescored(reference: Reference, t_ref: FloatArray, heading_ref: FloatArray, t: FloatArray, heading: FloatArray,
              absolute: bool) -> float:
    """E_psi against ``reference`` with its times or headings mended as a check supposes (the
    reference's own gap rule and weights), in silence: the comparison as given said what it had
    to."""
    with collected([]):
        return Reference(t_ref, heading_ref, gap_factor=reference.gap_factor,
                         time_weighted=reference.time_weighted).e_psi(t, heading, absolute=absolute)


#: A reference whose turns follow the estimate's this much later or earlier [s] (and at least 3 of
#: the steps compared) looks like another clock. On the 18 real logs as they are (static_bias) the
#: turns match best within 0.1 s (KITTI's reference leads by one 10 Hz sample); shifted by 0.5 s,
#: f110_ds3 scored E_psi 14.4 deg against 3.65, by 18 s (GPS against UTC) 91.3.
OFFSET_LAG = 0.25
#: ... and where the turns match that well there (a correlation of the two rates): on a drive that
#: barely turns, or one too short for the lag, the best match is chance. The real logs shifted by
#: 0.5 to 18 s matched at 0.54 to 1.00 where the lag was found, at 0.22 and 0.32 where it was not.
OFFSET_MATCH = 0.5
#: The longest lag looked for [s]: beyond it the two spans mostly do not overlap, which the span
#: checks say.
OFFSET_SEARCH = 60.0


def warn_if_offset(reference: Reference, t: ArrayLike, heading: ArrayLike, e_psi: float, *, absolute: bool) -> None:
    """Warn where the reference's turns follow the estimate's :data:`OFFSET_LAG` or more later or
    earlier: a reference on a clock offset from the gyro's (GPS time against UTC, a logger's
    latency) was scored as it was given, each turn counted at the wrong time. The lag is where the
    cross-correlation of the two rates (their changes on a common grid, by FFT) peaks."""
    te, est = as_float_array("t", t), as_float_array("heading", heading, unit="rad")
    lo, hi = max(te[0], reference.t[0]), min(te[-1], reference.t[-1])
    step = max(float(np.median(np.diff(te))), float(np.median(np.diff(reference.t))), (hi - lo) / 2**17)
    grid = np.arange(lo, hi, step)
    ours, theirs = np.diff(np.interp(grid, te, est)), np.diff(np.interp(grid, reference.t, reference.heading))
    k = min(int(OFFSET_SEARCH / step), len(ours) // 4)
    if k < 3:  # too short an overlap to look for a lag (and an empty one has no mean)
        return
    ours, theirs = ours - ours.mean(), theirs - theirs.mean()
    norm = float(np.linalg.norm(ours) * np.linalg.norm(theirs))
    if norm == 0:
        return
    size = 1 << int(math.ceil(math.log2(2 * len(ours))))
    corr = np.fft.irfft(np.fft.rfft(theirs, size) * np.conj(np.fft.rfft(ours, size)), size)
    corr = np.concatenate((corr[-k:], corr[: k + 1])) / norm  # lags -k .. k steps
    best = int(np.argmax(corr))
    lag = (best - k) * step
    if abs(lag) < max(OFFSET_LAG, 3 * step) or corr[best] < OFFSET_MATCH or corr[best] <= corr[k]:
        return
    shifted = _rescored(reference, reference.t - lag, reference.given, te, est, absolute)
    warn(f"the reference's turns follow the estimate's {lag:.3g} s {'later' if lag > 0 else 'earlier'} (their "
         f"rates match {corr[best]:.2f} there, {corr[k]:.2f} at the same times): its clock looks offset from the "
         f"gyro's; E_psi {e_psi:.4g} deg as given, {shifted:.4g} deg with the reference's times less {lag:.3g} s. "
         f"Give both on one clock (GPS time runs 18 s ahead of UTC)")


#: A reference this many times as long as the heading it scores looks like times in another unit.
LONGER_RATIO = 100.0


def warn_if_longer(reference: Reference, t: ArrayLike, n: int) -> None:
    """Warn where the reference spans :data:`LONGER_RATIO` times as long as the heading: a reference
    timed in ms against a gyro in seconds, both from 0, overlaps the heading over its first
    thousandth and was scored there on a handful of samples (f110_ds3 with static_bias: 4 samples,
    E_psi 109.6 deg against 3.65)."""
    te = as_float_array("t", t)
    span, ref_span = float(te[-1] - te[0]), float(reference.t[-1] - reference.t[0])
    if ref_span >= LONGER_RATIO * span:
        warn(f"the reference spans {ref_span:.6g} s, {ref_span / span:.3g} times the heading's {span:.6g} s: only "
             f"{n} of its {len(reference.t)} samples fall inside the heading's span and are scored; if the "
             f"reference's times are in ms, us or ns, convert them to seconds")


def _turning(t: FloatArray, heading: FloatArray, start: float) -> float:
    """How far ``heading`` [rad] at the times ``t`` turns from where it is at ``start`` (the first
    compared time): its mean distance from there [deg] from then on."""
    after = heading[t >= start]
    return float(np.degrees(np.mean(np.abs(after - np.interp(start, t, heading))))) if len(after) else 0.0


def improvement(raw: HeadingErrors, method: HeadingErrors) -> float:
    """Relative improvement over plain integration: E_psi without / E_psi with (HDR Table II); 1
    where neither has an error (0 / 0 was infinite), infinite where the method alone has none."""
    if method.e_psi_deg > 0:
        return raw.e_psi_deg / method.e_psi_deg
    return math.inf if raw.e_psi_deg > 0 else 1.0


@no_path_for_arrays("gyrocore.evaluate.return_orientation_error", READ_A_HEADING)
def return_orientation_error(
    t: ArrayLike,
    heading: ArrayLike,
    *,
    t_start: float | None = None,
    t_end: float | None = None,
    rotation: float | None = None,
) -> float:
    """Return orientation error E_g of a closed path [rad] (FOG section 4.1).

    The rotation measured from ``t_start`` to ``t_end`` (default: the whole record; the heading is
    interpolated at both) minus the actual rotation ``rotation`` [rad]. Without a reference the
    actual rotation of a closed lap is a whole number of turns; by default the whole number nearest
    to the measured rotation (right while the error stays below half a turn). Positive: the
    estimate turned further counter-clockwise than the vehicle.
    """
    te = as_float_array("t", t)
    psi = as_float_array("heading", heading, unit="rad")
    require_series("t", te, "heading", psi)
    if len(te) < 2:  # no sample was a bare IndexError
        raise ValueError(f"a return orientation error needs at least two samples, got {len(te)}")
    if rotation is not None:  # NaN gave NaN, text a bare TypeError of the subtraction
        rotation = check_number("rotation", rotation, low=None, unit=" [rad]")
    warn_if_wrapped(te, psi)  # a wrap between the lap's ends counted as a turn
    # text was numpy's bare UFuncTypeError, 10**400 an OverflowError, True the time 1 s
    t0 = te[0] if t_start is None else check_number("t_start", t_start, low=None, unit=" [s]")
    t1 = te[-1] if t_end is None else check_number("t_end", t_end, low=None, unit=" [s]")
    if not te[0] <= t0 < t1 <= te[-1]:
        raise ValueError(f"the lap [{t0}, {t1}] s must lie inside the record [{te[0]}, {te[-1]}] s")
    measured = float(np.interp(t1, te, psi) - np.interp(t0, te, psi))
    if rotation is None:
        rotation = 2 * math.pi * round(measured / (2 * math.pi))
    return measured - rotation

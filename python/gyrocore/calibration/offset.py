"""A gyro's time offset against its reference heading: how far the gyro's clock is from the
reference's, fitted jointly with the gyro's bias and scale error."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .._arrays import READ_WITH_REFERENCE, no_path_for_arrays
from .._checks import check_number
from ..evaluate import unwrap
from ..fixes import Fixes
from ..fixes_check import MIN_PAIRS, Agreement, agreement
from .least_squares import MIN_SCALE_TURN, _turn, check_gain, reference_rows

#: The largest offset looked for by default [s]. The real logs' are within 0.07 s; from
#: ``evaluate``'s :data:`~gyrocore.evaluate_metrics.OFFSET_LAG` (0.25 s) on, scoring a heading
#: warns of an offset and says how large (a cross-correlation of the rates, to the grid's step).
MAX_OFFSET = 0.5

#: A reference that turns by less than this [rad] besides its least-squares line in time (a steady
#: turn, or none) tells no offset, whatever the fit's standard error says: a gyro's noise alone
#: makes the rate change, and fits it a small, wrong offset with a small standard error. The real
#: logs' references turn so by 0.98 (broad_10) to 6.1 rad (f110_ds5, kitti_0018), comma_seg40's
#: by 0.021 (its fit gave +0.005 +- 0.0005 s). As :data:`~.least_squares.MIN_SCALE_TURN` asks of the
#: gyro's turn for a scale.
MIN_TURN = MIN_SCALE_TURN

#: A fit whose offset's standard error exceeds this [s] cannot tell the offset: the drive does not
#: change its rate enough for its noise. On the real logs that turn it is at most 0.0016 s (f110_ds1).
MAX_OFFSET_STDERR = 0.01

#: The fit is shifted by this much [s] either way from the offset found, to see how much of a
#: shift it finds: 1 where the gyro's rate changes are the motion's; ...
PROBE = 0.01
#: ... under this, they are mostly the gyro's noise and the offset is not told: a turn of 0.15 rad
#: read by a gyro with 0.3 rad/s of noise (0.02 of it) found +0.004 s for +0.06 with a standard
#: error of 0.0006 s. The real logs that turn: 0.89 (broad_10) to 1.08 (kitti_0034).
MIN_FOLLOWS = 0.5

#: Each step of the fit moves the offset by the lag the first-order fit finds left; it stops when
#: that is below this fraction of the offset's standard error (or 1 us) ...
CONVERGED = 0.01
#: ... or after this many steps.
MAX_STEPS = 20


@dataclass(frozen=True)
class TimeOffset:
    """The time offset between a gyro and its reference heading (:func:`time_offset`).

    Attributes:
        offset: [s] to ADD to the gyro's times to put them on the reference's clock: the reading
            stamped ``t`` was taken at the reference's ``t + offset``. Negative for a gyro whose
            readings are stamped late (KITTI's OXTS rate: about -0.06 s), positive for one stamped
            early (the f110 car's: +0.03 s).
        offset_stderr: its standard error [s], from the robust scatter of the per-step residuals,
            over how much of a shift the fit sees (:data:`PROBE`; about 1 on the real logs).
        scale_error, scale_error_stderr: the gyro's scale error ``s`` [1] fitted with it (Hong eq 1).
        bias: the gyro's bias ``b`` [rad/s] fitted with it (the step residuals' rate).
        scatter: robust scatter [rad] of the residuals of the reference's steps (its heading's
            change between consecutive samples) after the shift.
        pairs: consecutive reference samples fitted (after leaving out outliers).
        window: the span of reference times fitted [s] (the reference's clock).
        steps: the fit's iterations.
    """

    offset: float
    offset_stderr: float
    scale_error: float
    scale_error_stderr: float
    bias: float
    scatter: float
    pairs: int
    window: tuple[float, float]
    steps: int

    def __repr__(self) -> str:
        return (f"TimeOffset(offset = {self.offset:+.4f} +- {self.offset_stderr:.2g} s (add to the gyro's times), "
                f"scale error = {100 * self.scale_error:.3g} +- {100 * self.scale_error_stderr:.2g} %, "
                f"bias = {self.bias:.4g} rad/s, step residual scatter {self.scatter:.3g} rad, {self.pairs} pairs, "
                f"window {self.window[0]:.12g} .. {self.window[1]:.12g} s)")


@no_path_for_arrays("gyrocore.calibration.time_offset", READ_WITH_REFERENCE)
def time_offset(
    t: ArrayLike,
    rate_measured: ArrayLike,
    t_ref: ArrayLike,
    heading_ref: ArrayLike,
    *,
    window: tuple[float, float] | None = None,
    max_offset: float = MAX_OFFSET,
) -> TimeOffset:
    """The offset [s] to add to a gyro's times to put them on its reference heading's clock.

    Example: KITTI's OXTS yaw rate is stamped about 0.06 s after the yaw it matches, so
    ``time_offset`` gives about -0.06; ``t + offset`` are then the gyro's times on the
    reference's clock (``gyrocore.process(t + offset, rate, ...)``, or score the heading at
    ``result.t + offset``). A positive offset is a gyro stamped early.

    The fit is the one :mod:`gyrocore.fixes_check` checks heading fixes with (the model the KITTI
    logs' ``meta.json`` ``checks.clean_steps_fit`` fits too): each step of the reference's heading
    between consecutive samples, less the gyro's integral over the same interval, fitted by least
    squares to the interval (the bias), the gyro's integral (the scale error) and the change of
    the gyro's rate across it (the first-order term of a shift: ``G(t + d) ~ G(t) + d r(t)``), with
    steps beyond 5 robust sigmas left out. Steps rather than the heading since the first sample
    (as :func:`heading_reference` fits): a gyro's white noise makes the heading's residuals a
    random walk, the steps' independent, so the standard errors hold. The first-order term is
    exact only for a small shift; the fit is repeated on the gyro's times shifted by the offset
    found so far (the gyro's integral at the reference's times then the exact integral of its
    linearly interpolated rate) until what it finds left is a hundredth of its standard error, at
    most :data:`MAX_STEPS` times (Gauss-Newton on the shift; three or four on the real logs). The
    result is not tied to a grid of samples: a 10 Hz gyro stamped 0.06 s late gives -0.06, not 0
    or -0.1, and an offset of a few samples is found as precisely as a small one.

    Args:
        t, rate_measured: gyro timestamps [s] and readings [rad/s].
        t_ref, heading_ref: reference times [s] and heading [rad, may be wrapped], on a clock
            offset from the gyro's by at most ``max_offset``.
        window: ``(start, end)`` [s] to fit over (the log's time base); None: all.
        max_offset: the largest offset looked for [s] (default :data:`MAX_OFFSET`).

    Raises:
        ValueError: what :func:`heading_reference` refuses (bad samples, a reference in degrees,
            too few reference samples inside the gyro's span: here :data:`MIN_PAIRS` + 1);
            a drive whose rate does not change enough to tell an offset (a reference that turns by
            less than :data:`MIN_TURN` besides a steady turn: a straight drive, a constant turn; a
            gyro whose rate changes are mostly its noise, the fit seeing under :data:`MIN_FOLLOWS`
            of a shift; or an offset's standard error over :data:`MAX_OFFSET_STDERR`): refused,
            not returned with a warning, since no value would be right; an offset the fit does
            not settle on within ``max_offset`` (a larger one: ``gyrocore evaluate`` warns of
            those and says how large).
    """
    max_offset = check_number("max_offset", max_offset, unit=" [s]")
    ta, ra, tr, hr, inside = reference_rows(t, rate_measured, t_ref, heading_ref, window, minimum=MIN_PAIRS + 1)
    # sigma 1/sqrt(2): the pairs are weighted 1, their scatter is in rad
    fixes = Fixes(tr[inside], unwrap(hr)[inside], np.full(len(inside), math.sqrt(0.5)))
    turn = _turn(fixes.heading - fixes.heading[0], fixes.t - fixes.t[0])
    if not turn >= MIN_TURN:
        raise ValueError(f"the rate must change during calibration to tell a time offset: the reference turns by "
                         f"{turn:.3g} rad besides a steady turn, under {MIN_TURN:g} rad; fit over a drive with turns "
                         "that start and end")
    offset, steps = 0.0, 0
    fit = _fit(ta, ra, fixes, 0.0)
    check_gain("time_offset", 1.0 + fit.scale)  # a reference in degrees, or turning the other way
    while True:
        steps += 1
        offset += fit.lag  # the reference stamped later than the gyro by lag: the gyro's times gain it
        if not abs(offset) <= max_offset:
            raise ValueError(f"the gyro's time offset against the reference looks larger than max_offset = "
                             f"{max_offset:g} s (the fit reached {offset:+.3g} s): give a larger max_offset, or "
                             "score the heading (gyrocore evaluate), which warns of offsets of 0.25 s and more")
        fit = _fit(ta, ra, fixes, offset)
        if abs(fit.lag) <= max(CONVERGED * fit.lag_se, 1e-6) or steps >= MAX_STEPS:
            break
    # How much of a shift the fit sees: a gyro's noise in its rate's changes shrinks the first-order
    # coefficient towards 0 (errors in the variable), and with it the offset's standard error.
    follows = (_fit(ta, ra, fixes, offset - PROBE).lag - _fit(ta, ra, fixes, offset + PROBE).lag) / (2 * PROBE)
    if not follows >= MIN_FOLLOWS:
        raise ValueError(f"the rate must change during calibration to tell a time offset: the gyro's rate changes "
                         f"are mostly its noise (a shift of its times by {PROBE:g} s moves the fit by {follows:.2g} of "
                         f"it, under {MIN_FOLLOWS:g}); fit over a drive with turns that start and end")
    stderr = fit.lag_se / follows
    if not stderr <= MAX_OFFSET_STDERR:
        raise ValueError(f"the rate must change during calibration to tell a time offset: the offset's standard "
                         f"error is {stderr:.3g} s, over {MAX_OFFSET_STDERR:g} s; fit over a drive with turns "
                         "that start and end")
    s_bar = 1.0 + fit.scale  # the reference's turn over the gyro's, the inverse of Hong's 1 + s
    return TimeOffset(
        offset=offset,
        offset_stderr=stderr,
        scale_error=1.0 / s_bar - 1.0,
        scale_error_stderr=fit.scale_se / s_bar**2,
        bias=-fit.bias / s_bar,
        scatter=fit.scatter,
        pairs=fit.pairs,
        window=(float(fixes.t[0]), float(fixes.t[-1])),
        steps=steps,
    )


def _fit(t: np.ndarray, rate: np.ndarray, fixes: Fixes, offset: float) -> Agreement:
    """The first-order fit of :func:`~gyrocore.fixes_check.agreement` with the gyro's times shifted
    by ``offset``; a ValueError where the motion does not let it fit.

    The gyro's readings are first given samples at the reference's times (its rate interpolated
    there), so that its trapezoid integral there is the exact integral of its linearly interpolated
    rate: ``agreement`` interpolates the integral linearly between the gyro's samples, a chord that
    at KITTI's 10 Hz is off by up to a tenth of the step's turn and made the shifted fit's
    residuals larger than the unshifted (where the two sets of times coincide)."""
    times = np.union1d(t, fixes.t - offset)
    fit = agreement(times + offset, np.interp(times, t, rate), fixes)
    if fit is None:
        raise ValueError("the rate must change during calibration to tell a time offset: the reference's steps fit "
                         "no turn of the gyro (a drive at rest or at one rate)")
    return fit

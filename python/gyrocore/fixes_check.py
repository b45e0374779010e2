"""Heading fixes checked against the gyro of a whole log, before they are fused.

Between two consecutive fixes the gyro says how far the heading turned. A fix's heading change
less the gyro's integral over the same interval is, for good fixes on the gyro's clock, the fixes'
noise plus what the gyro's bias and scale error add, and the filter estimates those two. A least
squares fit of that difference over every pair of consecutive fixes (:func:`agreement`) to the
interval (the bias), the gyro's turn (the scale error) and the change of the rate (a lag between
the two clocks: a fix stamped ``lag`` seconds after the heading it gives differs by ``-lag`` times
the rate) shows three mistakes the filter cannot see: fixes that turn other than the gyro (a bearing
clockwise from north: the turn's coefficient near -2; radians read as degrees: -0.98), fixes late
or early on the gyro's clock (a receiver's latency, another clock's offset), and fixes that scatter
far beyond their stated sigma. Each made the fused heading wrong by 2 to 100 deg on the KITTI drives, mostly with no
warning, or with the outlier gate's, which named units (docs/fixes_model.md, "Fixes checked against
the gyro").
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ._arrays import FloatArray
from ._checks import warn

if TYPE_CHECKING:
    from .fixes import Fixes

#: The fewest pairs of consecutive fixes a fit is made from.
MIN_PAIRS = 10
#: A coefficient is trusted this many standard errors from the value it is tested against.
SIGMAS = 3.0
#: The fixes' heading change over the gyro's, less 1, beyond this (a gyro's scale error is a few
#: per cent) means the fixes are no heading in rad counter-clockwise from east: -2 for a mirrored
#: heading (a bearing clockwise from north), -0.98 for radians read as degrees.
MAX_SCALE = 0.5
#: Radians read as degrees turn this many times less (180 / pi).
DEGREES_PER_RAD = 180.0 / math.pi
#: A lag [s] beyond this is warned about. The KITTI drives' fixes from their own reference lead
#: the gyro by 0.00-0.10 s (the published rate lags the reference); fixes 0.1 s late cost up to
#: 0.3 deg, 0.3 s late 1.6-19.7 deg, and those were found 0.20-0.27 s late.
MAX_LAG = 0.15
#: A robust scatter of the pairs' normalised differences beyond this many times 1 means the fixes'
#: stated sigma is too small: 0.08-1.51 for honest fixes on the KITTI drives (1 deg simulated, from
#: GNSS velocities or from positions; consecutive fixes from positions share one), 1.5-2.4 for
#: sigmas 1.5 times too small (which already had the gate reject good fixes one after another and
#: the heading 87 deg off on one drive), 7.9-9.4 for 10 times.
MAX_SCATTER = 2.0


@dataclass(frozen=True)
class Agreement:
    """How a whole log's fixes agree with its gyro between consecutive fixes (the fit of
    :func:`agreement`; standard errors from the pairs' robust scatter)."""

    pairs: int
    scale: float
    """The fixes' heading change over the gyro's, less 1 (near 0; -2 for a mirrored heading)."""
    scale_se: float
    lag: float
    """[s] how much later the fixes are stamped than the heading they give, on the gyro's clock."""
    lag_se: float
    scatter: float
    """The robust scatter of the pairs' differences, each over what the fixes' stated sigmas make it
    (1 for honest sigmas)."""
    bias: float
    """[rad/s] the fixes' heading rate beyond the gyro's (the interval's coefficient: minus the
    gyro's bias, to first order)."""


def agreement(t: FloatArray, rate: FloatArray, fixes: Fixes) -> Agreement | None:
    """The fit of consecutive fixes' heading changes to the gyro's (``t`` [s], ``rate`` [rad/s],
    readings that are not finite left out), or None with under :data:`MIN_PAIRS` pairs of fixes
    within the gyro's span, or too little motion to fit."""
    kept = np.isfinite(rate)
    if not kept.all():
        t, rate = t[kept], rate[kept]
    if len(t) < 2:
        return None
    inside = (fixes.t >= t[0]) & (fixes.t <= t[-1])
    if np.count_nonzero(inside) <= MIN_PAIRS:
        return None
    ft, heading, sigma = fixes.t[inside], fixes.heading[inside], fixes.sigma[inside]
    gyro, omega = np.diff(np.interp(ft, t, _turned(t, rate))), np.diff(np.interp(ft, t, rate))
    dt = np.diff(ft)
    pair = dt > 0  # two fixes at one time span no turn
    if np.count_nonzero(pair) < MIN_PAIRS:
        return None
    # the fixes' change less the gyro's, wrapped: fixes wrapped at +-pi or continuous alike
    y = np.angle(np.exp(1j * (np.diff(heading) - gyro)))[pair]
    a = np.column_stack((dt, gyro, -omega))[pair]
    weight = 1.0 / np.sqrt(sigma[:-1] ** 2 + sigma[1:] ** 2)[pair]
    return _fit(a * weight[:, None], y * weight)


def _turned(t: FloatArray, rate: FloatArray) -> FloatArray:
    """The gyro's turn [rad] from the first sample to each, by the trapezoid rule: the values of
    ``0.5 * (rate[1:] + rate[:-1]) * np.diff(t)`` summed, built in one array (a log's fixes are
    checked on every call, and the temporaries of the plain expression took twice the time of the
    fused run itself)."""
    turned = np.empty(len(t))
    turned[0] = 0.0
    step = turned[1:]
    np.add(rate[1:], rate[:-1], out=step)
    step *= 0.5
    step *= np.subtract(t[1:], t[:-1])
    np.cumsum(step, out=step)
    return turned


def _fit(a: FloatArray, y: FloatArray) -> Agreement | None:
    """Least squares of ``y`` on ``a``'s columns (interval, gyro turn, rate change), fitted again
    without the pairs beyond 5 robust sigmas (a burst of outliers enters and leaves with two)."""
    keep = np.ones(len(y), dtype=bool)
    for _ in range(2):
        x, *_ = np.linalg.lstsq(a[keep], y[keep], rcond=None)
        residual = y - a @ x
        scatter = 1.4826 * float(np.median(np.abs(residual[keep])))
        keep = np.abs(residual) <= 5.0 * scatter
        if np.count_nonzero(keep) < MIN_PAIRS or scatter == 0.0:
            return None
    x, *_ = np.linalg.lstsq(a[keep], y[keep], rcond=None)
    normal = a[keep].T @ a[keep]
    if np.linalg.cond(normal) > 1e12:  # no motion: the turn and the interval are one column
        return None
    se = scatter * np.sqrt(np.diag(np.linalg.inv(normal)))
    return Agreement(int(np.count_nonzero(keep)), float(x[1]), float(se[1]), float(x[2]), float(se[2]),
                     scatter, float(x[0]))


def warn_disagreement(t: FloatArray, rate: FloatArray, fixes: Fixes) -> None:
    """Warns (:class:`~gyrocore.InputWarning`) when a whole log's fixes turn other than its gyro
    (against it, or in another unit), lag or lead it by more than :data:`MAX_LAG`, or scatter
    beyond :data:`MAX_SCATTER` times their stated sigma (:func:`agreement`)."""
    fit = agreement(t, rate, fixes)
    if fit is None:
        return
    said = f"(a fit over {fit.pairs} pairs of consecutive fixes against the gyro's turn between them)"
    if abs(fit.scale) > MAX_SCALE + SIGMAS * fit.scale_se:
        cause = _written_as(t, rate, fixes) or _turn_cause(fit.scale)
        warn(f"the heading fixes change by {1.0 + fit.scale:.3g} times the gyro's turn {said}: {cause}")
        return
    if abs(fit.lag) > MAX_LAG and abs(fit.lag) > SIGMAS * fit.lag_se:
        late = "later" if fit.lag > 0 else "earlier"
        warn(f"the heading fixes are stamped about {abs(fit.lag):.2g} s (+-{fit.lag_se:.1g}) {late} than the heading "
             f"they give, on the gyro's clock {said}; a fix that far off in time is off by the turn in between, and "
             f"the gate rejects good fixes: give the fixes' times on the gyro's clock (fixes.t "
             f"{'-' if fit.lag > 0 else '+'} {abs(fit.lag):.2g}{': a receiver latency' if fit.lag > 0 else ''})")
    if fit.scatter > MAX_SCATTER:
        sigma = math.degrees(float(np.median(fixes.sigma)))
        written = _written_as(t, rate, fixes)
        if written is not None:  # the unit, not the sigma: "state each fix's sigma" would mislead
            warn(f"the heading fixes disagree with the gyro's turn between them {fit.scatter:.3g} times as much as "
                 f"their stated sigma allows {said}: {written}")
            return
        warn(f"the heading fixes disagree with the gyro's turn between them {fit.scatter:.3g} times as much as their "
             f"stated sigma allows (about {fit.scatter * sigma:.2g} deg a fix, where the median sigma is {sigma:.3g} "
             f"deg) {said}: the filter trusts them too much, its gate rejects good fixes, and the heading goes wrong. "
             f"If their headings are right, state each fix's sigma as its real error (about {fit.scatter:.2g} times "
             "larger); headings in degrees or a bearing clockwise from north do this too: they are in rad, "
             "counter-clockwise from east")


#: What fix headings may have been written as, how to convert them, and the conversion.
_WRITTEN_AS = (
    ("degrees", "numpy.radians", np.radians),
    ("bearings in degrees clockwise from north", "from_gnss, or pi/2 - radians(bearing)",
     lambda h: np.pi / 2 - np.radians(h)),
)


def _written_as(t: FloatArray, rate: FloatArray, fixes: Fixes) -> str | None:
    """What the fixes' headings are, where read so they turn as the gyro does; None if no reading
    does. A continuous heading in degrees steps by tens of rad between fixes, and wrapped those
    fit no turn at all: the sample drive's fitted -2.71, and was said to be a bearing the other way."""
    from .fixes import Fixes  # fixes imports this module

    for what, how, convert in _WRITTEN_AS:
        fit = agreement(t, rate, Fixes(fixes.t, convert(fixes.heading), fixes.sigma))
        if fit is not None and abs(fit.scale) <= MAX_SCALE + SIGMAS * fit.scale_se:
            return (f"read as {what} they turn as the gyro does: convert them ({how}); headings are in rad, "
                    "counter-clockwise from east")
    return None


def _turn_cause(scale: float) -> str:
    """What makes fixes turn ``1 + scale`` times as far as the gyro, where a scale error is small."""
    ratio = 1.0 + scale
    if ratio < 0.0:
        return ("they turn the other way. A bearing clockwise from north (a compass or GNSS course) given as a "
                "heading counter-clockwise from east does that: convert it (from_gnss, or pi/2 - radians(bearing)); "
                "or the gyro counts clockwise (negate its rate)")
    if abs(ratio * DEGREES_PER_RAD - 1.0) < MAX_SCALE:
        return ("57 times less: an angle in radians read as degrees (from_gnss and read_gnss_csv take the bearing in "
                "degrees, clockwise from north), or a rate in deg/s (it is in rad/s)")
    return "check the units: fix headings in rad, counter-clockwise from east, the rate in rad/s"

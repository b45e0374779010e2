"""The rests of a whole log: found, measured and accepted (for :mod:`gyrocore.wholelog`), as
:class:`gyrocore.rests.Rest` records.

A rest is found where a given speed shows the vehicle standing still (speed below
:data:`SPEED_THRESHOLD` m/s throughout) or, where no speed is known, from the rate alone
(:func:`gyrocore.calibration.rest_windows`). Each is measured by the core's static bias test (the estimator of the pipeline's
rest window; FOG section 2, HDR eq 1-2): its time-weighted mean, the noise of one reading and
the batch-means standard error, which stays honest when slow motion or low-frequency noise
moves the mean. A found rest is used only when it lasts :data:`MIN_REST` seconds, its noise is
at most :data:`NOISE_RATIO` times the median of the rests' noise (a stop with the engine
shaking or the vehicle creeping is not a rest) and, among three or more, its mean agrees with
what the others give within :data:`OUTLIER_SIGMAS` (leave-one-out, through the smoother). A rest
the rate alone found is no stronger evidence than a steady turn, which reads as steady: it is used
only where it spans :data:`MIN_RATE_BLOCKS` of the finder's blocks or is far quieter than the rest
of the log (:data:`QUIET_RATIO`, at the upper confidence bound of its noise), and only where the
rate's rests agree (one of them refused as an outlier, or two that disagree, and none of them is
used).

Units: s, rad/s, m/s.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import replace
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from . import _gyrocore
from ._arrays import FloatArray
from ._checks import usable
from ._motion import warn_if_turning
from ._smoother import LeaveOneOut
from ._time_steps import time_steps_named
from .rests import Rest
from .window import (
    MIN_WINDOW_READINGS, RestWindowError, no_usable_reading, refuse_few_readings, refuse_past_end, refuse_window_outside,
    rest_window_text,
)

#: Below this speed [m/s] the vehicle stands still (wheel and CAN speeds read a few cm/s of noise).
SPEED_THRESHOLD = 0.05
#: A stop whose mean rate exceeds this [rad/s] is a turn on the spot, not a rest (as
#: :func:`gyrocore.calibration.rest_windows`' ``max_rate``).
MAX_REST_RATE = 0.05
#: Left out at each end of a stop the speed shows [s] (at most a quarter of the stop).
EDGE = 0.5
#: A found rest lasts at least this long [s] by default (chosen by leave-one-log-out; docs/whole_log.md).
MIN_REST = 1.0
#: A found rest whose noise exceeds this many times the median of the rests' noise is refused.
NOISE_RATIO = 2.0
#: Among three or more rests, one whose mean is this many standard deviations from what the
#: others give (leave-one-out) is refused, the worst first, one at a time.
OUTLIER_SIGMAS = 4.0
#: A rest found from the rate alone is used only where it spans this many blocks of
#: :func:`gyrocore.calibration.rest_windows` (0.25 s, at least 4 readings each: 2 s at 16 Hz or
#: more, 3.2 s at 10 Hz). About a fifth of the 4-reading blocks of a gyro's noise at 10 Hz are as
#: quiet as its test asks (a standard deviation below about 0.6 of the noise's), turning or not: a
#: run of 8 comes by chance about once in 2 x 10^5 blocks (22 hours at 10 Hz), a run of 3 once in
#: 100 (40 s).
MIN_RATE_BLOCKS = 8
#: ... or where its noise is at most this fraction of the rest of the log's: a real gyro on a
#: moving vehicle shakes (f110's rests read 1 % of its motion's noise, broad's hand-held IMU's 1 %),
#: a gyro whose noise is the same moving or not (a simulation) is quiet by chance as often resting
#: as turning (23-76 %), and the OXTS rate of KITTI, filtered, reads 7-18 % in slow driving too.
QUIET_RATIO = 0.05
#: The quiet test holds for the upper bound of a rest's noise at this one-sided confidence,
#: as a standard normal quantile (95 %): the noise of a few readings is known only within a
#: chi-square factor (4 readings: up to 4.2 times what they read), and a steady curve of a smooth
#: rate averaged to 2 Hz read a twenty-eighth of the drive's noise over 4 readings.
QUIET_CONFIDENCE_Z = 1.645


def _runs(t: FloatArray, flag: np.ndarray) -> list[tuple[float, float]]:
    """Stretches where ``flag`` holds, from their first to their last time."""
    edges = np.diff(np.concatenate(([0], flag.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(float(t[a]), float(t[b])) for a, b in zip(starts, ends)]


class Found(NamedTuple):
    """What :func:`find_rests` found."""

    windows: list[tuple[float, float, str]]
    """Every candidate rest as ``(start, end, found_by)``, in time order."""
    motion_noise: float = math.nan
    """The rate's noise outside the rests found from the rate [rad/s] (the median standard
    deviation of its blocks), against which :func:`accept` judges them; NaN where none was looked
    for, or the log is nearly all rest."""


def find_rests(t: FloatArray, rate: FloatArray, speed: FloatArray | None = None, min_rest: float = MIN_REST) -> Found:
    """Every candidate rest of the log; ``t`` is finite and strictly increasing (the plan's caller
    checked it: :func:`gyrocore.wholelog.times_ok`).

    Where the speed (one per sample, NaN where unknown) is known, a rest is where it stays below
    :data:`SPEED_THRESHOLD` for ``min_rest`` [s] (``speed``), less :data:`EDGE` at each end (at
    most a quarter of the stop: braking and pulling off rock the vehicle, and a speed sampled
    slower than the gyro lags); one whose mean rate exceeds :data:`MAX_REST_RATE` (a turn on the
    spot) is found and then refused by :func:`accept`, so that the report lists it. Where it is not, a rest is where the rate alone shows one
    (:func:`gyrocore.calibration.rest_windows`, ``rate``).
    """
    from .calibration.rest import rests_and_motion  # calibration builds on the pipeline module too

    taken = usable(rate)  # the readings the pipeline takes (a NaN or 1e300 would spoil a block's variance)
    found: list[tuple[float, float, str]] = []
    known = np.zeros(len(t), dtype=bool) if speed is None else np.isfinite(speed)

    def within(a: float, b: float) -> slice:
        # the samples of [a, b] (t increases): a slice, not a mask over the whole log per rest,
        # so that a log with many stops costs no more than its length times a few
        return slice(int(np.searchsorted(t, a, side="left")), int(np.searchsorted(t, b, side="right")))

    if speed is not None:
        for a, b in _runs(t, known & (np.abs(np.where(known, speed, 0.0)) <= SPEED_THRESHOLD)):
            trim = min(EDGE, (b - a) / 4)
            inside = within(a + trim, b - trim)
            if b - a >= min_rest and taken[inside].any():  # one of a mean rate too large is refused by accept
                found.append((a + trim, b - trim, "speed"))
    motion = math.nan
    if np.count_nonzero(taken) >= 8 and not known.all():
        try:
            # the times were checked once for the whole log, and these are its usable readings
            every = taken.all()  # then no copy of the log
            windows, motion = rests_and_motion(t if every else t[taken], rate if every else rate[taken], min_rest)
        except ValueError:  # too sparse to judge a rest from the rate: none is found (the plan warns)
            windows = []
        found += [(a, b, "rate") for a, b in windows if not known[within(a, b)].any()]
    return Found(sorted(found), motion)


def few_readings_hint(t: FloatArray, speed: FloatArray | None) -> str:
    """Where the rate alone was searched for rests (no speed, or samples without one) and none was
    found, the sample rate, where it is what hid them: the finder judges a rest by the spread of
    its blocks of 0.25 s, and at a slow rate (10 Hz: 4 readings a block) a block's spread scatters
    so much that a rest's blocks are seldom all quiet, so a rest is too short in readings at this
    rate however long it lasts. Larger blocks would pass a steady drive for rest: the window is to
    be given. A clause to append to the "no rest" message ("" where the blocks hold readings enough)."""
    from .calibration.rest import BLOCK, FEW_BLOCK_READINGS, block_readings  # calibration builds on this module too

    if speed is not None and np.isfinite(speed).all():
        return ""
    interval, readings = block_readings(t)
    if readings >= FEW_BLOCK_READINGS:
        return ""
    width = readings * interval
    return (f"; the rate alone was searched for rests, and at this log's {1.0 / interval:.3g} Hz its blocks of "
            f"{width:.3g} s (at least {BLOCK:g} s and 4 readings) hold {readings:.0f} readings, too few for their "
            f"spread to tell a rest from motion (at least {FEW_BLOCK_READINGS:.0f}): at this sample rate a rest is too "
            "short in readings to be found from the rate alone, even a long one; give its window (bias_window or "
            "bias_duration) or the vehicle's speed")


def unseen_stop_hint(t: FloatArray, rate: FloatArray, speed: FloatArray, min_rest: float = MIN_REST) -> str:
    """Where a speed is given and no rest was found: the longest stretch the rate alone takes for a
    rest (:func:`gyrocore.calibration.rest_windows`) where the speed shows motion, as a clause to
    append to the "no rest" message ("" if there is none). Where the speed is known the rate's rests
    are not looked for, so the rate finder's own hint (a steady level beyond its largest bias) does
    not hold: a speed noisy at rest (a receiver's) or sampled slower than the stop shows no stop."""
    from .calibration.rest import longest_steady  # calibration builds on the pipeline module too

    longest = longest_steady(t, rate, min_rest)
    if longest is None:
        return ""
    a, b, level = longest
    inside = slice(int(np.searchsorted(t, a)), int(np.searchsorted(t, b, side="right")))
    known = speed[inside][np.isfinite(speed[inside])]
    return (f"; the speed shows no stop (below {SPEED_THRESHOLD:g} m/s for {min_rest:g} s), but the rate is as steady as "
            f"a rest {a - t[0]:.6g} .. {b - t[0]:.6g} s after the first sample, reading {math.degrees(level):.4g} deg/s, "
            f"where the speed reads {np.min(known):.3g} .. {np.max(known):.3g} m/s: a stop the speed does not show (a "
            "speed noisy at rest, or sampled slower than the stop) or a steady drive; give a rest window there "
            "(bias_window, --bias-window), or find the rests from the rate alone (use_speed=False, --no-speed)")


def measure_rest(chunks: Iterable[tuple[FloatArray, FloatArray]], window: tuple[float, float], found_by: str) -> Rest:
    """The rest ``window`` measured over ``chunks`` of ``(t, rate)`` (read only up to the first
    sample after the window: flat memory for a streamed file); readings the pipeline does not take
    (not finite, or beyond its limit) are left out, as the pipeline holds or skips them.
    ``found_by`` ``given: bias_duration`` names a window that is the first seconds of the log.

    Raises:
        RestWindowError: the window ends before the first sample, holds no reading, or reaches
            past the end of the log; a given window that starts before the first sample, or holds
            fewer than :data:`~gyrocore.pipeline.MIN_WINDOW_READINGS` readings.
    """
    start, end = window
    first = last = math.nan
    kept_t: list[FloatArray] = []
    kept_r: list[FloatArray] = []
    kept_at: list[npt.NDArray[np.intp]] = []  # the kept samples' indices in the log, for an error to name
    before = 0
    for t, rate in chunks:
        if len(t) == 0:
            continue
        if math.isnan(first):
            first = float(t[0])
        last = float(t[-1])
        i0 = max(int(np.searchsorted(t, start, side="left")) - 1, 0)  # the reading before weighs the first
        i1 = int(np.searchsorted(t, end, side="right")) + 1
        kept_t.append(t[i0:i1])
        kept_r.append(rate[i0:i1])
        kept_at.append(np.arange(before + i0, before + min(i1, len(t))))
        before += len(t)
        if last > end:
            break
    if math.isnan(first):
        raise RestWindowError(f"the bias window [{start}, {end}] s: the log has no sample")
    if found_by == "given: bias_duration":  # its start is the log's: its own words
        refuse_past_end(start, end, first, last, duration=end - start)
    refuse_window_outside(start, end, first, last)  # a found rest lies inside the log
    ts, rs, at = np.concatenate(kept_t), np.concatenate(kept_r), np.concatenate(kept_at)
    taken = usable(rs)
    ts, rs, at = ts[taken], rs[taken], at[taken]
    samples = int(np.count_nonzero((ts >= start) & (ts <= end)))
    if samples == 0:
        raise no_usable_reading(start, end, first, last)
    # first: it names a bad sample; times of the window rounded to float32 are named as the whole
    # log's are (a tuning case's rest window was the one pass over them that said "sort the log")
    with time_steps_named(ts, at):
        bias, _, noise, batch_error = _gyrocore.static_bias_test(ts, rs, start, end)
    if found_by.startswith("given"):
        given = {"bias_duration": end - start} if found_by == "given: bias_duration" else {"bias_window": (start, end)}
        refuse_few_readings(rest_window_text(given), samples)
    within = (ts >= start) & (ts <= end)
    inside = rs[within]
    if found_by.startswith("given"):  # a found rest is still by its finder's rules
        warn_if_turning(window, inside, bias)
    white_noise = noise if noise is not None else float(np.std(inside))
    # From the rate alone, readings that correlate are slow motion as likely as a filtered gyro at
    # rest: their mean counts them so. A stop the speed shows, or a given window, is a rest, where
    # correlation is the sensor's filter and batch means see it in all but the shortest.
    one = _correlated(float(np.std(inside)), white_noise, len(inside)) if found_by == "rate" else white_noise
    error = one * _weighted_share(ts[within])
    return Rest(start, end, bias, max(error, batch_error or 0.0), white_noise, samples, found_by.split(":")[0])


def _correlated(spread: float, noise: float, n: int) -> float:
    """One reading's noise as the standard error of a mean of ``n`` readings counts it where
    neighbouring readings are correlated (a filtered rate; slow motion taken for a rest), from
    ``spread`` (their standard deviation) and ``noise`` (from successive differences, which see
    ``1 - rho`` of the variance of readings with lag-1 correlation ``rho``: von Neumann's ratio).
    ``rho`` is corrected for its bias in ``n`` readings (``+ (1 + 3 rho) / n``, Kendall's), and
    the variance of the mean of first-order autoregressive readings is ``spread^2 / n`` times
    ``1 + 2 sum_j (1 - j/n) rho^j``, at most ``spread^2``. White noise (``rho <= 0``) gives
    ``noise``."""
    if not noise < spread:
        return noise
    measured = 1.0 - (noise / spread) ** 2
    rho = min(measured + (1.0 + 3.0 * measured) / n, 1.0)
    lags = np.arange(1, n)
    return spread * math.sqrt(1.0 + 2.0 * float(np.sum((1.0 - lags / n) * rho**lags)))


def _weighted_share(t: FloatArray) -> float:
    """The white-noise standard error of the core's time-weighted mean over readings at ``t``, per
    unit of one reading's noise: ``sqrt(sum w^2) / sum w``, each reading weighted by the time since
    the one before (the first by none). ``1 / sqrt(n)`` counted every reading alike: a rest with a
    gap (readings skipped, a logger's pause) took the one reading after it for the whole gap and
    still read the error of all of them."""
    w = np.diff(t)
    total = float(np.sum(w))
    return math.sqrt(float(np.sum(w * w))) / total if total > 0 else 1.0


def accept(rests: list[Rest], walk: float, motion_noise: float = math.nan) -> list[Rest]:
    """``rests`` (found ones) with those that are not rests marked ``refused`` (see the module doc);
    ``motion_noise`` is :attr:`Found.motion_noise`. A rest of fewer than
    :data:`~gyrocore.window.MIN_WINDOW_READINGS` readings (a short stop of a slow log) is refused
    first: its spread is unknown, and one reading read "+- 0" and outweighed every other rest. So is
    a stop whose mean rate exceeds :data:`MAX_REST_RATE`: a turn on the spot, or a bias that large,
    which the log's stops cannot tell apart (it was left out unlisted: "no rest was found")."""
    rests = [_refuse(r, f"{r.samples} reading(s): a rest's bias needs at least {MIN_WINDOW_READINGS}")
             if r.samples < MIN_WINDOW_READINGS else _refuse(r, _turning(r)) if abs(r.bias) > MAX_REST_RATE else r
             for r in rests]
    measured = [r.noise for r in rests if r.refused is None]
    noise = float(np.median(measured)) if measured else 0.0
    judged = [
        r if r.refused is not None
        else _refuse(r, f"noise {math.degrees(r.noise):.2g} deg/s, over {NOISE_RATIO:g} x the rests' median")
        if r.noise > NOISE_RATIO * noise
        else _refuse(r, _unproven(r, motion_noise)) if _by_rate(r) and not _proven(r, motion_noise)
        else r
        for r in rests
    ]
    out, disagreeing = _refuse_outliers(judged, walk)
    if disagreeing is None:
        return out
    # The rate has taken motion for rest somewhere: none of its rests is used, and the stops the
    # speed shows are judged again among themselves (one refused against the rate's rests was not
    # refused on their word alone).
    why = (f"the rests found from the rate disagree (the one of {disagreeing.start:.3f} .. {disagreeing.end:.3f} s, "
           f"reading {math.degrees(disagreeing.bias):.5f} deg/s, among them): steady turning passes for rest "
           "there, so none of them is used")
    rated = [r if _by_rate(r) else before for r, before in zip(out, judged)]  # a stop's verdict is taken again
    return _refuse_outliers([_refuse(r, why) if _by_rate(r) and r.refused is None else r for r in rated], walk)[0]


def _refuse_outliers(rests: list[Rest], walk: float) -> tuple[list[Rest], Rest | None]:
    """``rests`` with those refused whose mean lies beyond :data:`OUTLIER_SIGMAS` of what the others
    give, the worst first, one at a time (among three or more); and the first rest found from the
    rate that disagrees with the others (one refused so, or one of two that disagree), where the
    refusing stops (its verdict covers the rate's rests, and the rounds after it cannot change it)."""
    out = list(rests)
    used = [i for i, r in enumerate(out) if r.refused is None]
    if len(used) < 2:
        return out, None
    # each refusal filters again only the rests near it (LeaveOneOut), not all of them
    middle, bias, error = (np.array([getattr(out[i], name) for i in used]) for name in ("middle", "bias", "bias_std_error"))
    test = LeaveOneOut(middle, bias, error, walk)
    while True:
        worst = int(np.argmax(np.abs(test.scores)))
        z = float(test.scores[worst])
        if abs(z) <= OUTLIER_SIGMAS:
            break
        if len(used) == 2:  # each lies as far from the other: which is wrong is not known
            rated = [out[i] for i in used if _by_rate(out[i])]
            return out, (rated[0] if rated else None)  # a rest the rate found is no stronger than a steady turn
        i = used.pop(worst)
        out[i] = _refuse(out[i], f"{abs(z):.1f} sigma from what the other rests give")
        if _by_rate(out[i]):
            return out, rests[i]
        test.remove(worst)
    return out, None


def _by_rate(rest: Rest) -> bool:
    return rest.found_by == "rate"


def _proven(rest: Rest, motion_noise: float) -> bool:
    """Whether a rest found from the rate is no chance run of quiet readings: it spans
    :data:`MIN_RATE_BLOCKS` of the finder's blocks, or it is far quieter than the rest of the log
    (:data:`QUIET_RATIO`, by the upper bound of its noise, :func:`_noise_bound`; NaN where the log
    is nearly all rest)."""
    return _blocks(rest) >= MIN_RATE_BLOCKS or not _noise_bound(rest) > QUIET_RATIO * motion_noise


def _noise_bound(rest: Rest) -> float:
    """The upper one-sided confidence bound (:data:`QUIET_CONFIDENCE_Z`) of ``rest``'s noise, which
    its readings' successive differences estimate (von Neumann's mean square successive difference,
    as the core's static bias test does): over ``m = n - 1`` differences of white noise its variance
    is ``(3m - 1) / m^2`` times the noise's fourth power, about ``nu = 2 m^2 / (3m - 1)`` degrees of
    freedom of a chi-square, whose lower quantile is Wilson and Hilferty's cube
    ``nu (1 - 2/(9 nu) - z sqrt(2/(9 nu)))^3`` (``n >= 3``: fewer readings are refused first)."""
    m = rest.samples - 1
    nu = 2.0 * m * m / (3.0 * m - 1.0)
    c = 2.0 / (9.0 * nu)
    return rest.noise / math.pow(1.0 - c - QUIET_CONFIDENCE_Z * math.sqrt(c), 1.5)


def _block_counts(rest: Rest) -> tuple[float, float]:
    """How many of :func:`gyrocore.calibration.rest_windows`' blocks ``rest`` spans by its time
    (blocks of 0.25 s) and by its readings (blocks of 4 sample intervals)."""
    from .calibration.rest import BLOCK  # calibration builds on the pipeline module too

    return (rest.end - rest.start) / BLOCK, (rest.samples - 1) / 4


def _blocks(rest: Rest) -> float:
    """How many of :func:`gyrocore.calibration.rest_windows`' blocks ``rest`` spans (0.25 s, and
    at least 4 sample intervals each)."""
    return min(_block_counts(rest))


def _unproven(rest: Rest, motion_noise: float) -> str:
    return (f"{rest.end - rest.start:.3g} s and {rest.samples} readings ({_blocks(rest):.3g} blocks of 0.25 s or 4 "
            f"readings), its noise {math.degrees(rest.noise):.2g} deg/s (at most {math.degrees(_noise_bound(rest)):.2g} at "
            f"95 % confidence) against {math.degrees(motion_noise):.2g} deg/s "
            "in the rest of the log: too short and not quiet enough for the rate alone to tell a rest from a chance "
            f"run of quiet readings (at least {MIN_RATE_BLOCKS} blocks, or {1 / QUIET_RATIO:g} x quieter)"
            + _short_in_readings(rest))


def _short_in_readings(rest: Rest) -> str:
    """Where the sample rate is what leaves ``rest`` too short: its span holds
    :data:`MIN_RATE_BLOCKS` blocks of 0.25 s, but its readings fewer blocks of 4 (a slow log: 10 Hz
    asks for 3.2 s where 16 Hz or more asks for 2 s). "" where it is not."""
    by_time, by_readings = _block_counts(rest)
    if rest.samples < 2 or by_time < MIN_RATE_BLOCKS or by_readings >= MIN_RATE_BLOCKS:
        return ""
    span = rest.end - rest.start
    interval = span / (rest.samples - 1)
    return (f"; its {span:.3g} s are long enough, but at this log's {1.0 / interval:.3g} Hz they hold too few "
            f"readings: a rest too short in readings at this sample rate (one of {4 * MIN_RATE_BLOCKS * interval:.3g} s "
            "or more is used)")


def _turning(rest: Rest) -> str:
    return (f"its mean rate {math.degrees(rest.bias):.3g} deg/s exceeds {math.degrees(MAX_REST_RATE):.3g} deg/s: a turn "
            "on the spot, or a bias that large (then give it: bias_window over this stop, or bias)")


def _refuse(rest: Rest, why: str) -> Rest:
    return replace(rest, refused=why)

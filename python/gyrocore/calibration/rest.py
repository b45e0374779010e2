"""Rests found from the rate alone, and the static bias test over one (FOG section 2, HDR eq 1-2)."""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _gyrocore
from .._arrays import READ_TO_CALIBRATE, FloatArray, as_window, no_path_for_arrays, span_text
from .._checks import MAX_READING, check_number, did_you_mean, usable
from .._motion import DEG_PER_S_FIX, warn_if_turning
from ..window import refuse_few_readings, refuse_window_outside
from .inputs import check_series
from .result import Calibration


#: Defaults of :func:`rest_windows`: ``block`` [s], ``noise_factor``, ``max_rate`` [rad/s], ``consistency``.
BLOCK, NOISE_FACTOR, MAX_RATE, CONSISTENCY = 0.25, 3.0, 0.05, 4.5
#: :func:`rests_and_motion` gives the motion's noise from at least this many blocks outside the rests.
MIN_MOTION_BLOCKS = 8
#: The options of :func:`rest_windows` that :func:`detect_rest`, :func:`static_bias` and
#: :func:`~gyrocore.calibration.rotary_table` pass on to it.
REST_OPTIONS = ("block", "noise_factor", "max_rate", "consistency")


def refuse_unknown_rest_options(where: str, options: dict[str, Any], also: tuple[str, ...] = ()) -> None:
    """A TypeError naming each of ``options`` that is neither an option of :func:`rest_windows` nor
    of ``also``: a typo failed as ``rest_windows_of_checked() got an unexpected keyword argument``,
    a function the caller never called, or was ignored beside a given window."""
    known = (*REST_OPTIONS, *also)
    unknown = [k for k in options if k not in known]
    if unknown:
        said = ", ".join(f"{k!r}{did_you_mean(k, known)}" for k in unknown)
        raise TypeError(f"{where}: unknown rest option(s) {said}; it takes {', '.join(known)}")


@no_path_for_arrays("gyrocore.calibration.rest_windows", READ_TO_CALIBRATE)
def rest_windows(
    t: ArrayLike,
    rate: ArrayLike,
    *,
    min_duration: float = 1.0,
    block: float = BLOCK,
    noise_factor: float = NOISE_FACTOR,
    max_rate: float = MAX_RATE,
    consistency: float = CONSISTENCY,
) -> list[tuple[float, float]]:
    """Every stretch where the gyro rests, found from the rate alone.

    The log is cut into blocks of ``block`` seconds (at least 4 sample intervals). A block is
    quiet when its standard deviation is at most ``noise_factor`` times the noise floor (the
    median standard deviation of the quietest 1 % of blocks, at least 3) and its mean is within
    ``max_rate`` [rad/s] of zero: a gyro at rest reads only its bias and noise, while a steadier
    than noise reading beyond ``max_rate`` (0.05 rad/s = 2.9 deg/s by default; raise it for a gyro
    with a larger bias) is a steady turn. Consecutive quiet blocks form a rest as long as each
    block's mean agrees with the rest's mean so far within ``consistency`` standard errors (the
    white-noise errors from the floor, scaled by the factor that the readings' correlation within
    quiet blocks gives their means: a gyro's noise may be correlated over a few samples; a
    rest has a constant level; slow motion drifts; one stray block between agreeing ones is
    kept, as a 4-sigma block is expected now and then in a long rest). Rests shorter than
    ``min_duration`` [s] are dropped. Returns ``(start, end)`` pairs [s] in the log's time base,
    from the first to the last sample of the quiet blocks.
    """
    ta, ra = check_series(t, rate)
    return rest_windows_of_checked(ta, ra, min_duration, block, noise_factor, max_rate, consistency)


def rest_windows_of_checked(
    ta: FloatArray, ra: FloatArray, min_duration: float, block: float = BLOCK, noise_factor: float = NOISE_FACTOR,
    max_rate: float = MAX_RATE, consistency: float = CONSISTENCY,
) -> list[tuple[float, float]]:
    """:func:`rest_windows` of samples already checked (equal lengths, finite values, strictly
    increasing times), for a caller that checks them once."""
    return rests_and_motion(ta, ra, min_duration, block, noise_factor, max_rate, consistency)[0]


def rests_and_motion(
    ta: FloatArray, ra: FloatArray, min_duration: float, block: float = BLOCK, noise_factor: float = NOISE_FACTOR,
    max_rate: float = MAX_RATE, consistency: float = CONSISTENCY,
) -> tuple[list[tuple[float, float]], float]:
    """:func:`rest_windows_of_checked`, and the noise of the rest of the log: the median standard
    deviation of the blocks outside every window (NaN where fewer than :data:`MIN_MOTION_BLOCKS`
    lie outside: a log all at rest). Whole mode asks whether a rest is quieter than the motion
    around it (:mod:`gyrocore._rests`)."""
    for name, value in (("min_duration", min_duration), ("block", block), ("noise_factor", noise_factor),
                        ("max_rate", max_rate), ("consistency", consistency)):
        check_number(name, value)
    if len(ta) < 8:
        raise ValueError(f"need at least 8 samples to find a rest, got {len(ta)}")
    # Temporaries as long as the log are made in place where they can be: a whole log of 10^8
    # samples is searched in memory.
    rel = ta - ta[0]  # epoch timestamps lose precision in arithmetic
    width = _block_width(block, float(np.median(np.diff(rel), overwrite_input=True)))
    # The blocks that hold samples, numbered 0, 1, ... in time order: a gap or a jump of the
    # clock costs nothing (one bin per block of the time span would grow with the jump).
    number = np.floor(np.divide(rel, width, out=rel)).astype(np.int64)
    del rel
    k = np.zeros(len(number), dtype=np.intp)
    np.cumsum(np.diff(number) != 0, out=k[1:])
    count = np.bincount(k)
    total = np.bincount(k, ra)
    mean = total / count
    dev = mean[k]
    np.subtract(ra, dev, out=dev)
    var = np.bincount(k, np.square(dev)) / np.maximum(count - 1, 1)
    sd = np.sqrt(var)
    filled = count >= 3
    if not filled.any():
        raise ValueError(f"no block of {width:.3g} s holds 3 samples: the log is too sparse to find a rest")
    quietest = np.sort(sd[filled])
    floor = float(np.median(quietest[: max(3, len(quietest) // 100)]))
    if floor == 0.0:  # a quantized gyro may read one value throughout a block
        steps = np.abs(np.diff(ra))
        floor = float(steps[steps > 0].min()) / math.sqrt(12.0) if (steps > 0).any() else 0.0
    quiet = filled & (sd <= noise_factor * floor) & (np.abs(mean) <= max_rate)
    spread = floor * _correlation_factor(dev, k, quiet)
    # A rest spans quiet blocks only, and no gap (a block that is not quiet, or holds no sample,
    # ends it), so the level test runs over each stretch of quiet neighbours, not every block.
    blocks = number[np.flatnonzero(np.diff(k, prepend=-1))]
    joined = quiet[:-1] & quiet[1:] & (np.diff(blocks) == 1)
    firsts = np.flatnonzero(quiet & ~np.concatenate(([False], joined)))
    ends = np.flatnonzero(quiet & ~np.concatenate((joined, [False]))) + 1
    runs = [run for first, end in zip(firsts.tolist(), ends.tolist())
            for run in _level_runs(first, end, mean, count, total, spread, consistency)]
    outside = filled.copy()
    windows: list[tuple[float, float]] = []
    if runs:
        first_block, last_block = np.array(runs).T
        t0 = ta[np.searchsorted(k, first_block, side="left")]
        t1 = ta[np.searchsorted(k, last_block, side="right") - 1]
        for a, b, f, e in zip(t0.tolist(), t1.tolist(), first_block.tolist(), last_block.tolist()):
            if b - a >= min_duration:
                windows.append((a, b))
                outside[f : e + 1] = False
    motion = float(np.median(sd[outside])) if np.count_nonzero(outside) >= MIN_MOTION_BLOCKS else math.nan
    return windows, motion


def _block_width(block: float, interval: float) -> float:
    """The width [s] of :func:`rest_windows`' blocks: ``block``, and at least 4 sample intervals."""
    return max(block, 4.0 * interval)


def _level_runs(
    first: int, end: int, mean: FloatArray, count: NDArray[np.intp], total: NDArray[Any], spread: float,
    consistency: float,
) -> list[tuple[int, int]]:
    """The runs of blocks ``first .. end - 1`` (all quiet) whose means agree with their run's mean
    so far within ``consistency`` standard errors, as ``(first block, last block)`` pairs."""
    means, counts, totals = mean[first:end].tolist(), count[first:end].tolist(), total[first:end].tolist()
    runs: list[tuple[int, int]] = []
    start, level, weight = 0, means[0], float(counts[0])

    def agrees(b: int) -> bool:
        return bool(abs(means[b] - level) <= consistency * math.sqrt(spread**2 / counts[b] + spread**2 / weight))

    for b in range(1, end - first):
        # One stray block whose successor agrees again is an outlier, not the end of the rest.
        if agrees(b) or (b + 1 < end - first and agrees(b + 1)):
            level = (level * weight + totals[b]) / (weight + counts[b])
            weight += counts[b]
            continue
        runs.append((first + start, first + b - 1))
        start, level, weight = b, means[b], float(counts[b])
    runs.append((first + start, end - 1))
    return runs


def _correlation_factor(dev: FloatArray, k: NDArray[np.int64], quiet: NDArray[np.bool_]) -> float:
    """How much more a quiet block's mean scatters than white noise of the same size would make
    it (at least 1), from the lag-one correlation ``rho`` of the readings about their block's
    mean in the quiet blocks: ``sqrt((1 + rho) / (1 - rho))``, the first-order (AR(1)) variance
    factor of a mean. A gyro's noise is correlated over a few samples when its bandwidth is below
    half its sampling rate (the CRS03's 10 Hz at 100 Hz: rho 0.53, a factor of 1.8), and a level
    test that assumed white noise would cut a rest into pieces. Within a block, motion that
    changes from block to block does not count."""
    same = (k[1:] == k[:-1]) & quiet[k[1:]]
    power = float(np.sum(dev[1:][same] ** 2))
    if power == 0.0:
        return 1.0
    rho = float(np.sum(dev[1:][same] * dev[:-1][same])) / power
    return math.sqrt((1.0 + rho) / (1.0 - rho)) if 0.0 < rho < 1.0 else 1.0


@no_path_for_arrays("gyrocore.calibration.detect_rest", READ_TO_CALIBRATE)
def detect_rest(
    t: ArrayLike,
    rate: ArrayLike,
    *,
    min_duration: float = 1.0,
    which: Literal["first", "longest"] = "first",
    **options: float,
) -> tuple[float, float]:
    """The first (or longest) rest of at least ``min_duration`` seconds, as ``(start, end)`` [s].

    ``options`` go to :func:`rest_windows` (``block``, ``noise_factor``, ``max_rate``,
    ``consistency``). Raises ValueError "no rest found" with what the quietest stretch looked like.
    """
    refuse_unknown_rest_options("detect_rest", options)
    return _detect_rest_of_checked(*check_series(t, rate), min_duration, which, options)


def _detect_rest_of_checked(
    ta: FloatArray, ra: FloatArray, min_duration: float, which: object, options: dict[str, Any]
) -> tuple[float, float]:
    """:func:`detect_rest` of the series :func:`check_series` gave (and warned of, once)."""
    if which not in ("first", "longest"):
        raise ValueError(f"which must be 'first' or 'longest', got {which!r}")
    windows = rest_windows_of_checked(ta, ra, min_duration, **options)
    if not windows:
        max_rate = options.get("max_rate", MAX_RATE)
        raise ValueError(
            f"no rest found: no stretch of at least {min_duration:g} s where the rate is as steady as "
            f"the log's quietest blocks and within {max_rate:g} rad/s of zero (give the rest window, "
            "or a shorter min_duration / larger max_rate if this gyro's bias is large)" + _few_readings_hint(ta, options)
            + steady_stretch_hint(ta, ra, min_duration, max_rate)
        )
    if which == "first":
        return windows[0]
    return max(windows, key=lambda w: w[1] - w[0])


#: Turns [rad/s] at the 99th percentile of ``|rate|`` beyond which a steady level that a deg/s rest
#: would read names the unit: 115 deg/s, while a car in deg/s turns at 10 to 30.
DEG_PER_S_TURNS = 2.0
#: The largest bias [rad/s] a steady level read in deg/s may be for that clause: 11.5 deg/s, beyond
#: the 3.9 deg/s of comma_seg40's phone gyro (the rest test's own 0.05 rad/s left it unsaid there).
DEG_PER_S_BIAS = 0.2


def longest_steady(
    ta: FloatArray, ra: FloatArray, min_duration: float, max_rate: float = MAX_RATE
) -> tuple[float, float, float] | None:
    """The longest stretch the rate alone shows as a rest (:func:`rest_windows_of_checked`, levels
    up to ``max_rate``) as ``(start, end, mean reading)``, or None where there is none or the log is
    too sparse to judge. ``ta`` are checked times (finite, increasing); readings the core refuses
    are left out."""
    taken = usable(ra)
    if np.count_nonzero(taken) < 8:
        return None
    t, rate = (ta, ra) if taken.all() else (ta[taken], ra[taken])
    try:
        windows = rest_windows_of_checked(t, rate, min_duration, max_rate=max_rate)
    except ValueError:  # too sparse to judge: the caller's message says so, or nothing more
        return None
    if not windows:
        return None
    a, b = max(windows, key=lambda w: w[1] - w[0])
    return a, b, float(np.mean(rate[np.searchsorted(t, a) : np.searchsorted(t, b, side="right")]))


def steady_stretch_hint(ta: FloatArray, ra: FloatArray, min_duration: float, max_rate: float = MAX_RATE) -> str:
    """Where no rest was found: the longest stretch as steady as a rest whose level lies beyond
    ``max_rate`` [rad/s], and what it may be, as a clause to append to the "no rest" message ("" if
    there is none). A log in deg/s read as rad/s rests at 57 times its bias, beyond ``max_rate``, and
    its turns stay under the unit check's 20 rad/s: "no rest found" alone left the unit unsuspected.
    ``ta`` are checked times (finite, increasing); readings the core refuses are left out."""
    longest = longest_steady(ta, ra, min_duration, max_rate=MAX_READING)  # any level
    if longest is None:
        return ""
    a, b, level = longest
    taken = usable(ra)
    rate, first = ra[taken], float(ta[taken][0])  # the first sample the core takes
    text = (f"; the steadiest stretch, {a - first:.6g} .. {b - first:.6g} s after the first sample, reads "
            f"{level:.4g} rad/s ({math.degrees(level):.4g} deg/s), as steady as a rest but beyond {max_rate:g} rad/s: "
            "a steady turn, or a rest or straight drive with a bias that large (give a rest window or the bias)")
    # deg/s read as rad/s: a level a deg/s rest reads, and turns a vehicle makes only in deg/s (a
    # highway drive in rad/s with a large bias, comma_seg40, is steady beyond max_rate too)
    if abs(math.radians(level)) <= DEG_PER_S_BIAS and float(np.percentile(np.abs(rate), 99)) > DEG_PER_S_TURNS:
        text += f", or a rate in deg/s read as rad/s ({DEG_PER_S_FIX})"
    return text


#: A block of fewer readings than this tells a rest by its spread too poorly: it scatters so much
#: that a log wholly at rest at 10 Hz (4 readings a block) showed none.
FEW_BLOCK_READINGS = 25.0


def block_readings(ta: FloatArray, block: float = BLOCK) -> tuple[float, float]:
    """The median sample interval of ``ta`` [s] (0 with fewer than two times) and how many readings
    a block of :func:`rest_windows` holds at it (infinite where the interval is 0)."""
    interval = float(np.median(np.diff(ta))) if len(ta) > 1 else 0.0
    return interval, (_block_width(block, interval) / interval if interval > 0 else math.inf)


def _few_readings_hint(ta: FloatArray, options: dict[str, float]) -> str:
    """Where the log's blocks hold fewer than :data:`FEW_BLOCK_READINGS` readings, what to give instead."""
    block = options.get("block", BLOCK)
    interval, readings = block_readings(ta, block)
    if readings >= FEW_BLOCK_READINGS:
        return ""
    return (f"; at this log's {1.0 / interval:.3g} Hz a block of {block:g} s holds {readings:.0f} readings, too few "
            f"to tell a rest by its spread: give block={24.0 * interval:.3g} (25 readings) to find it")


def time_weights(t: FloatArray) -> FloatArray:
    """Weight of each reading: the interval since the previous one (the first gets none), the
    rectangle rule of HDR eq 3 that the pipeline's static bias uses too."""
    w = np.empty_like(t)
    w[0] = 0.0
    w[1:] = np.diff(t)
    return w


@no_path_for_arrays("gyrocore.calibration.static_bias", READ_TO_CALIBRATE)
def static_bias(
    t: ArrayLike,
    rate: ArrayLike,
    window: tuple[float, float] | None = None,
    *,
    min_duration: float = 1.0,
    **detect_options: Any,
) -> Calibration:
    """Static bias test (FOG section 2; HDR eq 1-2's ``eps0``): the mean reading at rest.

    Args:
        t: timestamps [s], strictly increasing (any time base, e.g. Unix epoch).
        rate: readings [rad/s].
        window: ``(start, end)`` rest window [s, log time base]; None finds the first rest of at
            least ``min_duration`` seconds (:func:`detect_rest`, which takes ``detect_options``).
        min_duration: shortest acceptable rest [s] (also for a given window).

    The bias and its standard error come from the core's static bias test, the one the
    pipeline's ``bias_window`` runs, so ``bias=cal.bias`` gives the bias that
    ``bias_window=cal.window`` ends with (the pipeline uses its running mean inside the window):
    the mean weighs each reading by the interval since the previous one, and the standard error
    is that of the means of the window's eight equal parts (batch means), which stays honest
    when the noise is correlated (bias instability); for white noise it equals ``sd / sqrt(n)``.
    Returns a :class:`Calibration` with ``bias``, ``bias_stderr``,
    ``residual_rms`` (the readings' standard deviation) and the ``window`` used.

    Raises:
        ValueError: bad samples, a window shorter than ``min_duration``, or no rest found.
        TypeError: ``detect_options`` with a ``window`` (they would not be used).
        RestWindowError: a given window that does not lie inside the log, or holds fewer than
            :data:`~gyrocore.window.MIN_WINDOW_READINGS` readings (the pipeline's refusals).
    """
    refuse_unknown_rest_options("static_bias", detect_options, also=("which",))  # detect_rest's too
    ta, ra = check_series(t, rate)
    min_duration = check_number("min_duration", min_duration, strict=False)  # NaN passed every window
    if window is None:
        which = detect_options.pop("which", "first")  # the series checked once: their units warned of once
        window = _detect_rest_of_checked(ta, ra, min_duration, which, detect_options)
    elif detect_options:  # they choose how a rest is found, and a given window is not searched for
        raise TypeError(f"{', '.join(sorted(detect_options))}: options of the search for a rest (detect_rest), "
                        "which a given window skips; leave them out, or the window")
    start, end = as_window("the rest window", window)
    if len(ta):  # the pipeline's refusals: a window cut to the log (or one of 2 readings, "+- 0") came without a word
        refuse_window_outside(start, end, float(ta[0]), float(ta[-1]))
    inside = np.flatnonzero((ta >= start) & (ta <= end))
    log = span_text(ta) if len(ta) else "which has no sample"
    refuse_few_readings(f"the rest window [{start}, {end}] s of the log ({log})", len(inside))
    tw, rw = ta[inside] - ta[inside[0]], ra[inside]
    duration = float(tw[-1])
    if duration < min_duration:
        raise ValueError(
            f"the rest window [{start}, {end}] s covers {duration:.3g} s of readings, shorter than "
            f"min_duration = {min_duration:g} s: the bias would be mostly noise"
        )
    bias, _, _, batch_stderr = _gyrocore.static_bias_test(ta, ra, start, end)
    warn_if_turning((start, end), rw, bias)
    sd = float(np.sqrt(np.sum(time_weights(tw) * (rw - bias) ** 2) / duration))
    # The batch means need readings in two parts of the window; with fewer, the white-noise error.
    stderr = sd / math.sqrt(len(rw)) if batch_stderr is None else batch_stderr
    return Calibration(
        method="static_bias",
        bias=bias,
        bias_stderr=stderr,
        residual_rms=sd,
        window=(float(ta[inside[0]]), float(ta[inside[-1]])),
        samples=len(rw),
    )

"""Rest tracking (``track_rests=True``): the rests a drive makes, found as it streams, each one
re-measuring the static bias through a one-state Kalman filter (see rust/src/rest_tracker.rs and
docs/rest_tracking.md).

This module holds the Python side: :class:`Rest`, the one record of a rest for the tracker and for
whole-log processing; the speed a caller gives (per gyro sample, or a series at its own times such
as a log folder's ``odometry.csv``, interpolated onto the gyro's); and :func:`bias_walk`, the
filter's process noise from a gyro's Allan parameters.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray, as_float_array, covered_share
from ._checks import MAX_READING, check_number, public_dir, require_finite, require_series, warn

__all__ = [
    "GATE_REFUSED", "LISTED_RESTS", "MIN_OVERLAP", "Rest", "bias_walk", "from_core", "refuse_speed_t_alone",
    "rest_lines", "speed_at", "speed_on",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


@dataclass(frozen=True)
class Rest:
    """One rest of a log and what it measured: found by whole-log processing
    (``HeadingResult.rests``, :mod:`gyrocore.wholelog`) or by the streaming rest tracker
    (``HeadingResult.tracked_rests``, :attr:`gyrocore.Pipeline.rests`). Times are in the log's own
    clock; rates in rad/s.

    Attributes:
        start, end: first and last time of the part measured [s] (the tracker leaves out a stop's
            first and last detection block, whole mode a stop's edges).
        bias: mean reading over it [rad/s]: the bias it measured, time-weighted as the pipeline's
            rest window.
        bias_std_error: standard error of ``bias`` [rad/s]: the batch-means error, at least the
            white-noise error of the time-weighted mean (``noise / sqrt(samples)`` for evenly
            spaced readings); for a rest whole mode found from the rate alone, counting the
            readings' correlation where neighbours correlate (docs/whole_log.md, "Measurement").
        noise: standard deviation of one reading [rad/s].
        samples: readings inside it.
        found_by: ``given`` (bias_window, bias_duration, meta.json), ``speed`` (a speed below the
            threshold) or ``rate`` (the rate alone).
        refused: why the rest was not used (whole mode's noise and outlier tests, the tracker's
            gate), or None when it was.
        filtered: for the tracker, the filtered bias after this rest [rad/s]: what the pipeline
            subtracts from then on; None in whole mode.
    """

    start: float
    end: float
    bias: float
    bias_std_error: float
    noise: float
    samples: int
    found_by: str
    refused: str | None = None
    filtered: float | None = None

    @property
    def accepted(self) -> bool:
        """True when the rest was used (not refused)."""
        return self.refused is None

    @property
    def middle(self) -> float:
        """The time the rest's bias stands for [s]."""
        return (self.start + self.end) / 2

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON (SI units)."""
        return asdict(self)

    def __str__(self) -> str:
        text = (
            f"[{self.start:.3f}, {self.end:.3f}] s ({self.found_by}): bias {math.degrees(self.bias):.5f} "
            f"+- {math.degrees(self.bias_std_error):.2g} deg/s"
        )
        return text if self.refused is None else f"{text}, not used: {self.refused}"


#: Why the tracker did not use a rest it found.
GATE_REFUSED = "its mean is further from the filtered bias than rest_gate_sigmas standard deviations allow"


def from_core(rest: tuple[float, float, float, float, float, int, bool, bool, float], origin: float) -> Rest:
    """A rest as the core's tracker reports it (times since the first sample), with times from
    ``origin`` [s] (the first sample's time) on."""
    start, end, bias, error, noise, samples, by_speed, accepted, filtered = rest
    return Rest(
        origin + start, origin + end, bias, error, noise, samples, "speed" if by_speed else "rate",
        None if accepted else GATE_REFUSED, filtered,
    )


def bias_walk(*, rate_random_walk: float, bias_instability: float, horizon: float = 60.0) -> float:
    """The random-walk intensity ``q`` [rad^2/s^3] of the bias from Allan parameters: ``K^2`` from
    the rate random walk K [rad/s/sqrt(s)], plus the bias instability's floor ``(0.664 B)^2``
    [B in rad/s] spread over ``horizon`` seconds (a flicker bias wanders by about its floor over
    the time between stops; a random walk is the filter's one-state stand-in for it)."""
    # within a reading's limit: 1e300 overflowed (a bare OverflowError); text was math's bare TypeError
    rate_random_walk, bias_instability = (
        check_number(name, value, strict=False, high=MAX_READING)
        for name, value in (("rate_random_walk", rate_random_walk), ("bias_instability", bias_instability)))
    horizon = check_number("horizon", horizon, unit=" [s]")
    from .allan import FLICKER_FLOOR  # allan imports the pipeline, which imports this module

    return rate_random_walk**2 + (FLICKER_FLOOR * bias_instability) ** 2 / horizon


def speed_at(t: FloatArray, speed: ArrayLike, speed_t: ArrayLike | None = None) -> FloatArray:
    """The speed [m/s] at each gyro time ``t``: ``speed`` itself (one per sample), or, with its own
    strictly increasing times ``speed_t``, interpolated linearly; NaN (no speed: the tracker judges
    those samples by the rate) outside ``speed_t``'s span. Errors name the offending index."""
    s = as_float_array("speed", speed, unit="m/s")
    require_finite("speed", s)
    if speed_t is None:
        if len(s) != len(t):
            raise ValueError(
                f"speed has {len(s)} samples but t has {len(t)}: give one speed per gyro sample, "
                "or the speed's own times as speed_t"
            )
        return s
    return speed_on(t, speed_t, s, where="speed")


def refuse_speed_t_alone(speed: ArrayLike | None, speed_t: ArrayLike | None) -> None:
    """Refuse ``speed_t`` without ``speed`` (it would be ignored without a word)."""
    if speed_t is not None and speed is None:
        raise ValueError("speed_t is given without speed: give the speed [m/s] at those times too, or leave speed_t out")


def speed_on(t: FloatArray, t_speed: ArrayLike, speed: ArrayLike, *, where: str = "speed") -> FloatArray:
    """A speed series at its own times, interpolated linearly onto the gyro's times ``t``.

    Outside the series' span the speed is unknown (NaN), so no rest is taken from there; a series
    that covers less than half of the gyro's span, or has fewer than two samples in it, warns
    (:class:`~gyrocore.InputWarning`: another time base or unit).

    Raises:
        ValueError: lengths differ, a time or speed is not finite, or the times do not strictly
            increase (naming ``where`` and the index).
    """
    ts, vs = as_float_array(f"{where} times", t_speed), as_float_array(where, speed, unit="m/s")
    require_series("t", ts, "speed", vs, context=where)
    _warn_overlap(t, ts, where)
    if len(ts) == 0:
        return np.full(len(t), np.nan)
    return np.asarray(np.interp(t, ts, vs, left=np.nan, right=np.nan), dtype=np.float64)


#: A speed series that covers less than this share of the gyro's time span, or fewer than two of
#: whose samples fall in it, is in another time base or unit (e.g. relative time against epoch
#: seconds, or ns): a warning says so.
MIN_OVERLAP = 0.5


def _warn_overlap(t: FloatArray, ts: FloatArray, where: str) -> None:
    """Warn when the speed's times ``ts`` barely overlap the gyro's ``t``: rests are then judged
    by the rate alone where the speed is unknown, which no error would otherwise reveal."""
    if len(t) < 2 or not (np.isfinite(t[0]) and np.isfinite(t[-1]) and t[-1] > t[0]):
        return  # no span to overlap (the pipeline names bad times)
    first, last = float(t[0]), float(t[-1])
    share = covered_share(t, ts)
    inside = int(np.count_nonzero((ts >= first) & (ts <= last)))
    if share >= MIN_OVERLAP and inside >= 2:
        return
    spans = f"[{ts[0]:.10g}, {ts[-1]:.10g}] s" if len(ts) else "no sample"
    warn(
        f"{where}: its times ({spans}) cover {100 * share:.3g} % of the gyro's [{first:.10g}, {last:.10g}] s, "
        f"with {inside} speed sample(s) inside it: the speed is unknown elsewhere, and rests there are found "
        "from the rate alone; give the speed's times in the gyro's clock, in seconds"
    )


#: A report lists at most this many rests under its bias line (a long drive's rate showed 120, a
#: day's log thousands, each a line of the report); the JSON report holds every one.
LISTED_RESTS = 12


def rest_lines(source: str, rests: tuple[Rest, ...], indent: str) -> list[str]:
    """The lines listing ``rests`` under a report's ``source`` line (none when that line names the
    one rest used, as ``first 10 s: rest ...`` does too): the first :data:`LISTED_RESTS` and a
    line counting the others."""
    if len(rests) == 1 and f"rest {rests[0]}" in source:
        return []
    shown = rests if len(rests) <= LISTED_RESTS else rests[: LISTED_RESTS - 1]
    lines = [f"{indent}rest {r}" for r in shown]
    others = rests[len(shown):]
    if others:
        used = sum(r.accepted for r in others)
        lines.append(f"{indent}... and {len(others)} more rests ({used} of them used): the JSON report (--json; "
                     ".rests in Python) lists every one")
    return lines

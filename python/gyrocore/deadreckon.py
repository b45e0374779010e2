"""Gyro-aided odometry (FOG section 4.2): position from the odometry's speed and the gyro's heading.

The odometry gives how far the vehicle moved, the gyro which way. Between two odometry samples the
speed is taken as linear (trapezoid distance) and the heading as turning at a constant rate, so
each step is a circular arc: exact for a vehicle on a circle at constant speed, and free of the
first-order error that stepping along the start or mid heading makes in turns.

Units: s, m, m/s, rad (counter-clockwise positive, from the x axis).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import READ_ODOMETRY, FloatArray, as_float_array, no_path_for_arrays, too_few_inside
from ._checks import check_number, public_dir, require_finite, require_radians, require_series, warn_if_wrapped
from .io import Log
from .pipeline import HeadingResult

__all__ = ["PositionErrors", "Track", "dead_reckon", "dead_reckon_log", "position_errors", "return_position_error"]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


@dataclass(frozen=True, repr=False, eq=False)
class Track:
    """A dead-reckoned track: position ``(x, y)`` [m] and heading [rad] at the odometry times ``t`` [s]."""

    t: FloatArray
    x: FloatArray
    y: FloatArray
    heading: FloatArray

    @property
    def distance(self) -> float:
        """Path length travelled [m]."""
        return float(np.hypot(np.diff(self.x), np.diff(self.y)).sum())

    def __repr__(self) -> str:
        return (
            f"Track(n={len(self.t)}, duration={self.t[-1] - self.t[0]:.3f} s, distance={self.distance:.3f} m, "
            f"end=({self.x[-1]:.3f}, {self.y[-1]:.3f}) m)"
        )


@no_path_for_arrays("gyrocore.deadreckon.dead_reckon", READ_ODOMETRY)
def dead_reckon(
    t_speed: ArrayLike,
    speed: ArrayLike,
    t_heading: ArrayLike,
    heading: ArrayLike,
    *,
    position: tuple[float, float] = (0.0, 0.0),
    heading_offset: float = 0.0,
) -> Track:
    """Position from speed and heading (FOG section 4.2, gyro-aided odometry).

    Args:
        t_speed, speed: odometry times [s] and forward speed [m/s] (negative when reversing).
        t_heading, heading: continuous heading [rad] at its own times, e.g. a
            :class:`~gyrocore.HeadingResult`; it is interpolated at the odometry times. Odometry
            samples outside the heading's time span are left out.
        position: position at the first odometry sample used [m].
        heading_offset: added to the heading [rad] (the gyro gives only heading changes).

    Returns:
        The track at the odometry times used.

    Raises:
        ValueError: samples that are not finite, times not strictly increasing, lengths apart, a
            heading that wraps by 360 (in degrees, which it says), too few samples
            inside the heading's span; a ``position`` that is not two finite numbers or a
            ``heading_offset`` that is not finite (NaN made every position NaN).
        TypeError: a ``position`` or ``heading_offset`` that is no number (text failed inside numpy).

    Warns:
        InputWarning: a heading that looks wrapped to +-pi (:func:`gyrocore._checks.warn_if_wrapped`).
    """
    x0, y0 = _point("position", position)
    heading_offset = check_number("heading_offset", heading_offset, low=None, unit=" [rad]")
    ts = as_float_array("t_speed", t_speed)
    v = as_float_array("speed", speed, unit="m/s")
    th = as_float_array("t_heading", t_heading)
    psi = as_float_array("heading", heading, unit="rad")
    require_series("t_speed", ts, "speed", v)
    require_series("t_heading", th, "heading", psi)
    if len(th) < 2:
        raise ValueError("need at least two heading samples")
    # a heading that wraps is interpolated across each wrap and its step's chord shrinks to nothing there
    require_radians("the heading", th, psi)
    warn_if_wrapped(th, psi)
    inside = (ts >= th[0]) & (ts <= th[-1])
    if inside.sum() < 2:
        raise ValueError(too_few_inside("the odometry", ts, "the heading", th))  # both spans: a clock apart shows
    ts, v = ts[inside], v[inside]
    psi_s = np.interp(ts, th, psi) + heading_offset
    dt = np.diff(ts)
    distance = 0.5 * (v[1:] + v[:-1]) * dt
    turn = np.diff(psi_s)
    # A chord of an arc that turns by d: length s * sin(d/2)/(d/2), along the mean heading.
    chord = distance * np.sinc(turn / (2 * math.pi))
    mid = psi_s[:-1] + 0.5 * turn
    x = x0 + np.concatenate(([0.0], np.cumsum(chord * np.cos(mid))))
    y = y0 + np.concatenate(([0.0], np.cumsum(chord * np.sin(mid))))
    return Track(ts, x, y, psi_s)


def dead_reckon_log(log: Log, result: HeadingResult) -> Track:
    """Dead reckoning of a log with ``result``'s heading, aligned with the reference at the start.

    The track starts at the reference position and heading at the first odometry time inside the
    reference's and the heading's spans (only relative heading is meaningful).
    """
    if log.t_odometry is None or log.speed is None:
        raise ValueError(f"log {log.name}: no odometry (odometry.csv)")
    t_ref, heading_ref = log.reference()
    _, x_ref, y_ref = log.track()
    start = max(t_ref[0], result.t[0])
    later = log.t_odometry >= start
    if not later.any():
        raise ValueError(f"log {log.name}: no odometry sample after the start of the reference and heading")
    t0 = float(log.t_odometry[np.flatnonzero(later)[0]])
    offset = float(np.interp(t0, t_ref, np.unwrap(heading_ref)) - np.interp(t0, result.t, result.heading))
    position = (float(np.interp(t0, t_ref, x_ref)), float(np.interp(t0, t_ref, y_ref)))
    return dead_reckon(
        log.t_odometry[later], log.speed[later], result.t, result.heading, position=position, heading_offset=offset
    )


@dataclass(frozen=True)
class PositionErrors:
    """Distance [m] between a dead-reckoned track and a reference track, at the reference's times."""

    mean_error_m: float
    max_error_m: float
    final_error_m: float
    """Error at the last compared reference time."""
    distance_m: float
    """Path length of the reference over the compared span."""
    final_error_percent: float
    """Final error as a percentage of the distance travelled (the usual dead-reckoning figure)."""
    n: int
    """Reference samples compared."""

    def as_dict(self) -> dict[str, float]:
        """The metrics as a plain dict (for JSON)."""
        return asdict(self)


def position_errors(track: Track, t_ref: ArrayLike, x_ref: ArrayLike, y_ref: ArrayLike) -> PositionErrors:
    """Compare ``track`` (interpolated) with the reference positions inside the track's time span.

    Raises:
        ValueError: reference samples that are not finite (a NaN position made every metric NaN),
            times not strictly increasing, lengths apart, or fewer than two inside the track's span.
    """
    tr, xr, yr = as_float_array("t_ref", t_ref), as_float_array("x_ref", x_ref), as_float_array("y_ref", y_ref)
    if not len(tr) == len(xr) == len(yr):
        raise ValueError("t_ref, x_ref and y_ref must have equal lengths")
    require_series("t_ref", tr, "x_ref", xr, context="reference")
    require_finite("y_ref", yr, context="reference")
    inside = (tr >= track.t[0]) & (tr <= track.t[-1])
    if inside.sum() < 2:
        raise ValueError(too_few_inside("the reference", tr, "the track", track.t))
    tr, xr, yr = tr[inside], xr[inside], yr[inside]
    err = np.hypot(np.interp(tr, track.t, track.x) - xr, np.interp(tr, track.t, track.y) - yr)
    distance = float(np.hypot(np.diff(xr), np.diff(yr)).sum())
    return PositionErrors(
        mean_error_m=float(err.mean()),
        max_error_m=float(err.max()),
        final_error_m=float(err[-1]),
        distance_m=distance,
        final_error_percent=100.0 * float(err[-1]) / distance if distance > 0 else math.nan,
        n=len(tr),
    )


def return_position_error(track: Track, *, displacement: tuple[float, float] = (0.0, 0.0)) -> float:
    """Return position error of a closed path [m] (FOG section 4.2, Figure 8).

    The distance between where the track ends and where it should end: its start plus the true
    ``displacement`` [m] from start to end (zero for a path that returns to its start).

    Raises:
        ValueError: a ``displacement`` that is not two finite numbers (NaN gave NaN).
        TypeError: a ``displacement`` that is no pair of numbers.
    """
    east, north = _point("displacement", displacement)
    dx = track.x[-1] - track.x[0] - east
    dy = track.y[-1] - track.y[0] - north
    return math.hypot(dx, dy)


def _point(name: str, value: object) -> tuple[float, float]:
    """``value`` as ``(x, y)`` [m]: two finite numbers (a TypeError or ValueError naming ``name``
    otherwise: text failed inside numpy, and three numbers were taken as two)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, (tuple, list, np.ndarray)):
        raise TypeError(f"{name} must be (x, y) in metres, got {value!r}")
    if len(value) != 2:
        raise ValueError(f"{name} must be (x, y) in metres, two numbers, got {value!r}")
    return (check_number(f"{name}[0]", value[0], low=None, unit=" [m]"),
            check_number(f"{name}[1]", value[1], low=None, unit=" [m]"))

"""The motion itself: yaw rate and speed piecewise linear between knots, the heading exact, the
position integrated on the knots; and the builder the profiles use, phase by phase.

Units: s, rad/s, rad, m, m/s; counter-clockwise positive (see :mod:`gyrocore.motion`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray, as_float_array
from ._checks import check_number

#: Knot spacing used for swerving and for integrating the position [s].
GRID = 0.05
_DEG = math.pi / 180.0
#: The longest motion built [s], 36 hours: a motion is built manoeuvre by manoeuvre in memory, and
#: one of 1e6 s (a car drive's 20 million knots) took over a minute, of a billion s or runs until the
#: memory ran out.
MAX_DURATION = 2.0**17


def rest_window(rest: float) -> tuple[float, float] | None:
    """The rest window of a motion that begins with ``rest`` seconds: none for no rest (a window
    [0, 0] held one sample, too few for a bias)."""
    return (0.0, rest) if rest > 0 else None


def check_duration(what: str, seconds: float) -> None:
    """A ValueError if a motion of ``seconds`` (``what`` says whose) is longer than :data:`MAX_DURATION`."""
    if seconds > MAX_DURATION:
        raise ValueError(f"{what} would last {seconds:.6g} s, more than the {MAX_DURATION:.0f} s a motion may last "
                         "(is the duration in seconds?)")


def check_positive(**values: float) -> None:
    """Refuse, naming it, a value that is not a finite number > 0 (a speed, rate or ramp of 0 was a
    ZeroDivisionError, NaN numpy's "arange: cannot compute length")."""
    for name, value in values.items():
        check_number(name, value)


@dataclass(frozen=True)
class Segment:
    """A labelled stretch of a motion: ``kind`` (``rest``, ``straight``, ``turn``, ``curve``, ...)
    from ``start`` to ``end`` [s]; ``angle`` is the rotation it commands [rad] (0 if none)."""

    kind: str
    start: float
    end: float
    angle: float = 0.0


@dataclass(frozen=True, repr=False, eq=False)
class Truth:
    """The motion at given times: rate [rad/s], heading [rad], x, y [m], speed [m/s]."""

    t: FloatArray
    rate: FloatArray
    heading: FloatArray
    x: FloatArray
    y: FloatArray
    speed: FloatArray

    def __repr__(self) -> str:
        return f"Truth(n={len(self.t)})"


@dataclass(frozen=True, repr=False, eq=False)
class Motion:
    """Yaw rate and speed, linear between knots; heading exact, position integrated on the knots.

    Build one with the profile functions of this module, or from knots directly. Attributes:
        name: label. knots: knot times [s], strictly increasing from 0. rate, speed: values at the
        knots [rad/s, m/s]. segments: labelled stretches. rest: rest window at the start [s] or None.
    """

    name: str
    knots: FloatArray
    rate: FloatArray
    speed: FloatArray
    segments: tuple[Segment, ...] = ()
    rest: tuple[float, float] | None = None
    _heading: FloatArray = field(init=False, compare=False)
    _x: FloatArray = field(init=False, compare=False)
    _y: FloatArray = field(init=False, compare=False)

    def __post_init__(self) -> None:
        k = as_float_array("knots", self.knots)
        if len(k) < 2 or k[0] != 0.0 or np.any(np.diff(k) <= 0):
            raise ValueError("motion knots must start at 0 and strictly increase (at least two)")
        if len(self.rate) != len(k) or len(self.speed) != len(k):
            raise ValueError("rate and speed need one value per knot")
        h = np.diff(k)
        # Exact integral of a piecewise-linear rate (the trapezoid rule is exact for it).
        heading = np.concatenate(([0.0], np.cumsum(0.5 * (self.rate[1:] + self.rate[:-1]) * h)))
        # Position: trapezoid rule of v (cos, sin) of the exact heading on the knots.
        vx, vy = self.speed * np.cos(heading), self.speed * np.sin(heading)
        x = np.concatenate(([0.0], np.cumsum(0.5 * (vx[1:] + vx[:-1]) * h)))
        y = np.concatenate(([0.0], np.cumsum(0.5 * (vy[1:] + vy[:-1]) * h)))
        object.__setattr__(self, "_heading", heading)
        object.__setattr__(self, "_x", x)
        object.__setattr__(self, "_y", y)

    @property
    def duration(self) -> float:
        """Length [s]."""
        return float(self.knots[-1])

    def sample(self, t: ArrayLike) -> Truth:
        """The motion at times ``t`` [s] (clamped to ``[0, duration]``)."""
        ta = np.clip(as_float_array("t", t), 0.0, self.duration)
        k = np.clip(np.searchsorted(self.knots, ta, side="right") - 1, 0, len(self.knots) - 2)
        tau = ta - self.knots[k]
        h = self.knots[k + 1] - self.knots[k]
        slope = (self.rate[k + 1] - self.rate[k]) / h
        return Truth(
            t=ta,
            rate=self.rate[k] + slope * tau,
            heading=self._heading[k] + self.rate[k] * tau + 0.5 * slope * tau * tau,
            x=np.interp(ta, self.knots, self._x),
            y=np.interp(ta, self.knots, self._y),
            speed=np.interp(ta, self.knots, self.speed),
        )

    def segments_of(self, kind: str) -> list[Segment]:
        """The segments of one kind, in time order."""
        return [s for s in self.segments if s.kind == kind]

    @property
    def distance(self) -> float:
        """Distance travelled [m]."""
        return float(np.sum(0.5 * (self.speed[1:] + self.speed[:-1]) * np.diff(self.knots)))

    def __repr__(self) -> str:
        return (
            f"Motion({self.name!r}, {self.duration:.1f} s, {len(self.segments)} segments, "
            f"net turn {math.degrees(float(self._heading[-1])):.1f} deg, distance {self.distance:.0f} m)"
        )


class _Track:
    """Builds a motion phase by phase: each phase moves rate and speed linearly to new values."""

    def __init__(self) -> None:
        self.t = [0.0]
        self.rate = [0.0]
        self.speed = [0.0]
        self.segments: list[Segment] = []
        self.swerves: list[tuple[float, float, float, float, float]] = []

    @property
    def now(self) -> float:
        return self.t[-1]

    def phase(self, duration: float, rate: float | None = None, speed: float | None = None) -> None:
        """Move linearly to ``rate`` [rad/s] and ``speed`` [m/s] (unchanged if None) over ``duration``."""
        if duration <= 0:
            return
        self.t.append(self.now + duration)
        self.rate.append(self.rate[-1] if rate is None else rate)
        self.speed.append(self.speed[-1] if speed is None else speed)

    def label(self, kind: str, start: float, angle: float = 0.0) -> None:
        self.segments.append(Segment(kind, start, self.now, angle))

    def rest(self, duration: float, kind: str = "rest") -> None:
        """Stand still: rate and speed must already be 0."""
        start = self.now
        self.phase(duration, 0.0, 0.0)
        self.label(kind, start)

    def drive(self, duration: float, speed: float, *, accel: float = 2.0, kind: str = "straight") -> None:
        """Drive straight for ``duration`` seconds, first changing speed at ``accel`` [m/s^2]."""
        start = self.now
        ramp = min(abs(speed - self.speed[-1]) / accel, duration)
        self.phase(ramp, 0.0, speed)
        self.phase(duration - ramp, 0.0, speed)
        self.label(kind, start)

    def distance(self, metres: float, speed: float, accel: float, kind: str = "straight") -> None:
        """Drive ``metres`` from rest to rest: accelerate to ``speed`` at ``accel``, cruise, stop."""
        start = self.now
        ramp = speed / accel
        if speed * ramp > metres:  # never reaches the speed: a triangle
            speed = math.sqrt(metres * accel)
            ramp = speed / accel
        self.phase(ramp, 0.0, speed)
        self.phase(metres / speed - ramp, 0.0, speed)
        self.phase(ramp, 0.0, 0.0)
        self.label(kind, start)

    def turn(self, angle: float, peak: float, accel: float, *, kind: str = "turn") -> None:
        """Turn by ``angle`` [rad] with a trapezoidal rate: ramps at ``accel`` [rad/s^2] to ``peak``
        [rad/s], so the rotation is exact. Speed is kept."""
        start = self.now
        peak = abs(peak)
        ramp = peak / accel
        if peak * ramp > abs(angle):
            peak = math.sqrt(abs(angle) * accel)
            ramp = peak / accel
        rate = math.copysign(peak, angle)
        self.phase(ramp, rate)
        self.phase(abs(angle) / peak - ramp, rate)
        self.phase(ramp, 0.0)
        self.label(kind, start, angle)

    def curve(self, duration: float, rate: float, *, ramp: float = 1.0, kind: str = "curve") -> None:
        """Hold ``rate`` [rad/s] for ``duration`` seconds between two linear ramps of ``ramp``
        seconds centred on the start and the end, so the rotation is ``rate * duration``."""
        start = self.now
        self.phase(ramp, rate)
        self.phase(duration - ramp, rate)
        self.phase(ramp, 0.0)
        self.label(kind, start, rate * duration)

    def swerve(self, start: float, end: float, amplitude: float, frequency: float, phase: float = 0.0) -> None:
        """Add ``amplitude sin(2 pi f t + phase)`` [rad/s] to the rate between ``start`` and ``end``,
        faded in and out over 1 s so the rate stays continuous."""
        if end > start and amplitude != 0.0:
            self.swerves.append((start, end, amplitude, frequency, phase))

    def build(self, name: str, rest: tuple[float, float] | None, end: float | None = None) -> Motion:
        """The motion so far, cut at ``end`` [s] if given (segments are cut there too)."""
        t, rate, speed = np.array(self.t), np.array(self.rate), np.array(self.speed)
        segments = tuple(self.segments)
        if end is not None and end < t[-1]:
            keep = t < end
            t, rate, speed = (np.append(a[keep], np.interp(end, t, a)) for a in (t, rate, speed))
            segments = tuple(
                Segment(s.kind, s.start, min(s.end, end), s.angle if s.end <= end else 0.0)
                for s in segments
                if s.start < end
            )
        # Knots: the phases' corners and a fine grid, so position integrates accurately and
        # swerves are resolved; rate and speed stay exactly piecewise linear between the corners.
        fine = np.arange(0.0, t[-1], GRID)
        knots = np.union1d(t, fine)
        knots = knots[np.concatenate(([True], np.diff(knots) > 1e-9))]
        r = np.interp(knots, t, rate)
        for start, end, amplitude, frequency, phase in self.swerves:
            inside = (knots > start) & (knots < end)
            tk = knots[inside]
            fade = np.clip(np.minimum(tk - start, end - tk), 0.0, 1.0)
            r[inside] += amplitude * fade * np.sin(2 * math.pi * frequency * tk + phase)
        return Motion(name, knots, r, np.interp(knots, t, speed), segments, rest)

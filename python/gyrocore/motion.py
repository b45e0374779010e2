"""True planar motion as a function of continuous time, and the papers' motion profiles.

A :class:`Motion` is a yaw rate and a forward speed that are piecewise linear between knots, so the
heading (their integral) is exact at any time, and one motion can be sampled at any rate. Position
is integrated on the knots (0.05 s apart at most) and interpolated. Units: s, rad/s, rad, m, m/s;
counter-clockwise positive; the heading starts at 0 and is continuous.

Profiles:

- :func:`hdr_figure3`: the HDR paper's Figure 3 and 5 drive: straight with a slight 0.1 Hz swerve,
  curving at 2 deg/s from 660 s to 680 s, then straight again.
- :func:`car`: a car drive of straight stretches, swaying, curves, 90-degree turns and stops, in the
  road mixes of the HDR paper's Tables II and IV (:data:`ROAD_MIXES`, :data:`TABLE_II_DRIVES`).
- :func:`square_path`: the FOG paper's 4x4 m bi-directional square path (0.4 m/s, 30 deg/s turns).
- :func:`rotary_table`: the FOG paper's rotary-table runs, 360 deg cw then ccw at 30 deg/s.
- :func:`robot_run`: the Hong & Park robot run: 160 s, the first 20 s calibration motion, up to 2 m/s.

For example, a square path ends where it began, heading as it started:

    >>> import numpy as np, gyrocore.motion as motion
    >>> m = motion.square_path(runs=1)
    >>> truth = m.sample(np.array([0.0, m.duration]))
    >>> [round(float(np.degrees(h)), 9) for h in truth.heading]
    [0.0, 0.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray, as_float_array

#: Knot spacing used for swerving and for integrating the position [s].
GRID = 0.05
_DEG = math.pi / 180.0


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


# --- HDR --------------------------------------------------------------------------------------


def hdr_figure3(
    *,
    duration: float = 800.0,
    rest: float = 20.0,
    speed: float = 15.0,
    curve_start: float = 660.0,
    curve_end: float = 680.0,
    curve_dps: float = 2.0,
    swerve_dps: float = 0.2,
) -> Motion:
    """The drive of the HDR paper's Figures 3 and 5: after a rest of ``rest`` seconds, straight
    driving with a very slight 0.1 Hz sinusoidal swerve (amplitude ``swerve_dps``), slow curving at
    ``curve_dps`` from ``curve_start`` to ``curve_end`` (1 s ramps centred there), then straight
    again until ``duration``."""
    if not rest < curve_start < curve_end < duration:
        raise ValueError("need rest < curve_start < curve_end < duration")
    tr = _Track()
    tr.rest(rest)
    tr.drive(curve_start - 0.5 - rest, speed)
    tr.curve(curve_end - curve_start, curve_dps * _DEG)
    tr.drive(duration - tr.now, speed)
    tr.swerve(rest, duration, swerve_dps * _DEG, 0.1)
    return tr.build("HDR Figure 3", (0.0, rest))


@dataclass(frozen=True)
class Road:
    """How a kind of road is driven: speed range [m/s]; the weights of the manoeuvres (straight,
    sway, curve, turn, stop); straight length range [s]; curve rates [deg/s] and lengths [s];
    turn peak rate [deg/s]."""

    speed: tuple[float, float]
    weights: tuple[float, float, float, float, float]
    straight_s: tuple[float, float]
    curve_dps: tuple[float, float]
    curve_s: tuple[float, float]
    turn_dps: float = 15.0
    stop_s: tuple[float, float] = (5.0, 30.0)


#: Kinds of road. Curve rates below HDR's turn threshold (0.564 deg/s) are the hard case.
ROADS: dict[str, Road] = {
    "city": Road((8.0, 14.0), (0.45, 0.15, 0.05, 0.25, 0.10), (15.0, 60.0), (2.0, 6.0), (5.0, 15.0)),
    "downtown": Road((6.0, 11.0), (0.35, 0.10, 0.0, 0.40, 0.15), (10.0, 30.0), (2.0, 6.0), (5.0, 10.0), 18.0),
    "suburbs": Road((8.0, 13.0), (0.15, 0.10, 0.55, 0.15, 0.05), (5.0, 25.0), (1.0, 8.0), (8.0, 30.0)),
    "rural": Road((15.0, 25.0), (0.55, 0.15, 0.22, 0.08, 0.0), (30.0, 180.0), (0.5, 4.0), (10.0, 40.0), 10.0),
    "highway": Road((25.0, 33.0), (0.70, 0.15, 0.15, 0.0, 0.0), (60.0, 400.0), (0.2, 1.5), (20.0, 90.0)),
    "curvy_highway": Road((24.0, 31.0), (0.45, 0.15, 0.40, 0.0, 0.0), (30.0, 150.0), (0.3, 2.5), (20.0, 90.0)),
}

#: Road mixes: (road, share of the driving time) in driving order.
ROAD_MIXES: dict[str, tuple[tuple[str, float], ...]] = {
    "city": (("city", 1.0),),
    "downtown": (("downtown", 1.0),),
    "suburbs": (("suburbs", 1.0),),
    "rural": (("rural", 1.0),),
    "rural_suburbs": (("rural", 0.7), ("suburbs", 0.3)),
    "city_rural": (("city", 0.5), ("rural", 0.5)),
    "highway": (("city", 0.05), ("highway", 0.9), ("city", 0.05)),
    "curvy_highway": (("city", 0.05), ("curvy_highway", 0.9), ("city", 0.05)),
    "highway_rural": (("rural", 0.15), ("highway", 0.7), ("rural", 0.15)),
    # The HDR paper's Mixed Drive (section 5.1): 8 km rural, 11.5 km highway, 3.75 km city.
    "mixed": (("rural", 0.35), ("highway", 0.4), ("city", 0.25)),
}


@dataclass(frozen=True)
class DriveSpec:
    """One drive of the HDR paper's Tables II and IV: name, duration [min], road mix, description."""

    name: str
    minutes: float
    mix: str
    description: str


#: The nine training drives of HDR Table II.
TABLE_II_DRIVES: tuple[DriveSpec, ...] = (
    DriveSpec("City 1", 19.4, "city", "Mostly straight streets, few turns"),
    DriveSpec("Suburbs", 24.3, "suburbs", "Mostly curving streets in the suburbs"),
    DriveSpec("Mixed", 20.0, "mixed", "Mix of city streets, rural roads, and highway"),
    DriveSpec("Rural 1", 12.9, "rural", "Mostly straight streets, few turns"),
    DriveSpec("Rural 2", 18.9, "rural_suburbs", "Mostly straight rural roads, some curving suburban streets"),
    DriveSpec("Highway 1", 52.1, "highway", "90% highway, mostly straight"),
    DriveSpec("Highway 2", 50.4, "curvy_highway", "90% highway, some curving"),
    DriveSpec("Highway Mix", 47.6, "highway_rural", "70% highway with some curving, 30% rural, mostly straight"),
    DriveSpec("City 2", 21.6, "downtown", "100% downtown streets, over 40 90-degree turns"),
)

#: The five test drives of HDR Table IV.
TABLE_IV_DRIVES: tuple[DriveSpec, ...] = (
    DriveSpec("City 3", 22.2, "city", "Mostly straight streets, few turns"),
    DriveSpec("Mixed 2", 19.2, "mixed", "Mix of city streets, rural roads, and highway"),
    DriveSpec("Rural 3", 16.6, "city_rural", "Mix of city streets and rural roads"),
    DriveSpec("Highway 3", 36.9, "curvy_highway", "Highway with many curving segments"),
    DriveSpec("Highway 4", 43.2, "curvy_highway", "Highway with many curving segments"),
)

_MANOEUVRES = ("straight", "sway", "curve", "turn", "stop")


def car(duration: float, *, mix: str = "mixed", seed: int = 0, rest: float = 20.0, swerve_dps: float = 0.2) -> Motion:
    """A car drive of ``duration`` seconds: a rest of ``rest`` seconds (the static bias test), then
    the roads of ``mix`` (:data:`ROAD_MIXES`) in order, each driven as a random sequence of its
    manoeuvres (:data:`ROADS`): straight stretches with a slight 0.1 Hz swerve of ``swerve_dps``,
    swaying (small random steering corrections), curves, 90-degree turns, and stops.

    Same arguments, same drive.
    """
    if mix not in ROAD_MIXES:
        raise ValueError(f"unknown road mix {mix!r}; choose one of {', '.join(ROAD_MIXES)}")
    if not 0 <= rest < duration:
        raise ValueError(f"the rest ({rest} s) must be shorter than the drive ({duration} s)")
    rng = np.random.default_rng([seed, 0x5EED])
    tr = _Track()
    tr.rest(rest)
    driving = duration - rest
    section_end = rest
    for road_name, share in ROAD_MIXES[mix]:
        section_end = min(section_end + share * driving, duration)
        while tr.now < section_end:
            _manoeuvre(tr, ROADS[road_name], rng, section_end, swerve_dps * _DEG)
    # The last manoeuvre may run past the end: the drive is cut there.
    return tr.build(f"car ({mix})", (0.0, rest) if rest > 0 else None, end=duration)


def _manoeuvre(tr: _Track, road: Road, rng: np.random.Generator, end: float, swerve: float) -> None:
    """Append one manoeuvre of ``road`` (cut short at ``end``)."""
    kind = _MANOEUVRES[int(rng.choice(5, p=np.array(road.weights) / sum(road.weights)))]
    speed = float(rng.uniform(*road.speed))
    left = end - tr.now
    start = tr.now
    if kind == "stop" or tr.speed[-1] == 0.0:
        if tr.speed[-1] > 0.0:
            tr.drive(tr.speed[-1] / 2.0 + 0.1, 0.0, accel=2.0, kind="brake")
            tr.rest(float(rng.uniform(*road.stop_s)), kind="stop")
        tr.drive(min(speed / 2.0 + 5.0, max(left, 1.0)), speed, kind="straight")
        tr.swerve(start, tr.now, swerve, 0.1, float(rng.uniform(0, 2 * math.pi)))
    elif kind in ("straight", "sway"):
        length = min(float(rng.uniform(*road.straight_s)), max(left, 1.0))
        tr.drive(length, speed, kind=kind)
        if kind == "straight":
            tr.swerve(start, tr.now, swerve, 0.1, float(rng.uniform(0, 2 * math.pi)))
        else:
            # Swaying: small steering corrections, a few random low frequencies (HDR 4.1.1).
            for _ in range(3):
                tr.swerve(start, tr.now, float(rng.uniform(0.2, 0.6)) * _DEG, float(rng.uniform(0.03, 0.3)),
                          float(rng.uniform(0, 2 * math.pi)))
    elif kind == "curve":
        length = min(float(rng.uniform(*road.curve_s)), max(left, 2.0))
        rate = float(rng.uniform(*road.curve_dps)) * _DEG * float(rng.choice((-1.0, 1.0)))
        tr.curve(length, rate)
    else:
        # A 90-degree turn at a corner: slow down, turn, speed up.
        tr.drive(3.0, min(tr.speed[-1], 6.0), kind="slow")
        tr.turn(math.copysign(math.pi / 2, float(rng.choice((-1.0, 1.0)))), road.turn_dps * _DEG, 10.0 * _DEG)
        tr.drive(min(5.0, max(left, 1.0)), speed, kind="straight")


# --- FOG ---------------------------------------------------------------------------------------


def square_path(
    *,
    runs: int = 1,
    side: float = 4.0,
    speed: float = 0.4,
    accel: float = 0.2,
    turn_dps: float = 30.0,
    turn_accel_dps2: float = 30.0,
    rest: float = 20.0,
) -> Motion:
    """The FOG paper's bi-directional square path (section 4.1): each run is a clockwise lap and a
    counter-clockwise lap of a ``side`` x ``side`` m square, each lap preceded by a static bias test
    of ``rest`` seconds. Straight sides at up to ``speed`` [m/s] (from rest to rest), four
    on-the-spot 90-degree turns at up to ``turn_dps``. With the defaults a lap takes 64 s, as in the
    paper. Segments: ``rest``, ``lap_cw``, ``lap_ccw`` (each lap's ``angle`` is -+2 pi)."""
    if runs < 1:
        raise ValueError(f"runs must be >= 1, got {runs}")
    tr = _Track()
    for _ in range(runs):
        for direction, sign in (("cw", -1.0), ("ccw", 1.0)):
            tr.rest(rest)
            start = tr.now
            for _ in range(4):
                tr.distance(side, speed, accel)
                tr.turn(sign * math.pi / 2, turn_dps * _DEG, turn_accel_dps2 * _DEG)
            tr.label(f"lap_{direction}", start, sign * 2 * math.pi)
    tr.rest(1.0)
    return tr.build("FOG square path", (0.0, rest))


def rotary_table(
    *,
    runs: int = 150,
    rate_dps: float = 30.0,
    accel_dps2: float = 60.0,
    rest: float = 20.0,
    pause: float = 1.5,
) -> Motion:
    """The FOG paper's rotary-table runs (section 3): each run is a static bias test of ``rest``
    seconds, a clockwise 360 deg turn, a ``pause``, a counter-clockwise turn and a pause, turning
    at ``rate_dps`` with ramps of ``accel_dps2``; with the defaults a run takes 48 s, and 150 runs
    span the 2 hours the paper's gyro needed to reach a steady temperature.
    Segments: ``rest``, ``turn_cw``, ``turn_ccw``."""
    if runs < 1:
        raise ValueError(f"runs must be >= 1, got {runs}")
    tr = _Track()
    for _ in range(runs):
        tr.rest(rest)
        for direction, sign in (("cw", -1.0), ("ccw", 1.0)):
            tr.turn(sign * 2 * math.pi, rate_dps * _DEG, accel_dps2 * _DEG, kind=f"turn_{direction}")
            tr.rest(pause, kind="pause")
    return tr.build("FOG rotary table", (0.0, rest))


# --- Hong & Park -------------------------------------------------------------------------------


def robot_run(
    *,
    duration: float = 160.0,
    power_up: float = 5.0,
    calibration: float = 20.0,
    max_speed: float = 2.0,
    turn_deg: float = 90.0,
) -> Motion:
    """The Hong & Park robot run (section 4.1): a preprogrammed trajectory of ``duration`` seconds.
    The robot stands for ``power_up`` seconds after switching on (segment ``rest``), then turns back
    and forth on the spot at rates from 20 to 90 deg/s until ``calibration`` seconds (segment
    ``calibration``: the rate must change for the least squares of Hong eq 7 and 9), then drives
    straight legs at up to ``max_speed`` [m/s] with on-the-spot turns of ``turn_deg`` (> 0) to
    alternate sides, so the heading stays within +-``turn_deg``."""
    if not 0 < power_up < calibration < duration:
        raise ValueError("need 0 < power_up < calibration < duration")
    if not 0 < turn_deg <= 180:
        raise ValueError(f"turn_deg must be in (0, 180], got {turn_deg!r}")
    tr = _Track()
    tr.rest(power_up)
    for angle_deg, rate_dps in ((60, 40), (-120, 90), (90, 20), (-30, 60), (45, 70), (-45, 30)):
        tr.turn(angle_deg * _DEG, rate_dps * _DEG, 200 * _DEG)
        tr.rest(0.2, kind="pause")
    tr.rest(max(calibration - tr.now, 0.0), kind="pause")
    tr.label("calibration", power_up)
    legs = ((6.0, 1), (10.0, -1), (4.0, -1), (12.0, 1), (8.0, 1), (6.0, -1), (10.0, -1), (5.0, 1))
    i = 0
    while tr.now < duration:
        metres, side = legs[i % len(legs)]
        tr.distance(metres, max_speed, 1.0)
        tr.rest(1.0, kind="pause")
        tr.turn(side * turn_deg * _DEG, 60 * _DEG, 120 * _DEG)
        tr.rest(1.0, kind="pause")
        i += 1
    return tr.build("Hong & Park robot run", (0.0, power_up), end=duration)

"""The HDR paper's drives: its Figure 3 and 5 drive, and car drives on the road mixes of its
Tables II and IV."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._checks import check_number, check_seed, require_choice
from .motion_model import _DEG, Motion, _Track, check_duration, check_positive, rest_window


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
    check_positive(duration=duration, speed=speed)
    check_duration("the drive", duration)
    for name, value in (("curve_dps", curve_dps), ("swerve_dps", swerve_dps)):
        check_number(name, value, low=None, unit=" [deg/s]")  # NaN made every rate NaN
    if not 0 <= rest < curve_start < curve_end < duration:
        raise ValueError("need rest < curve_start < curve_end < duration")
    tr = _Track()
    tr.rest(rest)
    tr.drive(curve_start - 0.5 - rest, speed)
    tr.curve(curve_end - curve_start, curve_dps * _DEG)
    tr.drive(duration - tr.now, speed)
    tr.swerve(rest, duration, swerve_dps * _DEG, 0.1)
    return tr.build("HDR Figure 3", rest_window(rest))


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

    Raises:
        ValueError: an unknown ``mix``, a ``duration`` that is not finite and > 0 or longer than
            :data:`gyrocore.motion.MAX_DURATION`, a ``rest`` not in [0, duration), a
            ``swerve_dps`` that is not finite, a ``seed`` outside [0, 2^64).
        TypeError: a number argument that is text or a bool.
    """
    duration = check_number("duration", duration, unit=" [s]")
    check_duration("the drive", duration)  # built manoeuvre by manoeuvre: 1e9 s ran out of memory
    rest = check_number("rest", rest, strict=False, unit=" [s]")
    check_number("swerve_dps", swerve_dps, low=None, unit=" [deg/s]")  # NaN, 1e300: every rate NaN or beyond reading
    seed = check_seed(seed)
    require_choice("road mix", mix, ROAD_MIXES)
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
    return tr.build(f"car ({mix})", rest_window(rest), end=duration)


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
        # the swerve from the drive-off on: from the braking, it turned the car while it stood
        moving = tr.now
        tr.drive(min(speed / 2.0 + 5.0, max(left, 1.0)), speed, kind="straight")
        tr.swerve(moving, tr.now, swerve, 0.1, float(rng.uniform(0, 2 * math.pi)))
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

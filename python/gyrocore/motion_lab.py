"""The FOG and Hong & Park papers' motions: the square path and the rotary table (FOG), the robot
run (Hong & Park)."""

from __future__ import annotations

import math

from ._checks import check_count, check_number
from .motion_model import _DEG, Motion, _Track, check_duration, check_positive, rest_window


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
    paper. Segments: ``rest``, ``lap_cw``, ``lap_ccw`` (each lap's ``angle`` is -+2 pi).

    Raises:
        ValueError: ``runs`` that is no whole number >= 1 or that would last longer than
            :data:`gyrocore.motion.MAX_DURATION`, a ``rest`` that is not finite and >= 0,
            another argument that is not finite and > 0 (each named).
    """
    runs = check_count("runs", runs)
    check_positive(side=side, speed=speed, accel=accel, turn_dps=turn_dps, turn_accel_dps2=turn_accel_dps2)
    check_number("rest", rest, strict=False, unit=" [s]")
    if runs > 1:  # one run's length times runs, before they are built one by one
        one = square_path(runs=1, side=side, speed=speed, accel=accel, turn_dps=turn_dps, turn_accel_dps2=turn_accel_dps2,
                          rest=rest)
        check_duration(f"the square path of {runs} runs", float(one.knots[-1]) * runs)
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
    return tr.build("FOG square path", rest_window(rest))


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
    Segments: ``rest``, ``turn_cw``, ``turn_ccw``.

    Raises:
        ValueError: as :func:`square_path` (``pause`` finite and >= 0, as ``rest``).
    """
    runs = check_count("runs", runs)
    check_positive(rate_dps=rate_dps, accel_dps2=accel_dps2)
    check_number("rest", rest, strict=False, unit=" [s]")
    check_number("pause", pause, strict=False, unit=" [s]")  # a negative pause was taken
    if runs > 1:
        one = rotary_table(runs=1, rate_dps=rate_dps, accel_dps2=accel_dps2, rest=rest, pause=pause)
        check_duration(f"the rotary table of {runs} runs", float(one.knots[-1]) * runs)
    tr = _Track()
    for _ in range(runs):
        tr.rest(rest)
        for direction, sign in (("cw", -1.0), ("ccw", 1.0)):
            tr.turn(sign * 2 * math.pi, rate_dps * _DEG, accel_dps2 * _DEG, kind=f"turn_{direction}")
            tr.rest(pause, kind="pause")
    return tr.build("FOG rotary table", rest_window(rest))


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
    check_positive(duration=duration, max_speed=max_speed)  # NaN speed: numpy's "arange: cannot compute length"
    check_duration("the robot run", duration)
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

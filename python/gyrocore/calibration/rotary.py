"""Rotary-table scale factors per turn direction with a temperature-linear model (FOG eq 1-6)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .._arrays import READ_TO_CALIBRATE, FloatArray, no_path_for_arrays
from .._checks import check_number
from ..integration import angle_of
from .inputs import check_series, check_temperature
from .rest import MAX_RATE, refuse_unknown_rest_options, rest_windows, static_bias
from .result import Calibration


@dataclass(frozen=True)
class Turn:
    """One 360-degree table turn (FOG section 3).

    Attributes:
        start, end: time span of the motion [s].
        direction: ``"cw"`` (negative rate) or ``"ccw"``.
        angle: measured change of orientation theta_meas [rad], signed, after the static bias.
        error: E_cw = -theta - 2 pi or E_ccw = theta - 2 pi (FOG eq 1) [rad].
        factor: C = 2 pi / |theta| (FOG eq 2).
        bias: static bias subtracted, from the rest before the turn [rad/s].
        temperature: mean sensor temperature during the turn [degC], or None.
    """

    start: float
    end: float
    direction: str
    angle: float
    error: float
    factor: float
    bias: float
    temperature: float | None

    @property
    def error_deg(self) -> float:
        """E in degrees (the paper's unit)."""
        return math.degrees(self.error)


@dataclass(frozen=True)
class RotaryTable:
    """Turns of a rotary-table log and the calibration fitted to them (FOG eq 1-6).

    Attributes:
        turns: every turn found, in time order.
        calibration: ``c_cw``/``c_ccw`` and, with a temperature, ``temp_slope``/``temp_offset``.
        e_cw, e_ccw: mean turn errors per direction [rad] (FOG eq 1).
        temperature_fit: ``(slope [rad/degC], offset [rad], residual rms [rad])`` of FOG eq 5
            fitted to all turns, or None without a temperature.
    """

    turns: tuple[Turn, ...]
    calibration: Calibration
    e_cw: float
    e_ccw: float
    temperature_fit: tuple[float, float, float] | None


#: A stretch turning less than this fraction of the turn angle is no turn (a bias step, a nudge).
NUDGE = 0.05


def _refuse_slow_turns(
    ta: FloatArray, ra: FloatArray, pauses: list[tuple[float, float]], first: tuple[float, float], turn_angle: float,
    max_rate: float,
) -> None:
    """Refuse a rest that turns: a table turn slower than ``max_rate`` is as steady as a rest and
    within it of zero, so :func:`rest_windows` finds it as one. Taken for a pause it was dropped,
    and for a static bias test it made the bias its rate (2 deg/s turns: a bias of -1.98 deg/s).
    A rest reads the bias of the first one; one whose level differs so much that it turns by a
    turn's ``NUDGE`` is a turn."""
    def level(window: tuple[float, float]) -> float:
        return float(np.mean(ra[np.searchsorted(ta, window[0]) : np.searchsorted(ta, window[1], side="right")]))

    bias = level(first)
    for a, b in pauses:
        offset = level((a, b)) - bias
        if abs(offset) * (b - a) >= NUDGE * turn_angle:
            raise ValueError(
                f"the stretch from {a:.6g} to {b:.6g} s, found as a rest, turns {math.degrees(offset * (b - a)):.4g} "
                f"deg at {math.degrees(offset):.3g} deg/s from the first rest's level: a turn slower than max_rate = "
                f"{max_rate:g} rad/s ({math.degrees(max_rate):.3g} deg/s) reads as steady as a rest; give a smaller "
                f"max_rate (max_rate={abs(offset) / 2:.2g})"
            )


@no_path_for_arrays("gyrocore.calibration.rotary_table", READ_TO_CALIBRATE)
def rotary_table(
    t: ArrayLike,
    rate: ArrayLike,
    *,
    temperature: ArrayLike | None = None,
    turn_angle: float = 2.0 * math.pi,
    tolerance: float = 0.25,
    min_rest: float = 5.0,
    min_pause: float = 0.2,
    **rest_options: float,
) -> RotaryTable:
    """Scale-factor calibration from a rotary-table log of 360-degree turns (FOG section 3).

    The log alternates pauses and turns: the table stops for at least ``min_pause`` seconds
    after each turn (a cw turn may be followed at once by its ccw turn, as in FOG's runs), and
    pauses of at least ``min_rest`` seconds are static bias tests. Pauses are found with
    :func:`rest_windows` (``rest_options``). Each motion between pauses is integrated
    (trapezoid) into theta_meas after subtracting the mean of the last static bias test before
    it (FOG: a test before each run, subtracted during the run), and must be within
    ``tolerance`` of ``turn_angle`` in size (a stretch between pauses turning less than 5 % of
    it is a bias step or a nudge, not a turn); motion before the first test is ignored. Then per
    turn E (FOG eq 1) and C (eq 2).

    Without a temperature, ``c_cw`` and ``c_ccw`` are eq 2 on each direction's mean angle. With
    a temperature [degC per sample], E of all turns is fitted by ``E_T = a T + c`` (eq 5; the paper
    found cw and ccw alike), giving ``temp_slope = a / 2 pi`` and ``temp_offset = c / 2 pi`` for the
    pipeline's C_T (eq 6); ``c_cw``/``c_ccw`` are then what remains per direction, the mean of
    C / C_T over its turns (factors multiply, FOG eq 4).

    Raises:
        ValueError: bad samples, no rest before the first turn, a motion that is not a turn of
            ``turn_angle``, a rest that turns (a turn slower than ``max_rate``, found as a rest),
            or no turn at all.
    """
    # checked here: a turn_angle or tolerance of 0 or NaN gave "no turn found", a NaN min_rest "no rest of
    # at least nan s", and min_pause was named min_duration (rest_windows' name for it)
    for name, value in (("turn_angle", turn_angle), ("tolerance", tolerance), ("min_rest", min_rest),
                        ("min_pause", min_pause)):
        check_number(name, value)
    refuse_unknown_rest_options("rotary_table (its pauses' min_duration is min_pause)", rest_options)
    ta, ra = check_series(t, rate)
    temp = None if temperature is None else check_temperature(temperature, len(ta))
    pauses = rest_windows(ta, ra, min_duration=min_pause, **rest_options)
    tests = [w for w in pauses if w[1] - w[0] >= min_rest]
    if not tests:
        raise ValueError(
            f"no rest of at least {min_rest:g} s found: the static bias before the turns cannot be measured"
        )
    _refuse_slow_turns(ta, ra, pauses, tests[0], turn_angle, rest_options.get("max_rate", MAX_RATE))
    turns: list[Turn] = []
    for k, (_, p1) in enumerate(pauses):
        if p1 < tests[0][1]:
            continue  # no static bias test yet
        following = pauses[k + 1][0] if k + 1 < len(pauses) else float(ta[-1])
        moving = np.flatnonzero((ta >= p1) & (ta <= following))
        if len(moving) < 3:
            continue
        test = [w for w in tests if w[1] <= p1][-1]
        bias = static_bias(ta, ra, test, min_duration=min_rest).bias
        tm, rm = ta[moving], ra[moving] - bias
        angle = float(angle_of(tm - tm[0], rm)[-1])  # the input warned of its units
        if abs(angle) < NUDGE * turn_angle:
            continue  # a step of the bias or a nudge between pauses, not a turn
        if abs(abs(angle) - turn_angle) > tolerance * turn_angle:
            raise ValueError(
                f"the motion from {p1:.6g} to {following:.6g} s turned {math.degrees(angle):.4g} deg, "
                f"not {math.degrees(turn_angle):.4g} deg (within {tolerance:.0%}); is the log a rotary-table "
                "run of single turns, each followed by a pause?"
            )
        direction = "ccw" if angle > 0 else "cw"
        error = abs(angle) - turn_angle  # FOG eq 1a (-theta - 360) and 1b (theta - 360)
        mean_temp = None if temp is None else float(np.mean(temp[moving]))
        factor = turn_angle / abs(angle)
        turns.append(Turn(float(tm[0]), float(tm[-1]), direction, angle, error, factor, bias, mean_temp))
    if not turns:
        raise ValueError("no turn found between the rests")
    cw = [x for x in turns if x.direction == "cw"]
    ccw = [x for x in turns if x.direction == "ccw"]
    e_cw = float(np.mean([x.error for x in cw])) if cw else math.nan
    e_ccw = float(np.mean([x.error for x in ccw])) if ccw else math.nan
    fit = None
    slope = offset = None
    if temp is None:
        c_cw = turn_angle / float(np.mean([abs(x.angle) for x in cw])) if cw else 1.0
        c_ccw = turn_angle / float(np.mean([abs(x.angle) for x in ccw])) if ccw else 1.0
    else:
        temps = np.array([x.temperature for x in turns], dtype=np.float64)
        errors = np.array([x.error for x in turns])
        if len(turns) < 2 or np.ptp(temps) == 0:
            raise ValueError("fitting E_T = a T + c (FOG eq 5) needs turns at two or more temperatures")
        design = np.column_stack([temps, np.ones_like(temps)])
        (a, c), *_ = np.linalg.lstsq(design, errors, rcond=None)
        rms = float(np.sqrt(np.mean((errors - design @ np.array([a, c])) ** 2)))
        fit = (float(a), float(c), rms)
        slope, offset = float(a) / turn_angle, float(c) / turn_angle

        def residual_factor(group: list[Turn]) -> float:
            # C_T of FOG eq 6 at each turn's temperature; what is left is the direction's factor.
            if not group:
                return 1.0
            factor = np.array([x.factor for x in group])
            temperature = np.array([x.temperature for x in group], dtype=np.float64)
            return float(np.mean(factor * np.abs(1.0 + slope * temperature + offset)))

        c_cw, c_ccw = residual_factor(cw), residual_factor(ccw)
    calibration = Calibration(
        method="rotary_table",
        bias=float(np.mean([x.bias for x in turns])),
        c_cw=c_cw,
        c_ccw=c_ccw,
        temp_slope=slope,
        temp_offset=offset,
        window=(turns[0].start, turns[-1].end),
        samples=int(sum(np.count_nonzero((ta >= x.start) & (ta <= x.end)) for x in turns)),
        notes=(f"{len(cw)} cw and {len(ccw)} ccw turns",),
    )
    return RotaryTable(tuple(turns), calibration, e_cw, e_ccw, fit)

"""The noise parameters read off an Allan deviation curve (angle random walk N, bias instability B,
rate random walk K; IEEE Std 952-1997), and pipeline settings derived from them;
:mod:`gyrocore.allan` re-exports the public names."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _gyrocore
from ._arrays import FloatArray
from ._checks import MAX_READING, MAX_SECONDS, check_number, real_number, shown
from .window import MIN_WINDOW_READINGS

if TYPE_CHECKING:  # pragma: no cover
    # only a type here: importing the curve module at run time would import the pipeline, which
    # imports gyrocore.rests, which takes FLICKER_FLOOR from here
    from .allan_curve import AllanResult

_RAD_TO_DEG = 180.0 / math.pi
#: sqrt(s) per sqrt(h), and s per h: for the customary units deg/sqrt(h), deg/h, deg/h/sqrt(h).
_SQRT_HOUR = 60.0
_HOUR = 3600.0
#: IEEE 952: the Allan deviation's flat floor is sqrt(2 ln 2 / pi) = 0.664 times the bias instability.
FLICKER_FLOOR = math.sqrt(2.0 * math.log(2.0) / math.pi)
#: The shortest interval the core takes [s] (``gyrocore::MIN_INTERVAL``), for ``dt`` and ``hdr_interval``.
MIN_INTERVAL: float = _gyrocore.MIN_INTERVAL
#: The smallest noise :func:`settings_from_noise` takes (N [rad/sqrt(s)], B [rad/s]): 500 times
#: below the best gyros' (a bias instability of 1e-4 deg/h is 5e-10 rad/s); far smaller values are
#: a unit gone wrong, and below 1e-154 N^2 underflowed to settings of 0.
MIN_NOISE = 1e-12
#: :func:`noise_parameters` takes a slope tolerance below this: half the step between the slopes
#: -1/2, 0 and +1/2, so that no point counts for two noise types (at 5, white noise of N = 1e-3
#: read as a flat floor and a +1/2 line over its whole curve: B = 0.0107 rad/s, K = 0.071).
MAX_SLOPE_TOLERANCE = 0.25


@dataclass(frozen=True)
class NoiseParameter:
    """One noise coefficient read from the curve.

    Attributes:
        value: the coefficient in SI units (``unit``), for a rate in rad/s.
        unit: its unit.
        value_deg: the same in the customary degree unit ``unit_deg``.
        unit_deg: deg/sqrt(h), deg/h or deg/h/sqrt(h).
        tau_range: (first, last) averaging time [s] of the part of the curve it came from.
        method: how it was read.
    """

    value: float
    unit: str
    value_deg: float
    unit_deg: str
    tau_range: tuple[float, float]
    method: str


@dataclass(frozen=True, repr=False)
class NoiseParameters:
    """Angle random walk ``N``, bias instability ``B`` and rate random walk ``K`` (IEEE 952),
    each None where the curve does not show its slope; ``notes`` says why, and warns where a
    value is only a bound."""

    arw: NoiseParameter | None
    bias_instability: NoiseParameter | None
    rrw: NoiseParameter | None
    dt: float
    notes: tuple[str, ...] = ()

    def __str__(self) -> str:
        lines = []
        for label, p in (("angle random walk N", self.arw), ("bias instability B", self.bias_instability),
                         ("rate random walk K", self.rrw)):
            if p is None:
                lines.append(f"{label}: not found")
            else:
                lines.append(
                    f"{label}: {p.value:.4g} {p.unit} ({p.value_deg:.4g} {p.unit_deg}), "
                    f"tau {p.tau_range[0]:.4g} .. {p.tau_range[1]:.4g} s, {p.method}"
                )
        return "\n".join(lines + [f"note: {n}" for n in self.notes])

    def __repr__(self) -> str:
        """One line of the three values; ``print()`` adds where each was read, and the notes."""
        values = [f"{label} {'not found' if p is None else f'{p.value:.4g} {p.unit}'}" for label, p in
                  (("N", self.arw), ("B", self.bias_instability), ("K", self.rrw))]
        notes = f"; {len(self.notes)} note(s)" if self.notes else ""
        return f"NoiseParameters({', '.join(values)}{notes}: print() it for where each was read and the notes)"

    def as_dict(self) -> dict[str, Any]:
        """Plain values (for JSON)."""
        def one(p: NoiseParameter | None) -> dict[str, Any] | None:
            return None if p is None else {
                "value": p.value, "unit": p.unit, "value_deg": p.value_deg, "unit_deg": p.unit_deg,
                "tau_range_s": list(p.tau_range), "method": p.method,
            }
        return {"arw": one(self.arw), "bias_instability": one(self.bias_instability), "rrw": one(self.rrw),
                "dt": self.dt, "notes": list(self.notes)}

    def kalibr_yaml(self, *, rostopic: str = "/imu0", rrw: float | None = None) -> str:
        """The gyroscope entries of a Kalibr-style IMU noise YAML (imu.yaml).

        ``gyroscope_noise_density`` is ``N`` [rad/s/sqrt(Hz)] and ``gyroscope_random_walk`` is
        ``K`` [rad/s^2/sqrt(Hz)], both continuous-time densities as Kalibr expects. Give ``rrw``
        [rad/s^2/sqrt(Hz)] when the curve does not show the rate random walk (record too short);
        the accelerometer entries must come from the accelerometers' own analysis.
        """
        if self.arw is None:
            raise ValueError("the angle random walk was not found on the curve; cannot write a noise density")
        if not (isinstance(rostopic, str) and rostopic.strip() and rostopic.isprintable() and " " not in rostopic):
            # a line break wrote a YAML key of its own, and an empty topic a file Kalibr cannot use
            raise ValueError(f"rostopic must be a ROS topic name (e.g. /imu0): text without spaces or line breaks, "
                             f"got {rostopic!r}")
        given = None if rrw is None else real_number(rrw)  # a numpy float32 was refused, 10**400 an OverflowError
        if rrw is not None and not (given is not None and math.isfinite(given) and given > 0):  # True was K = 1
            raise ValueError(f"rrw (--rrw) = {shown(rrw)}: give the rate random walk K, a finite number > 0 "
                             "[rad/s^2/sqrt(Hz)]")
        k = given if given is not None else (None if self.rrw is None else self.rrw.value)
        if k is None:
            raise ValueError(
                "the rate random walk was not found (the record is too short to show the +1/2 slope); "
                "pass rrw= (--rrw on the command line) [rad/s^2/sqrt(Hz)] from a longer record or the datasheet"
            )
        return "\n".join([
            "# Gyroscope noise from an Allan deviation (gyrocore), IEEE Std 952-1997 coefficients:",
            f"#   N (angle random walk) = {self.arw.value:.6g} rad/s/sqrt(Hz) = rad/sqrt(s) "
            f"= {self.arw.value_deg:.6g} deg/sqrt(h)",
            f"#   K (rate random walk)  = {k:.6g} rad/s^2/sqrt(Hz) = rad/s/sqrt(s) "
            f"= {k * _RAD_TO_DEG * _HOUR * _SQRT_HOUR:.6g} deg/h/sqrt(h)",
            "# Both are continuous-time densities; the per-sample (discrete) values at rate f are",
            "# N*sqrt(f) [rad/s] and K/sqrt(f) [rad/s^2]. Not the same as deg/s/sqrt(Hz) or deg/sqrt(h).",
            "# Accelerometer entries are not included: take them from the accelerometers' analysis.",
            "",
            "#Gyroscopes",
            f"gyroscope_noise_density: {self.arw.value:.6e}   # [ rad / s / sqrt(Hz) ]   ( gyro \"white noise\" )",
            f"gyroscope_random_walk: {k:.6e}   # [ rad / s^2 / sqrt(Hz) ]  ( gyro bias diffusion )",
            "",
            f"rostopic: {rostopic}",
            f"update_rate: {1.0 / self.dt:.6g}   # [ Hz ]",
            "",
        ])


def noise_parameters(result: AllanResult, *, slope_tolerance: float = 0.15) -> NoiseParameters:
    """Read N, B and K off an Allan deviation curve of a rate in rad/s (IEEE 952 Annex C).

    - Angle random walk ``N``: the longest stretch where the curve falls with slope -1/2 (each
      point's slope taken to the point about an octave further, within ``slope_tolerance``, or
      within three standard errors (and 0.02) where the curve is known more closely than that);
      a line of slope -1/2 is fitted there (weighted by each point's degrees of freedom) and read
      at tau = 1 s: ``N = sigma(1 s)``.
    - Bias instability ``B``: the flat minimum divided by sqrt(2 ln 2 / pi) = 0.664. The flat
      minimum is the lowest stretch of slope 0 (within ``slope_tolerance``), its level the
      weighted mean there; without such a stretch, the lowest point. A flat stretch the curve
      later falls clearly below (the hump of a sensor's internal filter at the shortest taus) is
      not the floor, nor is one that ends on the -1/2 line of N within its confidence interval
      (white noise's scatter). If the minimum is the last tau (the floor is not reached), the
      first (an internal filter) or lies on that line, ``B`` is only an upper bound (see notes).
    - Rate random walk ``K``: as N, for slope +1/2, read at tau = 3 s: ``K = sigma(3 s)``.
    - A rate ramp (slope +1, ``sigma = R tau / sqrt(2)``: the rate drifts steadily) is named in
      ``notes`` with its ``R`` [rad/s^2]; B and K read within two octaves before it are marked as
      upper bounds, since the curve's bend into it passes through the slopes 0 and +1/2.

    Raises a TypeError for a ``result`` that is no :class:`~gyrocore.allan.AllanResult` (a list
    failed as "'list' object has no attribute 'kind'"), and a ValueError for a curve that is 0 at
    every tau (constant readings: there is no noise to read) or a ``slope_tolerance`` outside
    (0, :data:`MAX_SLOPE_TOLERANCE`).
    """
    from .allan_curve import AllanResult  # here: at import time it would import the pipeline (above)

    if not isinstance(result, AllanResult):
        raise TypeError("give the AllanResult of gyrocore.allan.deviation (or deviation_from_timestamps), not "
                        f"{type(result).__name__}")
    if result.kind != "allan":
        raise ValueError(f"noise parameters are read from the Allan deviation, not the {result.kind} deviation")
    if len(result.taus) < 3:
        raise ValueError(f"the curve has {len(result.taus)} taus; need at least 3 to read slopes")
    taus, dev, w = result.taus, result.adev, result.edf
    if result.flat_zero:  # the slopes of log 0 are no noise's
        raise ValueError("the Allan deviation is 0 at every tau: the readings are constant (a sensor stuck, saturated "
                         "or quantised coarser than its noise), so there is no noise to read N, B and K from")
    notes: list[str] = []
    slope_tolerance = check_number("slope_tolerance", slope_tolerance)  # NaN or -1 found no slope without a word
    if not slope_tolerance < MAX_SLOPE_TOLERANCE:
        raise ValueError(f"slope_tolerance must be below {MAX_SLOPE_TOLERANCE:g} (half the step between the slopes "
                         f"-1/2, 0 and +1/2: a point would count for two noise types), got {slope_tolerance:g}")
    arw = _slope_line(taus, dev, w, -0.5, 1.0, slope_tolerance)
    rrw = _slope_line(taus, dev, w, 0.5, 3.0, slope_tolerance)
    arw_p = rrw_p = None
    if arw is None:
        notes.append("no stretch of slope -1/2: angle random walk not identified")
    else:
        value, span = arw
        arw_p = NoiseParameter(value, "rad/s/sqrt(Hz)", value * _RAD_TO_DEG * _SQRT_HOUR, "deg/sqrt(h)", span,
                               "line of slope -1/2 read at tau = 1 s")
    # IEEE 952's rate ramp R (slope +1, sigma = R tau / sqrt(2)): a rate that drifts steadily. The
    # curve bends into it through the slopes 0 and +1/2, so a floor or a +1/2 line within two
    # octaves of its start is the ramp's as much as any noise's, and only bounds B or K from above.
    # A ramp rises to the longest tau: a rise of slope +1 the curve later falls from is a
    # sinusoid's (IEEE 952's sinusoidal term, a period of 400 s was taken for a ramp) or motion's.
    ramp = _slope_line(taus, dev, w, 1.0, 1.0, slope_tolerance, to_the_end=True)
    beside = math.inf  # the shortest tau [s] a stretch may end at to lie beside the ramp
    if ramp is not None:
        level, (start, end) = ramp
        beside = start / 4.0
        notes.append(
            f"the curve rises with slope +1 over tau {start:.4g} .. {end:.4g} s: a rate ramp, R = "
            f"{math.sqrt(2.0) * level:.3g} rad/s^2 (the rate drifts steadily, e.g. while the gyro warms up); the bias "
            "instability and rate random walk read beside it are upper bounds: remove the drift, or analyse a "
            "stretch without it"
        )
    if rrw is None:
        notes.append("no stretch of slope +1/2: rate random walk not identified (record too short?)")
    else:
        value, span = rrw
        method = "line of slope +1/2 read at tau = 3 s" + (_BESIDE_RAMP if span[1] >= beside else "")
        rrw_p = NoiseParameter(value, "rad/s^2/sqrt(Hz)", value * _RAD_TO_DEG * _HOUR * _SQRT_HOUR,
                               "deg/h/sqrt(h)", span, method)
    # The flat bottom: of the flat stretches, the lowest; its level is the edf-weighted mean,
    # since the single lowest point of a noisy floor is biased low (few terms at long tau). A
    # stretch the curve later falls below half of (confidence interval included) is no bottom: a
    # sensor's internal filter flattens the shortest taus before the white noise's -1/2 fall,
    # while a floor's own points stay well within a factor 2 of its level. Nor is a stretch that
    # ends, past the start of the white noise's -1/2 line, on that line (within its interval):
    # the scatter of the last few points of white noise, read as a floor in 10 of 60 records of it.
    def on_white_line(i: int) -> bool:
        return arw is not None and taus[i] >= arw[1][0] and bool(result.adev_low[i] <= arw[0] / math.sqrt(taus[i]))

    flat = [
        (float(np.average(dev[a : b + 1], weights=w[a : b + 1])), (a, b))
        for a, b in _slope_runs(taus, dev, w, 0.0, slope_tolerance)
    ]
    flat = [(level, run) for level, run in flat
            if not np.any(result.adev_high[run[1] + 1 :] < level / 2) and not on_white_line(run[1])]
    if flat:
        floor, (lo, hi) = min(flat)
        method = "flat minimum (slope 0, weighted mean) / 0.664"
    else:
        lo = hi = int(np.argmin(dev))
        floor = float(dev[lo])
        method = "minimum / 0.664"
    if lo == 0 and not flat:
        # every point of the curve is at least 0.664 B, so the level still bounds B from above
        method += " (upper bound: the minimum is at the shortest tau)"
        notes.append(
            "the Allan deviation is lowest at the shortest taus, where a sensor's internal filter shapes the "
            "curve, not its bias instability: bias instability is an upper bound"
        )
    elif hi == len(dev) - 1 and not flat:
        method += " (upper bound: the curve still falls at the longest tau)"
        notes.append("the Allan deviation has no minimum within the record: bias instability is an upper bound")
    elif on_white_line(hi) and not flat:
        method += " (upper bound: the minimum lies on the -1/2 line)"
        notes.append(f"the Allan deviation's minimum at tau = {taus[hi]:.4g} s lies on the angle random walk's -1/2 "
                     "line within its interval: the floor is not reached, bias instability is an upper bound")
    elif taus[hi] >= beside:
        method += _BESIDE_RAMP
    b = floor / FLICKER_FLOOR
    bias_p = NoiseParameter(b, "rad/s", b * _RAD_TO_DEG * _HOUR, "deg/h", (float(taus[lo]), float(taus[hi])), method)
    return NoiseParameters(arw_p, bias_p, rrw_p, result.dt, tuple(notes))


#: The least tolerance of a slope where the curve is known closely (see :func:`_slope_runs`).
SLOPE_SLACK = 0.02
#: What a bias instability or rate random walk read beside a rate ramp is (see :func:`noise_parameters`).
_BESIDE_RAMP = " (upper bound: beside a rate ramp)"


def _slope_runs(
    taus: FloatArray, dev: FloatArray, edf: FloatArray, slope: float, tolerance: float
) -> list[tuple[int, int]]:
    """Index ranges ``(first, last)`` of the stretches where the curve has ``slope`` within
    ``tolerance``: each point's slope is taken to the first point an octave further (robust on
    dense tau sets), and a run of matching points spans up to the last one's octave partner.

    Where the curve is known closely (many degrees of freedom ``edf``: the shortest taus) the
    tolerance narrows to what its scatter allows: three standard errors of the slope (the log of
    a deviation scatters by 1/sqrt(2 edf)) and :data:`SLOPE_SLACK`. A sensor's bandwidth bends
    the shortest taus (slope -0.4 for the simulated XV3500's 20 Hz at 100 Hz), well known there
    and within 0.15 of -1/2: taken into N's line, they weighed most and read N 8 % low."""
    lt, ld = np.log(taus), np.log(dev)
    ahead = np.searchsorted(lt, lt + math.log(2.0) - 1e-9)
    ok = ahead < len(lt)
    local = np.full(len(lt), np.nan)
    local[ok] = (ld[ahead[ok]] - ld[ok]) / (lt[ahead[ok]] - lt[ok])
    spread = np.full(len(lt), np.inf)
    spread[ok] = np.sqrt(0.5 / edf[ok] + 0.5 / edf[ahead[ok]]) / (lt[ahead[ok]] - lt[ok])
    match = np.abs(local - slope) <= np.minimum(tolerance, SLOPE_SLACK + 3.0 * spread)
    runs = []
    i = 0
    while i < len(match):
        if match[i]:
            j = i
            while j + 1 < len(match) and match[j + 1]:
                j += 1
            runs.append((i, int(ahead[j])))
            i = j + 1
        else:
            i += 1
    return runs


def _slope_line(
    taus: FloatArray, dev: FloatArray, weight: FloatArray, slope: float, at: float, tolerance: float,
    *, to_the_end: bool = False,
) -> tuple[float, tuple[float, float]] | None:
    """Fit ``log dev = c + slope log tau`` (weights: degrees of freedom) on the stretch of that
    slope spanning the most octaves (with ``to_the_end``, only one that reaches the longest tau);
    returns (dev at tau = ``at``, tau range) or None."""
    runs = _slope_runs(taus, dev, weight, slope, tolerance)
    if to_the_end:
        runs = [run for run in runs if run[1] == len(taus) - 1]
    if not runs:
        return None
    a, b = max(runs, key=lambda r: taus[r[1]] / taus[r[0]])
    lt, ld = np.log(taus[a : b + 1]), np.log(dev[a : b + 1])
    c = np.average(ld - slope * lt, weights=weight[a : b + 1])
    return float(np.exp(c + slope * math.log(at))), (float(taus[a]), float(taus[b]))


# --- settings from noise: parameters from the Allan analysis ------------------------------------


@dataclass(frozen=True)
class NoiseSettings:
    """Pipeline settings derived from a gyro's noise (see :func:`settings_from_noise`); SI units."""

    threshold: float
    """Dead band r_thres of Hong eq 12 [rad/s]."""
    bias_duration: float
    """Static-bias averaging time T_bias (HDR section 2) [s]."""
    hdr_increment: float
    """HDR nominal increment i_c (HDR eq 4, 11) [rad/s per step]."""
    hdr_turn_threshold: float
    """HDR turn threshold Theta_w (HDR eq 8) [rad/s]."""
    bias_error: float
    """Expected standard error of the static bias after T_bias [rad/s]."""
    hdr_interval: float = 1.0
    """HDR step length [s] that ``hdr_turn_threshold`` was set for."""

    def overrides(self) -> dict[str, float]:
        """Parameters for ``gyrocore.Pipeline(preset, **overrides)``: with the HDR step the turn
        threshold was set for (a step of 0.5 s was given a threshold for it while the pipeline
        kept its 1 s steps)."""
        return {
            "threshold": self.threshold,
            "bias_duration": self.bias_duration,
            "hdr_increment": self.hdr_increment,
            "hdr_turn_threshold": self.hdr_turn_threshold,
            "hdr_interval": self.hdr_interval,
        }


def settings_from_noise(
    *,
    arw: float,
    bias_instability: float,
    dt: float,
    hdr_interval: float = 1.0,
    threshold_factor: float = 0.72,
    turn_sigmas: float = 3.0,
) -> NoiseSettings:
    """Pipeline settings from a gyro's Allan parameters, so a new gyro needs no hand-tuning.

    Args:
        arw: angle random walk N [rad/s/sqrt(Hz) = rad/sqrt(s)].
        bias_instability: B [rad/s].
        dt: sample interval the pipeline will see [s].
        hdr_interval: HDR step length [s] (the paper's 1 s).
        threshold_factor: r_thres in units of the per-sample noise (see below).
        turn_sigmas: Theta_w in standard deviations of a straight-line step (see below).

    The reasoning, step by step (white rate noise averages down as N/sqrt(T); the bias
    instability does not average down below its floor 0.664 B):

    1. **T_bias** (HDR section 2, "estimated by using the Allan Variance analysis"): averaging a
       rest of T seconds leaves a bias error of about sqrt(N^2/T + (0.664 B)^2). The knee where
       both terms are equal, ``T_bias = (N / 0.664 B)^2``, is where averaging stops paying: a
       shorter rest leaves mostly white-noise error, a longer one gains at most a factor sqrt(2).
       The bias error after T_bias is then ``e_b = sqrt(2) * 0.664 B``. T_bias is at least
       ``3 dt``, the readings the pipeline's static bias needs (with one interval to spare), and
       ``e_b = sqrt(N^2 / T_bias + (0.664 B)^2)`` then.
    2. **Threshold** (Hong eq 12): readings below r_thres are zeroed, so it is set against the
       per-sample white noise ``sigma_w = N / sqrt(dt)``: ``r_thres = k sigma_w``. The default
       k = 0.72 is Hong & Park's own choice expressed this way: their XV3500 (N = 2.5 deg/sqrt(h))
       at 100 Hz has sigma_w = 0.417 deg/s and they used 0.3 deg/s. About half the readings at
       rest are zeroed (erf(0.72/sqrt(2)) = 0.53) while turns faster than a few r_thres pass.
    3. **HDR increment i_c** (HDR eq 4): the binary controller moves I by i_c per step and
       oscillates about the drift by about i_c; it has to absorb the residual bias e_b and follow
       the bias instability, so ``i_c = e_b`` (one step reaches the expected residual, and the
       ripple stays at the size of the error being removed).
    4. **Turn threshold Theta_w** (HDR eq 8): a straight-line step reads the white noise averaged
       over the step plus the residual bias, with standard deviation
       ``sqrt(N^2 / T_h + e_b^2)``; ``Theta_w = turn_sigmas`` times that, so noise on a straight
       road rarely (0.3 % at 3 sigma) suspends HDR, and anything larger is taken as a turn.
    """
    # a bool or text passed for a number ("1e-3" was a bare TypeError of math, True a value of 1)
    # and within the pipeline's limits: 1e300 overflowed N^2 (a bare OverflowError), a dt of 1e300 s
    # was taken, a noise of 1e-300 underflowed to settings of 0 that the pipeline refused by their names
    arw, bias_instability = (check_number(name, value, low=MIN_NOISE, high=MAX_READING, unit=unit) for name, value, unit in
                             (("arw", arw, " [rad/sqrt(s)]"), ("bias_instability", bias_instability, " [rad/s]")))
    dt, hdr_interval = (check_number(name, value, low=MIN_INTERVAL, strict=False, high=MAX_SECONDS, unit=" [s]")
                        for name, value in (("dt", dt), ("hdr_interval", hdr_interval)))
    threshold_factor, turn_sigmas = (check_number(name, value) for name, value in (
        ("threshold_factor", threshold_factor), ("turn_sigmas", turn_sigmas)))
    floor = FLICKER_FLOOR * bias_instability
    t_bias = (arw / floor) ** 2 if arw / floor < MAX_SECONDS else math.inf  # ** overflowed: a bare OverflowError
    if t_bias > MAX_SECONDS:
        raise ValueError(
            f"arw = {arw:g} and bias_instability = {bias_instability:g} give T_bias = (N / 0.664 B)^2 = {t_bias:.3g} s, "
            f"beyond the pipeline's 2^40 s: are both in rad/s units (N in rad/sqrt(s), B in rad/s)?"
        )
    # At least the readings the pipeline's static bias needs, with one interval to spare for times
    # that round: where the bias instability outweighs the white noise the knee lies below one
    # sample (N = 1e-6, B = 1e-3: 2.3 us), a rest the pipeline refused as holding 1 reading.
    t_bias = max(t_bias, MIN_WINDOW_READINGS * dt)
    bias_error = math.sqrt(arw**2 / t_bias + floor**2)
    return NoiseSettings(
        threshold=threshold_factor * arw / math.sqrt(dt),
        bias_duration=t_bias,
        hdr_increment=bias_error,
        hdr_turn_threshold=turn_sigmas * math.sqrt(arw**2 / hdr_interval + bias_error**2),
        bias_error=bias_error,
        hdr_interval=hdr_interval,
    )

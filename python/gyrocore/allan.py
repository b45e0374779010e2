"""Allan deviation of gyro data and the noise parameters read from it.

The curve is IEEE Std 952-1997 Annex C's (Hong & Park section 2.1 read their gyro's angle random
walk and bias instability from it): the rate averaged over ``tau`` seconds, differenced between
adjacent intervals. The sums run in Rust on all cores, O(N) per averaging time over the angle
(the integral of the rate, computed once), so a day of 1 kHz data takes about a second.

Units: for a rate in rad/s the deviation is in rad/s; the angle random walk ``N`` is in
rad/s/sqrt(Hz) (= rad/sqrt(s)), the bias instability ``B`` in rad/s, the rate random walk ``K`` in
rad/s^2/sqrt(Hz) (= rad/s/sqrt(s)); each parameter also carries the customary degree units.

Confidence intervals are chi-squared intervals with the equivalent degrees of freedom of
Greenhall & Riley ("Uncertainty of stability variances based on finite differences", PTTI 2003),
the method Stable32 uses; the noise type they assume is white rate noise (``noise_alpha=0``,
the angle-random-walk regime) unless told otherwise.

    >>> import numpy as np, gyrocore.allan as allan
    >>> rate = np.random.default_rng(1).normal(0.0, 0.01, 100_000)  # white noise, dt = 0.01 s
    >>> r = allan.deviation(rate, 0.01)
    >>> bool(abs(r.adev[0] / (0.01 * np.sqrt(0.01) / np.sqrt(r.taus[0])) - 1) < 0.01)
    True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _gyrocore
from ._arrays import FloatArray, as_float_array
from ._extras import require
from .pipeline import integrate

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

#: Two-sided confidence of one standard deviation, erf(1/sqrt(2)) (Stable32's 0.683).
ONE_SIGMA = math.erf(1.0 / math.sqrt(2.0))

Kind = Literal["allan", "modified", "hadamard"]
TauSpec = Literal["octave", "decade", "log", "all"]

_RAD_TO_DEG = 180.0 / math.pi
#: sqrt(s) per sqrt(h), and s per h: for the customary units deg/sqrt(h), deg/h, deg/h/sqrt(h).
_SQRT_HOUR = 60.0
_HOUR = 3600.0
#: IEEE 952: the Allan deviation's flat floor is sqrt(2 ln 2 / pi) = 0.664 times the bias instability.
FLICKER_FLOOR = math.sqrt(2.0 * math.log(2.0) / math.pi)


@dataclass(frozen=True, repr=False)
class AllanResult:
    """An Allan-family deviation curve.

    Attributes:
        taus: averaging times [s] (whole multiples of the sample interval).
        adev: the deviation at each tau, in the units of the rate (rad/s for rad/s input); for
            ``kind="modified"`` the modified, for ``"hadamard"`` the Hadamard deviation.
        n: number of terms averaged at each tau (Stable32's ``#``).
        adev_low, adev_high: confidence interval of the deviation at ``confidence``.
        edf: equivalent degrees of freedom behind the interval (Greenhall & Riley 2003).
        dt: sample interval of the data [s].
        kind: ``"allan"``, ``"modified"`` or ``"hadamard"``.
        overlapping: whether the overlapping estimator was used.
        confidence: two-sided confidence of the interval (0.683 = one sigma).
        noise_alpha: power-law exponent of the rate noise assumed for the interval
            (0 white, -1 flicker, -2 random walk).
        samples: number of rate (or phase) samples analysed.
    """

    taus: FloatArray
    adev: FloatArray
    n: NDArray[np.int64]
    adev_low: FloatArray
    adev_high: FloatArray
    edf: FloatArray
    dt: float
    kind: str
    overlapping: bool
    confidence: float
    noise_alpha: int
    samples: int

    def __len__(self) -> int:
        return len(self.taus)

    def __repr__(self) -> str:
        name = f"{'overlapping ' if self.overlapping and self.kind != 'modified' else ''}{self.kind}"
        if len(self.taus) == 0:
            return f"AllanResult({name}, empty)"
        k = int(np.argmin(self.adev))
        return (
            f"AllanResult({name}, {len(self.taus)} taus {self.taus[0]:.4g} .. {self.taus[-1]:.4g} s, "
            f"adev {self.adev[0]:.4g} at {self.taus[0]:.4g} s, minimum {self.adev[k]:.4g} at "
            f"{self.taus[k]:.4g} s, {self.samples} samples at dt = {self.dt:.6g} s)"
        )

    def as_dict(self) -> dict[str, Any]:
        """Plain lists and numbers (for JSON)."""
        return {
            "kind": self.kind,
            "overlapping": self.overlapping,
            "dt": self.dt,
            "samples": self.samples,
            "confidence": self.confidence,
            "noise_alpha": self.noise_alpha,
            "taus": self.taus.tolist(),
            "adev": self.adev.tolist(),
            "adev_low": self.adev_low.tolist(),
            "adev_high": self.adev_high.tolist(),
            "edf": self.edf.tolist(),
            "n": self.n.tolist(),
        }


def deviation(
    rate: ArrayLike,
    dt: float,
    *,
    taus: TauSpec | ArrayLike = "octave",
    overlapping: bool = True,
    kind: Kind = "allan",
    confidence: float = ONE_SIGMA,
    noise_alpha: int = 0,
) -> AllanResult:
    """Allan deviation of a regularly sampled rate.

    Args:
        rate: rate samples, e.g. rad/s (the deviation comes out in the same unit).
        dt: sample interval [s].
        taus: ``"octave"`` (tau = 1, 2, 4, ... dt), ``"decade"`` (1, 2, 4, 10, 20, 40, ... dt),
            ``"log"`` (about 10 per decade), ``"all"`` (every multiple of dt; for short records),
            or an array of averaging times [s], each a whole multiple of dt. The named sets stop
            at a quarter of the record (at least three non-overlapping terms, as Stable32);
            explicit taus may go up to the longest with one term.
        overlapping: overlapping estimator (more terms, tighter interval, same quantity).
        kind: ``"allan"``, ``"modified"`` (always overlapping) or ``"hadamard"`` (blind to a
            linear rate drift).
        confidence: two-sided confidence of ``adev_low``/``adev_high``.
        noise_alpha: rate-noise type assumed for the interval: 0 white (angle random walk),
            -1 flicker (bias instability), -2 random walk (rate random walk).

    Raises:
        ValueError: NaN/inf (naming the index), too few samples, a tau that is not a whole
            multiple of dt or too long for the record, an unknown option.
    """
    data = as_float_array("rate", rate)
    return _curve(data, dt, is_rate=True, taus=taus, overlapping=overlapping, kind=kind,
                  confidence=confidence, noise_alpha=noise_alpha)


def phase_deviation(
    phase: ArrayLike,
    dt: float,
    *,
    taus: TauSpec | ArrayLike = "octave",
    overlapping: bool = True,
    kind: Kind = "allan",
    confidence: float = ONE_SIGMA,
    noise_alpha: int = 0,
) -> AllanResult:
    """Allan deviation from phase data: an angle [rad] sampled every ``dt`` seconds (a rate
    integrated by the sensor, or Stable32's phase files). The deviation is in rad/s (phase unit
    per second). Options as :func:`deviation`; ``samples`` counts phase samples."""
    data = as_float_array("phase", phase)
    return _curve(data, dt, is_rate=False, taus=taus, overlapping=overlapping, kind=kind,
                  confidence=confidence, noise_alpha=noise_alpha)


def deviation_from_timestamps(
    t: ArrayLike,
    rate: ArrayLike,
    *,
    dt: float | None = None,
    taus: TauSpec | ArrayLike = "octave",
    overlapping: bool = True,
    kind: Kind = "allan",
    confidence: float = ONE_SIGMA,
    noise_alpha: int = 0,
) -> AllanResult:
    """Allan deviation of a log with timestamps, which may be irregular.

    The rate [rad/s] is integrated over the actual intervals into the angle, each reading
    standing for the interval since the previous one (the rectangle rule of HDR eq 3, so a
    reading is the mean rate over its interval, as the Allan variance assumes; a trapezoid
    would average neighbours and halve the white-noise deviation at the shortest tau). The angle
    is sampled on a regular grid of ``dt`` seconds (default: the mean interval) by linear
    interpolation and analysed as phase data. For a regular log this is
    ``deviation(rate[1:], dt)`` (the first reading has no interval).

    Raises ValueError for an interval longer than :data:`GAP_FACTOR` median intervals: across a
    gap the grid would hold a straight line nobody measured (and the default ``dt``, the mean
    interval, would grow with the gap), so each continuous part must be analysed on its own.
    """
    ta = as_float_array("t", t)
    ra = as_float_array("rate", rate)
    if len(ta) < 3:
        raise ValueError(f"need at least 3 samples for an Allan deviation, got {len(ta)}")
    angle = integrate(ta - ta[0], ra, method="rectangle")  # validates lengths, NaN, increasing t
    _refuse_gaps(ta)
    span = ta[-1] - ta[0]
    # The mean interval keeps a regular log's grid on its samples (a median of float-rounded
    # epoch intervals would drift off them over a long log).
    step = span / (len(ta) - 1) if dt is None else float(dt)
    if not (math.isfinite(step) and step > 0):
        raise ValueError(f"dt must be finite and > 0, got {step}")
    if span / step > MAX_OVERSAMPLING * len(ta):  # a finer grid only interpolates (and 1e-9 s asked for 738 GiB)
        raise ValueError(
            f"dt = {step:g} s would resample the {len(ta)} samples onto {span / step:.3g} points; give dt of at "
            f"least {span / (MAX_OVERSAMPLING * len(ta)):.3g} s (the mean interval is {span / (len(ta) - 1):.3g} s)"
        )
    grid = np.arange(int(span / step + 1e-9) + 1) * step
    phase = np.interp(grid, ta - ta[0], angle)
    return phase_deviation(phase, step, taus=taus, overlapping=overlapping, kind=kind,
                           confidence=confidence, noise_alpha=noise_alpha)


#: The grid of :func:`deviation_from_timestamps` holds at most this many points per sample.
MAX_OVERSAMPLING = 10
#: An interval longer than this many median intervals is a gap in an Allan record.
GAP_FACTOR = 10.0


def _refuse_gaps(t: FloatArray) -> None:
    """Name the longest gap of a record, if it has one (see :func:`deviation_from_timestamps`)."""
    intervals = np.diff(t)
    median = float(np.median(intervals))
    i = int(np.argmax(intervals))
    if intervals[i] > GAP_FACTOR * median:
        raise ValueError(
            f"the record has a gap of {intervals[i]:.6g} s from t[{i}] = {t[i]} to t[{i + 1}] = {t[i + 1]} s, "
            f"{intervals[i] / median:.3g} times its median interval ({median:.6g} s); an Allan deviation needs "
            "a continuous record: analyse each part on its own (gyrocore allan --window T0 T1, or slices of "
            "t and rate)"
        )


def _curve(
    data: FloatArray,
    dt: float,
    *,
    is_rate: bool,
    taus: TauSpec | ArrayLike,
    overlapping: bool,
    kind: str,
    confidence: float,
    noise_alpha: int,
) -> AllanResult:
    if kind not in ("allan", "modified", "hadamard"):
        raise ValueError(f"unknown kind {kind!r}: use 'allan', 'modified' or 'hadamard'")
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise TypeError(f"dt must be a number [s], got {dt!r}") from None
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a finite number > 0 [s], got {dt!r}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    if noise_alpha not in _TABLES:
        raise ValueError(f"noise_alpha must be 0 (white), -1 (flicker) or -2 (random walk), got {noise_alpha}")
    overlapping = overlapping or kind == "modified"
    variance = _VARIANCE[(kind, overlapping)]
    n_phase = len(data) + 1 if is_rate else len(data)
    if is_rate and not math.isfinite(float(np.sum(np.abs(data[np.isfinite(data)]))) * dt):
        raise ValueError(f"dt = {dt} s: the angle, the sum of rate x dt, overflows; give dt in seconds")
    factors = _factors(taus, n_phase, float(dt), variance)
    try:
        var, terms = _gyrocore.allan_variances(data, float(dt), factors.tolist(), variance, is_rate)
    except ValueError:
        # The core finds a NaN or infinity within its own passes (a separate pass here would cost
        # as much as a tau); this names the first one.
        bad = np.flatnonzero(~np.isfinite(data))
        if len(bad):
            what = "rate" if is_rate else "phase"
            raise ValueError(
                f"{what}[{bad[0]}] is {data[bad[0]]}: samples must be finite (drop or fill them first)"
            ) from None
        raise
    dev = np.sqrt(var)
    d = 3 if kind == "hadamard" else 2
    edf = np.array([
        equivalent_dof(noise_alpha, d, int(m), n_phase, overlapping=overlapping, modified=kind == "modified")
        for m in factors
    ])
    low, high = confidence_interval(dev, edf, confidence)
    return AllanResult(
        taus=np.asarray(factors * float(dt), dtype=np.float64),
        adev=dev,
        n=terms.astype(np.int64),
        adev_low=low,
        adev_high=high,
        edf=edf,
        dt=float(dt),
        kind=kind,
        overlapping=overlapping,
        confidence=float(confidence),
        noise_alpha=int(noise_alpha),
        samples=len(data),
    )


#: (kind, overlapping) -> the core's variance name.
_VARIANCE = {
    ("allan", False): "allan",
    ("allan", True): "overlapping_allan",
    ("modified", True): "modified_allan",
    ("hadamard", False): "hadamard",
    ("hadamard", True): "overlapping_hadamard",
}


def _longest(variance: str, n: int) -> int:
    """The longest averaging factor with at least one term over ``n`` phase samples (the core's
    counts: Allan ``floor((n-1)/m) - 1``, overlapping ``n - 2m``, Hadamard one difference more,
    modified ``n - 3m + 1``)."""
    if variance == "modified_allan":
        return n // 3
    return (n - 1) // (3 if "hadamard" in variance else 2)


def _factors(taus: TauSpec | ArrayLike, n: int, dt: float, variance: str) -> NDArray[np.int64]:
    """Averaging factors m (tau = m dt) for a tau specification, over ``n`` phase samples."""
    longest = _longest(variance, n)
    if longest < 1:
        raise ValueError(f"too few samples for this deviation: {n - 1} intervals")
    if isinstance(taus, str):
        top = max(1, (n - 1) // 4)  # named sets: at least 3 non-overlapping Allan terms
        top = min(top, longest)
        if taus == "octave":
            m = 2 ** np.arange(int(math.log2(top)) + 1)
        elif taus == "decade":
            m = np.array([k * 10**e for e in range(int(math.log10(top)) + 1) for k in (1, 2, 4)])
        elif taus == "log":
            m = np.round(np.logspace(0.0, math.log10(top), int(10 * math.log10(top)) + 2))
        elif taus == "all":
            m = np.arange(1, top + 1)
        else:
            raise ValueError(f"unknown taus {taus!r}: use 'octave', 'decade', 'log', 'all' or an array [s]")
        m = np.unique(m.astype(np.int64))
        return m[m <= top]
    requested = as_float_array("taus", taus)
    if len(requested) == 0:
        raise ValueError("taus is empty")
    bad = np.flatnonzero(~(np.isfinite(requested) & (requested > 0)))
    if len(bad):
        raise ValueError(f"taus[{bad[0]}] = {requested[bad[0]]}: averaging times must be finite and > 0 [s]")
    m = np.round(requested / dt)
    off = np.flatnonzero((np.abs(m * dt - requested) > 1e-6 * requested) | (m < 1))
    if len(off):
        i = off[0]
        raise ValueError(f"taus[{i}] = {requested[i]} s is not a whole multiple (>= 1) of dt = {dt} s")
    too_long = np.flatnonzero(m > longest)
    if len(too_long):
        i = too_long[0]
        raise ValueError(f"taus[{i}] = {requested[i]} s is too long: the record allows at most {longest * dt} s")
    return np.unique(m.astype(np.int64))


# --- equivalent degrees of freedom (Greenhall & Riley 2003) and chi-squared intervals ----------

#: (a0, a1) of their Table 1 (modified variances, d = 2) and Table 2 (unmodified, d = 2 and 3),
#: for the rate-noise exponents supported here: 1/edf = (a0 - a1/r)/r for long records.
_TABLES = {
    0: {"modified": (1.033, 0.607), 2: (2.0 / 3.0, 1.0 / 3.0), 3: (7.0 / 9.0, 1.0 / 2.0)},
    -1: {"modified": (1.048, 0.534), 2: (0.852, 0.375), 3: (0.997, 0.617)},
    -2: {"modified": (1.302, 0.535), 2: (1.079, 0.368), 3: (1.033, 0.607)},
}
_J_MAX = 100


def _sw(t: NDArray[np.float64], alpha: int) -> NDArray[np.float64]:
    """Their eq 7, the generalized autocovariance of phase noise with exponent ``alpha`` (up to a
    constant); ``_sx`` without a filter asks for ``alpha + 2``."""
    a = np.abs(t)
    with np.errstate(divide="ignore", invalid="ignore"):
        log = np.where(a > 0, np.log(np.where(a > 0, a, 1.0)), 0.0)
    if alpha == 2:
        return -a
    if alpha == 1:
        return t**2 * log
    if alpha == 0:
        return a**3
    if alpha == -1:
        return t**4 * log
    if alpha == -2:
        return a**5
    if alpha == -3:
        return t**6 * log
    if alpha == -4:
        return a**7
    raise ValueError(f"unsupported noise exponent {alpha}")


def _sx(t: NDArray[np.float64], f: float, alpha: int) -> NDArray[np.float64]:
    """Their eq 8: ``sw`` after the averaging filter of length 1/F (F = inf: no filter)."""
    if math.isinf(f):
        return _sw(t, alpha + 2)
    return f * f * (2.0 * _sw(t, alpha) - _sw(t - 1.0 / f, alpha) - _sw(t + 1.0 / f, alpha))


def _sz(t: NDArray[np.float64], f: float, alpha: int, d: int) -> NDArray[np.float64]:
    """Their eq 9: ``sx`` after the d-th difference, sum_k (-1)^k C(2d, d+k) sx(t + k)."""
    out = np.zeros_like(t)
    for k in range(-d, d + 1):
        out += (-1) ** abs(k) * math.comb(2 * d, d + k) * _sx(t + k, f, alpha)
    return out


def _basic_sum(j: int, m_terms: float, s: float, f: float, alpha: int, d: int) -> float:
    """Their eq 10."""
    idx = np.arange(1, j, dtype=np.float64)
    inner = float(np.sum(2.0 * (1.0 - idx / m_terms) * _sz(idx / s, f, alpha, d) ** 2))
    first = float(_sz(np.zeros(1), f, alpha, d)[0] ** 2)
    last = (1.0 - j / m_terms) * float(_sz(np.array([j / s]), f, alpha, d)[0] ** 2)
    return first + last + inner


def equivalent_dof(alpha: int, d: int, m: int, n: int, *, overlapping: bool, modified: bool) -> float:
    """Equivalent degrees of freedom of a variance estimate (Greenhall & Riley 2003, their
    section 4 algorithm): ``alpha`` the rate-noise exponent (0, -1, -2), ``d`` the difference
    order (2 Allan, 3 Hadamard), ``m`` the averaging factor, ``n`` phase samples."""
    if alpha not in _TABLES or d not in (2, 3) or (modified and d != 2):
        raise ValueError(f"no EDF for alpha = {alpha}, d = {d}, modified = {modified}")
    f = 1.0 if modified else float(m)  # filter factor
    s = float(m) if overlapping else 1.0  # stride factor
    length = m / f + m * d  # span of the filter on the phase
    if n < length:
        raise ValueError(f"{n} phase samples are too few for m = {m}")
    m_terms = 1.0 + math.floor(s * (n - length) / m)
    j = int(min(m_terms, (d + 1) * s))
    r = m_terms / s
    if modified:
        if j <= _J_MAX:
            inv = _basic_sum(j, m_terms, s, 1.0, alpha, d) / (_sz(np.zeros(1), 1.0, alpha, d)[0] ** 2 * m_terms)
        elif r > d + 1:
            a0, a1 = _TABLES[alpha]["modified"]
            inv = (a0 - a1 / r) / r
        else:
            inv = _basic_sum(_J_MAX, _J_MAX, _J_MAX / r, 1.0, alpha, d) / (
                _sz(np.zeros(1), 1.0, alpha, d)[0] ** 2 * _J_MAX
            )
    else:
        if j <= _J_MAX:
            fm = float(m) if m * (d + 1) <= _J_MAX else math.inf
            inv = _basic_sum(j, m_terms, s, fm, alpha, d) / (_sz(np.zeros(1), fm, alpha, d)[0] ** 2 * m_terms)
        elif r > d + 1:
            a0, a1 = _TABLES[alpha][d]
            inv = (a0 - a1 / r) / r
        else:
            inv = _basic_sum(_J_MAX, _J_MAX, _J_MAX / r, math.inf, alpha, d) / (
                _sz(np.zeros(1), math.inf, alpha, d)[0] ** 2 * _J_MAX
            )
    return float(1.0 / inv)


def confidence_interval(
    dev: ArrayLike, edf: ArrayLike, confidence: float = ONE_SIGMA
) -> tuple[FloatArray, FloatArray]:
    """Chi-squared interval of a deviation with ``edf`` degrees of freedom (NIST SP 1065 eq 45):
    ``dev * sqrt(edf / chi2_{(1+c)/2})`` .. ``dev * sqrt(edf / chi2_{(1-c)/2})``."""
    chi2 = require("scipy.stats", "the Allan deviation").chi2  # scipy's only use here

    d = np.asarray(dev, dtype=np.float64)
    e = np.asarray(edf, dtype=np.float64)
    tail = (1.0 - confidence) / 2.0
    return d * np.sqrt(e / chi2.ppf(1.0 - tail, e)), d * np.sqrt(e / chi2.ppf(tail, e))


# --- noise parameters -----------------------------------------------------------------------


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


@dataclass(frozen=True)
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
        k = rrw if rrw is not None else (None if self.rrw is None else self.rrw.value)
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
      point's slope taken to the point about an octave further, within ``slope_tolerance``); a
      line of slope -1/2 is fitted there (weighted by each point's degrees of freedom) and read
      at tau = 1 s: ``N = sigma(1 s)``.
    - Bias instability ``B``: the flat minimum divided by sqrt(2 ln 2 / pi) = 0.664. The flat
      minimum is the lowest stretch of slope 0 (within ``slope_tolerance``), its level the
      weighted mean there; without such a stretch, the lowest point. A flat stretch the curve
      later falls clearly below (the hump of a sensor's internal filter at the shortest taus) is
      not the floor. If the minimum is the last tau (the floor is not reached) or the first (an
      internal filter), ``B`` is only an upper bound (see notes).
    - Rate random walk ``K``: as N, for slope +1/2, read at tau = 3 s: ``K = sigma(3 s)``.
    """
    if result.kind != "allan":
        raise ValueError(f"noise parameters are read from the Allan deviation, not the {result.kind} deviation")
    if len(result.taus) < 3:
        raise ValueError(f"the curve has {len(result.taus)} taus; need at least 3 to read slopes")
    taus, dev, w = result.taus, result.adev, result.edf
    notes: list[str] = []
    arw = _slope_line(taus, dev, w, -0.5, 1.0, slope_tolerance)
    rrw = _slope_line(taus, dev, w, 0.5, 3.0, slope_tolerance)
    arw_p = rrw_p = None
    if arw is None:
        notes.append("no stretch of slope -1/2: angle random walk not identified")
    else:
        value, span = arw
        arw_p = NoiseParameter(value, "rad/s/sqrt(Hz)", value * _RAD_TO_DEG * _SQRT_HOUR, "deg/sqrt(h)", span,
                               "line of slope -1/2 read at tau = 1 s")
    if rrw is None:
        notes.append("no stretch of slope +1/2: rate random walk not identified (record too short?)")
    else:
        value, span = rrw
        rrw_p = NoiseParameter(value, "rad/s^2/sqrt(Hz)", value * _RAD_TO_DEG * _HOUR * _SQRT_HOUR,
                               "deg/h/sqrt(h)", span, "line of slope +1/2 read at tau = 3 s")
    # The flat bottom: of the flat stretches, the lowest; its level is the edf-weighted mean,
    # since the single lowest point of a noisy floor is biased low (few terms at long tau). A
    # stretch the curve later falls below half of (confidence interval included) is no bottom: a
    # sensor's internal filter flattens the shortest taus before the white noise's -1/2 fall,
    # while a floor's own points stay well within a factor 2 of its level.
    flat = [
        (float(np.average(dev[a : b + 1], weights=w[a : b + 1])), (a, b))
        for a, b in _slope_runs(taus, dev, 0.0, slope_tolerance)
    ]
    flat = [(level, run) for level, run in flat if not np.any(result.adev_high[run[1] + 1 :] < level / 2)]
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
    b = floor / FLICKER_FLOOR
    bias_p = NoiseParameter(b, "rad/s", b * _RAD_TO_DEG * _HOUR, "deg/h", (float(taus[lo]), float(taus[hi])), method)
    return NoiseParameters(arw_p, bias_p, rrw_p, result.dt, tuple(notes))


def _slope_runs(taus: FloatArray, dev: FloatArray, slope: float, tolerance: float) -> list[tuple[int, int]]:
    """Index ranges ``(first, last)`` of the stretches where the curve has ``slope`` within
    ``tolerance``: each point's slope is taken to the first point an octave further (robust on
    dense tau sets), and a run of matching points spans up to the last one's octave partner."""
    lt, ld = np.log(taus), np.log(dev)
    ahead = np.searchsorted(lt, lt + math.log(2.0) - 1e-9)
    ok = ahead < len(lt)
    local = np.full(len(lt), np.nan)
    local[ok] = (ld[ahead[ok]] - ld[ok]) / (lt[ahead[ok]] - lt[ok])
    match = np.abs(local - slope) <= tolerance
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
    taus: FloatArray, dev: FloatArray, weight: FloatArray, slope: float, at: float, tolerance: float
) -> tuple[float, tuple[float, float]] | None:
    """Fit ``log dev = c + slope log tau`` (weights: degrees of freedom) on the stretch of that
    slope spanning the most octaves; returns (dev at tau = ``at``, tau range) or None."""
    runs = _slope_runs(taus, dev, slope, tolerance)
    if not runs:
        return None
    a, b = max(runs, key=lambda r: taus[r[1]] / taus[r[0]])
    lt, ld = np.log(taus[a : b + 1]), np.log(dev[a : b + 1])
    c = np.average(ld - slope * lt, weights=weight[a : b + 1])
    return float(np.exp(c + slope * math.log(at))), (float(taus[a]), float(taus[b]))


# --- settings from noise (issue: parameters from the Allan analysis) --------------------------


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

    def overrides(self) -> dict[str, float]:
        """Parameters for ``gyrocore.Pipeline(preset, **overrides)``."""
        return {
            "threshold": self.threshold,
            "bias_duration": self.bias_duration,
            "hdr_increment": self.hdr_increment,
            "hdr_turn_threshold": self.hdr_turn_threshold,
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
       The bias error after T_bias is then ``e_b = sqrt(2) * 0.664 B``.
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
    for name, value in (("arw", arw), ("bias_instability", bias_instability), ("dt", dt),
                        ("hdr_interval", hdr_interval), ("threshold_factor", threshold_factor),
                        ("turn_sigmas", turn_sigmas)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and > 0, got {value}")
    floor = FLICKER_FLOOR * bias_instability
    t_bias = (arw / floor) ** 2
    bias_error = math.sqrt(arw**2 / t_bias + floor**2)
    return NoiseSettings(
        threshold=threshold_factor * arw / math.sqrt(dt),
        bias_duration=t_bias,
        hdr_increment=bias_error,
        hdr_turn_threshold=turn_sigmas * math.sqrt(arw**2 / hdr_interval + bias_error**2),
        bias_error=bias_error,
    )


# --- plot -----------------------------------------------------------------------------------


def plot(
    result: AllanResult,
    *,
    parameters: NoiseParameters | None = None,
    ax: Axes | None = None,
    unit: str = "rad/s",
    label: str | None = None,
) -> Axes:
    """Log-log plot of the deviation with its confidence interval; with ``parameters``, the
    slope -1/2 (N), floor (0.664 B) and slope +1/2 (K) lines over the ranges they came from.
    Needs matplotlib (``pip install gyrocore[plot]``); returns the axes."""
    plt = require("matplotlib.pyplot", "plotting an Allan deviation")
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 4.8))
    err = np.vstack([result.adev - result.adev_low, result.adev_high - result.adev])
    ax.errorbar(result.taus, result.adev, yerr=err, fmt="o-", ms=3, capsize=2,
                label=label or f"{result.kind} deviation")
    if parameters is not None:
        span = np.array([result.taus[0], result.taus[-1]])
        if parameters.arw is not None:
            ax.plot(span, parameters.arw.value / np.sqrt(span), "--",
                    label=f"N = {parameters.arw.value_deg:.3g} deg/sqrt(h)")
        if parameters.bias_instability is not None:
            bound = "<=" if "upper bound" in parameters.bias_instability.method else "="
            ax.plot(span, [FLICKER_FLOOR * parameters.bias_instability.value] * 2, ":",
                    label=f"0.664 B, B {bound} {parameters.bias_instability.value_deg:.3g} deg/h")
        if parameters.rrw is not None:
            ax.plot(span, parameters.rrw.value * np.sqrt(span / 3.0), "-.",
                    label=f"K = {parameters.rrw.value_deg:.3g} deg/h/sqrt(h)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("averaging time tau [s]")
    ax.set_ylabel(f"deviation [{unit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax

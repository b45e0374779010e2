"""The Allan-family deviation curves (IEEE Std 952-1997 Annex C): of a rate, of a phase, and of a
rate at irregular timestamps; :mod:`gyrocore.allan` re-exports the public names."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _gyrocore
from ._arrays import READ_FOR_ALLAN, READ_RATE_FOR_ALLAN, FloatArray, as_float_array, no_path_for_arrays
from ._checks import MAX_READING, check_number, require_flag, require_increasing, require_readings, warn
from ._motion import warn_if_moving
from .allan_edf import _TABLES, ONE_SIGMA, confidence_interval, equivalent_dof
from .integration import integrate

Kind = Literal["allan", "modified", "hadamard"]
TauSpec = Literal["octave", "decade", "log", "all"]


@dataclass(frozen=True, repr=False, eq=False)
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

    @property
    def flat_zero(self) -> bool:
        """Whether the deviation is 0 at every tau (constant readings): no noise to read, nothing
        for log axes to show."""
        return not np.any(self.adev > 0)

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


@no_path_for_arrays("gyrocore.allan.deviation", READ_RATE_FOR_ALLAN)
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
            or an array of averaging times [s], each a whole multiple of dt, in increasing order
            (the result holds them in the order given; one out of order or given twice is refused,
            naming it: ``taus must strictly increase: taus[2] = 0.5 follows 1.0``). The named sets stop
            at a quarter of the record (at least three non-overlapping terms, as Stable32);
            explicit taus may go up to the longest with one term.
        overlapping: overlapping estimator (more terms, tighter interval, same quantity).
        kind: ``"allan"``, ``"modified"`` (always overlapping: ``overlapping=False`` is refused) or
            ``"hadamard"`` (blind to a linear rate drift).
        confidence: two-sided confidence of ``adev_low``/``adev_high``.
        noise_alpha: rate-noise type assumed for the interval: 0 white (angle random walk),
            -1 flicker (bias instability), -2 random walk (rate random walk).

    Raises:
        SampleError: a rate that is NaN, infinite or beyond +-2^20 (the pipeline's limit), naming
            the index.
        ValueError: too few samples, a tau that is not a whole
            multiple of dt or too long for the record, taus out of order or given twice,
            averaging times that would sum more than
            :data:`MAX_ALL_TERMS` terms (samples times taus), an unknown option.
    """
    data = as_float_array("rate", rate, masked=_MASKED, unit="rad/s")
    result = _curve(data, dt, is_rate=True, taus=taus, overlapping=overlapping, kind=kind,
                    confidence=confidence, noise_alpha=noise_alpha)
    warn_if_moving(data, dt)
    return _zero_if_constant(result, data)


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
    data = as_float_array("phase", phase, masked=_MASKED, unit="rad")
    return _curve(data, dt, is_rate=False, taus=taus, overlapping=overlapping, kind=kind,
                  confidence=confidence, noise_alpha=noise_alpha)


@no_path_for_arrays("gyrocore.allan.deviation_from_timestamps", READ_FOR_ALLAN)
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

    Warns an :class:`~gyrocore.InputWarning` of rates that look like deg/s or times like ms, as
    :func:`gyrocore.process` does (:func:`noise_parameters` would read N, B and K in other units),
    and of a ``dt`` finer than the log's interval: the grid then interpolates between readings,
    and the deviation at taus up to a few intervals reads low.
    """
    ta = as_float_array("t", t, masked=_MASKED)
    ra = as_float_array("rate", rate, masked=_MASKED, unit="rad/s")
    _refuse_non_overlapping_modified(kind, overlapping)  # before the log is integrated
    if len(ta) < 3:
        raise ValueError(f"need at least 3 samples for an Allan deviation, got {len(ta)}")
    # The core validates lengths, NaN, the readings' range and increasing t, naming the values as
    # given; its intervals are the same as from ta - ta[0] (a difference of two close floats is exact).
    # integrate warns, as process does, of times in ms (taus 1000 times too long) or rates in deg/s.
    angle = integrate(ta, ra, method="rectangle")
    median = _refuse_gaps(ta)
    span = ta[-1] - ta[0]
    # The mean interval keeps a regular log's grid on its samples (a median of float-rounded
    # epoch intervals would drift off them over a long log).
    # dt="x" was a bare ValueError of float(), and "0.01" or True passed for a number
    step = span / (len(ta) - 1) if dt is None else check_number("dt", dt, unit=" [s]")
    if not (math.isfinite(step) and step > 0):
        raise ValueError(f"dt must be finite and > 0, got {step}")
    if span / step > MAX_OVERSAMPLING * len(ta):  # a finer grid only interpolates (and 1e-9 s asked for 738 GiB)
        raise ValueError(
            f"dt = {step:g} s would resample the {len(ta)} samples onto {span / step:.3g} points; give dt of at "
            f"least {span / (MAX_OVERSAMPLING * len(ta)):.3g} s (the mean interval is {span / (len(ta) - 1):.3g} s)"
        )
    # The log's interval: the median, or the mean where smaller (times rounded to 1 ms at 285.7 Hz
    # step by 3 and 4 ms, median 4 ms, mean 3.5; short gaps raise the mean, not the median).
    interval = min(median, span / (len(ta) - 1))
    if dt is not None and step < 0.99 * interval:
        # Linear interpolation of the angle holds the rate over each interval: a finer grid's averages
        # within one interval are equal, and the deviation up to a few intervals reads low (white
        # noise at 100 Hz on a 2.5 ms grid: 27 % at 0.01 s, N 8 %; a grid 5 % finer: 31 % at its tau).
        warn(f"dt = {step:g} s is finer than the log's interval ({interval:.6g} s): the grid interpolates "
             "between readings, and the deviation at taus up to a few intervals reads lower than the sensor's "
             f"(white noise: 27 % at one interval on a grid 4 times finer); give dt of at least {interval:.6g} s")
    grid = np.arange(int(span / step + 1e-9) + 1) * step
    phase = np.interp(grid, ta - ta[0], angle)
    result = phase_deviation(phase, step, taus=taus, overlapping=overlapping, kind=kind,
                             confidence=confidence, noise_alpha=noise_alpha)
    warn_if_moving(ra, span / (len(ta) - 1))
    return _zero_if_constant(result, ra[1:])  # the first reading stands for no interval


#: The grid of :func:`deviation_from_timestamps` holds at most this many points per sample.
MAX_OVERSAMPLING = 10
#: Averaging times are refused above this many terms (samples times averaging times; ``taus="all"``
#: asks for n^2/4): a day at 100 Hz asked for 1.9e13, hours of work with nothing shown (a modified
#: deviation over 160,000 samples took 19 s here); 1e10 is seconds to half a minute.
MAX_ALL_TERMS = 1e10
#: An interval longer than this many median intervals is a gap in an Allan record.
GAP_FACTOR = 10.0
#: What to do with masked readings: an Allan deviation takes no missing one (it has no ``nonfinite=``).
_MASKED = ("an Allan deviation takes no missing reading: give the others with their times to "
           "allan.deviation_from_timestamps (it integrates over the intervals between them; a gap beyond "
           f"{GAP_FACTOR:g} median intervals is refused), or analyse each unmasked stretch on its own")


def _zero_if_constant(result: AllanResult, rate: FloatArray) -> AllanResult:
    """``result`` of readings that are all one value with its deviation exactly 0, as it is: the
    angle they integrate to is a straight line, whose float rounding (7.9e-31 rad/s from a rate of
    0.01, 2.4e-15 through the timestamps' grid) was read as noise, N, B and K of a stuck sensor."""
    if np.ptp(rate) != 0:
        return result
    zero = np.zeros_like(result.adev)
    return replace(result, adev=zero, adev_low=zero, adev_high=zero)


def _refuse_gaps(t: FloatArray) -> float:
    """Name the longest gap of a record, if it has one (see :func:`deviation_from_timestamps`);
    returns the median interval [s]."""
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
    return median


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
    # a bool or text passed for a number (dt=True was 1 s, "0.01" was parsed)
    dt = check_number("dt", dt, unit=" [s]")
    if not 0.0 < check_number("confidence", confidence) < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    require_flag("overlapping", overlapping)  # "no" was a KeyError, 0 and 1 worked by chance
    if noise_alpha not in _TABLES:
        raise ValueError(f"noise_alpha must be 0 (white), -1 (flicker) or -2 (random walk), got {noise_alpha}")
    _refuse_non_overlapping_modified(kind, overlapping)
    variance = _VARIANCE[(kind, overlapping)]
    n_phase = len(data) + 1 if is_rate else len(data)
    if is_rate:
        # The pipeline's limit (a rate of 1e300 made the deviation inf, and +-1e300 made it 0); it
        # also bounds the angle, the sum of rate x dt, without a pass over the rates.
        require_readings("rate", data)
        if not math.isfinite(MAX_READING * len(data) * dt):
            raise ValueError(f"dt = {dt} s: the angle, the sum of rate x dt, could overflow; give dt in seconds")
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


def _refuse_non_overlapping_modified(kind: str, overlapping: bool) -> None:
    """The modified Allan deviation has no non-overlapping estimator: asked for one, refuse rather
    than compute the overlapping one."""
    if kind == "modified" and overlapping is False:
        raise ValueError("overlapping=False: the modified Allan deviation is always overlapping; leave it out, or "
                         "give kind='allan' or 'hadamard' for a non-overlapping estimate")


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
        raise ValueError(f"too few samples for this deviation: {max(n - 1, 0)} intervals")
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
            _refuse_too_many_terms(top, n, "taus='all' (--taus all) over {intervals} intervals asks for {count} averaging "
                                   "times, {terms} terms to sum ({limit}); use taus='log' (about 10 per decade), or give "
                                   "the averaging times [s], or analyse a shorter record")
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
    # The result's points are the taus given, one for one, and a grid that does not increase is
    # refused (numpy.histogram's bins, scipy's splines): taus out of order or twice were sorted and
    # merged without a word, so that the i-th point was not taus[i].
    require_increasing("taus", requested)
    m = np.round(requested / dt)
    off = np.flatnonzero((np.abs(m * dt - requested) > 1e-6 * requested) | (m < 1))
    if len(off):
        i = off[0]
        raise ValueError(f"taus[{i}] = {requested[i]} s is not a whole multiple (>= 1) of dt = {dt} s")
    too_long = np.flatnonzero(m > longest)
    if len(too_long):
        i = too_long[0]
        raise ValueError(f"taus[{i}] = {requested[i]} s is too long: the record allows at most {longest * dt} s")
    require_increasing("taus", np.asarray(m * dt, dtype=np.float64), context="as whole multiples of dt")  # two taus nearer than 1e-6
    m = m.astype(np.int64)
    # each averaging time costs a pass over the record, whether named or listed
    _refuse_too_many_terms(len(m), n, "taus: {count} averaging times over {intervals} intervals ask for {terms} terms "
                           "to sum ({limit}); give fewer (taus='log' gives about 10 per decade), or analyse a shorter "
                           "record")
    return m


def _refuse_too_many_terms(count: int, n: int, message: str) -> None:
    """Refuse ``count`` averaging times over ``n`` phase samples beyond :data:`MAX_ALL_TERMS` terms,
    before the work, with ``message`` filled in (``{count}``, ``{intervals}``, ``{terms}``, ``{limit}``)."""
    if n * count > MAX_ALL_TERMS:
        raise ValueError(message.format(count=count, intervals=n - 1, terms=f"{n * count:.2g}",
                                        limit=f"more than {MAX_ALL_TERMS:.0e}: minutes to hours of work"))

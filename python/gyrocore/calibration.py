"""Gyro calibration: static bias (FOG section 2, HDR eq 1-2), least-squares self-calibration
against a heading or rate reference (Hong eq 4-9), rotary-table scale factors with a
temperature-linear model (FOG eq 1-6), and a bias-versus-temperature look-up table.

The error model is Hong eq 1: ``r_m = (1 + s) r + b + w``, with the scale error ``s`` and the bias
``b`` (what the gyro reads at rest; corrected = measured - bias, HDR eq 2). Hong eq 3 writes the
inverse as ``r = s_bar r_m + b_bar`` with ``s_bar = 1/(1+s)`` and ``b_bar = -b/(1+s)``.

Every result is a :class:`Calibration`: it prints readably, saves to and loads from versioned
JSON with units, and ``overrides()`` gives the pipeline's parameters::

    cal = static_bias(log.t, log.rate)               # rest window found automatically
    gyrocore.process(log.t, log.rate, "hdr", **cal.overrides())

Units: s, rad, rad/s, degC; counter-clockwise positive.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _gyrocore
from ._arrays import FloatArray, as_float_array, as_window
from .evaluate import unwrap
from .pipeline import integrate

#: Saved calibrations carry this format name and version.
FORMAT = "gyrocore-calibration"
VERSION = 1

_UNITS = {
    "bias": "rad/s (what the gyro reads at rest; corrected = measured - bias)",
    "bias_stderr": "rad/s",
    "scale_error": "1 (s of Hong eq 1: r_m = (1 + s) r + b)",
    "scale_error_stderr": "1",
    "residual_rms": "rad/s, or rad for heading_reference",
    "condition_number": "1",
    "window": "s (log time base)",
    "samples": "count",
    "c_cw": "1 (FOG eq 2a)",
    "c_ccw": "1 (FOG eq 2b)",
    "temp_slope": "1/degC (FOG eq 5's E_T slope / 360 deg)",
    "temp_offset": "1 (FOG eq 5's E_T at 0 degC / 360 deg)",
    "bias_table": "temperatures degC, biases rad/s",
}
#: What a saved field of each type must be, for the errors of :meth:`Calibration.from_dict`.
_KINDS = {"str": "text", "int": "a whole number"}


@dataclass(frozen=True)
class BiasTable:
    """Bias versus temperature look-up table (FOG section 2), linearly interpolated.

    Beyond the table's temperatures the nearest entry is used: extrapolating a thermal bias
    curve is unreliable.

    Attributes:
        temperatures: mean temperature of each bin [degC], increasing.
        biases: mean rest reading in each bin [rad/s].
        stderr: standard error of each bias [rad/s] (white-noise estimate within the bin).
        counts: readings per bin.
    """

    temperatures: tuple[float, ...]
    biases: tuple[float, ...]
    stderr: tuple[float, ...]
    counts: tuple[int, ...]

    def __call__(self, temperature: ArrayLike) -> FloatArray:
        """Bias [rad/s] at ``temperature`` [degC] (scalar or array)."""
        return np.interp(np.asarray(temperature, dtype=np.float64), self.temperatures, self.biases)

    def correct(self, rate: ArrayLike, temperature: ArrayLike) -> FloatArray:
        """``rate - bias(temperature)`` [rad/s]; give the result to the pipeline with ``bias=0``."""
        r = as_float_array("rate", rate)
        temp = as_float_array("temperature", temperature)
        if len(r) != len(temp):
            raise ValueError(f"rate has {len(r)} samples but temperature has {len(temp)}")
        return r - self(temp)


@dataclass(frozen=True, repr=False)
class Calibration:
    """A gyro calibration and how it was obtained (units in :data:`_UNITS` and the JSON).

    Attributes:
        method: ``static_bias``, ``rate_reference``, ``heading_reference`` or ``rotary_table``.
        bias: ``b`` [rad/s], what the gyro reads at rest (for ``rotary_table``: the mean of the
            static tests before the turns, informative only).
        scale_error: ``s`` of Hong eq 1 [1] (0 where not estimated).
        bias_stderr, scale_error_stderr: their standard errors (None where not estimated).
        residual_rms: RMS of the fit's residuals (rad/s; rad for ``heading_reference``); for the
            static bias the standard deviation of the readings.
        condition_number: of the column-scaled least-squares problem (None without one).
        window: the time span used [s]: the rest window of a static bias test, the fitted span.
        samples: readings used.
        c_cw, c_ccw: direction correction factors (FOG eq 2).
        temp_slope, temp_offset: temperature-linear scale factor (FOG eq 5-6, per 360 deg).
        bias_table: bias versus temperature (FOG section 2).
    """

    method: str
    bias: float = 0.0
    scale_error: float = 0.0
    bias_stderr: float | None = None
    scale_error_stderr: float | None = None
    residual_rms: float | None = None
    condition_number: float | None = None
    window: tuple[float, float] | None = None
    samples: int = 0
    c_cw: float = 1.0
    c_ccw: float = 1.0
    temp_slope: float | None = None
    temp_offset: float | None = None
    bias_table: BiasTable | None = None
    notes: tuple[str, ...] = field(default=())

    @property
    def s_bar(self) -> float:
        """``s_bar = 1/(1+s)`` (Hong eq 3) [1]."""
        return 1.0 / (1.0 + self.scale_error)

    @property
    def b_bar(self) -> float:
        """``b_bar = -b/(1+s)`` (Hong eq 3) [rad/s]."""
        return -self.bias / (1.0 + self.scale_error)

    def overrides(self, *, include_bias: bool | None = None) -> dict[str, float]:
        """Parameters for ``gyrocore.Pipeline(preset, **overrides)`` (and ``process``).

        The least-squares fits give Hong eq 3 as ``s_bar * (r_m - b)``, which equals
        ``s_bar r_m + b_bar``: ``scale = s_bar``, ``offset = 0`` and ``bias = b``, so the pipeline
        has an explicit bias and does not measure another one over a rest window. Pass
        ``include_bias=False`` to keep only the scale (and let the pipeline measure a fresh
        static bias). A rotary-table calibration gives the scale factors only (its static biases
        belong to the table runs; FOG section 2 measures the bias again before use).
        """
        if include_bias is None:
            include_bias = self.method != "rotary_table"
        out: dict[str, float] = {}
        if include_bias:
            out["bias"] = self.bias
        if self.method in ("rate_reference", "heading_reference"):
            out["scale"] = self.s_bar
            out["offset"] = 0.0
        if self.method == "rotary_table":
            out["c_cw"] = self.c_cw
            out["c_ccw"] = self.c_ccw
            if self.temp_slope is not None and self.temp_offset is not None:
                out["temp_slope"] = self.temp_slope
                out["temp_offset"] = self.temp_offset
        return out

    def __repr__(self) -> str:
        parts = [self.method]
        err = "" if self.bias_stderr is None else f" +- {self.bias_stderr:.3g}"
        parts.append(f"bias = {self.bias:.6g}{err} rad/s ({math.degrees(self.bias):.4g} deg/s)")
        if self.method in ("rate_reference", "heading_reference"):
            serr = "" if self.scale_error_stderr is None else f" +- {100 * self.scale_error_stderr:.3g}"
            parts.append(f"scale error = {100 * self.scale_error:.4g}{serr} %")
            parts.append(f"s_bar = {self.s_bar:.6g}, b_bar = {self.b_bar:.6g} rad/s")
        if self.method == "rotary_table":
            parts.append(f"c_cw = {self.c_cw:.6g}, c_ccw = {self.c_ccw:.6g}")
            if self.temp_slope is not None and self.temp_offset is not None:
                parts.append(
                    f"E_T = {360 * self.temp_slope:.4g} deg/degC * T + {360 * self.temp_offset:.4g} deg"
                )
        if self.bias_table is not None:
            parts.append(f"bias table of {len(self.bias_table.temperatures)} temperatures")
        if self.residual_rms is not None:
            unit = "rad" if self.method == "heading_reference" else "rad/s"
            parts.append(f"residual rms = {self.residual_rms:.4g} {unit}")
        if self.condition_number is not None:
            parts.append(f"condition number = {self.condition_number:.3g}")
        if self.window is not None:
            parts.append(f"window {self.window[0]:.12g} .. {self.window[1]:.12g} s")
        parts.append(f"{self.samples} samples")
        return f"Calibration({', '.join(parts)})"

    # --- JSON ---

    def to_dict(self) -> dict[str, Any]:
        """The saved form: format, version, units and the values."""
        values = asdict(self)
        values["window"] = None if self.window is None else list(self.window)
        values["notes"] = list(self.notes)
        return {"format": FORMAT, "version": VERSION, "units": dict(_UNITS), "calibration": values}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Calibration:
        """Rebuild from :meth:`to_dict`; raises ValueError on another format or version."""
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            found = data.get("format") if isinstance(data, dict) else None
            raise ValueError(f"not a gyrocore calibration (format {found!r})")
        if data.get("version") != VERSION:
            raise ValueError(f"calibration format version {data.get('version')!r} is not supported (this is {VERSION})")
        if not isinstance(data.get("calibration"), dict):
            raise ValueError("no calibration object")
        values = dict(data["calibration"])
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise ValueError(f"unknown calibration field(s): {', '.join(unknown)}")
        for f in fields(cls):  # JSON types: a number must not be text ("bias": "abc")
            value = values.get(f.name)
            if value is None or f.name in ("window", "bias_table", "notes"):
                continue
            expected = {"str": str, "int": int}.get(str(f.type), (int, float))
            if isinstance(value, bool) or not isinstance(value, expected):
                raise ValueError(f"{f.name} must be {_KINDS.get(str(f.type), 'a number')}, got {value!r}")
        if values.get("window") is not None:
            values["window"] = as_window("window", values["window"])
        if values.get("bias_table") is not None:
            table = values["bias_table"]
            if not isinstance(table, dict):
                raise ValueError(f"bias_table must be an object of lists, got {table!r}")
            values["bias_table"] = BiasTable(**{k: tuple(v) for k, v in table.items()})
        values["notes"] = tuple(values.get("notes", ()))
        return cls(**values)

    def save(self, path: str | Path) -> None:
        """Write the calibration as JSON (see :meth:`to_dict`)."""
        Path(path).write_text(json.dumps(self.to_dict(), indent=2) + "\n", encoding="utf-8")

    @classmethod
    def load(cls, path: str | Path) -> Calibration:
        """Read a calibration saved by :meth:`save`."""
        p = Path(path)
        try:
            data = json.loads(p.read_text(encoding="utf-8"))
        except json.JSONDecodeError as e:
            raise ValueError(f"{p}: line {e.lineno} column {e.colno}: {e.msg}") from None
        except UnicodeDecodeError as e:
            raise ValueError(f"{p}: not UTF-8 text (at byte offset {e.start}: {e.reason})") from None
        try:
            return cls.from_dict(data)
        except (KeyError, TypeError, ValueError) as e:  # missing keys, wrong shapes and types
            raise ValueError(f"{p}: not a valid calibration: {e}") from None


# --- input checks ---------------------------------------------------------------------------


def _series(
    t: ArrayLike, rate: ArrayLike, *, t_name: str = "t", rate_name: str = "rate"
) -> tuple[FloatArray, FloatArray]:
    """Equal lengths, finite values, strictly increasing times; ValueError naming the index."""
    ta, ra = as_float_array(t_name, t), as_float_array(rate_name, rate)
    if len(ta) != len(ra):
        raise ValueError(f"{rate_name} has {len(ra)} samples but {t_name} has {len(ta)}")
    for name, a in ((t_name, ta), (rate_name, ra)):
        bad = np.flatnonzero(~np.isfinite(a))
        if len(bad):
            raise ValueError(f"{name}[{bad[0]}] is {a[bad[0]]}: samples must be finite (drop or fill them first)")
    steps = np.flatnonzero(np.diff(ta) <= 0)
    if len(steps):
        i = int(steps[0]) + 1
        raise ValueError(f"{t_name} must strictly increase: {t_name}[{i}] = {ta[i]} follows {ta[i - 1]}")
    return ta, ra


# --- static bias (FOG section 2, HDR eq 1-2) --------------------------------------------------


def rest_windows(
    t: ArrayLike,
    rate: ArrayLike,
    *,
    min_duration: float = 1.0,
    block: float = 0.25,
    noise_factor: float = 3.0,
    max_rate: float = 0.05,
    consistency: float = 4.5,
) -> list[tuple[float, float]]:
    """Every stretch where the gyro rests, found from the rate alone.

    The log is cut into blocks of ``block`` seconds (at least 4 sample intervals). A block is
    quiet when its standard deviation is at most ``noise_factor`` times the noise floor (the
    median standard deviation of the quietest 1 % of blocks, at least 3) and its mean is within
    ``max_rate`` [rad/s] of zero: a gyro at rest reads only its bias and noise, while a steadier
    than noise reading beyond ``max_rate`` (0.05 rad/s = 2.9 deg/s by default; raise it for a gyro
    with a larger bias) is a steady turn. Consecutive quiet blocks form a rest as long as each
    block's mean agrees with the rest's mean so far within ``consistency`` standard errors (a
    rest has a constant level; slow motion drifts; one stray block between agreeing ones is
    kept, as a 4-sigma block is expected now and then in a long rest). Rests shorter than
    ``min_duration`` [s] are dropped. Returns ``(start, end)`` pairs [s] in the log's time base,
    from the first to the last sample of the quiet blocks.
    """
    ta, ra = _series(t, rate)
    for name, value in (("min_duration", min_duration), ("block", block), ("noise_factor", noise_factor),
                        ("max_rate", max_rate), ("consistency", consistency)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and > 0, got {value}")
    if len(ta) < 8:
        raise ValueError(f"need at least 8 samples to find a rest, got {len(ta)}")
    rel = ta - ta[0]  # epoch timestamps lose precision in arithmetic
    width = max(block, 4.0 * float(np.median(np.diff(rel))))
    k = np.floor(rel / width).astype(np.int64)
    nb = int(k[-1]) + 1
    count = np.bincount(k, minlength=nb)
    total = np.bincount(k, ra, minlength=nb)
    mean = total / np.maximum(count, 1)
    dev = ra - mean[k]
    var = np.bincount(k, dev * dev, minlength=nb) / np.maximum(count - 1, 1)
    sd = np.sqrt(var)
    usable = count >= 3
    if not usable.any():
        raise ValueError(f"no block of {width:.3g} s holds 3 samples: the log is too sparse to find a rest")
    quietest = np.sort(sd[usable])
    floor = float(np.median(quietest[: max(3, len(quietest) // 100)]))
    if floor == 0.0:  # a quantized gyro may read one value throughout a block
        steps = np.abs(np.diff(ra))
        floor = float(steps[steps > 0].min()) / math.sqrt(12.0) if (steps > 0).any() else 0.0
    quiet = usable & (sd <= noise_factor * floor) & (np.abs(mean) <= max_rate)
    runs: list[tuple[int, int]] = []
    start = -1
    level = weight = 0.0

    def agrees(b: int) -> bool:
        return bool(quiet[b]) and abs(mean[b] - level) <= consistency * math.sqrt(
            floor**2 / count[b] + floor**2 / weight
        )

    for b in range(nb):
        # One stray block whose successor agrees again is an outlier, not the end of the rest.
        if start >= 0 and (agrees(b) or (quiet[b] and b + 1 < nb and agrees(b + 1))):
            level = (level * weight + total[b]) / (weight + count[b])
            weight += count[b]
            continue
        if start >= 0:
            runs.append((start, b - 1))
            start = -1
        if quiet[b]:
            start, level, weight = b, mean[b], float(count[b])
    if start >= 0:
        runs.append((start, nb - 1))
    windows = []
    first_index = np.searchsorted(k, np.arange(nb), side="left")
    last_index = np.searchsorted(k, np.arange(nb), side="right") - 1
    for a, b in runs:
        t0, t1 = ta[first_index[a]], ta[last_index[b]]
        if t1 - t0 >= min_duration:
            windows.append((float(t0), float(t1)))
    return windows


def detect_rest(
    t: ArrayLike,
    rate: ArrayLike,
    *,
    min_duration: float = 1.0,
    which: Literal["first", "longest"] = "first",
    **options: float,
) -> tuple[float, float]:
    """The first (or longest) rest of at least ``min_duration`` seconds, as ``(start, end)`` [s].

    ``options`` go to :func:`rest_windows` (``block``, ``noise_factor``, ``max_rate``,
    ``consistency``). Raises ValueError "no rest found" with what the quietest stretch looked like.
    """
    if which not in ("first", "longest"):
        raise ValueError(f"which must be 'first' or 'longest', got {which!r}")
    windows = rest_windows(t, rate, min_duration=min_duration, **options)
    if not windows:
        max_rate = options.get("max_rate", 0.05)
        raise ValueError(
            f"no rest found: no stretch of at least {min_duration:g} s where the rate is as steady as "
            f"the log's quietest blocks and within {max_rate:g} rad/s of zero (give the rest window, "
            "or a shorter min_duration / larger max_rate if this gyro's bias is large)"
        )
    if which == "first":
        return windows[0]
    return max(windows, key=lambda w: w[1] - w[0])


def _time_weights(t: FloatArray) -> FloatArray:
    """Weight of each reading: the interval since the previous one (the first gets none), the
    rectangle rule of HDR eq 3 that the pipeline's static bias uses too."""
    w = np.empty_like(t)
    w[0] = 0.0
    w[1:] = np.diff(t)
    return w


def static_bias(
    t: ArrayLike,
    rate: ArrayLike,
    window: tuple[float, float] | None = None,
    *,
    min_duration: float = 1.0,
    **detect_options: Any,
) -> Calibration:
    """Static bias test (FOG section 2; HDR eq 1-2's ``eps0``): the mean reading at rest.

    Args:
        t: timestamps [s], strictly increasing (any time base, e.g. Unix epoch).
        rate: readings [rad/s].
        window: ``(start, end)`` rest window [s, log time base]; None finds the first rest of at
            least ``min_duration`` seconds (:func:`detect_rest`, which takes ``detect_options``).
        min_duration: shortest acceptable rest [s] (also for a given window).

    The bias and its standard error come from the core's static bias test, the one the
    pipeline's ``bias_window`` runs, so ``bias=cal.bias`` gives the bias that
    ``bias_window=cal.window`` ends with (the pipeline uses its running mean inside the window):
    the mean weighs each reading by the interval since the previous one, and the standard error
    is that of the means of the window's eight equal parts (batch means), which stays honest
    when the noise is correlated (bias instability); for white noise it equals ``sd / sqrt(n)``.
    Returns a :class:`Calibration` with ``bias``, ``bias_stderr``,
    ``residual_rms`` (the readings' standard deviation) and the ``window`` used.

    Raises:
        ValueError: bad samples, a window shorter than ``min_duration`` or holding fewer than 2
            readings, or no rest found.
    """
    ta, ra = _series(t, rate)
    if window is None:
        window = detect_rest(ta, ra, min_duration=min_duration, **detect_options)
    start, end = as_window("the rest window", window)
    inside = np.flatnonzero((ta >= start) & (ta <= end))
    if len(inside) < 2:
        raise ValueError(
            f"the rest window [{start}, {end}] s holds {len(inside)} reading(s) of the log "
            f"({ta[0]} .. {ta[-1]} s); give it in the log's own time base"
        )
    tw, rw = ta[inside] - ta[inside[0]], ra[inside]
    duration = float(tw[-1])
    if duration < min_duration:
        raise ValueError(
            f"the rest window [{start}, {end}] s covers {duration:.3g} s of readings, shorter than "
            f"min_duration = {min_duration:g} s: the bias would be mostly noise"
        )
    bias, _, _, batch_stderr = _gyrocore.static_bias_test(ta, ra, start, end)
    sd = float(np.sqrt(np.sum(_time_weights(tw) * (rw - bias) ** 2) / duration))
    # The batch means need readings in two parts of the window; with fewer, the white-noise error.
    stderr = sd / math.sqrt(len(rw)) if batch_stderr is None else batch_stderr
    return Calibration(
        method="static_bias",
        bias=bias,
        bias_stderr=stderr,
        residual_rms=sd,
        window=(float(ta[inside[0]]), float(ta[inside[-1]])),
        samples=len(rw),
    )


# --- least squares (Hong eq 4-9) --------------------------------------------------------------


def _solve(g: NDArray[np.float64], z: FloatArray) -> tuple[FloatArray, FloatArray, float, float]:
    """Least squares ``z = G q`` with equilibrated columns (SVD via lstsq): returns q, its
    covariance from the residuals, the residual RMS and the condition number of scaled G."""
    norms = np.linalg.norm(g, axis=0)
    if np.any(norms == 0):
        return np.full(2, np.nan), np.full((2, 2), np.nan), math.nan, math.inf
    scaled = g / norms
    q_scaled, _, rank, sv = np.linalg.lstsq(scaled, z, rcond=None)
    cond = float(sv[0] / sv[-1]) if rank == g.shape[1] and sv[-1] > 0 else math.inf
    q = q_scaled / norms
    resid = z - g @ q
    dof = max(len(z) - 2, 1)
    sigma2 = float(resid @ resid) / dof
    cov = sigma2 * np.linalg.pinv(scaled.T @ scaled) / np.outer(norms, norms)
    return q, cov, float(np.sqrt(np.mean(resid**2))), cond


#: A least-squares problem whose reference motion is worse conditioned than this cannot
#: separate scale from bias (Hong: "the robot should be changing rate during the calibration").
MAX_CONDITION = 1e6


def _calibration_from_q(
    method: str, q: FloatArray, cov: FloatArray, rms: float, cond: float, window: tuple[float, float], n: int
) -> Calibration:
    """s and b from ``q = (s_bar, b_bar)`` (Hong eq 3 inverted), with first-order standard errors."""
    s_bar, b_bar = float(q[0]), float(q[1])
    if not s_bar > 0:
        raise ValueError(
            f"the fit gives s_bar = {s_bar:.4g} <= 0 (the gyro would read against the motion): "
            "the rate must change during calibration, and the reference must match the gyro's axis and sign"
        )
    scale_error = 1.0 / s_bar - 1.0
    bias = -b_bar / s_bar
    # Jacobians of s = 1/s_bar - 1 and b = -b_bar/s_bar with respect to (s_bar, b_bar).
    js = np.array([-1.0 / s_bar**2, 0.0])
    jb = np.array([b_bar / s_bar**2, -1.0 / s_bar])
    return Calibration(
        method=method,
        bias=bias,
        scale_error=scale_error,
        bias_stderr=float(np.sqrt(max(jb @ cov @ jb, 0.0))),
        scale_error_stderr=float(np.sqrt(max(js @ cov @ js, 0.0))),
        residual_rms=rms,
        condition_number=cond,
        window=window,
        samples=n,
    )


def _excited(reference_design: NDArray[np.float64], what: str) -> None:
    """Raise unless the reference motion excites the scale factor (columns not collinear)."""
    norms = np.linalg.norm(reference_design, axis=0)
    cond = math.inf
    if np.all(norms > 0):
        sv = np.linalg.svd(reference_design / norms, compute_uv=False)
        cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    if not cond < MAX_CONDITION:
        raise ValueError(
            f"the rate must change during calibration: {what} cannot separate the scale error "
            f"from the bias (condition number {cond:.3g}); calibrate over a motion with turns of "
            "different rates (Hong section 3.1)"
        )


def rate_reference(rate_measured: ArrayLike, rate_reference: ArrayLike) -> Calibration:
    """Least squares against a reference rate at the same instants (Hong eq 8-9).

    Minimises ``sum (r - s_bar r_m - b_bar)^2`` for ``q = (s_bar, b_bar)``. Hong eq 8 as printed
    has the columns of its matrix swapped (its first row reads ``sum r_m * s_bar + sum r_m^2 *
    b_bar = sum r r_m``); the normal equations of this fit are
    ``[[sum r_m^2, sum r_m], [sum r_m, n]] q = [sum r r_m, sum r]``, which is what is solved
    (by SVD on column-scaled data rather than by Cramer's rule, for conditioning).

    Args:
        rate_measured: gyro readings r_m [rad/s].
        rate_reference: true rates r at the same instants [rad/s].

    Raises:
        ValueError: unequal lengths, NaN, fewer than 3 samples, or a reference rate that does not
            change ("the rate must change during calibration").
    """
    rm = as_float_array("rate_measured", rate_measured)
    r = as_float_array("rate_reference", rate_reference)
    if len(rm) != len(r):
        raise ValueError(f"rate_measured has {len(rm)} samples but rate_reference has {len(r)}")
    if len(rm) < 3:
        raise ValueError(f"need at least 3 samples to fit scale and bias, got {len(rm)}")
    for name, a in (("rate_measured", rm), ("rate_reference", r)):
        bad = np.flatnonzero(~np.isfinite(a))
        if len(bad):
            raise ValueError(f"{name}[{bad[0]}] is {a[bad[0]]}: samples must be finite")
    ones = np.ones_like(r)
    _excited(np.column_stack([r, ones]), "a constant reference rate")
    q, cov, rms, cond = _solve(np.column_stack([rm, ones]), r)
    if not cond < MAX_CONDITION:
        raise ValueError(
            f"the rate must change during calibration: the gyro's readings are constant (condition number {cond:.3g})"
        )
    return _calibration_from_q("rate_reference", q, cov, rms, cond, (0.0, float(len(r) - 1)), len(r))


def heading_reference(
    t: ArrayLike,
    rate_measured: ArrayLike,
    t_ref: ArrayLike,
    heading_ref: ArrayLike,
    *,
    window: tuple[float, float] | None = None,
) -> Calibration:
    """Least squares against a reference heading (Hong eq 4-7), at the reference's own times.

    Hong eq 5 stacks ``psi(k+n) - psi(k) = s_bar h sum r_m + n h b_bar``: the heading change
    since the first reference sample equals ``s_bar`` times the gyro's integral plus ``b_bar``
    times the elapsed time. Here the gyro's integral (trapezoid over its actual intervals) is
    interpolated at each reference time, so the reference may come at another rate and at
    other instants (the paper: 20 Hz reference, 100 Hz gyro); rows are the reference samples
    inside the gyro's span (and ``window``). With a regular gyro and a reference at its sample
    times this is eq 6-7 with the trapezoid rule for eq 4's sum.

    Args:
        t, rate_measured: gyro timestamps [s] and readings [rad/s].
        t_ref, heading_ref: reference times [s, same time base] and heading [rad, may be
            wrapped to (-pi, pi]; it is unwrapped].
        window: ``(start, end)`` [s] to calibrate over (Hong used the first 20 s); None: all.

    The residuals of a heading fit are correlated (they are integrals), so ``bias_stderr`` and
    ``scale_error_stderr`` are optimistic; the residual RMS is in rad.

    Raises:
        ValueError: bad samples, fewer than 3 reference samples inside the gyro's span, or a
            motion that does not change rate ("the rate must change during calibration").
    """
    ta, ra = _series(t, rate_measured, rate_name="rate_measured")
    tr, hr = _series(t_ref, heading_ref, t_name="t_ref", rate_name="heading_ref")
    lo, hi = ta[0], ta[-1]
    if window is not None:
        start, end = as_window("window", window)
        lo, hi = max(lo, start), min(hi, end)
    inside = np.flatnonzero((tr >= lo) & (tr <= hi))
    if len(inside) < 3:
        raise ValueError(
            f"only {len(inside)} reference sample(s) fall inside the gyro's span {lo} .. {hi} s; "
            "need at least 3 (are both in the same time base?)"
        )
    origin = ta[0]
    angle = integrate(ta - origin, ra)
    times = tr[inside] - origin
    psi = unwrap(hr)[inside]
    g1 = np.interp(times, ta - origin, angle)
    g = np.column_stack([g1 - g1[0], times - times[0]])
    z = psi - psi[0]
    _excited(
        np.column_stack([z, times - times[0]])[1:],
        "a reference heading that turns at one constant rate (or not at all)",
    )
    q, cov, rms, cond = _solve(g[1:], z[1:])
    return _calibration_from_q(
        "heading_reference", q, cov, rms, cond, (float(tr[inside[0]]), float(tr[inside[-1]])), len(inside)
    )


# --- rotary table (FOG eq 1-6) -----------------------------------------------------------------


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
            ``turn_angle``, or no turn at all.
    """
    ta, ra = _series(t, rate)
    temp = None if temperature is None else _temperature(temperature, len(ta))
    pauses = rest_windows(ta, ra, min_duration=min_pause, **rest_options)
    tests = [w for w in pauses if w[1] - w[0] >= min_rest]
    if not tests:
        raise ValueError(
            f"no rest of at least {min_rest:g} s found: the static bias before the turns cannot be measured"
        )
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
        angle = float(integrate(tm - tm[0], rm)[-1])
        if abs(angle) < 0.05 * turn_angle:
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


def _temperature(temperature: ArrayLike, n: int) -> FloatArray:
    """The temperature record [degC], checked: as long as the timestamps, every value finite."""
    temp = as_float_array("temperature", temperature)
    if len(temp) != n:
        raise ValueError(f"temperature has {len(temp)} samples but t has {n}")
    bad = np.flatnonzero(~np.isfinite(temp))
    if len(bad):
        raise ValueError(f"temperature[{bad[0]}] is {temp[bad[0]]}: samples must be finite")
    return temp


def bias_temperature_table(
    t: ArrayLike,
    rate: ArrayLike,
    temperature: ArrayLike,
    *,
    bin_width: float = 1.0,
    min_samples: int = 10,
) -> BiasTable:
    """Bias versus temperature from a record at rest (FOG section 2, its Figure 2).

    Readings [rad/s] are grouped into temperature bins ``bin_width`` degC wide; each bin with at
    least ``min_samples`` readings gives one entry: its mean temperature and its time-weighted
    mean reading (as :func:`static_bias`). The record must be at rest throughout (cut it to the
    rest first); the temperature should change slowly (a warm-up after power-on).
    """
    ta, ra = _series(t, rate)
    temp = _temperature(temperature, len(ta))
    if not (math.isfinite(bin_width) and bin_width > 0):
        raise ValueError(f"bin_width must be finite and > 0 [degC], got {bin_width}")
    w = _time_weights(ta - ta[0])
    w[0] = w[1] if len(w) > 1 else 1.0
    k = np.floor((temp - temp.min()) / bin_width).astype(np.int64)
    nb = int(k.max()) + 1
    counts = np.bincount(k, minlength=nb)
    wsum = np.bincount(k, w, nb)
    keep = (counts >= min_samples) & (wsum > 0)
    if keep.sum() < 2:
        raise ValueError(
            f"fewer than 2 temperature bins of {bin_width:g} degC hold {min_samples} readings: the temperature "
            f"spans only {np.ptp(temp):.3g} degC"
        )
    bias = np.bincount(k, w * ra, nb) / np.where(wsum > 0, wsum, 1.0)
    mean_t = np.bincount(k, w * temp, nb) / np.where(wsum > 0, wsum, 1.0)
    var = np.bincount(k, w * (ra - bias[k]) ** 2, nb) / np.where(wsum > 0, wsum, 1.0)
    stderr = np.sqrt(var / np.maximum(counts, 1))
    idx = np.flatnonzero(keep)
    order = idx[np.argsort(mean_t[idx])]
    return BiasTable(
        temperatures=tuple(float(v) for v in mean_t[order]),
        biases=tuple(float(v) for v in bias[order]),
        stderr=tuple(float(v) for v in stderr[order]),
        counts=tuple(int(v) for v in counts[order]),
    )

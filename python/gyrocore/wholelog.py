"""Whole-log processing: the bias known before the first sample, from every rest in the log.

A causal pipeline (:class:`gyrocore.Pipeline`, a robot on the move) can only use a rest once it
has seen it: a rest in the middle of a log corrects only what follows it. A whole log is all
there, so whole mode (``mode="whole"``, the default of :func:`gyrocore.process`,
:meth:`gyrocore.Log.process`, ``gyrocore process`` and ``gyrocore evaluate``) takes the bias from
the rests wherever they lie and applies it from the first sample:

* a given rest window (``bias_window``, ``bias_duration``, or a log folder's meta.json
  ``stationary``): its mean, from the first sample on;
* otherwise every rest found in the log, from the rate alone
  (:func:`gyrocore.calibration.rest_windows`) and, where a speed is given, where the speed stays
  below :data:`SPEED_THRESHOLD` for :data:`MIN_REST` seconds. One rest gives its bias; several
  give a bias interpolated linearly in time between their middles (constant before the first
  and after the last), which follows a bias that wanders during the drive;
* no rest at all: a warning, and the bias is 0, as in causal mode.

Each rest is measured by the core's own rest window (the same time-weighted mean, noise and
standard error as the causal pipeline), the bias series is subtracted from the rate, and the
pipeline runs with ``bias=0``. Presets whose dead band or HDR bound scale with the rest's noise
(``threshold_sigmas``, ``hdr_bound_sigmas``) get the explicit ``threshold`` and
``hdr_max_correction`` that rest gives, so the result is what the causal pipeline gives with that
rest at the start of the log. With several rests the noise is pooled (root mean square, weighted
by readings) and the bound uses the largest standard error: an interpolated bias is never less
certain than its worse neighbour.

Units: s, rad/s, m/s.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _gyrocore
from ._arrays import FloatArray, as_float_array
from ._checks import warn
from .pipeline import HeadingResult, Pipeline, _to_si, preset_params, uses_static_bias

#: The ways to process a whole log: ``whole`` (bias from every rest, known from the first sample)
#: or ``causal`` (what a streaming :class:`gyrocore.Pipeline` gives, sample after sample).
MODES = ("whole", "causal")
#: Below this speed [m/s] the vehicle stands still (wheel and CAN speeds read a few cm/s of noise).
SPEED_THRESHOLD = 0.05
#: A rest lasts at least this long [s] (as :func:`gyrocore.calibration.rest_windows`' default).
MIN_REST = 1.0
#: A speed rest whose mean rate exceeds this [rad/s] is a turn on the spot, not a rest
#: (:func:`gyrocore.calibration.rest_windows`' ``max_rate``; a gyro with a larger bias needs its
#: rest window given).
MAX_REST_RATE = 0.05


@dataclass(frozen=True)
class Rest:
    """One rest whose mean reading gave (part of) the bias.

    Attributes:
        start, end: first and last time of the window [s, the log's time base].
        bias: mean reading over the window [rad/s], time-weighted as the pipeline's rest window.
        bias_std_error: standard error of ``bias`` [rad/s] (batch means), or None from too few
            readings.
        noise: standard deviation of one reading [rad/s], or None from too few readings.
        samples: readings inside the window.
        found_by: ``given`` (bias_window, bias_duration, meta.json), ``rate``, ``speed`` or
            ``rate+speed``.
    """

    start: float
    end: float
    bias: float
    bias_std_error: float | None
    noise: float | None
    samples: int
    found_by: str

    @property
    def middle(self) -> float:
        """The time the rest's bias stands for [s] when rests are interpolated."""
        return (self.start + self.end) / 2

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON (SI units)."""
        return asdict(self)

    def __str__(self) -> str:
        error = "" if self.bias_std_error is None else f" +- {math.degrees(self.bias_std_error):.2g}"
        return (
            f"[{self.start:.3f}, {self.end:.3f}] s ({self.found_by}): "
            f"bias {math.degrees(self.bias):.5f}{error} deg/s"
        )


def check_mode(mode: str) -> None:
    """Refuse a mode that is not one of :data:`MODES`."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}, got {mode!r}")


# --- finding rests -----------------------------------------------------------------------------


def speed_on(t: FloatArray, t_speed: ArrayLike, speed: ArrayLike, *, where: str = "speed") -> FloatArray:
    """A speed series at its own times, interpolated linearly onto the gyro's times ``t``.

    Outside the series' span the speed is unknown (NaN), so no rest is taken from there.

    Raises:
        ValueError: lengths differ, a time or speed is not finite, or the times do not strictly
            increase (naming ``where`` and the index).
    """
    ts, vs = as_float_array(f"{where} times", t_speed), as_float_array(where, speed)
    if len(ts) != len(vs):
        raise ValueError(f"{where}: {len(ts)} times but {len(vs)} speeds")
    for label, a in (("time", ts), ("speed", vs)):
        bad = np.flatnonzero(~np.isfinite(a))
        if len(bad):
            raise ValueError(f"{where}: {label} at index {bad[0]} is {a[bad[0]]}; speeds must be finite")
    steps = np.flatnonzero(np.diff(ts) <= 0)
    if len(steps):
        i = int(steps[0]) + 1
        raise ValueError(f"{where}: times must strictly increase, but index {i} ({ts[i]}) follows {ts[i - 1]}")
    if len(ts) == 0:
        return np.full(len(t), np.nan)
    return np.asarray(np.interp(t, ts, vs, left=np.nan, right=np.nan), dtype=np.float64)


def _runs(t: FloatArray, flag: np.ndarray, min_duration: float) -> list[tuple[float, float]]:
    """Stretches where ``flag`` holds, from their first to their last time, at least ``min_duration`` long."""
    edges = np.diff(np.concatenate(([0], flag.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(float(t[a]), float(t[b])) for a, b in zip(starts, ends) if t[b] - t[a] >= min_duration]


def find_rests(t: FloatArray, rate: FloatArray, speed: FloatArray | None = None) -> list[tuple[float, float, str]]:
    """Every rest of the log as ``(start, end, found_by)``, in time order.

    From the rate (:func:`gyrocore.calibration.rest_windows` over the finite readings) and, with a
    ``speed`` per sample [m/s], where the speed stays below :data:`SPEED_THRESHOLD`. With a speed, a
    rate rest during which the speed exceeds the threshold is dropped: it was a straight, steady
    stretch of driving, whose curvature the bias would take in. Overlapping rests are merged.
    """
    from .calibration import rest_windows  # calibration builds on the pipeline module too

    finite = np.isfinite(rate)
    found: list[tuple[float, float, str]] = []
    if np.count_nonzero(finite) >= 8:
        found = [(a, b, "rate") for a, b in rest_windows(t[finite], rate[finite], min_duration=MIN_REST)]
    if speed is not None:
        # NaN (no speed known there) is neither stopped nor moving
        stopped = np.abs(speed) <= SPEED_THRESHOLD
        moving = np.abs(speed) > SPEED_THRESHOLD
        found = [w for w in found if not moving[(t >= w[0]) & (t <= w[1])].any()]
        for a, b in _runs(t, stopped, MIN_REST):
            inside = (t >= a) & (t <= b) & finite
            if inside.any() and abs(float(np.mean(rate[inside]))) <= MAX_REST_RATE:
                found.append((a, b, "speed"))
    return _merge(sorted(found))


def _merge(windows: list[tuple[float, float, str]]) -> list[tuple[float, float, str]]:
    """Overlapping windows (sorted by start) as one, labelled with every way it was found."""
    merged: list[tuple[float, float, str]] = []
    for a, b, how in windows:
        if merged and a <= merged[-1][1]:
            a0, b0, how0 = merged[-1]
            ways = sorted(set(how0.split("+")) | {how})
            merged[-1] = (a0, max(b, b0), "+".join(ways))
        else:
            merged.append((a, b, how))
    return merged


# --- measuring rests ---------------------------------------------------------------------------


def measure_rest(
    chunks: Iterable[tuple[FloatArray, FloatArray, int]],
    window: tuple[float, float],
    found_by: str,
    nonfinite: str | None,
) -> Rest:
    """The bias, noise and standard error of the rest ``window``, measured by the core's own rest
    window over ``chunks`` of ``(t, rate, index of the first sample)``, read only up to the first
    sample after the window (flat memory for a streamed file).

    Raises:
        ValueError: the window holds no reading (naming it).
    """
    start, end = window
    overrides: dict[str, Any] = {"bias_window": (start, end)}
    if nonfinite is not None:
        overrides["nonfinite"] = nonfinite
    # The extension directly: the user's pipeline warns about units and repairs once, not per rest.
    core = _gyrocore.Pipeline("static_bias", overrides)
    samples, first_time, last = 0, math.nan, -math.inf
    for t, rate, first in chunks:
        if len(t) == 0:
            continue
        if first == 0:
            first_time = float(t[0])
        core.process(t, rate, None, first)
        samples += int(np.count_nonzero((t >= start) & (t <= end)))
        last = float(t[-1])
        if last > end:
            break
    else:
        # The log ends inside the window: one reading past it closes the window (and is not used).
        core.process(np.array([max(last, end) + 1.0]), np.zeros(1), None, 0)
    if end < first_time:
        raise ValueError(
            f"the bias window [{start}, {end}] s ends before the first sample (t[0] = {first_time}); "
            "give the window in the log's own time base"
        )
    if samples == 0:
        raise ValueError(f"the bias window [{start}, {end}] s held no sample of the log")
    stats = core.rest_statistics()
    if stats is None:
        return Rest(start, end, core.bias()[0], None, None, samples, found_by)
    return Rest(start, end, core.bias()[0], stats[1], stats[0], samples, found_by)


def _slices(t: FloatArray, rate: FloatArray, window: tuple[float, float]) -> Iterator[tuple[FloatArray, FloatArray, int]]:
    """The samples from the one before ``window`` to the one after it: what the core's rest window
    reads of them (each reading weighs the interval since the one before)."""
    i0 = max(int(np.searchsorted(t, window[0], side="left")) - 1, 0)
    i1 = int(np.searchsorted(t, window[1], side="right")) + 1
    yield t[i0:i1], rate[i0:i1], i0


# --- the bias of a whole log -------------------------------------------------------------------


@dataclass(frozen=True)
class BiasPlan:
    """Where whole mode takes the bias from, before the first sample is processed.

    Attributes:
        source: one line saying so (for reports).
        rests: the rests used, in time order (empty for a given bias or none found).
        overrides: what the pipeline then runs with (``bias=0`` when the rests' bias is subtracted
            from the rate, and the explicit dead band and HDR bound of the rests' noise).
        warning: what the user should know (no rest found), or None.
    """

    source: str
    rests: tuple[Rest, ...]
    overrides: dict[str, Any]
    warning: str | None = None

    def bias(self, t: FloatArray) -> FloatArray | float:
        """The bias to subtract at the times ``t`` [rad/s]: one rest's bias, or the rests' biases
        interpolated between their middles."""
        if not self.rests:
            return 0.0
        if len(self.rests) == 1:
            return self.rests[0].bias
        mids = np.array([r.middle for r in self.rests])
        return np.asarray(np.interp(t, mids, [r.bias for r in self.rests]), dtype=np.float64)

    def result(self, result: HeadingResult) -> HeadingResult:
        """``result`` saying where its bias came from."""
        return replace(result, bias_source=self.source, rests=self.rests)


def _bias_source(si: dict[str, Any]) -> str | None:
    """Which bias source the (SI) overrides set, or None."""
    return next((k for k in ("bias", "bias_window", "bias_duration") if si.get(k) is not None), None)


def causal_source(preset: str, si: dict[str, Any]) -> str:
    """One line saying where the causal pipeline takes the bias from."""
    if not uses_static_bias(preset):
        return "none (the preset removes no static bias)"
    key = _bias_source(si)
    if key == "bias":
        return f"given: {math.degrees(si['bias']):.5f} deg/s"
    if key == "bias_window":
        a, b = si["bias_window"]
        return f"rest window [{a:.3f}, {b:.3f}] s (given), applied from its end (causal)"
    if key == "bias_duration":
        return f"first {si['bias_duration']:g} s, applied from their end (causal)"
    return "none: no bias or rest window given; bias 0 (causal)"


def _scaled(preset: str, si: dict[str, Any], rests: tuple[Rest, ...]) -> dict[str, float]:
    """The explicit dead band and HDR bound that the rests' noise gives a noise-scaled preset."""
    params = preset_params(preset, **si)
    measured = [(r.noise, r.bias_std_error, r.samples) for r in rests if r.noise is not None and r.bias_std_error is not None]
    if not measured:
        return {}
    noise, error, samples = (np.array(column, dtype=np.float64) for column in zip(*measured))
    out: dict[str, float] = {}
    if params.get("threshold_sigmas") is not None:
        out["threshold"] = params["threshold_sigmas"] * math.sqrt(float(np.average(noise**2, weights=samples)))
    if params.get("hdr_bound_sigmas") is not None:
        out["hdr_max_correction"] = params["hdr_bound_sigmas"] * float(error.max())
    return out


def plan(
    preset: str,
    si: dict[str, Any],
    t_start: float,
    measure: Callable[[tuple[float, float], str], Rest],
    find: Callable[[], list[tuple[float, float, str]]],
) -> BiasPlan:
    """Where whole mode takes the bias from.

    Args:
        preset: the preset.
        si: the user's overrides in SI names.
        t_start: the log's first time [s] (``bias_duration`` counts from it).
        measure: ``measure(window, found_by) -> Rest``.
        find: ``find() -> [(start, end, found_by)]``, called only when no bias source is given.
    """
    rest_of = {k: v for k, v in si.items() if k not in ("bias", "bias_window", "bias_duration")}
    key = _bias_source(si)
    if not uses_static_bias(preset) or key == "bias":
        return BiasPlan(causal_source(preset, si), (), si)
    if key == "bias_window":
        windows = [(float(si["bias_window"][0]), float(si["bias_window"][1]), "given")]
    elif key == "bias_duration":
        windows = [(t_start, t_start + float(si["bias_duration"]), "given")]
    else:
        windows = find()
    if not windows:
        warning = (
            f"preset {preset!r} removes a static bias, but no bias, bias_window or bias_duration was given, "
            "the log gives no rest window and no rest was found in it: the bias is taken as 0, as in causal "
            "mode (on the command line: --bias-window, --bias-duration or --bias-dps)"
        )
        return BiasPlan("none: no rest found in the log; bias 0", (), {**rest_of, "bias": 0.0}, warning)
    rests = tuple(measure((a, b), how) for a, b, how in windows)
    if len(rests) == 1:
        label = f"first {si['bias_duration']:g} s: " if key == "bias_duration" else ""
        source = f"{label}rest {rests[0]}, applied from the first sample"
    else:
        source = f"{len(rests)} rests, bias interpolated between their middles"
    return BiasPlan(source, rests, {**rest_of, "bias": 0.0, **_scaled(preset, rest_of, rests)})


def plan_arrays(
    preset: str, si: dict[str, Any], t: FloatArray, rate: FloatArray, speed: FloatArray | None
) -> BiasPlan:
    """:func:`plan` for a log in memory (times already checked by :func:`times_ok`)."""
    return plan(
        preset,
        si,
        float(t[0]) if len(t) else 0.0,
        lambda window, how: measure_rest(_slices(t, rate, window), window, how, si.get("nonfinite")),
        lambda: find_rests(t, rate, speed),
    )


def plan_stream(
    preset: str,
    overrides: dict[str, Any],
    chunks: Callable[[], Iterable[tuple[FloatArray, FloatArray, int]]],
    read_all: Callable[[], tuple[FloatArray, FloatArray, FloatArray | None]],
) -> BiasPlan:
    """:func:`plan` for a log read chunk after chunk (``gyrocore process``): a given rest window is
    measured by a first pass that reads only up to the window's end (flat memory); finding the
    rests needs the whole log's times and rates (16 bytes a sample) from ``read_all() -> (t, rate,
    speed or None)``. The heading itself is then a second, streamed pass."""
    si = _to_si(overrides)
    if uses_static_bias(preset) and _bias_source(si) is None:
        t, rate, speed = read_all()
        if not times_ok(t):
            # The second pass, through the pipeline, names the bad sample.
            return BiasPlan("none: the log's times are invalid", (), {**si, "bias": 0.0})
        return plan_arrays(preset, si, t, rate, speed)
    t_start = 0.0
    if si.get("bias_duration") is not None:  # counts from the first sample
        t_start = next((float(t[0]) for t, _, _ in chunks() if len(t)), 0.0)
    return plan(preset, si, t_start, lambda window, how: measure_rest(chunks(), window, how, si.get("nonfinite")), list)


def process_log(
    t: ArrayLike,
    rate: ArrayLike,
    preset: str,
    *,
    mode: str = "whole",
    temperature: ArrayLike | None = None,
    speed: ArrayLike | None = None,
    **overrides: Any,
) -> HeadingResult:
    """:func:`gyrocore.process` (see there and the module doc)."""
    check_mode(mode)
    si = _to_si(overrides)
    if mode == "causal":
        if speed is not None:
            raise ValueError("speed is used by mode='whole' only: the causal pipeline does not track rests")
        result = Pipeline(preset, **overrides).process(t, rate, temperature=temperature)
        return replace(result, bias_source=causal_source(preset, si))
    ta, ra = as_float_array("t", t), as_float_array("rate", rate)
    sp = None if speed is None else as_float_array("speed", speed)
    if sp is not None and len(sp) != len(ta):
        raise ValueError(f"speed has {len(sp)} samples but t has {len(ta)}: give one speed per gyro sample")
    if len(ta) != len(ra) or len(ta) == 0 or not times_ok(ta):
        # The pipeline is the one place that names the bad sample (and gives an empty log back).
        result = Pipeline(preset, **overrides).process(ta, ra, temperature=temperature)
        return replace(result, bias_source=causal_source(preset, si))
    bias_plan = plan_arrays(preset, si, ta, ra, sp)
    if bias_plan.warning:
        warn(bias_plan.warning)
    result = Pipeline(preset, **bias_plan.overrides).process(ta, ra - bias_plan.bias(ta), temperature=temperature)
    return bias_plan.result(result)


def times_ok(t: FloatArray) -> bool:
    """Finite, strictly increasing times (otherwise the pipeline refuses them, naming the sample)."""
    return bool(np.isfinite(t).all() and (np.diff(t) > 0).all())

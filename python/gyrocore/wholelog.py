"""Whole-log processing: the bias known before the first sample, from every rest in the log.

A causal pipeline (:class:`gyrocore.Pipeline`, a robot on the move) can only use a rest once it
has seen it: a rest in the middle of a log corrects only what follows it. A whole log is all
there, so whole mode (``mode="whole"``, the default of :func:`gyrocore.process`,
:meth:`gyrocore.Log.process`, :mod:`gyrocore.batch`, ``gyrocore process`` and ``gyrocore
evaluate``) takes the bias from the rests wherever they lie and applies it from the first sample:

* a given rest window (``bias_window``, ``bias_duration``, or a log folder's meta.json
  ``stationary``): its mean, from the first sample on, exactly as ``bias=`` that mean would;
* otherwise every rest found in the log (:mod:`gyrocore._rests`: from the rate, where a speed is
  given only where the vehicle stands still; too short, too noisy or inconsistent ones refused),
  each a measurement of the bias with its own standard error, smoothed as a random walk of
  strength ``bias_walk`` [rad/s/sqrt(s)] by a Rauch-Tung-Striebel smoother
  (:mod:`gyrocore._smoother`): one rest gives its bias, several a bias that follows the
  wandering only as far as the rests' precision supports;
* no rest at all: a warning, and the bias is 0, as in causal mode.

The bias series is subtracted from the rate and the pipeline runs with ``bias=0``; a bias that is
one number over the whole log goes to the pipeline as ``bias=`` instead (the same subtraction, in
the core, with no copy of the rate). Presets whose
dead band or HDR bound scale with the rest's noise (``threshold_sigmas``, ``hdr_bound_sigmas``)
get the explicit ``threshold`` (the rests' pooled noise) and ``hdr_max_correction`` (the bias's
standard error, root mean square over the log, growing away from the rests with ``hdr_bound_walk``:
how far HDR may correct there, a setting of its own), so a single rest at the start gives what
the causal pipeline gives.

Units: s, rad/s, m/s.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from numpy.typing import ArrayLike

from ._arrays import MASKED_AS_NONFINITE, FloatArray, as_float_array
from ._checks import MAX_SECONDS, first_infinite, public_dir, refuse_no_usable_reading, require_times, warn
from ._gyrocore import SampleError
from ._rests import (MIN_REST, SPEED_THRESHOLD, Found, accept, few_readings_hint, find_rests, measure_rest,
                     unseen_stop_hint)
from ._smoother import SmoothedBias, smooth
from ._time_steps import whole_log_steps
from .pipeline import ALL_OUTPUTS, BIAS_SOURCES, HeadingResult, Pipeline, core_pipeline, uses_static_bias
from .pipeline_params import _to_si
from .result import OutArrays, filled, out_arrays
from .rests import Rest, refuse_speed_t_alone, rest_lines, speed_on
from .wholelog_options import (
    BIAS_OPTIONS_HINT, BIAS_SIGMAS, BIAS_WALK, HDR_BOUND_WALK, MODES, WHOLE_OPTIONS, Options, check_mode, refuse_tracking,
    refuse_whole_options, untracked,
)
from .wholelog_bias_plan import BiasPlan
from .window import RestWindowError, Window, refuse_window_objects, window_span

if TYPE_CHECKING:
    from .fixes import Fixes, FixesLike

__all__ = [
    "BIAS_OPTIONS_HINT", "BIAS_SIGMAS", "BIAS_WALK", "HDR_BOUND_WALK", "MIN_REST", "MODES", "SPEED_THRESHOLD", "WHOLE_OPTIONS", "BiasPlan", "Options", "Rest",
    "check_mode", "plan_arrays", "plan_log", "plan_stream", "process_log", "refuse_tracking", "refuse_whole_options", "rest_lines", "untracked",
    "without_bias",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

#: ``chunks()``: the ``(t, rate)`` pieces of a log from its start, anew at each call.
Chunks = Callable[[], Iterable[tuple[FloatArray, FloatArray]]]


def check_parameters(preset: str, overrides: dict[str, Any]) -> None:
    """Refuse, naming it, a parameter of ``overrides`` that the core refuses (whole mode's own
    options and a window still counted from the first sample aside), before whole mode reads the
    rest window itself: a window of three bounds was read in part, and a zero ``bias_duration`` was
    blamed on the HDR bound derived from it. A :class:`Window` is checked once resolved against the
    log: here (0, 1) s stands in for it, so that a second bias source beside it is still refused
    (``--bias-window 0 5 --param bias_duration=3`` dropped the duration without a word)."""
    core_pipeline(preset, _to_si({k: (0.0, 1.0) if isinstance(v, Window) else v for k, v in overrides.items()
                                  if k not in WHOLE_OPTIONS}))


def without_bias(si: dict[str, Any]) -> dict[str, Any]:
    """``si`` with ``bias=0`` in place of its bias source (a pipeline refuses both), without
    :data:`WHOLE_OPTIONS` (a pipeline does not take them) and with the preset's rest tracker off:
    what the pipeline runs with where whole mode takes the bias off the rate itself, or takes none
    (a sample the core refuses: the pipeline then names it)."""
    kept = {k: v for k, v in si.items() if k not in BIAS_SOURCES and k not in WHOLE_OPTIONS}
    return {**untracked(kept), "bias": 0.0}


def _bias_source(si: dict[str, Any]) -> str | None:
    """Which bias source the (SI) overrides set, or None."""
    return next((k for k in BIAS_SOURCES if si.get(k) is not None), None)


def causal_source(preset: str, si: dict[str, Any]) -> str:
    """One line saying where the causal pipeline takes the bias from."""
    key = _bias_source(si)
    # a preset that wants no static bias (raw) still removes one it is given: say which
    if not uses_static_bias(preset) and key is None:
        return "none (the preset removes no static bias)"
    if key == "bias":
        return f"given: {math.degrees(si['bias']):.5f} deg/s"
    if key == "bias_window":
        a, b = si["bias_window"]
        return f"rest window [{a:.3f}, {b:.3f}] s (given), applied from its end (causal)"
    if key == "bias_duration":
        return f"first {si['bias_duration']:g} s, applied from their end (causal)"
    return "none: no bias or rest window given; bias 0 (causal)"


def _smooth(rests: tuple[Rest, ...], walk: float) -> SmoothedBias:
    """The smoother over ``rests``, each a measurement at its middle."""
    return smooth([r.middle for r in rests], [r.bias for r in rests], [r.bias_std_error for r in rests], walk)


def plan(
    preset: str,
    si: dict[str, Any],
    t_start: float,
    measure: Callable[[tuple[float, float], str], Rest],
    find: Callable[[], Found],
    times: FloatArray | None,
    options: Options,
) -> BiasPlan:
    """Where whole mode takes the bias from.

    Args:
        preset: the preset.
        si: the user's overrides in SI names.
        t_start: the log's first time [s] (``bias_duration`` counts from it).
        measure: ``measure(window, found_by) -> Rest``.
        find: ``find() -> Found``, called only when no bias source is given.
        times: the log's times where known (found rests): the HDR bound is the smoothed bias's
            standard error over them (its walk ``options.hdr_bound_walk``; :attr:`BiasPlan.bias_error`).
        options: the bias's walk, the significance test (``bias_sigmas``: found rests whose mean
            is within this many standard errors of 0 leave the bias at 0: a calibrated gyro, whose
            rests show how it reads at rest, not a bias) and the HDR bound's walk.
    """
    walk = options.bias_walk
    rest_of, overrides = untracked({k: v for k, v in si.items() if k not in BIAS_SOURCES}), without_bias(si)
    key = _bias_source(si)
    if not uses_static_bias(preset) or key == "bias":
        return BiasPlan(causal_source(preset, si), overrides=untracked(si))
    if key is not None:  # the user's window: the bias of the whole log, constant
        window = window_span(si, t_start)
        assert window is not None  # the key says which is given
        rest = measure(window, f"given: {key}")
        label = f"first {si['bias_duration']:g} s: " if key == "bias_duration" else ""
        smoothed = _smooth((rest,), 0.0)
        source = f"{label}rest {rest}, applied from the first sample"
        given = BiasPlan(source, (rest,), overrides, smoothed, given_error=rest.bias_std_error)
        return given.with_scaled(preset, rest_of)
    candidates = find()
    rests = accept([measure((a, b), how) for a, b, how in candidates.windows], walk, candidates.motion_noise)
    used = tuple(r for r in rests if r.refused is None)
    if not used:  # none found, or every one refused
        none = f"{len(rests)} rest(s) found, none used" if rests else "no rest found in the log"
        warning = (
            f"preset {preset!r} removes a static bias, but no bias, bias_window or bias_duration was given, the "
            f"log gives no rest window and {f'{none} ({rests[0].refused})' if rests else 'no rest was found in it'}: "
            f"the bias is taken as 0, as in causal mode {BIAS_OPTIONS_HINT}"
        )
        return BiasPlan(f"none: {none}; bias 0", tuple(rests), overrides, None, warning)
    smoothed, bound = _smooth(used, walk), _smooth(used, options.hdr_bound_walk)
    refused = f"; {len(rests) - len(used)} refused" if len(rests) > len(used) else ""
    # the inverse-variance mean of the rests (the smoother without a walk): is there a bias at all?
    level = _smooth(used, 0.0)
    mean, error = float(level.mean[0]), math.sqrt(float(level.variance[0]))
    if abs(mean) <= options.bias_sigmas * error:
        source = (
            f"{len(used)} rest(s) read {math.degrees(mean):.5f} +- {math.degrees(error):.2g} deg/s, within "
            f"{options.bias_sigmas:g} standard errors of 0: bias 0{refused}"
        )
        return BiasPlan(source, tuple(rests), overrides, bound=bound, times=times).with_scaled(preset, rest_of)
    source = (
        f"rest {used[0]}, applied from the first sample"
        if len(used) == 1
        else f"{len(used)} rests, bias smoothed between them (bias_walk {walk:.3g} rad/s/sqrt(s))"
    )
    found = BiasPlan(source + refused, tuple(rests), overrides, smoothed, bound=bound, times=times)
    return found.with_scaled(preset, rest_of)


def plan_arrays(
    preset: str, si: dict[str, Any], t: FloatArray, rate: FloatArray, speed: FloatArray | None, options: Options
) -> BiasPlan:
    """:func:`plan` for a log in memory (times already checked by :func:`times_ok`); where no rest
    is found, its warning says what the steadiest stretch reads (a rate in deg/s, say)."""
    found = plan(
        preset,
        si,
        float(t[0]),
        lambda window, how: measure_rest([(t, rate)], window, how),
        lambda: find_rests(t, rate, speed, options.min_rest),
        t,
        options,
    )
    if found.warning is None:
        return found
    # a slow log's rests, the first one said too short in readings or none found: the rate is why
    slow = "" if any("too short in readings" in (r.refused or "") for r in found.rests) else few_readings_hint(t, speed)
    if found.rests:  # the steady stretch's hint is for a log where nothing looked like a rest
        return replace(found, warning=found.warning + slow)
    from .calibration.rest import steady_stretch_hint  # calibration builds on the pipeline module too

    # where the speed is known the rate's rests were not looked for: a steady stretch there may be a
    # stop the speed does not show; beyond it, one the rate finder refused for its level
    hint = (speed is not None and unseen_stop_hint(t, rate, speed, options.min_rest)) or steady_stretch_hint(
        t, rate, options.min_rest)
    return replace(found, warning=found.warning + hint + slow)


def plan_log(
    preset: str, si: dict[str, Any], t: FloatArray, rate: FloatArray, speed: FloatArray | None, options: Options
) -> BiasPlan:
    """:func:`plan_arrays` for a log in memory whose times are not checked yet: times that are not
    finite and strictly increasing (or none) plan no bias, and the pipeline, which runs the log
    next, names the bad sample where it is."""
    if len(t) == 0 or not times_ok(t):
        return _no_plan(si)
    return plan_arrays(preset, si, t, rate, speed, options)


def _no_plan(si: dict[str, Any]) -> BiasPlan:
    """No bias for a log whose times the core refuses: the pipeline that runs it names the sample."""
    return BiasPlan("none: the log's times are invalid", overrides=without_bias(si))


def _window_beyond_time(si: dict[str, Any], t_start: float) -> bool:
    """Whether the given rest window (``bias_window``, or ``bias_duration`` from ``t_start``)
    reaches beyond the core's +-2^40 s, which the core refuses as a parameter: for times in
    nanoseconds read as seconds, the bad time (and its unit) is the error to give first."""
    given: Any = si.get("bias_window")
    if (given is None and si.get("bias_duration") is None) or isinstance(given, Window):
        return False  # none, or one counted from the first sample
    try:
        if si.get("bias_duration") is not None:
            given = (t_start, t_start + float(si["bias_duration"]))
        return max(abs(float(given[0])), abs(float(given[1]))) > MAX_SECONDS
    except (TypeError, ValueError, LookupError, OverflowError):  # no window: check_parameters names what it is
        return False


def plan_stream(
    preset: str,
    overrides: dict[str, Any],
    chunks: Chunks,
    read_all: Callable[[], tuple[FloatArray, FloatArray, FloatArray | None]],
) -> BiasPlan:
    """:func:`plan` for a log read chunk after chunk (``gyrocore process``): a given rest window is
    measured by a first pass that reads only up to the window's end (flat memory); finding the
    rests needs the whole log's times and rates (16 bytes a sample) from ``read_all() -> (t, rate,
    speed or None)``. The heading itself is then a second, streamed pass."""
    si = _to_si(overrides)
    options = Options.pop(si)
    if uses_static_bias(preset) and _bias_source(si) is None:
        found = plan_log(preset, si, *read_all(), options)  # the second pass names a bad sample
        # Its bound is scaled now, for this one preset: the log's times (8 bytes a sample) need
        # not stay through the streamed pass, beside another file's on a second thread.
        return replace(found, times=None)
    t_start = 0.0
    if si.get("bias_duration") is not None:  # counts from the first sample
        t_start = next((float(t[0]) for t, _ in chunks() if len(t)), 0.0)
    if _window_beyond_time(si, t_start) and not all(times_ok(t) for t, _ in itertools.islice(chunks(), 1)):
        return _no_plan(si)
    try:
        return plan(preset, si, t_start, lambda window, how: measure_rest(chunks(), window, how), lambda: Found([]),
                    None, options)
    except RestWindowError:
        if _times_ok_across(chunks()):
            raise
        # Times out of order: the window was judged on them ("the log runs from 19.99 to 0 s" of a
        # log in reverse); the second pass names the bad sample, with the file and line.
        return _no_plan(si)


def _times_ok_across(chunks: Iterable[tuple[FloatArray, FloatArray]]) -> bool:
    """Whether the times of ``chunks`` are usable (:func:`times_ok`) and go on increasing from one
    chunk to the next."""
    last = -math.inf
    for t, _ in chunks:
        if len(t) and (not times_ok(t) or t[0] <= last):
            return False
        last = float(t[-1]) if len(t) else last
    return True


@whole_log_steps()  # one series given at once: no stream's clock to restart
def process_log(
    t: ArrayLike,
    rate: ArrayLike,
    preset: str,
    *,
    mode: str = "whole",
    temperature: ArrayLike | None = None,
    speed: ArrayLike | None = None,
    speed_t: ArrayLike | None = None,
    outputs: tuple[str, ...] = ALL_OUTPUTS,
    fixes: FixesLike | None = None,
    fusion: dict[str, float] | None = None,
    out: OutArrays | None = None,
    **overrides: Any,
) -> HeadingResult:
    """:func:`gyrocore.process` (see there and the module doc); in whole mode ``bias_walk``,
    ``min_rest``, ``bias_sigmas`` and ``hdr_bound_walk`` change :class:`Options`. In causal mode a ``speed`` feeds
    the core's rest tracker (``track_rests=True``), which whole mode refuses: it already uses every
    rest of the log."""
    check_mode(mode)
    refuse_speed_t_alone(speed, speed_t)
    refuse_window_objects(overrides)
    si = _to_si(overrides)
    # a whole log is known to end here, as a stream is not: one of no usable reading has no heading
    refuse_no_usable_reading(as_float_array("rate", rate, masked=MASKED_AS_NONFINITE, unit="rad/s"), si.get("nonfinite"))
    if mode == "causal":
        refuse_whole_options(si)
        checked = None if fixes is None else _checked(fixes)
        pipeline = Pipeline(preset, fusion=fusion if checked is not None else None, **overrides)
        pipeline._fixes.said_by_whole_log()  # the checks below say these, of every fix
        result = pipeline.process(
            t, rate, temperature=temperature, outputs=outputs, speed=speed, speed_t=speed_t, fixes=checked, out=out
        )
        pipeline.finish()
        if checked is not None and result.fusion is not None:
            from .fixes_warnings import warn_whole_log  # as fuse warns for a whole log (the smoothed fix stage's)

            warn_whole_log(result.t, as_float_array("rate", rate, unit="rad/s"), checked, result.fusion.counts)
        return replace(result, bias_source=causal_source(preset, si))
    refuse_tracking(si)
    options = Options.pop(si)
    ta, ra = as_float_array("t", t), as_float_array("rate", rate, unit="rad/s")
    windowed = _bias_source(si) in ("bias_window", "bias_duration")
    if windowed:
        # A whole log's bad time comes first (as a window beyond +-2^40 s, epoch ns read as s, is no
        # window to measure): the core met the rest window before a bad time after it (a log in
        # reverse: "the bias window [0, 1] s holds no sample of the samples from t = 29.99 to 29.99 s").
        require_times(ta)
    check_parameters(preset, si)
    sp = None if speed is None else as_float_array("speed", speed, unit="m/s") if speed_t is None else speed_on(ta, speed_t, speed)
    if sp is not None and len(sp) != len(ta):
        raise ValueError(f"speed has {len(sp)} samples but t has {len(ta)}: give one speed per gyro sample")
    if sp is not None and (i := first_infinite(sp)) is not None:  # as the causal mode's tracker refuses it
        raise ValueError(f"speed[{i}] is {sp[i]}: give a finite speed [m/s], or NaN where it is unknown")
    inputs = {"t": (t, ta), "rate": (rate, ra), "temperature": (temperature,), "speed": (speed, sp)}
    arrays = out_arrays(out, outputs, len(ta), inputs)  # checked before any work
    given = fixes is None and (not uses_static_bias(preset) or _bias_source(si) == "bias")
    # times a window's check passed are not checked again (a pass over the log)
    if given or len(ta) != len(ra) or len(ta) == 0 or not (windowed or times_ok(ta)):
        # A given bias (or none to remove) and no fixes need no plan: the log goes to the pipeline
        # as it is, with no pass over it here (what plan() would give). Bad times: the pipeline is
        # the one place that names the bad sample (and gives an empty log back).
        result = Pipeline(preset, **untracked(si)).process(ta, ra, temperature=temperature, outputs=outputs, out=out)
        return replace(result, bias_source=causal_source(preset, si))
    try:
        bias_plan = plan_arrays(preset, si, ta, ra, sp, options)
    except SampleError:
        # A rest's measurement saw a slice of the log: the pipeline names the sample in the log.
        Pipeline(preset, **without_bias(si)).process(ta, ra, temperature=temperature)
        raise
    pipeline, corrected = bias_plan.pipeline(preset), bias_plan.corrected(ta, ra)
    if fixes is None:
        result = pipeline.process(ta, corrected, temperature=temperature, outputs=outputs, out=out)
    else:
        from .fixes import smoothed_stage, stage_settings  # the fix stage over the whole log

        result = pipeline.process(ta, corrected, temperature=temperature, outputs=(*outputs, "rate"))
        result = filled(smoothed_stage(result, fixes, stage_settings(pipeline.params, fusion), outputs), arrays)
    if bias_plan.warning:  # after the run: a log the pipeline refuses (a NaN temperature) warned before its error
        warn(bias_plan.warning)
    return bias_plan.result(result)


def _checked(fixes: FixesLike) -> Fixes:
    """A whole log's fixes, every one checked, not only those its samples reach
    (:func:`gyrocore.fixes.check_all`; imported here, as :mod:`gyrocore.fixes` builds on this module)."""
    from .fixes import check_all

    return check_all(fixes)


def times_ok(t: FloatArray) -> bool:
    """Whether the core takes the times ``t``: finite, strictly increasing, within +-2^40 s
    (:func:`~gyrocore._checks.require_times`, the core's own rule; otherwise the pipeline refuses
    them, naming the sample; a rest found among epoch nanoseconds read as seconds was a rest
    window the core refused by its own limit, without the unit's hint)."""
    try:
        require_times(t)
    except SampleError:
        return False
    return True

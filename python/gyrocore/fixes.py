"""Absolute heading fixes fused with the gyro: heading, bias and scale estimated online.

A fix is ``(t, heading, sigma)``: time [s] on the gyro's clock, heading [rad, counter-clockwise
from east, as the logs' ``reference.csv``] and its standard deviation [rad]. Fixes come from a
GNSS receiver's course over ground (:func:`from_gnss`, :func:`read_gnss_csv`), a log folder's
``fixes.csv`` (:func:`read_fixes_csv`), or a simulated receiver (:func:`gyrocore.sim.gnss_fixes`).

:func:`fuse` runs the core's 3-state Kalman filter (heading, and Hong eq 3's scale and bias: the
recursive form of Hong eq 4-7's least squares) over a whole log, causal or smoothed
(Rauch-Tung-Striebel); :class:`Fusion` is the same filter for a stream, bit-identical however the
stream is cut, and picklable. The noise settings are the gyro's Allan parameters: ``arw`` (N,
rad/sqrt(s)) and ``bias_walk`` (rate random walk K, rad/s/sqrt(s)); see docs/fixes_model.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, Literal, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from . import _gyrocore
from ._arrays import (
    READ_GNSS, READ_WITH_FIXES, FloatArray, array_fields, as_float_array, float_fields, no_path_for_arrays,
)
from ._checks import (
    MAX_READING, check_number, did_you_mean, public_dir, real_number, require_finite, require_increasing,
    require_radians, warn, warn_units,
)
from ._inuse import Turn, one_at_a_time
from ._time_steps import name_time_step, time_steps_named
from .result import fix_output_flags
from .fixes_stream import TWICE, StreamFixes, say_how_to_wait
from .fixes_warnings import MIN_SHARE_INSIDE, warn_whole_log

if TYPE_CHECKING:
    from .pipeline import HeadingResult

#: The largest magnitude of a fix's heading [rad], the core's limit of a fix heading as of a reading
#: (2^20): headings may be continuous (unwrapped), but one beyond this is another unit or a corrupt
#: value, and the filter's wrapped innovation would lose its precision (at 2^20 rad a double still
#: resolves 2e-10 rad).
MAX_HEADING = MAX_READING
#: A median fix sigma at or above this [rad] (29 deg) is warned about: more likely degrees than a
#: fix anyone would give.
VAGUE_SIGMA = 0.5

#: The filter's settings (defaults: the core's ``FusionConfig::default``); what each is, with its
#: unit: ``dict(_gyrocore.fusion_setting_names())``.
SETTINGS = tuple(name for name, _ in _gyrocore.fusion_setting_names())


@dataclass(frozen=True, repr=False, eq=False)
class Fixes:
    """Absolute headings: times [s], headings [rad, CCW from east], standard deviations [rad].

    A heading beyond +-:data:`MAX_HEADING` is an error when the fixes are built; NaN, ``sigma <= 0``
    and the time order are checked by the filter, for the fixes it reaches (docs/fixes_model.md)."""

    t: FloatArray
    heading: FloatArray
    sigma: FloatArray

    def __post_init__(self) -> None:
        # lists, text and pandas columns, as Fixes.of; copied: the caller's array changed later (a heading
        # beyond MAX_HEADING, times out of order) would pass into the filter unchecked
        float_fields(self, ("t", "heading", "sigma"), "fix ", copy=True, units={"heading": "rad", "sigma": "rad"})
        if not (len(self.t) == len(self.heading) == len(self.sigma)):
            raise ValueError(f"fix t, heading and sigma must have one length, got {len(self.t)}, "
                             f"{len(self.heading)} and {len(self.sigma)}")
        far = np.flatnonzero(np.abs(self.heading) > MAX_HEADING)  # NaN is not beyond: the filter names it
        if len(far):
            i = int(far[0])
            raise ValueError(f"fix {i}: heading = {float(self.heading[i])!r} is beyond +-2^20 rad ({MAX_HEADING:.0f}); "
                             "headings are in rad, counter-clockwise from east (wrapped or continuous): check the "
                             "column and unit")
        # Degrees read as radians turn the heading 57 times too far, and the outlier gate rejects
        # fix after fix: the wrap at +-180 (or 0/360) gives them away.
        require_radians("the fixes' heading", self.t, self.heading)

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return f"Fixes({len(self)} fixes)"

    @classmethod
    def of(cls, t: ArrayLike, heading: ArrayLike, sigma: ArrayLike | float) -> Fixes:
        """Fixes from arrays (``sigma`` may be one number for all)."""
        tt = as_float_array("fix t", t)
        # one number for all is checked like an array (an int becomes float, a bool is refused)
        s = as_float_array("fix sigma", np.full(len(tt), sigma) if np.ndim(sigma) == 0 else sigma, unit="rad")
        return cls(tt, as_float_array("fix heading", heading, unit="rad"), s)._warn_if_vague()

    def _warn_if_vague(self) -> Fixes:
        """These fixes, after a warning if their median sigma is :data:`VAGUE_SIGMA` or more: given
        sigmas of a few units are more likely degrees than fixes that vague (the ones
        :func:`from_positions` computes from short steps may be, and are not checked)."""
        sigma = float(np.nanmedian(self.sigma)) if len(self.sigma) else 0.0
        if sigma >= VAGUE_SIGMA:
            warn(f"the fixes' sigma is {sigma:.6g} rad ({math.degrees(sigma):.3g} deg) at the median: a fix that vague "
                 "barely moves the heading; sigmas are in rad (if they were written in degrees, convert them with "
                 "numpy.radians)")
        return self

    @classmethod
    def empty(cls) -> Fixes:
        """No fixes."""
        return cls.of([], [], [])


@dataclass(frozen=True, repr=False, eq=False)
class FusionResult:
    """Per gyro sample: heading [rad, continuous], its standard deviation [rad], bias [rad/s,
    what the gyro reads at rest] and scale error (Hong eq 1: the gyro reads ``(1 + s) r + b``).
    From a pipeline's fix stage, a column that ``outputs=`` left out (``heading_sigma``,
    ``fusion_bias``, ``fusion_scale``) is None: it was never computed."""

    t: FloatArray
    heading: FloatArray
    heading_sigma: FloatArray | None
    bias: FloatArray | None
    scale: FloatArray | None
    counts: dict[str, int]
    """Fixes ``applied``, ``rejected`` by the outlier gate, ``readmitted`` (of those applied, the ones
    applied after the gate had rejected every fix for ``readmit_after`` seconds: the filter had
    been surer of itself than the fixes allowed), ``before_start`` (before the first gyro
    sample: skipped) and, from :func:`fuse` and whole mode's smoother, ``after_end`` (after the
    last: unused) or, from a stream and causal mode (a :class:`~gyrocore.Pipeline`), ``waiting``
    (past the last sample processed, for a later block). A stream's counts are its totals since
    its first block (a pickle keeps them), not the block's own."""

    def __repr__(self) -> str:
        return f"FusionResult({len(self.t)} samples, fixes {self.counts})"

    def columns(self) -> dict[str, FloatArray]:
        """The per-sample arrays by name, those computed (``t`` [s], ``heading``, ``heading_sigma``
        [rad], ``bias`` [rad/s], ``scale`` [1]), not copies: ``pandas.DataFrame(fused.columns())``."""
        return array_fields(self)


@no_path_for_arrays("gyrocore.fuse", READ_WITH_FIXES)
def fuse(t: ArrayLike, rate: ArrayLike, fixes: FixesLike, *, mode: Literal["causal", "smoothed"] = "causal",
         **settings: float) -> FusionResult:
    """Heading, bias and scale of a whole log from its gyro and its fixes.

    Args:
        t: gyro times [s], strictly increasing.
        rate: gyro readings [rad/s], counter-clockwise positive.
        fixes: the absolute headings (:data:`FixesLike`; sorted by time; NaN, sigma <= 0 or a step back is an error
            naming the fix; fixes before the first gyro sample are counted and skipped, and a warning
            says so when under a tenth of them fall within the gyro's time span).
        mode: ``"causal"`` (each sample sees the fixes up to its time) or ``"smoothed"`` (the
            Rauch-Tung-Striebel smoother: each sees all fixes; whole logs only).
        settings: filter settings (:data:`SETTINGS`), SI units.
    """
    if mode not in ("causal", "smoothed"):
        raise ValueError(f"mode must be 'causal' or 'smoothed', got {mode!r}")
    tt, r = as_float_array("t", t, copy=True), as_float_array("rate", rate, unit="rad/s")  # the result's t: its own
    warn_units(tt, r)  # as gyrocore.process warns: ms times or deg/s rates gave fixes rejected one after another
    return _fused(tt, r, as_fixes(fixes), settings, mode == "smoothed")


def _fused(t: FloatArray, rate: FloatArray, fixes: Fixes, settings: dict[str, float], smoothed: bool) -> FusionResult:
    """:func:`fuse` of arrays already read (a pipeline's corrected rate, whose readings it judged)."""
    with time_steps_named(t):  # a counter's wrap, a clock set back: not mended by sorting
        h, s, b, sc, counts = _gyrocore.fuse(t, rate, fixes.t, fixes.heading, fixes.sigma, _settings(settings), smoothed)
    warn_whole_log(t, rate, fixes, counts)
    return FusionResult(t, h, s, b, sc, dict(counts))


def counts_dict(counts: tuple[int, int, int, int, int]) -> dict[str, int]:
    """A stream's fix counts, ``(applied, rejected, readmitted, before_start, waiting)``, by name."""
    return dict(zip(("applied", "rejected", "readmitted", "before_start", "waiting"), counts))


def _settings(settings: dict[str, float]) -> dict[str, float]:
    unknown = sorted(set(settings) - set(SETTINGS))
    if unknown:
        said = ", ".join(f"{n}{did_you_mean(n, SETTINGS)}" for n in unknown)
        raise TypeError(f"unknown fusion setting(s) {said}; choose from {', '.join(SETTINGS)}")
    numbers = {name: real_number(value) for name, value in settings.items()}  # an int beyond float64: inf
    for name, x in numbers.items():
        if x is None:
            raise TypeError(f"fusion setting {name} = {settings[name]!r}: must be a number (SI units, docs/fixes_model.md)")
    return {k: float(v) for k, v in numbers.items() if v is not None}


class Fusion:
    """The filter for a stream: ``process(t, rate, fixes)`` per block, the fixes of a block given
    with it or earlier (fixes past the block's last sample wait for the next block; give each fix
    once). Chunked runs and pickled copies are bit-identical to one call."""

    def __init__(self, **settings: float) -> None:
        self._turn = Turn()
        self._inner = _gyrocore.Fusion(_settings(settings))
        self._fixes = StreamFixes()

    @no_path_for_arrays("gyrocore.fixes.Fusion.process", READ_WITH_FIXES)
    @one_at_a_time
    def process(self, t: ArrayLike, rate: ArrayLike, fixes: FixesLike | None = None) -> FusionResult:
        """Processes one block (``fixes``: :data:`FixesLike`, as every entry point takes them);
        returns the estimate after each of its samples. A fix before one given with an earlier
        block that still waits is an error (the fixes were given again)."""
        f = Fixes.empty() if fixes is None else as_fixes(fixes)
        tt, r = as_float_array("t", t, copy=True), as_float_array("rate", rate, unit="rad/s")  # the result's t: its own
        f = self._fixes.check(f, waits=counts_dict(self._inner.counts())["waiting"] > 0)
        try:
            h, s, b, sc = self._inner.process(tt, r, f.t, f.heading, f.sigma)
        except ValueError as e:
            say_how_to_wait(e)
            if isinstance(e, _gyrocore.SampleError):  # a counter's wrap, a clock set back within the block
                name_time_step(e, tt, None, 0)
            raise
        self._fixes.taken(f, float(tt[-1]) if len(tt) else None)
        counts = self.counts()
        self._fixes.judge(counts)
        return FusionResult(tt, h, s, b, sc, counts)

    @one_at_a_time
    def check(self, fixes: FixesLike) -> None:
        """Raises the error of the first bad fix among the waiting ones and ``fixes``, every one,
        processing nothing (:meth:`process` checks those its block reaches, and the first past it:
        a bad fix further on fails the block that reaches it)."""
        f = as_fixes(fixes)
        self._inner.check(f.t, f.heading, f.sigma)

    @one_at_a_time
    def restart_clock(self) -> int:
        """Go on after the gyro's clock jumped back, which :meth:`process` refuses naming this (see
        :meth:`gyrocore.Pipeline.restart_clock`): the estimate and its covariance are kept, no time passing
        across the jump. Returns how many waiting fixes it dropped (on the old clock; with a warning)."""
        dropped = self._inner.restart_clock()
        if dropped is not None:  # None before the first sample: nothing to restart
            self._fixes.restarted(dropped)
        return dropped or 0

    @one_at_a_time
    def counts(self) -> dict[str, int]:
        """Fixes applied, rejected, readmitted, before_start, and waiting for a later block."""
        return counts_dict(self._inner.counts())

    @one_at_a_time
    def settings(self) -> dict[str, float]:
        """The filter's settings."""
        return dict(self._inner.settings())

    @one_at_a_time
    def __getstate__(self) -> dict[str, Any]:
        return {"state": self._inner.state_json(), **self._fixes.kept()}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self._turn = Turn()  # a copy's own: it is another stream
        self._inner = _gyrocore.Fusion.from_state_json(state["state"])
        self._fixes = StreamFixes.restored(state)

    #: What a filter is, in the words of a call refused while another thread's runs.
    _in_use_name = "this gyrocore.fixes.Fusion"

    def __repr__(self) -> str:
        if self._turn.busy():  # its state is out of reach while the other call runs
            return "Fusion(in use by another thread)"
        # a stream under way shows what its fixes did: it printed as a bare object
        return f"Fusion(settings={self.settings()!r}, counts={self.counts()!r})"


def stage_settings(params: dict[str, Any], settings: dict[str, float] | None) -> dict[str, float]:
    """The fix stage's settings in a pipeline with the parameters ``params``: it starts from the
    pipeline's initial heading unless ``settings`` say otherwise (an unknown name is a TypeError)."""
    if settings is not None and not isinstance(settings, Mapping):  # "'str' object is not a mapping"
        raise TypeError(f"fusion must be a dict of the fix stage's settings ({', '.join(SETTINGS)}), got "
                        f"{type(settings).__name__} {settings!r}")
    return _settings({"initial_heading": float(params["initial_heading"]), **(settings or {})})


Estimate = tuple[float, float, float, float]
"""One row of a :class:`FusionResult`: heading, heading_sigma, bias, scale."""
_COLUMNS = ("heading", "heading_sigma", "bias", "scale")


def _prior(fusion: Fusion) -> Estimate:
    """The estimate before any sample: the filter's initial heading, its sigma, its initial bias and
    a scale error of 0 (the :data:`Estimate` columns)."""
    s = fusion.settings()
    return s["initial_heading"], s["initial_heading_sigma"], s["initial_bias"], 0.0


def _on_kept(run: Callable[[FloatArray, FloatArray], FusionResult], t: FloatArray, rate: FloatArray,
             before: Estimate) -> FusionResult:
    """``run`` over the samples a pipeline kept: one it skipped (``nonfinite="skip"``: its rate is
    NaN) is left out of the filter, and its row repeats the estimate before it (``before`` ahead
    of the block's first kept sample), as the pipeline's own row repeats its heading."""
    kept = np.isfinite(rate)
    if kept.all():
        return run(t, rate)
    part = run(t[kept], rate[kept])
    at = np.cumsum(kept)  # 1 + the kept sample at or before each row; 0 before the first
    h, s, b, sc = (np.concatenate(([first], getattr(part, name)))[at] for name, first in zip(_COLUMNS, before))
    return FusionResult(t, h, s, b, sc, part.counts)


def smoothed_stage(result: HeadingResult, fixes: FixesLike, settings: dict[str, float],
                   outputs: tuple[str, ...]) -> HeadingResult:
    """The fix stage of a whole log: the smoother over the pipeline's corrected rate (``result``
    computed with the ``rate`` output); ``outputs`` are the ones the caller asked for (the smoother
    computes the whole state of each sample: the columns left out are dropped)."""
    if result.rate is None:
        raise ValueError("the fix stage needs the pipeline's rate output")
    given = as_fixes(fixes)
    fused = _on_kept(lambda tt, rr: _fused(tt, rr, given, settings, True), result.t, result.rate,
                     _prior(Fusion(**settings)))
    sigma, bias, scale = (column if wanted else None for column, wanted in
                          zip((fused.heading_sigma, fused.bias, fused.scale), fix_output_flags(outputs)))
    fused = replace(fused, heading_sigma=sigma, bias=bias, scale=scale)
    return replace(result, heading=fused.heading, rate=result.rate if "rate" in outputs else None,
                   heading_sigma=sigma, fusion=fused)


@no_path_for_arrays("gyrocore.fixes.from_gnss", READ_GNSS)
def from_gnss(t: ArrayLike, bearing_deg: ArrayLike, speed: ArrayLike, *, min_speed: float = 2.0,
              speed_sigma: float = 0.2, min_sigma_deg: float = 0.5) -> Fixes:
    """Fixes from a GNSS receiver's course over ground.

    The bearing is clockwise from north [deg]; the project's heading is counter-clockwise from
    east, so ``heading = pi/2 - radians(bearing)``. Course over ground is the direction of the
    velocity, so its error grows as the speed falls: ``sigma = hypot(min_sigma, speed_sigma /
    speed)`` [rad] for a velocity error ``speed_sigma`` [m/s]; below ``min_speed`` [m/s] the
    course is meaningless (a car at rest has none) and the sample is dropped, as is one without a
    bearing (NaN). Assumes the vehicle moves the way it points (no side slip, forward gear).

    A time that is not finite or not after the one before, a speed that is negative, NaN or
    infinite, or a bearing that is infinite or beyond +-2^20 deg, is an error naming its index;
    samples that give no fix at all warn why (an :class:`~gyrocore.InputWarning` with the speeds
    seen).
    """
    tt = as_float_array("t", t)
    bearing = as_float_array("bearing_deg", bearing_deg, unit="deg")
    v = as_float_array("speed", speed, unit="m/s")
    if not (len(tt) == len(bearing) == len(v)):
        raise ValueError(f"t, bearing_deg and speed must have one length, got {len(tt)}, {len(bearing)}, {len(v)}")
    min_speed, speed_sigma, min_sigma_deg = (check_number(name, value) for name, value in (
        ("min_speed", min_speed), ("speed_sigma", speed_sigma), ("min_sigma_deg", min_sigma_deg)))
    # checked here, by the sample's own index: the filter would name a bad time by its place
    # among the fixes kept, after the slow and course-less samples were dropped
    require_finite("t", tt)
    require_increasing("t", tt)
    bad = np.flatnonzero(~(v >= 0) | np.isinf(v))  # ~(v >= 0): negative or NaN
    if len(bad):
        i = int(bad[0])
        raise ValueError(f"speed[{i}] is {v[i]}: a speed over ground is finite and >= 0 [m/s]; drop or repair the "
                         "sample")
    # NaN is a sample without a course (dropped); an infinite or huge bearing is a corrupt value,
    # which wrapped into an arbitrary heading or was dropped as if it were NaN
    far = np.flatnonzero(np.abs(bearing) > MAX_HEADING)
    if len(far):
        i = int(far[0])
        raise ValueError(f"bearing_deg[{i}] is {bearing[i]}: beyond +-2^20 deg; a course over ground is in degrees "
                         "clockwise from north (NaN where there is none); drop or repair the sample")
    course = np.isfinite(bearing)
    keep = course & (v >= min_speed)
    if len(tt) and not keep.any():
        warn_no_fix(f"{len(tt)} GNSS samples", v[course], min_speed)
    sigma = np.hypot(math.radians(min_sigma_deg), speed_sigma / v[keep])
    return Fixes(tt[keep], heading_of_bearing(bearing[keep]), sigma)


def heading_of_bearing(bearing_deg: FloatArray) -> FloatArray:
    """Headings [rad, counter-clockwise from east, wrapped to +-pi] of bearings [deg, clockwise
    from north]: ``pi/2 - radians(bearing)``, a course over ground's or a true heading's (HDT)."""
    heading: FloatArray = np.angle(np.exp(1j * (math.pi / 2 - np.radians(bearing_deg))))
    return heading


def warn_no_fix(given: str, speeds: FloatArray, min_speed: float) -> None:
    """Warns that ``given`` (``"58 GNSS samples"``) gave no fix, and why: ``speeds`` [m/s] are those
    of the samples or steps that had a course, every one below ``min_speed``, or none."""
    if len(speeds):
        why = (f"every speed is below min_speed = {min_speed:g} m/s (speeds from {speeds.min():.3g} to "
               f"{speeds.max():.3g} m/s): too slow for a course; check the units (speeds in m/s, positions in m, "
               "times in s), or lower min_speed")
    else:
        why = "none has a course (every bearing or position is NaN)"
    warn(f"no heading fix from {given}: {why}")


#: What may be given as fixes: :class:`Fixes`, a fixes file, or ``(t, heading, sigma)`` arrays.
FixesLike: TypeAlias = Fixes | str | Path | tuple[ArrayLike, ArrayLike, ArrayLike]


def check_all(fixes: FixesLike) -> Fixes:
    """``fixes`` as :class:`Fixes`, every one checked (NaN, ``sigma <= 0``, out of time order): a
    whole log's fixes are checked at once, those after its last sample too, where a stream's block
    checks the ones it reaches."""
    checked = as_fixes(fixes)
    Fusion().check(checked)
    return checked


def as_fixes(fixes: FixesLike) -> Fixes:
    """``fixes`` as :class:`Fixes` (a path is read by :func:`read_fixes_file`), without a fix that
    repeats the one before it (:func:`without_repeats`)."""
    return without_repeats(_given(fixes))


def without_repeats(fixes: Fixes) -> Fixes:
    """``fixes`` without each fix that repeats the one before it exactly (time, heading and sigma),
    after a warning: it is one measurement written twice, and counted twice it weighs as a fix of
    sigma / sqrt(2), tighter than it is (kitti_2011_09_30_0020_mems with every fix twice: the gate
    rejected 168 of 230, the heading 17.6 deg off). Two fixes at one time that differ (two
    receivers) are both kept."""
    same = (np.diff(fixes.t) == 0) & (np.diff(fixes.heading) == 0) & (np.diff(fixes.sigma) == 0)
    repeat = 1 + np.flatnonzero(same)
    if not len(repeat):
        return fixes
    first = int(repeat[0])
    warn(f"{len(repeat)} heading fix(es) repeat the fix before them exactly (the first: fix {first} at t = "
         f"{float(fixes.t[first])!r} s) and are dropped: {TWICE}")
    keep = np.ones(len(fixes), dtype=bool)
    keep[repeat] = False
    return Fixes(fixes.t[keep], fixes.heading[keep], fixes.sigma[keep])


def _given(fixes: FixesLike) -> Fixes:
    """``fixes`` as :class:`Fixes`, as given."""
    if isinstance(fixes, Fixes):
        return fixes
    if isinstance(fixes, (str, Path)):
        return read_fixes_file(fixes)
    if isinstance(fixes, tuple) and len(fixes) == 3:
        return Fixes.of(*fixes)
    raise TypeError(f"fixes must be gyrocore.fixes.Fixes, a fixes file or a (t, heading, sigma) tuple, "
                    f"got {type(fixes).__name__}")


# Fixes from a track of positions, from NMEA sentences and from fix files live in their own
# modules, which build on Fixes, from_gnss and check_all above.
from .fixes_track import from_latlon, from_positions  # noqa: E402
from .fixes_nmea import KMH, KNOT, read_nmea  # noqa: E402
from .fixes_files import FIXES_COLUMNS, GNSS_COLUMNS, read_fixes_csv, read_fixes_file, read_gnss_csv  # noqa: E402

# The pipeline's own helpers of the fix stage (stage_settings, smoothed_stage, the warnings and
# refusals of a stream's fixes) are imported by name where they are used, and are not listed.
__all__ = [
    "FIXES_COLUMNS", "GNSS_COLUMNS", "KMH", "KNOT", "MAX_HEADING", "SETTINGS", "Fixes", "FixesLike", "Fusion", "FusionResult",
    "MIN_SHARE_INSIDE", "as_fixes", "check_all", "from_gnss", "from_latlon", "from_positions", "fuse", "read_fixes_csv", "read_fixes_file",
    "read_gnss_csv", "read_nmea",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

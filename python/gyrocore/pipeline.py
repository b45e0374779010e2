"""The heading pipeline: presets, streaming :class:`Pipeline`, :func:`process` and :func:`integrate`.

Units are SI at every API: seconds, rad, rad/s, counter-clockwise positive. Rate parameters also
accept a degree-per-second spelling with a ``_dps`` suffix (``threshold_dps=0.3``), and
``initial_heading_deg`` is the degree spelling of ``initial_heading``. The presets and the
parameters' names, spellings and checks are in :mod:`gyrocore.pipeline_params`, whose public names
this module re-exports.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from . import _gyrocore, rests
from ._arrays import (
    MASKED_AS_NONFINITE, READ_AND_PROCESS, FloatArray, as_float_array, as_float_array_owned, no_path_for_arrays,
)
from ._checks import public_dir, warn
from ._inuse import Turn, one_at_a_time
from ._motion import WindowWatch
from .fixes_stream import StreamFixes, say_how_to_wait
from .pipeline_input import (
    TEMPERATURE_MODEL, check_units, refuse_window_without_reading, say_what_to_do, warn_repairs, warn_speed_outside,
)
from .pipeline_params import (
    BIAS_SOURCES,
    _to_si,
    core_pipeline,
    has_bias_source,
    implausible_bias,
    parameters,
    preset_names,
    preset_params,
    recommended_preset,
    unmeasured_bias,
    uses_static_bias,
)
from .process_arrays import process as process
from .result import ALL_OUTPUTS as ALL_OUTPUTS, OUTPUTS as OUTPUTS, Filled, HeadingResult as HeadingResult
from .result import OutArrays, fix_output_flags, out_arrays, output_flags as output_flags
from .rests import Rest
from .window import (
    MIN_WINDOW_READINGS,
    RestWindowError,
    refuse_few_readings,
    refuse_start_before,
    refuse_unfinished,
    refuse_window_objects,
    rest_window_text,
    window_span,
)

if TYPE_CHECKING:
    from .fixes import Fixes, FixesLike

__all__ = [
    "ALL_OUTPUTS", "BIAS_SOURCES", "MIN_WINDOW_READINGS", "OUTPUTS", "TEMPERATURE_MODEL", "HeadingResult", "Pipeline",
    "RestWindowError", "core_pipeline", "has_bias_source", "implausible_bias", "output_flags", "parameters",
    "preset_names", "preset_params", "process", "recommended_preset", "refuse_few_readings", "refuse_start_before",
    "rest_window_text", "unmeasured_bias", "uses_static_bias",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

#: The fix stage's columns of a block from the core: heading sigma, bias, scale, and the fix
#: counts (applied, rejected, re-admitted, before the first sample, waiting for a later block).
_Fused = tuple[FloatArray | None, FloatArray | None, FloatArray | None, tuple[int, int, int, int, int]]

#: :meth:`Pipeline.process`'s ``index_offset`` is below this: any index of a chunk added to it fits
#: the core's 64-bit index.
MAX_INDEX = 2**63


class Pipeline:
    """Streaming heading pipeline (correction -> threshold -> low-pass -> HDR -> de-lag -> integrate).

    ``process`` may be called chunk after chunk: the output is bit-identical to one call over the
    whole log. Pickling keeps the full state, so a pipeline can be stopped and resumed.

    Args:
        preset: ``raw``, ``static_bias``, ``hong_park``, ``hdr``, ``combined``, ``tuned``, ``tracked``
            or ``recommended`` (the default, as for :func:`process`, ``Log.process`` and the
            command line).
        fusion: settings of the heading-fix stage (:data:`gyrocore.fixes.SETTINGS`, ``{}``: defaults),
            run last on the corrected rate from the first sample; without it, fixes start the stage
            only in the first block (docs/fixes_results.md).
        **overrides: parameters to change (see :func:`parameters`), e.g. ``bias_window=(t0, t1)``,
            ``bias=0.01`` [rad/s], ``threshold_dps=0.3``, ``hdr_increment=...``.

    Raises:
        ValueError: an unknown preset or parameter, or a parameter's value the core refuses.
        TypeError: a preset that is no name; a parameter of the wrong type (text for a number, a
            bool for anything but the switches ``delag``, ``hdr`` and ``track_rests``).

    Warns:
        InputWarning: a preset that removes a static bias given none (no ``bias``, ``bias_window``
            or ``bias_duration``), once, as its first samples are processed (a first chunk that is
            refused warns of nothing).
    """

    def __init__(
        self, preset: str = "recommended", *, fusion: dict[str, float] | None = None, **overrides: Any
    ) -> None:
        self._turn = Turn()
        refuse_window_objects(overrides)
        si = _to_si(overrides)
        self._inner = core_pipeline(preset, si)
        if (implausible := implausible_bias(si)) is not None:
            warn(implausible)
        self._preset = preset
        if fusion is not None:
            from .fixes import stage_settings  # it reads files through gyrocore.io, which builds on this module

            self._inner.start_fusion(stage_settings(self.params, fusion))
        # Said once the first samples are processed, not here: a run whose first chunk is refused
        # (a NaN reading, times out of order) warned of a bias it never used before its error.
        self._bias_warning = unmeasured_bias(preset, si)
        self._start_stream()

    def _start_stream(self) -> None:
        """What this wrapper keeps of a stream, as before its first sample (the core's own state
        apart): a new pipeline and :meth:`reset` start from here, and warn again as a new one does."""
        # the first samples, held until the unit check has an interval to judge (None once done)
        self._unit_head: tuple[FloatArray, FloatArray] | None = (np.empty(0), np.empty(0))
        self._first_time: float | None = None  # of the log, for the range :meth:`finish` names
        # where the core's rest times (the intervals taken) start on the clock, and those up to a restart
        self._origin: float | None = None
        self._elapsed = 0.0
        self._rests: list[Rest] = []
        self._fixes = StreamFixes()
        self._speed_said = False  # a chunk's samples outside its speed's times, said once
        self._repairs_said: set[str] = set()  # the input policies whose repairs, and the gaps, were said (once each)
        self._watch = self._new_watch()
        self._unmeasured = self._bias_warning  # None once said

    @property
    def preset(self) -> str:
        """The preset this pipeline started from."""
        return self._preset

    @property
    @one_at_a_time
    def params(self) -> dict[str, Any]:
        """The full flat SI parameter set in use."""
        return dict(self._inner.params())

    @property
    @one_at_a_time
    def bias(self) -> float:
        """The static bias in use now [rad/s] (what the gyro reads at rest)."""
        return float(self._inner.bias()[0])

    @no_path_for_arrays("gyrocore.Pipeline.process", READ_AND_PROCESS)
    @one_at_a_time
    def process(
        self,
        t: ArrayLike,
        rate: ArrayLike,
        *,
        temperature: ArrayLike | None = None,
        index_offset: int = 0,
        outputs: tuple[str, ...] = ALL_OUTPUTS,
        speed: ArrayLike | None = None,
        speed_t: ArrayLike | None = None,
        fixes: FixesLike | None = None,
        out: OutArrays | None = None,
    ) -> HeadingResult:
        """Process the next chunk of samples.

        Args:
            t: timestamps [s], strictly increasing (also across chunks).
            rate: yaw rate [rad/s], counter-clockwise positive.
            temperature: sensor temperature [degC], needed when ``temp_slope``/``temp_offset`` are set.
            index_offset: index of this chunk's first sample in the whole log; errors count from it.
            outputs: which of ``heading``, ``rate`` and ``drift`` to compute (the heading always),
                and with fixes which of the fix stage's :data:`gyrocore.result.FIX_OUTPUTS`
                (``heading_sigma``, ``fusion_bias``, ``fusion_scale``); the others are None and cost
                nothing: ``("heading",)`` fills one array, not three (six with fixes).
            speed: the vehicle's speed [m/s] for ``track_rests``: one per sample, or a series at its
                own times ``speed_t`` (e.g. a log folder's ``odometry.csv``), interpolated onto
                ``t``; outside its span, and without it, rests are judged by the rate alone.
            speed_t: the times [s] of ``speed``, strictly increasing, in the gyro's clock.
            fixes: absolute headings (:data:`gyrocore.fixes.FixesLike`) merged by time (those past
                this chunk wait for the next, so give each fix once; one before a processed sample or
                before a waiting one is an error); the heading is then the filter's, with
                ``heading_sigma`` and ``fusion`` (docs/fixes_results.md).
            out: arrays to fill instead of fresh ones, which the result then holds: one per name
                of ``heading``, ``rate`` and ``drift`` in ``outputs``, in that order (with
                ``outputs=("heading",)`` the array itself; the fix stage's columns are fresh),
                each float64, C-contiguous, writeable, as long as ``t`` and apart from the inputs
                and from each other. A caller that processes many logs or chunks of one length
                reuses them and so pays for no new memory: the result's ``t`` is then the caller's
                times, read-only, not a copy (without ``out`` it is the result's own). After an
                error their contents are unspecified.

        Raises:
            SampleError: (a ValueError) non-increasing or non-finite timestamps, or NaN/inf readings
                under ``nonfinite="error"``; its ``index`` and ``what`` name the first bad sample.
                A chunk that starts at or before :attr:`last_time` (sent again, or after a resume
                from a pickle that holds it already) says so: give only the samples after it; after
                a clock that jumped back, :meth:`restart_clock`.
            ValueError: mismatched lengths; timestamps whose interval overflows (near +-1e308); an
                ``index_offset`` that is no int in [0, 2^63); an ``out`` array of the wrong shape or
                layout, read-only, or sharing memory;
                :class:`RestWindowError` for a rest window that holds no sample (known once a
                reading after its end comes). Nothing of the chunk is processed after any of these.
            TypeError: non-numeric arrays; ``outputs`` that is no tuple of names (None); an ``out``
                array that is not float64.

        Warns:
            InputWarning: rates or timestamps that look like another unit, a temperature
                without a temperature model, or a rest tracker whose blocks hold fewer than two
                readings at the stream's rate (checked once the stream has two samples, however
                they were chunked; the temperature on the first chunk), readings held or skipped
                (``nonfinite="hold"/"skip"``), gaps longer than ``gap_limit``.
        """
        # below 2^63: the core adds it to an index within the chunk, which wrapped past 2^64 (2^64 - 1
        # named a bad fifth sample rate[4]) and 2^64 was a bare OverflowError
        if (isinstance(index_offset, bool) or not isinstance(index_offset, (int, np.integer))
                or not 0 <= index_offset < MAX_INDEX):
            raise ValueError(f"index_offset = {index_offset!r}: give the index of the chunk's first sample in the "
                             "whole log, an int >= 0 and below 2^63")
        # the result's t: its own copy (a chunk's times outlive a buffer the caller refills, and a
        # write to them reached the caller's), made while the core runs; with out=, which
        # allocates nothing per call, the caller's times read-only (a write through them fails)
        ta, kept_t = as_float_array_owned("t", t, copy=out is None)
        ra = as_float_array("rate", rate, masked=MASKED_AS_NONFINITE, unit="rad/s")
        temp = None if temperature is None else as_float_array("temperature", temperature, unit="degC")
        refuse_window_without_reading(self._inner, ta, ra, temp, self._first_time)
        # put back unless the core takes the chunk: a refused or interrupted (Ctrl-C) first chunk left the
        # unit check done, and the pipeline's pickle differed from the one before it
        head = self._unit_head
        try:
            if self._unit_head is not None and len(ta):
                self._unit_head = check_units(self._unit_head, ta, ra, temp, self.params)
            flags = output_flags(outputs)
            inner, fix_block = self._fixes.block_for(self._inner, fixes)
            rests.refuse_speed_t_alone(speed, speed_t)
            if speed is not None and not self.params["track_rests"]:
                raise ValueError("speed is given but rest tracking is off: pass track_rests=True, or no speed")
            sa = None if speed is None else rests.speed_at(ta, speed, speed_t)
            if speed_t is not None and sa is not None and not self._speed_said and inner.last_time() is not None:
                # not of a first chunk: one call's log may well outlast its odometry
                self._speed_said = warn_speed_outside(ta, sa, speed_t)
            inputs = {"t": (t, ta), "rate": (rate, ra), "temperature": (temperature, temp), "speed": (speed, sa)}
            given = out_arrays(out, outputs, len(ta), inputs)
            before = inner.report()
            window = None if self._watch.checked else self._window(ta)  # none once it is checked
            measuring = window is not None and inner.bias()[2]
            kept_t.start()
            try:
                heading, out_rate, drift, found, fused = self._run(
                    inner, ta, ra, temp, index_offset, (flags, fix_output_flags(outputs)), sa, fix_block, given
                )
            except _gyrocore.SampleError as e:
                say_what_to_do(e, ta, inner.last_time(), index_offset, self.params["nonfinite"])
                raise
            except ValueError as e:
                say_how_to_wait(e)
                raise
        except BaseException:
            self._unit_head = head
            kept_t.cancel()
            raise
        # kept only once the core took the chunk: the readings of a refused one, sent again mended,
        # were kept twice (a pickle of the refused pipeline differed from the one before)
        if measuring and window is not None:
            self._watch.add(window, ta, ra)
        self._inner = inner  # with the fix stage the first fixes started, now that they were good
        if fix_block is not None:
            self._fixes.taken(fix_block, inner.last_time())
        if window is not None and not inner.bias()[2]:  # the window is over
            self._watch.close(window, self.bias)
        report = dict(inner.report())
        warn_repairs(inner, before, report, ta, ra, temp, self._repairs_said)
        if self._unmeasured is not None and len(ta):
            warn(self._unmeasured)
            self._unmeasured = None
        if self._first_time is None and len(ta):
            self._first_time = float(ta[0])
        if self._origin is None and len(ta):
            self._origin = float(ta[0]) - self._elapsed
        self._rests.extend(found)
        ta = kept_t.get()
        if fused is None:
            return HeadingResult(ta, heading, out_rate, drift, tracked_rests=tuple(found), report=report)
        from .fixes import FusionResult, counts_dict

        sigma, bias, scale, stream_counts = fused
        counts = counts_dict(stream_counts)
        self._fixes.judge(counts)
        return HeadingResult(ta, heading, out_rate, drift, tracked_rests=tuple(found), heading_sigma=sigma,
                             fusion=FusionResult(ta, heading, sigma, bias, scale, counts), report=report)

    def _new_watch(self) -> WindowWatch:
        """A watch of the rest window, done already with a fixed bias (nothing to watch per chunk)."""
        p = self._inner.params()
        return WindowWatch() if p.get("bias_window") or p.get("bias_duration") else WindowWatch.restored(None)

    def _window(self, t: FloatArray) -> tuple[float, float] | None:
        """The rest window on the log's clock, once known (a ``bias_duration`` from the log's first
        sample, in ``t`` if it is the first chunk); None with a fixed bias."""
        first = self._first_time if self._first_time is not None else float(t[0]) if len(t) else None
        return window_span(self._inner.params(), first)

    def _run(
        self,
        inner: _gyrocore.Pipeline,
        t: FloatArray,
        rate: FloatArray,
        temp: FloatArray | None,
        index_offset: int,
        flags: tuple[tuple[bool, bool], tuple[bool, bool, bool]],
        speed: FloatArray | None,
        fixes: Fixes | None,
        out: Filled | None,
    ) -> tuple[FloatArray, FloatArray | None, FloatArray | None, list[Rest], _Fused | None]:
        """The core over the chunk (with the fix stage's columns where it has one; into the
        caller's arrays ``out`` where given), and the rests that ended in it (every one: the core
        hands each over as it ends)."""
        given = None if fixes is None else (fixes.t, fixes.heading, fixes.sigma)
        heading, out_rate, drift, found, fused = inner.process(t, rate, temp, index_offset, flags[0], speed, given, out,
                                                              flags[1])
        origin = self._origin if self._origin is not None else (float(t[0]) if len(t) else 0.0) - self._elapsed
        return heading, out_rate, drift, [rests.from_core(r, origin) for r in found], fused

    @property
    @one_at_a_time
    def last_time(self) -> float | None:
        """The time [s] of the last sample processed (None before the first): the next chunk
        starts after it. A pipeline resumed from a pickle holds every sample up to it, so a
        stream that restarts gives only the samples after it."""
        return self._inner.last_time()

    @property
    @one_at_a_time
    def rests(self) -> list[Rest]:
        """With ``track_rests=True``, every rest found so far, in order (see :class:`gyrocore.rests.Rest`)."""
        return list(self._rests)

    @property
    @one_at_a_time
    def tracked_bias(self) -> tuple[float, float | None] | None:
        """With ``track_rests=True``, the filtered bias [rad/s] and its standard error now [rad/s]
        (None before the first rest or rest window); None without rest tracking."""
        tracker = self._inner.rest_tracker()
        return None if tracker is None else (tracker[0], tracker[1])

    @one_at_a_time
    def finish(self) -> None:
        """Call after the last chunk of a log: raises :class:`RestWindowError` if the rest window
        reaches past the log's end (a ``bias_window`` after the log, or a ``bias_duration`` longer
        than the log), so that the bias was measured over less than asked, or not at all (0), or
        if it held fewer than :data:`MIN_WINDOW_READINGS` readings. Changes nothing.
        """
        _, count, learning = self._inner.bias()
        refuse_unfinished(self._inner.params(), self._first_time, self._inner.last_time(), count, learning)

    @one_at_a_time
    def reset(self) -> None:
        """Return to the state before the first sample (same parameters): what follows is
        checked and warned about as a new pipeline's first samples are."""
        self._inner.reset()
        self._start_stream()

    @one_at_a_time
    def restart_clock(self) -> int:
        """Go on after the clock jumped back (a time sync, a sensor's counter restarted, two logs
        stitched), which :meth:`process` refuses naming this method: the next chunk may start at any
        time, its first sample taken as the sample after a gap (``gap_action``) with no interval, so
        nothing is integrated across the jump. The heading, the bias, the tracked bias, the fix
        stage's estimate and every stage's state are kept, unlike :meth:`reset`; later rests carry
        the new clock's times. Returns how many fixes that waited for later samples it dropped (on
        the old clock; with a warning). Raises ValueError, changing nothing, while the rest window
        is measured (it lies on the old clock). Survives a pickle."""
        last = self._inner.last_time()
        dropped = self._inner.restart_clock()
        if last is not None:
            self._fixes.restarted(dropped)  # the fixes given were on the old clock
            if self._origin is not None:  # not again before the new clock's first sample
                self._elapsed, self._origin = last - self._origin, None
        return dropped

    @property
    @one_at_a_time
    def rest_statistics(self) -> dict[str, float] | None:
        """What the rest window measured besides the bias, once it is over: ``noise``, the standard
        deviation of one reading [rad/s], and ``bias_std_error``, the standard error of the static
        bias [rad/s]; None with a fixed bias, while measuring, or from too few readings. The
        ``threshold_sigmas`` and ``hdr_bound_sigmas`` parameters are in these units."""
        stats = self._inner.rest_statistics()
        return None if stats is None else {"noise": stats[0], "bias_std_error": stats[1]}

    @property
    @one_at_a_time
    def report(self) -> dict[str, float]:
        """What the input policy did so far: ``held``, ``skipped``, ``gaps``, ``longest_gap`` [s]."""
        return dict(self._inner.report())

    @one_at_a_time
    def __getstate__(self) -> dict[str, Any]:
        return {
            "preset": self._preset,
            "state": self._inner.state_json(),
            "first_time": self._first_time,
            "origin": self._origin,
            "elapsed": self._elapsed,
            "rests": self._rests,
            "unmeasured": self._unmeasured,
            "bias_warning": self._bias_warning,
            "watched": self._watch.readings,
            "repairs_said": sorted(self._repairs_said),
            **self._fixes.kept(),
            "unit_head": None if self._unit_head is None else [a.tolist() for a in self._unit_head],
        }

    def __setstate__(self, state: dict[str, Any]) -> None:
        self._turn = Turn()  # a copy's own: it is another stream
        self._preset = state["preset"]
        self._inner = _gyrocore.Pipeline.from_state_json(state["state"])
        head = state.get("unit_head", None if self._inner.last_time() is not None else ([], []))
        self._unit_head = None if head is None else (np.asarray(head[0], float), np.asarray(head[1], float))
        self._first_time = state.get("first_time")
        self._origin = state.get("origin", self._first_time)  # a pickle made before restarts existed
        self._elapsed = state.get("elapsed", 0.0)
        self._rests = list(state.get("rests", []))
        self._unmeasured = state.get("unmeasured")
        self._bias_warning = state.get("bias_warning", self._unmeasured)
        self._watch = WindowWatch.restored(state.get("watched", []))
        self._fixes = StreamFixes.restored(state)
        self._speed_said = False
        self._repairs_said = set(state.get("repairs_said", []))

    @property
    def _in_use_name(self) -> str:
        """What this pipeline is, in the words of a call refused while another thread's runs."""
        return f"this gyrocore.Pipeline (preset {self._preset!r})"

    def __repr__(self) -> str:
        if self._turn.busy():  # its parameters are out of reach while the other call runs
            return f"Pipeline(preset={self._preset!r}, in use by another thread)"
        last = self.last_time  # a stream under way refuses a chunk that starts at or before it: shown
        state = "" if last is None else f", last_time={last!r}"
        return f"Pipeline(preset={self._preset!r}, params={self.params!r}{state})"


def _stage_settings(params: dict[str, Any], settings: dict[str, float]) -> dict[str, float]:
    """The fix stage's settings (:func:`gyrocore.fixes.stage_settings`); :mod:`gyrocore.fixes` is
    imported on first use (it reads files through :mod:`gyrocore.io`, which builds on this module)."""
    from .fixes import stage_settings

    return stage_settings(params, settings)

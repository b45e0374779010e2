"""Time windows of a log: each bound in the log's own time base, or after its first sample.

A log stamped with the Unix epoch starts near 1.7e9 s, so ``20 .. 30`` holds nothing of it;
``+20 .. +30`` (a bound written with ``+``) means 20 to 30 s after the first sample, whatever the
time base. Every command that takes a window (``--window``, ``--bias-window``, ``--fit-window``)
reads it with :meth:`Window.parse`, and an empty window is reported with the log's time range.

    >>> import numpy as np
    >>> w = Window.parse(["+20", "+30"])
    >>> w.resolve(1.7e9)
    (1700000020.0, 1700000030.0)
    >>> w.samples(np.arange(1.7e9, 1.7e9 + 60.0), minimum=2).shape
    (11,)
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._arrays import FloatArray
from ._checks import public_dir

__all__ = [
    "MIN_WINDOW_READINGS", "PLUS_T", "T0_PLUS", "RestWindowError", "Window", "as_command_line_says",
    "ends_before_first", "in_log_clock", "no_usable_reading", "refuse_few_readings", "refuse_past_end",
    "refuse_start_before", "refuse_unfinished", "refuse_window_objects", "refuse_window_outside", "rest_window_text", "time_range",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


@dataclass(frozen=True)
class Window:
    """A span ``start .. end`` [s]; a bound with ``relative`` set counts from the first sample.

    Attributes:
        start, end: the bounds [s].
        relative: ``(start relative, end relative)``.
        option: how the user gave it (``--window``), to name it in errors.
    """

    start: float
    end: float
    relative: tuple[bool, bool] = (False, False)
    option: str = "window"

    @classmethod
    def parse(cls, bounds: Sequence[str], option: str = "window") -> Window:
        """Two bounds as written: ``["20", "30"]`` (log time base) or ``["+20", "+30"]`` (after the
        first sample).

        Raises:
            ValueError: not two numbers, not finite, or the end not after the start.
        """
        if len(bounds) != 2:
            raise ValueError(f"{option}: give two bounds T0 T1, got {len(bounds)}")
        values, relative = [], []
        for text in bounds:
            stripped = text.strip()
            try:
                values.append(float(stripped))
            except ValueError:
                raise ValueError(
                    f"{option} {' '.join(bounds)}: {text!r} is not a number of seconds "
                    "(write +T for T seconds after the first sample)"
                ) from None
            relative.append(stripped.startswith("+"))
        window = cls(values[0], values[1], (relative[0], relative[1]), option)
        if not all(map(math.isfinite, values)):
            raise ValueError(f"{option} {window}: the bounds must be finite")
        if relative[0] == relative[1] and values[1] <= values[0]:
            raise ValueError(f"{option} {window}: the end must come after the start")
        return window

    def resolve(self, t0: float) -> tuple[float, float]:
        """The bounds in the log's time base, for a log whose first sample is at ``t0`` [s]."""
        return (
            self.start + t0 if self.relative[0] else self.start,
            self.end + t0 if self.relative[1] else self.end,
        )

    def samples(self, t: FloatArray, *, minimum: int = 1, within: bool = False) -> np.ndarray:
        """Indices of the samples of ``t`` inside the window (bounds included).

        Raises:
            ValueError: fewer than ``minimum`` samples inside, or (``within``) a window that reaches
                outside the log, which would be cut to it without a word; naming the window and the
                log's range.
        """
        if len(t) == 0:
            raise ValueError(f"{self.option} {self}: the log has no samples")
        start, end = self.resolve(float(t[0]))
        inside = np.flatnonzero((t >= start) & (t <= end))
        if len(inside) < minimum:
            raise ValueError(
                f"{self.option} {self} holds {len(inside)} sample(s), fewer than {minimum}; "
                + time_range(float(t[0]), float(t[-1]), plus_t=True)
            )
        if within and (start < t[0] or end > t[-1]):
            span = time_range(float(t[0]), float(t[-1]), plus_t=True)
            raise ValueError(f"{self.option} {self} reaches outside the log ({span}); give a window inside it")
        return inside

    def __str__(self) -> str:
        def bound(value: float, relative: bool) -> str:
            return f"+{value:g}" if relative else f"{value:.10g}"

        return f"{bound(self.start, self.relative[0])} .. {bound(self.end, self.relative[1])} s"


#: How a window after the first sample is written, by who asks: the command line and batch take a
#: bound written ``+T`` (a :class:`Window`), the Python API's ``bias_window`` two numbers in the
#: log's own time base (it refuses "+T", which its errors told Python callers to write).
PLUS_T = "write a bound as +T for T seconds after the first sample"
T0_PLUS = "a window after the first sample is (t[0] + start, t[0] + end)"


def time_range(first: float, last: float | None = None, *, after_first: bool = True, plus_t: bool = False) -> str:
    """The span of a log (first and last timestamp [s], or only the first where the last is not
    known yet), for an error about a window: in both time bases where the window could be written
    after the first sample (``after_first``), else in the log's own clock alone (meta.json's
    ``stationary`` takes plain seconds: ``+T`` there is no number). The hint says how to write a
    window after the first sample in the Python API, or with ``plus_t`` for a :class:`Window`
    (:func:`as_command_line_says` turns the one into the other where a message reaches the command
    line or a batch)."""
    if not after_first:
        clock = "in its own clock, the one a window in plain seconds is written in"
        return f"the log starts at {first:.10g} s {clock}" if last is None else (
            f"the log runs from {first:.10g} to {last:.10g} s {clock}")
    hint = PLUS_T if plus_t else T0_PLUS
    if last is None:
        return f"the log starts at {first:.10g} s ({hint})"
    return (
        f"the log runs from {first:.10g} to {last:.10g} s (+0 .. +{last - first:.6g} s after its first sample; "
        f"{hint})"
    )


def in_log_clock(message: str, span: tuple[float, float] | None) -> str:
    """``message``, an error that shows the log's ``span`` (first and last time [s]) by
    :func:`time_range`, for a window that takes plain seconds of the log's clock only: the span
    then hints at that clock, not at ``+T``. Unchanged where ``span`` is None (none shown)."""
    return message if span is None else message.replace(time_range(*span), time_range(*span, after_first=False))


def as_command_line_says(message: str) -> str:
    """``message``, an error the Python API words, as the command line and a batch say it: their
    windows take a bound ``+T`` (:class:`Window`), and a switch the API takes as ``hdr=True`` is
    ``--param hdr=true`` there; the error is built once, where it arises."""
    message = re.sub(r"\bpass (\w+)=True\b", r"give --param \1=true", message)
    return message.replace(T0_PLUS, PLUS_T)


def refuse_window_objects(overrides: dict[str, Any]) -> None:
    """A TypeError for a :class:`Window` among the pipeline's ``overrides``: the command line's and
    a batch's window, which the Python API's take as two numbers (it failed as "'Window' object is
    not subscriptable"); the tuple to give instead is spelled out."""
    for key, value in overrides.items():
        if isinstance(value, Window):
            bounds = ", ".join(f"t[0] + {v:g}" if after else f"{v:.10g}"
                               for v, after in zip((value.start, value.end), value.relative))
            raise TypeError(f"invalid parameter {key} = Window({value}): a gyrocore.window.Window is the command "
                            f"line's and a batch's; here give the tuple ({bounds}), t[0] the log's first time [s]")


class RestWindowError(ValueError):
    """The rest window (``bias_window``, ``bias_duration``) does not fit the log: it holds no
    sample or fewer than :data:`MIN_WINDOW_READINGS`, starts before the log's first sample, or
    reaches past its end. ``span``: the log's first and last time [s] where the message shows them
    (:func:`gyrocore.window.in_log_clock` tells a window from meta.json its clock there)."""

    def __init__(self, message: str, span: tuple[float, float] | None = None) -> None:
        super().__init__(message)
        self.span = span


#: A rest window must hold at least this many readings: the mean of fewer is mostly noise, and
#: its spread unknown (one reading gave a bias "+- 0").
MIN_WINDOW_READINGS = 3


def refuse_few_readings(window: str, readings: int) -> None:
    """A :class:`RestWindowError` if the rest ``window`` (as the user gave it) held fewer than
    :data:`MIN_WINDOW_READINGS` readings."""
    if readings < MIN_WINDOW_READINGS:
        raise RestWindowError(
            f"{window} holds {readings} reading(s): the bias needs at least {MIN_WINDOW_READINGS}; "
            "give a longer rest window"
        )


def refuse_start_before(start: float, end: float, first: float) -> None:
    """A :class:`RestWindowError` for a ``bias_window`` that starts before the log's first sample
    ``first``: the bias would be measured over less than asked, as for one that reaches past its end."""
    if start < first <= end:
        raise RestWindowError(
            f"the bias window [{start}, {end}] s starts before the first sample (t[0] = {first}): the bias would be "
            f"measured over [{first}, {end}] s only; give a rest window inside the log, in its own time base"
        )


def ends_before_first(start: float, end: float, first: float) -> RestWindowError:
    """The error of a rest window ``[start, end]`` that ends before the log's first sample ``first``:
    most often times after the first sample given for a log on a clock of its own (Unix epoch), so
    it spells that window out in the log's time base."""
    return RestWindowError(
        f"the bias window [{start}, {end}] s ends before the first sample (t[0] = {first}); give the window in "
        f"the log's own time base (as times after its first sample: ({first + start!r}, {first + end!r}), "
        "t[0] + start and t[0] + end)"
    )


def refuse_window_outside(start: float, end: float, first: float, last: float) -> None:
    """A :class:`RestWindowError` for a given rest window ``[start, end]`` that does not lie
    inside the log (``first`` .. ``last`` [s]): it ends before the log, starts before it, or
    reaches past its end; the bias would be measured over less than asked, or nothing."""
    if end < first:
        raise ends_before_first(start, end, first)
    refuse_start_before(start, end, first)
    refuse_past_end(start, end, first, last)


def refuse_past_end(start: float, end: float, first: float, last: float, *, duration: float | None = None) -> None:
    """A :class:`RestWindowError` for a rest window ``[start, end]`` that reaches past the log's
    last sample ``last`` (the log begins at ``first``): one given as ``bias_duration`` (its
    ``duration``, from the log's first sample) says so in its own words, else the bias window."""
    if last >= end:
        return
    span = time_range(first, last)
    if duration is not None:
        raise RestWindowError(f"bias_duration = {duration} s is longer than the log ({span}); give a shorter rest at "
                              "the start, or a bias_window", (first, last))
    raise RestWindowError(f"the bias window [{start}, {end}] s reaches past the end of the log ({span}); give a rest "
                          "window inside the log, in its own time base", (first, last))


def no_usable_reading(start: float, end: float, first: float, last: float | None = None) -> RestWindowError:
    """The error of a rest window ``[start, end]`` whose samples are all readings the pipeline does
    not take (NaN, beyond its limit: skipped), in a log from ``first`` (to ``last`` where known):
    whole mode's and a stream's words alike (a stream called it a jump in the log)."""
    return RestWindowError(
        f"the bias window [{start}, {end}] s holds no usable reading (finite, within +-2^20 rad/s) of the log "
        f"({time_range(first, last)})", None if last is None else (first, last)
    )


def rest_window_text(params: dict[str, Any]) -> str:
    """The rest window of ``params`` as the user gave it."""
    if params.get("bias_window"):
        start, end = params["bias_window"]
        return f"the bias window [{start}, {end}] s"
    return f"bias_duration = {params['bias_duration']} s"


def window_span(params: dict[str, Any], first: float | None) -> tuple[float, float] | None:
    """The rest window of ``params`` on the log's clock: ``bias_window``, or ``bias_duration``
    seconds from the log's first time ``first``; None without one, or for a duration while the
    first time is not known."""
    if params.get("bias_window"):
        start, end = params["bias_window"]
        return float(start), float(end)
    if params.get("bias_duration") and first is not None:
        return first, first + float(params["bias_duration"])
    return None


def refuse_unfinished(params: dict[str, Any], first: float | None, last: float | None, count: int,
                      learning: bool) -> None:
    """What :meth:`gyrocore.Pipeline.finish` refuses of a stream whose samples ran from ``first`` to
    ``last`` [s] (None: none), with ``count`` readings in its rest window, still ``learning`` or not:
    a window past the log's end, or one with too few readings."""
    if last is None or first is None or not (params.get("bias_window") or params.get("bias_duration")):
        return  # no sample, or a fixed bias
    if not learning:  # the window is over
        refuse_few_readings(rest_window_text(params), count)
        return
    if params.get("bias_window"):
        start, end = params["bias_window"]
        refuse_past_end(start, end, first, last)
    else:
        end = first + params["bias_duration"]
        refuse_past_end(first, end, first, last, duration=params["bias_duration"])
    # A log that ends at the window's end leaves it open (no reading came after it): its
    # readings are all there is, as whole mode counts them (one at t = 0 of (0, 0) passed).
    refuse_few_readings(rest_window_text(params), count)

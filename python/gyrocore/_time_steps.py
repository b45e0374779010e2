"""Why times that must increase step back or repeat, where the data shows a cause that sorting
them (the core's advice) would not mend: a counter that wrapped round, a clock that started again,
or times rounded to float32 or float16 before they reached gyrocore (a file written from float32
holds float64 numbers, so the reader's float32 warning never sees it)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
import numpy.typing as npt

from . import _gyrocore
from ._arrays import FloatArray

#: Counters whose wrap sends times back: (bits, seconds per count, the count's unit); the times
#: may be the counts themselves (read as seconds) or the counts converted to seconds.
_COUNTERS = tuple((bits, per_count, unit) for bits in (32, 16)
                  for per_count, unit in ((1.0, ""), (1e-3, "ms"), (1e-6, "us"), (1e-9, "ns")))


def counter_wrap(previous: float, value: float) -> str | None:
    """What a time ``value`` that follows ``previous`` but lies before it is, where a counter that
    wrapped round explains it: a 32-bit count of microseconds starts again at 0 after 71.6
    minutes (a microcontroller's ``micros()``), of milliseconds after 49.7 days, a 16-bit one
    after 65.5 s. Such a time lies a whole period back, less the sample's interval (at most a
    thousandth of the period). Sorting the log, as the core's words advise, would put the samples
    after the wrap first."""
    for bits, per_count, unit in _COUNTERS:
        period = 2.0**bits * per_count
        step = value + period - previous
        if 0.0 < step <= period * 1e-3 and max(abs(previous), abs(value)) <= period:
            # a signed counter (an int32) goes on from just short of 2^31 at -2^31
            top, signed = (bits - 1, "signed ") if value < 0 else (bits, "")
            power, scale = f"2^{top} {unit}".rstrip(), per_count * 2.0**top
            counts = power + (f" = {scale:.10g} s" if unit else f" = {scale:.0f}")
            again = f"goes on at -{power}" if signed else "starts again at 0"
            return (f"(a {signed}{bits}-bit counter{' of ' + unit if unit else ''} that wrapped round: "
                    f"{previous:.15g} is just short of {counts}, where it {again}; unwrap the times first: add "
                    f"{period:.10g} to each time from here on, e.g. t = numpy.unwrap(t, period={period:.10g}))")
    return None


def rounded_to_float(t: FloatArray, fewest: int = 3, kinds: tuple[type[np.floating], ...] = (np.float16, np.float32)
                     ) -> str | None:
    """What repeated times ``t`` are where float16 or float32 rounding explains them: a quarter or
    more of the intervals 0, the others mostly a step or two of the type's spacing, each time a
    value of that type, and the type coarser than a millisecond there (float32: 128 s near epoch
    seconds). Whole epoch seconds are float32 values only every 128 s, so a log of genuine times
    fails the test; a duplicate sample repeats one interval, not a quarter, and the times of a
    short log (0, 1, 2, 2) that are float16 values lie far more than its spacing apart. ``fewest``:
    the fewest times that are judged (a stream's short chunk, with the time before it, has two);
    ``kinds``: the types whose rounding is looked for."""
    finite = t[np.isfinite(t)]
    steps = np.diff(finite)
    zero = int(np.count_nonzero(steps == 0))
    if len(finite) < fewest or 4 * zero < len(steps):
        return None
    size = float(np.max(np.abs(finite)))
    forward = steps[steps > 0]
    for kind in kinds:
        if size > float(np.finfo(kind).max):
            continue
        spacing = float(np.spacing(kind(size)))
        # rounding that merges samples leaves the others a step or two of its spacing apart
        close = not len(forward) or float(np.median(forward)) <= 2 * spacing
        if spacing > 1e-3 and close and np.array_equal(finite.astype(kind), finite):
            return (f"(the times repeat: {zero} of these {len(finite) - 1} intervals are 0, and every time is a "
                    f"{np.dtype(kind).name} value, which near {size:.4g} resolves only {spacing:g} s: they were rounded "
                    f"to {np.dtype(kind).name} before they were written or given; keep them as float64 from their "
                    "source, or as seconds from the first sample)")
    return None


#: A step back of more than this many of the log's median intervals, after which the times go on
#: at that pace for :data:`_RUNS_ON` intervals, is a clock that started again, not a row out of place.
_STEP_BACK_INTERVALS = 10
_RUNS_ON = 5


def clock_started_again(t: FloatArray, i: int, previous: float) -> str | None:
    """What a time ``t[i]`` that lies well before ``previous`` is, where the times after it go on at
    the log's pace: a clock set back (a time sync, a logger restarted) or two recordings joined.
    Sorting the log, as the core's words advise, would interleave the two runs; a row out of place
    (a swapped pair, one bad time) steps back by an interval or is followed by a jump forward."""
    value = float(t[i])
    steps = np.diff(t[np.isfinite(t)])
    pace = float(np.median(steps)) if len(steps) else 0.0
    after = np.diff(t[i : i + _RUNS_ON + 1])
    if not (pace > 0 and previous - value > _STEP_BACK_INTERVALS * pace and len(after) == _RUNS_ON
            and np.all((after > 0) & (after < 3 * pace))):
        return None
    return (f"(the clock steps back {previous - value:.6g} s here and runs on from there: a clock set back, or two "
            "recordings joined; sorting would interleave them: split the log at this sample and process each part)")


#: A stream's chunk shorter than this is judged for float32 rounding with the time before it: its
#: own times are too few to show the repeats (a chunk of 1 or 2 samples, ``--chunk-rows 2``).
_SHORT_CHUNK = 3


def why_times_step_back(t: FloatArray, i: int, previous: float, last: float | None = None) -> str | None:
    """What explains that the time ``t[i]`` comes at or before ``previous`` (``t[i - 1]``, or the
    last time of an earlier chunk), in parentheses, or None where nothing does. ``last``: the time
    of the sample before ``t[0]`` (a stream's earlier chunk, if any), which a short chunk is judged with:
    the repeat and the times at hand all float32 values, at a size where float32 resolves more
    than a millisecond (genuine float64 times that repeat are not all such values)."""
    value = float(t[i])
    wrap = counter_wrap(previous, value)
    if wrap is not None or value > previous:
        return wrap
    if value < previous:  # within the times given (a stream's chunk that starts back is named as sent again)
        return clock_started_again(t, i, previous) if i > 0 else None
    if len(t) < _SHORT_CHUNK:
        # float32 alone: whole numbers below 2048, ms read as s, are float16 values, and two times
        # cannot show that the others lie a step of its spacing apart
        return rounded_to_float(np.concatenate(([] if last is None else [last], t)), 2, (np.float32,))
    return rounded_to_float(t)


#: The core's advice for a time going back, which would mend neither a counter's wrap nor float32 rounding.
_SORT_ADVICE = "(sort the log and drop duplicate timestamps)"


def name_time_step(error: _gyrocore.SampleError, t: FloatArray, last: float | None, index_offset: int) -> bool:
    """Replaces the core's advice to sort the log in its error about a time going back or repeating
    with what explains the step (:func:`why_times_step_back`: a counter's
    wrap, times rounded to float32), which sorting would not mend (a file's reader names it too:
    ``log_message``); true if it did."""
    i = error.index - index_offset
    if error.what != "t" or not 0 <= i < len(t) or _SORT_ADVICE not in str(error):
        return False
    previous = t[i - 1] if i > 0 else last
    hint = None if previous is None else why_times_step_back(t, i, float(previous), last)
    if hint is None:
        return False
    # a file's reader and a whole log take the words of a series (the binding's, where they differ)
    error.log_message = getattr(error, "log_message", str(error)).replace(_SORT_ADVICE, hint)  # type: ignore[attr-defined]
    error.args = (str(error).replace(_SORT_ADVICE, hint),)
    return True


@contextmanager
def time_steps_named(t: FloatArray, positions: npt.NDArray[np.intp] | None = None) -> Iterator[None]:
    """Runs a core call on the times ``t`` (a whole series: no earlier chunk), naming in its
    :class:`~gyrocore.SampleError` what explains a time that steps back (:func:`name_time_step`).
    ``positions``: each sample's index in the whole log where ``t`` holds only some of its samples
    (a rest window's), so that the error names the log's sample, not the window's."""
    try:
        yield
    except _gyrocore.SampleError as e:
        name_time_step(e, t, None, 0)
        if positions is not None and 0 <= e.index < len(positions):
            at = int(positions[e.index])
            said = f"{e.what}[{e.index}]"
            e.args = (str(e).replace(said, f"{e.what}[{at}]", 1),)
            if hasattr(e, "log_message"):
                e.log_message = e.log_message.replace(said, f"{e.what}[{at}]", 1)
            e.index = at
        raise


def as_log_error(error: _gyrocore.SampleError) -> None:
    """A whole log's error about a time in the log's words, its ``log_message``, where a stream's
    words name a stream's way on: the binding gives a stream's step back the words of a whole
    series (the core's ``Error::of_series``, without ``restart_clock()``), and the hints added
    to a time's error are added to both (:func:`name_time_step`). A reading's error keeps its
    words: the policy that takes the reading applies to a log too."""
    message = getattr(error, "log_message", None)
    if error.what == "t" and message is not None:
        error.args = (message,)


@contextmanager
def whole_log_steps() -> Iterator[None]:
    """Runs a whole log's processing (also as a decorator), naming a time that goes back as a log's
    (:func:`as_log_error`), not a stream's."""
    try:
        yield
    except _gyrocore.SampleError as e:
        as_log_error(e)
        raise

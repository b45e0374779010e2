"""Conversion of user arrays to what the Rust core reads: 1-D, contiguous float64."""

from __future__ import annotations

import dataclasses
import datetime
import functools
import inspect
import math
import numbers
import os
import sys
import threading
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any, ParamSpec, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
_P = ParamSpec("_P")
_R = TypeVar("_R")


#: Counts per second of the timedelta64 units below a second (divided by: rounds once).
_PER_SECOND = {"as": 1e18, "fs": 1e15, "ps": 1e12, "ns": 1e9, "us": 1e6, "ms": 1e3, "s": 1.0}
#: Seconds per count of the longer units of a fixed length.
_SECONDS = {"m": 60.0, "h": 3600.0, "D": 86400.0, "W": 604800.0}


def durations_in_seconds(name: str, a: np.ndarray) -> np.ndarray:
    """A ``timedelta64`` array in seconds (NaT: NaN); any other array as it is. numpy counts
    timedelta64 as an integer type, whose raw counts are in its own unit (ms would read as s).
    Computed from the counts: numpy's own division overflows for attoseconds."""
    if a.dtype.kind != "m":
        return a
    unit, step = np.datetime_data(a.dtype)
    counts = a.astype(np.int64).astype(np.float64) * step
    if unit in _PER_SECOND:
        seconds = counts / _PER_SECOND[unit]
    elif unit in _SECONDS:
        seconds = counts * _SECONDS[unit]
    else:  # years and months, or no unit
        raise TypeError(f"{name} holds {a.dtype}, which has no fixed length in seconds")
    seconds[np.isnat(a)] = np.nan
    # the counts' own resolution: nanoseconds since the epoch closer than float64 tells apart merge
    per_second = _PER_SECOND[unit] / step if unit in _PER_SECOND else 1.0 / (_SECONDS[unit] * step)
    warn_merged_counts(a.view(np.int64), seconds, per_second)
    return seconds


def seconds_of(a: np.ndarray) -> np.ndarray:
    """An object array of ``datetime.timedelta`` in seconds, as float64 (a ``timedelta64[us]`` of
    Python's resolution wrapped past +-292,000 years without a word: 999999999 days read as
    -5.8e12 s)."""
    second = datetime.timedelta(seconds=1)
    return np.fromiter((v / second for v in a.flat), np.float64, count=a.size).reshape(a.shape)


#: What to do with masked values, for a function that takes NaN for a missing reading (``nonfinite=``).
MASKED_AS_NONFINITE = "give {name}.filled(numpy.nan) (with nonfinite='hold' or 'skip') or leave those samples out"
#: ... for any other: it has no missing value, so the caller leaves the samples out or fills them.
MASKED_LEFT_OUT = ("leave those samples out ({name}.compressed(), and the others' times), or fill them with values "
                   "of your own ({name}.filled(value))")


def _pandas_na_as_nan(a: np.ndarray) -> np.ndarray:
    """The object array ``a`` with pandas' missing value ``pandas.NA`` as NaN (a copy, where it
    holds one): pandas before 2.2 hands numpy a nullable (``Float64``, ``Int64``) or pyarrow-backed
    column with a gap as objects, ``pandas.NA`` in the gap, where later releases give NaN; a gap is
    a missing reading either way, for ``nonfinite=`` to hold or skip, not a value that is no number."""
    pandas = sys.modules.get("pandas")  # not imported: no pandas.NA can be among the values
    if pandas is None:
        return a
    missing = np.fromiter((v is pandas.NA for v in a), bool, count=a.size)
    if not missing.any():
        return a
    a = a.copy()  # the caller's objects stay as they are
    a[missing] = np.nan
    return a


def as_float_array(name: str, values: ArrayLike, *, copy: bool = False, masked: str = MASKED_LEFT_OUT,
                   unit: str | None = None) -> FloatArray:
    """Return ``values`` as a 1-D contiguous float64 array, copying only when needed, or always
    with ``copy`` (for an array a result or record keeps: the caller's own array, or the data an
    ``__array__`` hands over, kept as it is, changed with the caller's, ``r.t[:] -= r.t[0]`` moving
    the caller's times too; :class:`OwnCopy` makes that copy while the core runs).

    ``timedelta64`` values are durations and become seconds, whatever their unit (NaT becomes NaN);
    ``datetime64`` is refused, since which epoch a time counts from is the caller's choice.
    ``unit``: the values are a quantity in that unit (a rate in ``"rad/s"``), never a time, and
    durations and dates are refused (:func:`refuse_times`).

    Raises TypeError for non-numeric data and ValueError for a wrong shape or masked values (see
    :func:`refuse_masked`, ``masked`` its hint).
    """
    out, fresh = _converted(name, values, masked, unit)
    return out.copy() if copy and not fresh else out


def as_float_array_owned(name: str, values: ArrayLike, *, copy: bool = True) -> tuple[FloatArray, OwnCopy]:
    """:func:`as_float_array` of ``values``, and what a result keeps of it (:class:`OwnCopy`: a
    copy begun by its :meth:`~OwnCopy.start` before the work it may run beside, or without
    ``copy`` the array itself, read-only)."""
    out, fresh = _converted(name, values, MASKED_LEFT_OUT, None)
    return out, OwnCopy(out, fresh, copy=copy)


#: What to give instead of dates (``datetime64``, Python's with a time zone), for the array named.
_DATES = "times: give seconds, e.g. ({0} - {0}.min()) / numpy.timedelta64(1, 's')"
#: Arrays at least this long are copied on another thread (a thread's start costs tens of us).
COPIED_BESIDE = 1 << 18
#: The copy goes piece by piece, so that a call stopped (Ctrl-C) need not wait for the rest of it
#: (5*10^7 times took 0.8 s to copy whole, its fresh pages faulted in): one piece at the most.
_PIECE = 1 << 20


class OwnCopy:
    """A copy of the float64 array ``a`` for a result to keep, made on another thread while the
    core runs (numpy's copy and the core's loop both release the GIL): the copy of 10^7 times,
    its fresh pages faulted in, was a quarter of a heading-only call on this thread. ``fresh``:
    ``a`` is a conversion's new array already, kept as it is. Without ``copy`` (a call that fills
    the caller's own arrays and allocates nothing) ``a`` itself is kept, read-only: a write
    through it fails. :meth:`get` waits for the copy, :meth:`cancel` gives it up."""

    def __init__(self, a: FloatArray, fresh: bool, *, copy: bool = True) -> None:
        self._given = a if copy and not fresh else None
        self._own = a if copy else a.view()
        if not copy:
            self._own.flags.writeable = False
        self._thread: threading.Thread | None = None
        self._stop: threading.Event | None = None  # with the thread: an Event costs a stream's call 5 us

    def start(self) -> None:
        """Begin the copy: on another thread for a long array, at once for a short one."""
        if self._given is None:
            return
        given, self._given = self._given, None
        if len(given) < COPIED_BESIDE:
            self._own = given.copy()
            return
        self._own = np.empty_like(given)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._copy, args=(given, self._stop), name="gyrocore-copy", daemon=True)
        self._thread.start()

    def _copy(self, given: FloatArray, stop: threading.Event) -> None:
        for start in range(0, len(given), _PIECE):
            if stop.is_set():
                return
            np.copyto(self._own[start:start + _PIECE], given[start:start + _PIECE])

    def get(self) -> FloatArray:
        """The copy, complete (begun here if it was not)."""
        self.start()
        self._join()
        return self._own

    def cancel(self) -> None:
        """Give the copy up where the work failed or was stopped: no thread outlives the call, and
        the call's error comes without waiting for the rest of the copy."""
        if self._stop is not None:
            self._stop.set()
        self._join()

    def _join(self) -> None:
        if self._thread is not None:
            self._thread.join()
            self._thread = None


#: How a log given by its file's name is read, where a call takes its arrays.
_READ_LOG = "a log file or folder is read with gyrocore.read_log(path)"


def read_the_log(arrays: str = "log.t, log.rate", command: str = "") -> str:
    """What a file's name given for an array is told to do instead: read the log, give ``arrays``
    (and on the command line, ``command``)."""
    cli = f" (on the command line: {command})" if command else ""
    return f"{_READ_LOG}, and its arrays ({arrays}) are given here{cli}"


#: ... by default (each entry point says its own through :func:`no_path_for_arrays`).
READ_THE_LOG = read_the_log()
#: ... by the calls that process a log, as the command line's ``gyrocore process``.
READ_AND_PROCESS = f"{_READ_LOG}, then processed with its .process(preset) (on the command line: gyrocore process FILE)"
#: ... by the calls that process a log with its fixes.
READ_WITH_FIXES = ("a log folder is read with gyrocore.read_log(path), its fixes from its fixes.csv or gnss.csv, "
                   "then processed with its .process(preset) (a file of fixes is read with "
                   "gyrocore.fixes.read_fixes_file(path) or read_nmea(path); on the command line: gyrocore process "
                   "FILE --fixes FIXES)")
#: ... by the calls that make fixes of a GNSS log's arrays.
READ_GNSS = ("a GNSS log is read with gyrocore.fixes.read_nmea(path) (NMEA sentences), read_gnss_csv(path) (columns "
             "t, speed and bearing) or read_fixes_file(path)")
#: ... by the calibrations.
READ_TO_CALIBRATE = read_the_log(command="gyrocore calibrate FILE")
#: ... by the fits against a reference heading.
READ_WITH_REFERENCE = read_the_log("log.t, log.rate, log.t_ref, log.heading_ref", "gyrocore calibrate FILE")
#: ... by the fit against a reference rate.
READ_WITH_TRUE_RATES = read_the_log("log.rate, and the true rates at its times", "gyrocore calibrate FILE")
#: ... by the fit of the bias to the temperature.
READ_WITH_TEMPERATURES = read_the_log("log.t, log.rate and the temperatures", "gyrocore calibrate FILE")
#: ... by the heading's errors against a reference.
READ_TO_SCORE = read_the_log("a heading's t and heading, log.t_ref, log.heading_ref", "gyrocore evaluate FOLDER")
#: ... by the Allan deviation of timed readings, and of readings at a sample interval.
READ_FOR_ALLAN = read_the_log(command="gyrocore allan FILE")
READ_RATE_FOR_ALLAN = read_the_log("log.rate, and its sample interval as dt", "gyrocore allan FILE")
#: ... by the calls that take a heading.
READ_A_HEADING = read_the_log("a heading's t and heading")
#: ... by dead reckoning.
READ_ODOMETRY = read_the_log("log.t_odometry, log.speed, and a heading's t and heading")
#: The units said of a call's arrays where it lists them.
_UNITS = {"t": "s", "t_ref": "s", "t_speed": "s", "t_heading": "s", "rate": "rad/s", "rate_measured": "rad/s",
          "rate_reference": "rad/s", "heading": "rad", "heading_ref": "rad", "speed": "m/s", "bearing_deg": "deg",
          "lat_deg": "deg", "lon_deg": "deg", "x": "m", "y": "m", "dt": "s"}


def refuse_a_path(name: str, values: object, advice: str = READ_THE_LOG) -> None:
    """A file's name or path given for an array (``gyrocore.process("drive.csv", ...)``, as the
    command line takes files) is told how the file is read: numpy made it a text of one element,
    and the error of its dtype said nothing of files. ``advice``: what to do instead."""
    if isinstance(values, os.PathLike) or isinstance(values, str) and (os.sep in values or os.path.splitext(values)[1][1:2].isalpha()):
        raise TypeError(f"{name} = {values!r}: a file's name, not a sequence of numbers; {advice}")


def _listed(names: Sequence[str]) -> str:
    """``t [s], rate [rad/s] and fixes``: a call's arrays with their units."""
    said = [f"{n} [{_UNITS[n]}]" if n in _UNITS else n for n in names]
    return said[0] if len(said) == 1 else ", ".join(said[:-1]) + " and " + said[-1]


def no_path_for_arrays(call: str, advice: str = READ_THE_LOG) -> Callable[[Callable[_P, _R]], Callable[_P, _R]]:
    """Refuses a file's name or path given for the first array of ``call`` (its first parameter
    after ``self``) before Python binds the arguments (:func:`refuse_a_path`): given alone,
    ``gyrocore.process("log.csv")`` or ``gyrocore.fuse("log.csv")``, a first try as the command
    line takes files, it met Python's own ``missing 1 required positional argument: 'rate'``, which
    led to look for a rate to add. The words list the arrays the call takes (its parameters
    without a default), then ``advice``."""

    def wrap(f: Callable[_P, _R]) -> Callable[_P, _R]:
        params = list(inspect.signature(f).parameters.values())
        at = 1 if params[0].name == "self" else 0
        arrays = [p.name for p in params[at:] if p.default is p.empty and p.kind is p.POSITIONAL_OR_KEYWORD]
        first, takes = params[at].name, f"{call} takes {_listed(arrays)}; {advice}"

        @functools.wraps(f)
        def checked(*args: _P.args, **kwargs: _P.kwargs) -> _R:
            refuse_a_path(first, args[at] if len(args) > at else kwargs.get(first), takes)
            return f(*args, **kwargs)

        return checked

    return wrap


def _converted(name: str, values: ArrayLike, masked: str, unit: str | None) -> tuple[FloatArray, bool]:
    """:func:`as_float_array` of ``values`` without a copy, and whether it is a new array (a
    conversion's) rather than the caller's own."""
    refuse_masked(name, values, masked)
    refuse_a_path(name, values)
    try:
        array = np.asarray(values)
    except ValueError as e:  # a ragged list: numpy's message names neither the argument nor a fix
        raise ValueError(f"{name} must be one flat sequence of numbers ({e})") from None
    if unit is not None:
        refuse_times(name, array, unit)
    if array.dtype == np.object_ and array.size and all(isinstance(v, datetime.timedelta) for v in array.flat):
        array = seconds_of(array)  # Python's durations ([d - start for d in times]), as numpy's are
    a = durations_in_seconds(name, array)
    if a.dtype.kind == "M":
        raise TypeError(f"{name} holds {a.dtype} {_DATES.format(name)}")
    if a.dtype == np.object_ and a.ndim == 1:  # None or text among numbers: say which and where
        a = _pandas_na_as_nan(a)
        odd = next((i for i, v in enumerate(a) if isinstance(v, (bool, str, bytes)) or not isinstance(v, numbers.Real)), None)
        if odd is not None and isinstance(a[odd], datetime.datetime):  # pandas' times with a time zone
            raise TypeError(f"{name} holds dates and {_DATES.format(name)} ({name}[{odd}] is {a[odd]!r})")
        if odd is not None and isinstance(a[odd], (list, tuple, np.ndarray)):  # numpy < 1.24 keeps a ragged list
            raise ValueError(f"{name} must be one flat sequence of numbers (setting an array element with a "
                             f"sequence: {name}[{odd}] is {a[odd]!r})")
        if odd is not None:  # a Decimal is a number to its caller, but numpy reads it only when told to
            decimal = isinstance(a[odd], numbers.Number) and not isinstance(a[odd], numbers.Complex)  # not complex
            fix = f"numpy.asarray({name}, dtype=float)" if decimal else "numbers"
            raise TypeError(f"{name} must hold real numbers, got dtype object: {name}[{odd}] is {a[odd]!r} (give "
                            f"{fix}, NaN where a value is missing)")
        try:
            a = a.astype(np.float64)  # every one a number (Decimal is none; Fraction, a huge int are)
        except OverflowError:  # an int beyond float64 (10**400): a bare "int too large to convert to float"
            big = next(i for i, v in enumerate(a) if abs(v) > sys.float_info.max)  # exact for an int
            raise ValueError(f"{name}[{big}] is an int beyond the range of float64 (about 1.8e308): give numbers a "
                             "float64 holds") from None
    if a.dtype == np.object_ and a.ndim == 0:  # numpy holds what is no sequence whole: a generator, a set
        raise TypeError(f"{name} must be a sequence of numbers (a list or array), got {type(a.item()).__name__}"
                        + (f": give numpy.fromiter({name}, float)" if isinstance(a.item(), Iterator) else ""))
    if a.dtype == np.bool_ or not (
        np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)
    ):
        text = f" (text: give numbers, e.g. numpy.asarray({name}, dtype=float))" if a.dtype.kind in "US" else ""
        raise TypeError(f"{name} must hold real numbers, got dtype {a.dtype}{text}")
    if a.ndim != 1:
        # a column (N, 1) or row (1, N), numpy.matrix's one shape: which axis is time is plain only then
        flat = f": give one column, e.g. numpy.ravel({name})" if a.ndim == 2 and 1 in a.shape else ""
        raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}{flat}")
    if name == "t":
        warn_coarse_times(a)
    out = np.ascontiguousarray(a, dtype=np.float64)
    # not already a converted copy: numpy builds a new array of a list or tuple, but hands over an
    # ndarray, or the data an __array__ gives, as it is
    return out, out is not array or isinstance(values, (list, tuple))


def float_fields(record: object, names: Sequence[str], prefix: str = "", *, copy: bool = False,
                 frozen: bool = False, units: Mapping[str, str] | None = None) -> None:
    """Set each field ``names`` of the frozen dataclass ``record`` that is not None to
    :func:`as_float_array` of it (named ``prefix`` + its name in an error): a record built from
    pandas columns or lists then holds numpy arrays, and reads them by position (a Series' ``t[0]``
    is a look-up by label). ``frozen``: to :func:`frozen_array` of it. ``units``: the unit of each
    field that is a quantity, not a time (durations and dates refused in it)."""
    for name in names:
        value = getattr(record, name)
        if value is not None:
            unit = None if units is None else units.get(name)
            a = (frozen_array(prefix + name, value, unit=unit) if frozen
                 else as_float_array(prefix + name, value, copy=copy, unit=unit))
            object.__setattr__(record, name, a)


def refuse_times(name: str, values: np.ndarray, unit: str) -> None:
    """A TypeError for durations or dates (numpy's ``timedelta64``/``datetime64``, a pandas
    timedelta column, Python's ``timedelta``/``datetime``) given as ``name``, a quantity in ``unit``
    (a rate in rad/s, a heading in rad, a speed in m/s): read as a time, a duration became seconds
    and was processed as so many rad/s without a word. ``values`` as numpy reads them. Every array
    of a quantity passes here (:func:`as_float_array`'s ``unit``), and a file's column too."""
    kind = values.dtype.kind
    if kind == "O" and values.size:  # Python's (or pandas') objects: the first one tells
        first = values.flat[0]
        kind = "m" if isinstance(first, (datetime.timedelta, np.timedelta64)) else (
            "M" if isinstance(first, (datetime.datetime, datetime.date, np.datetime64)) else kind)
    if kind in "mM":
        what = "durations" if kind == "m" else "dates"
        raise TypeError(f"{name} holds {what} ({values.dtype}), not values in {unit}: give {name} as floats in {unit}")


def frozen_array(name: str, values: ArrayLike, *, unit: str | None = None) -> FloatArray:
    """``values`` as a read-only float64 array (:func:`as_float_array`) that the caller's writes do
    not reach: a read-only ndarray as it is (a memory map opened read-only, another record's frozen
    array: its holder keeps it unchanged, numpy's meaning of the flag), anything else copied (once:
    a conversion's new array is not copied again). A pandas column is copied too: the read-only
    view pandas' copy-on-write hands numpy still changes with ``df.loc[i, "t"] = x``."""
    given_read_only = isinstance(values, np.ndarray) and not values.flags.writeable
    a = as_float_array(name, values, copy=not given_read_only, unit=unit)
    a.flags.writeable = False  # a write through it fails: "assignment destination is read-only"
    return a


def array_fields(record: Any) -> dict[str, FloatArray]:
    """The fields of the dataclass ``record`` that hold a numpy array, by name in field order
    (those that are None or hold anything else left out): the arrays themselves, not copies. The
    ``columns()`` of a result, for a table: ``pandas.DataFrame(result.columns())``."""
    values = {f.name: getattr(record, f.name) for f in dataclasses.fields(record)}
    return {name: a for name, a in values.items() if isinstance(a, np.ndarray)}


def refuse_masked(name: str, values: object, hint: str = MASKED_LEFT_OUT) -> None:
    """A ValueError for a numpy masked array with masked values, naming how many and where the
    first is: numpy.asarray drops the mask, so the hidden values would be processed as valid.
    (Treating them as missing would hide a choice the caller should make.) ``hint`` says what the
    function offers instead (``{name}`` is the argument's): :data:`MASKED_AS_NONFINITE` only where
    it takes ``nonfinite=``, which the hint named for every function (the Allan deviation has none)."""
    if not np.ma.isMaskedArray(values):
        return
    masked = np.flatnonzero(np.ma.getmaskarray(values))
    if len(masked):
        first = masked[0] if np.ndim(values) <= 1 else tuple(int(i) for i in np.unravel_index(masked[0], np.shape(values)))
        raise ValueError(
            f"{name} is a masked array with {len(masked)} masked value(s), the first at index {first}: "
            + hint.format(name=name)
        )


def warn_coarse_times(t: np.ndarray, per_second: float = 1.0) -> None:
    """Warn when times stored as float32 or float16 (``per_second`` counts a second) cannot tell
    samples apart: near epoch seconds (1.7e9) float32 steps by 128 s, and float16 by 1/64 s from
    16 s on, so neighbouring samples read as equal or reversed, and the error that follows ("t[1] =
    ... follows ...") would not say why. One message for every chunk of a file (both step by powers
    of two)."""
    if t.dtype not in (np.float16, np.float32) or not np.isfinite(t).any():
        return
    spacing = float(np.spacing(t.dtype.type(np.nanmax(np.abs(t))))) / per_second
    if spacing > 1e-3:
        from ._checks import warn  # _checks builds on this module

        warn(f"the times are {t.dtype}, which at their size resolve only {spacing:g} s: store them as float64 "
             "(or as seconds from the first sample)")


def warn_merged_counts(raw: np.ndarray, t: FloatArray, per_second: float) -> None:
    """Warn when time counts (``per_second`` of them a second) that may differ in the file are
    one time ``t`` [s]: float64 resolves 2.4e-7 s near epoch seconds (1.7e9) and 256 ns near epoch
    nanoseconds (1.7e18, as a CSV file's numbers are read), so nanoseconds closer than that merge,
    and the error that follows ("sort the log and drop duplicate timestamps") names a fault the
    file may not have. Integer counts that step forward are known to have merged."""
    if len(t) < 2:
        return
    same = t[1:] <= t[:-1]
    if raw.dtype.kind in "iu":
        same &= raw[1:] > raw[:-1]
    if not same.any():
        return
    i = int(np.argmax(same)) + 1
    resolution = max(float(np.spacing(abs(t[i]))), float(np.spacing(abs(float(raw[i])))) / per_second)
    if resolution >= 1e-7:  # a repeat of finer times is one in the file
        from ._checks import warn  # _checks builds on this module

        first = raw[0].item()  # a CSV file's counts are read as float64: shown as written
        first_text = f"{first:.0f}" if isinstance(first, float) and first.is_integer() else str(first)
        warn(f"two times read as one, {float(t[i]):.9f} s (counts of 1/{per_second:g} s), where float64 resolves only "
             f"{resolution:.3g} s: if they differ in the file, give times from the first sample (subtract "
             f"{first_text} from each)")


def one_line(value: object) -> str:
    """``value`` for a message, on one line: an array-like as numpy reads it (a pandas Series
    shows its labels over several lines)."""
    return repr(np.asarray(value)) if hasattr(value, "__array__") else repr(value)


def as_window(name: str, window: object) -> tuple[float, float]:
    """``(start, end)`` [s] as two finite floats with ``start < end`` (a pandas Series read by
    position, as numpy reads it); ValueError naming ``name`` for anything else (one number, three,
    text, NaN, a reversed window, durations or dates)."""
    try:
        pair = np.asarray(window, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):  # an int beyond float64 too
        pair = np.empty(0)
    # bools are refused: (False, True) was the window 0 .. 1 s
    if pair.shape != (2,) or np.asarray(window).dtype == np.bool_ or any(isinstance(v, bool) for v in np.ravel(
            np.asarray(window, dtype=object))):
        raise ValueError(f"{name} must be (start, end) in seconds, got {one_line(window)}")
    if np.asarray(window).dtype.kind in "mM":  # their counts, read as seconds, were a window in ns or us
        raise ValueError(f"{name} must be (start, end) in seconds, got {one_line(window)}: give seconds (a numpy "
                         "duration d as d / numpy.timedelta64(1, 's'))")
    start, end = float(pair[0]), float(pair[1])
    if not (math.isfinite(start) and math.isfinite(end) and end > start):
        raise ValueError(f"{name} ({start}, {end}) must be finite with end > start")
    return start, end


def covered_share(t: FloatArray, other: FloatArray) -> float:
    """The share of the span of the times ``t`` (first to last, increasing) that the span of the
    times ``other`` covers: 1 when it holds all of it, 0 when the two do not overlap, when
    ``other`` is empty, or when ``t`` has no span (a series in another clock or unit shows as a
    small share, which no error reveals where the overlap is scored alone)."""
    if len(t) < 2 or len(other) == 0 or not t[-1] > t[0]:
        return 0.0
    first, last = float(t[0]), float(t[-1])
    overlap = min(last, float(other[-1])) - max(first, float(other[0]))
    return max(overlap, 0.0) / (last - first)


def span_text(t: FloatArray) -> str:
    """The span of the times ``t`` for a message: ``t = 1700000000.000 to 1700000030.000 s``."""
    return f"t = {t[0]:.3f} to {t[-1]:.3f} s" if len(t) else "no sample"


def too_few_inside(name: str, t: FloatArray, other: str, t_other: FloatArray) -> str:
    """The error for the series ``name`` at the times ``t`` with fewer than two samples inside the
    span of ``other`` (times ``t_other``): both spans, so that a clock or unit apart shows."""
    return (f"{name} has fewer than two samples inside {other}'s time span: {name} runs from {span_text(t)}, "
            f"{other} from {span_text(t_other)}; give both on the same clock")

"""Plausibility checks of user input: values that only make sense in another unit."""

from __future__ import annotations

import contextlib
import difflib
import inspect
import math
import numbers
import os
import sys
import threading
import types
import warnings
from collections.abc import Callable, Iterable, Iterator
from typing import Any, cast

import numpy as np

from . import _gyrocore
from ._arrays import FloatArray
from ._time_steps import time_steps_named, why_times_step_back

#: Above this the rates are implausible in rad/s (about 1150 deg/s) and likely deg/s.
RATE_LIMIT = 20.0
#: A median interval above this [s] suggests timestamps in ms, us or ns (no gyro for heading
#: reports slower than 0.5 Hz).
INTERVAL_LIMIT = 2.0
#: The core's limit of a reading (``gyrocore::MAX_READING``): a rate [rad/s] or temperature
#: [degC] must lie strictly within +-2^20; the core refuses any other (or, under
#: ``nonfinite="hold"/"skip"``, holds or skips it like a NaN).
MAX_READING: float = _gyrocore.MAX_READING
#: The core's limit of a timestamp and a duration [s] (``gyrocore::MAX_TIME``): +-2^40 s, 35,000
#: years (``bias_duration``, ``lowpass_tau``, a rest window's ends).
MAX_SECONDS: float = _gyrocore.MAX_TIME
#: Enough samples for a percentile; longer arrays are checked on a regular subset. The unit
#: mistakes differ by a factor of 57 (deg/s read as rad/s), far more than the percentile of
#: 10,000 values can be off; 100,000 took 2.5 ms of a 10^7-sample call (0.1 ms now).
SUBSET_SIZE = 10_000


class InputWarning(UserWarning):
    """Input that gyrocore processed but that looks wrong (units) or was repaired (NaN, gaps)."""


class UnitError(ValueError):
    """Input refused because it is in another unit than the one asked for (a heading in degrees
    given as radians): a mistake to correct, not a property of the data to work around."""


def typical_interval(t: FloatArray) -> float:
    """The median interval of ``t`` [s] (NaN with fewer than two finite times), on a regular subset
    of a long log (the median of its steps over as many samples): one gap or clock jump, which
    made the mean interval look like ms, moves it by nothing."""
    step = max(1, len(t) // SUBSET_SIZE)
    with np.errstate(invalid="ignore", over="ignore"):  # times near +-1e308 or NaN: the core names them
        intervals = np.diff(t[::step]) / step
        intervals = intervals[np.isfinite(intervals)]
        return float(np.median(intervals)) if len(intervals) else math.nan


def unit_problems(t: FloatArray, rate: FloatArray) -> list[str]:
    """Messages for rates or timestamps that look like another unit (empty if none)."""
    problems = []
    subset = rate[:: max(1, len(rate) // SUBSET_SIZE)]
    # Readings beyond the core's limit are no rates in any unit: the pipeline refuses them, or
    # holds or skips them as it does a NaN, so they are left out here as NaN is (a glitch of 1e7
    # in 2 % of the samples, held, read as deg/s and was advised to be converted).
    with np.errstate(invalid="ignore"):
        magnitude = np.abs(subset[np.abs(subset) < MAX_READING])
    # The 99th percentile can exceed the limit only if about 1 % of the values do (at least
    # 0.01 n - 0.01 of n); counting them costs a tenth of the percentile, computed only then.
    # No usable rate at all leaves nothing to judge (the pipeline names the first bad one).
    if len(magnitude) and np.count_nonzero(magnitude > RATE_LIMIT) > 0.01 * len(magnitude) - 1:
        p99 = float(np.percentile(magnitude, 99))
        if p99 > RATE_LIMIT:
            problems.append(
                f"rates look like deg/s, not rad/s: 99 % of |rate| are below {p99:.3g}, which is "
                f"{np.degrees(p99):.3g} deg/s if read as rad/s (convert with numpy.radians)"
            )
    interval = typical_interval(t)
    if interval > INTERVAL_LIMIT:
        problems.append(
            f"timestamps look like ms, us or ns, not seconds: the median interval is {interval:.6g} "
            "(convert to seconds first)"
        )
    return problems


#: A step of a reference heading [rad] between two samples beyond this is a heading in degrees:
#: one in radians steps by at most 2 pi where it wraps (28 turns between two samples would be
#: needed), one in degrees by about 360.
DEGREE_STEP = 180.0


def require_radians(name: str, t: FloatArray, heading: FloatArray) -> None:
    """A :class:`UnitError` if the heading ``name`` [rad] at the times ``t`` looks like degrees: a step
    between two samples beyond :data:`DEGREE_STEP` (a wrap at +-180 or 0/360 deg)."""
    steps = np.abs(np.diff(heading))
    i = int(np.argmax(steps)) if len(steps) else 0
    if len(steps) and steps[i] > DEGREE_STEP:
        raise UnitError(
            f"{name} looks like degrees, not radians: it jumps by {heading[i + 1] - heading[i]:.6g} from "
            f"{heading[i]:.6g} at t = {t[i]} to {heading[i + 1]:.6g} at t = {t[i + 1]} s (a heading in degrees "
            "wrapping by 360); convert it to radians (numpy.radians)"
        )


#: A step of a continuous heading [rad] between two samples beyond this, three quarters of a turn,
#: is a wrap when the whole heading stays within one turn: a wrap at +-pi steps by a turn less what
#: the heading turns in one interval (a quarter turn per sample would be a 90 deg/s turn at 1 Hz);
#: a continuous heading steps that far only across a gap or between sparse samples, where it has
#: mostly turned beyond one turn's range.
WRAP_STEP = 1.5 * math.pi


def warn_if_wrapped(t: FloatArray, heading: FloatArray, hint: str = "") -> None:
    """Warn where a heading taken as continuous [rad] stays within one turn and yet steps by more
    than :data:`WRAP_STEP` between two samples: a heading wrapped to +-pi (or 0 .. 2 pi), each wrap
    of which counts as a turn (a wrapped estimate scored 267 deg against its own continuous self,
    and dead reckoning lost each wrap's step without a word). ``hint``: another remedy, appended."""
    steps = np.diff(heading)
    i = int(np.argmax(np.abs(steps)))
    if abs(steps[i]) > WRAP_STEP and np.ptp(heading) <= 2 * math.pi:
        warn(f"the heading jumps by {steps[i]:.6g} rad from {heading[i]:.6g} at t = {t[i]} to {heading[i + 1]:.6g} "
             f"at t = {t[i + 1]} s, more than three quarters of a turn between two samples: it looks wrapped, and "
             f"it is taken as a continuous heading, each wrap counting as a turn; give the continuous heading "
             f"(numpy.unwrap){hint}")


_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
#: A context manager of the package that warns as it exits (a file's notes, raised again) is left
#: through contextlib's frames, which are no caller's either.
_CONTEXTLIB = os.path.abspath(contextlib.__file__)


#: Where :func:`warn` puts its messages on this thread instead of raising them (see :func:`collected`).
_collector = threading.local()


@contextlib.contextmanager
def collected(notes: list[str]) -> Iterator[None]:
    """Within the block, :func:`warn` on this thread appends its message to ``notes`` instead of
    raising it. The warnings module's filters and hooks are global (``catch_warnings`` is not
    thread-safe), so files of a batch on parallel threads recording their warnings with it lost or
    swapped each other's."""
    previous = getattr(_collector, "notes", None)
    _collector.notes = notes
    try:
        yield
    finally:
        _collector.notes = previous


def keep_readings(what: str, hold: str, skip: str) -> str:
    """What to do about a reading the pipeline does not take, besides editing the data: the input
    policy, spelled ``hold`` and ``skip`` where the caller gives it (a keyword, a command-line
    option); ``what`` is what is kept ("them", "the file as it is")."""
    return f"or keep {what}: {hold} uses the last usable reading there, {skip} leaves the sample out"


def warn(message: str) -> None:
    """Emit an :class:`InputWarning` attributed to the first caller outside this package (or
    collect it, inside :func:`collected` on this thread)."""
    notes = getattr(_collector, "notes", None)
    if notes is not None:
        notes.append(message)
        return
    # stacklevel 1 is this function; 2 its caller, and so on up to the first frame outside.
    level = 2
    frame: types.FrameType | None = sys._getframe(1)
    while frame is not None and _inside(os.path.abspath(frame.f_code.co_filename)):
        level, frame = level + 1, frame.f_back
    warnings.warn(message, InputWarning, stacklevel=level)


def _inside(path: str) -> bool:
    """Whether code in the file ``path`` is the package's (or contextlib's, running the package's)."""
    return path.startswith(_PACKAGE_DIR) or path == _CONTEXTLIB


def warn_of_file(path: str, messages: Iterable[str]) -> None:
    """Raise a file's warnings again for a caller of the API, each once, naming the file (the
    files of a batch often say the same words)."""
    for message in dict.fromkeys(messages):
        warn(message if message.startswith(f"{path}: ") else f"{path}: {message}")


def warn_units(t: FloatArray, rate: FloatArray) -> None:
    """Emit an :class:`InputWarning` for each unit problem."""
    for message in unit_problems(t, rate):
        warn(message)


def usable(values: FloatArray) -> np.ndarray:
    """Which of ``values`` the core takes as readings: finite and within :data:`MAX_READING`
    (the others it refuses, or holds or skips)."""
    return np.asarray(np.abs(values) < MAX_READING)  # NaN compares False


def no_usable_log(count: int) -> str:
    """The error of a log none of whose ``count`` readings the core takes: under
    ``nonfinite="hold"`` or ``"skip"`` it gave a heading of 0 throughout, made of no data."""
    return (f"no usable reading: all {count} readings are NaN or beyond +-2^20 rad/s, so there is no "
            "heading to give (nonfinite='hold' or 'skip' carries a log over some bad readings, not over all): "
            "check the rates and their unit")


class NoUsableReading(ValueError):
    """A whole log none of whose readings the core takes (:func:`refuse_no_usable_reading`): a
    ValueError a caller that knows the log's file can name it in."""


def refuse_no_usable_reading(values: FloatArray, nonfinite: str | None) -> None:
    """Refuse a whole log of rate ``values`` none of which is usable, under an input policy
    ``nonfinite`` that would hold or skip them all (``"error"``, the default, names the first
    one by its sample, which says more)."""
    if nonfinite in ("hold", "skip") and len(values) and not usable(values).any():
        raise NoUsableReading(no_usable_log(len(values)))


def require_readings(what: str, values: FloatArray) -> None:
    """The core's :class:`~gyrocore.SampleError` for the first of ``values`` (``what``: ``rate`` or
    ``temperature``) that is not finite or beyond :data:`MAX_READING`, naming its index; nothing if
    every value is usable. The core's own check of a block, so that its words and limit are the
    one rule."""
    times = np.arange(len(values), dtype=np.float64)  # valid times: the reading is what fails
    rate, temperature = (values, None) if what == "rate" else (np.zeros(len(values)), values)
    _gyrocore.check_samples(times, rate, temperature)


def require_times(t: FloatArray) -> None:
    """The core's :class:`~gyrocore.SampleError` for the first of the times ``t`` that is not
    finite, does not increase or lies beyond +-2^40 s, naming its index; nothing if all are
    usable. The core's own check of a block (the readings all valid), one rule and its words,
    where a time steps back or repeats with what explains it (:func:`time_steps_named`)."""
    with time_steps_named(t):
        _gyrocore.check_samples(t, np.zeros(len(t)), None)


def real_number(value: object) -> float | None:
    """``value`` as a float if it is one real number (an int, a float, a numpy scalar of either, or a
    0-d array of one), else None: not a bool, whose True would pass for 1 (``bias=True`` was a bias
    of 1 rad/s), nor text, which ``float()`` would parse ("0.01" passed for a number), nor None, nor
    a numpy duration or date (an integer type to numpy, for which ``float()`` raised a bare
    TypeError naming neither the argument nor its unit), nor a masked value (``numpy.ma.masked``,
    numpy.ma's mean of samples all masked), which reads as 0.0 or NaN."""
    if np.ma.is_masked(value):
        return None
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return float(value)
    if isinstance(value, (bool, np.bool_, np.timedelta64, np.datetime64)) or not isinstance(value, numbers.Real):
        return None
    try:
        return float(value)
    except OverflowError:  # an int (or Fraction) beyond float64, 10**400: out of every range, as inf is
        return math.inf if cast(Any, value) > 0 else -math.inf


def shown(value: object, limit: int = 40) -> str:
    """``value`` for an error message (a number as it reads, anything else as its ``repr``), cut
    to about ``limit`` characters: an int of 400 digits filled the message, and one beyond
    Python's 4300 digits could not be shown at all."""
    try:
        # a number as it reads (numpy 2 writes np.float64(-1.0)), anything else as Python shows it
        text = str(value) if isinstance(value, (numbers.Real, np.generic)) and not isinstance(value, bool) else repr(value)
    except ValueError:  # int's limit of digits
        return f"an int of {value.bit_length()} bits" if isinstance(value, int) else type(value).__name__
    return text if len(text) <= limit else f"{text[:limit // 2]}...{text[-8:]} ({len(text)} characters)"


def check_number(
    name: str, value: object, *, low: float | None = 0.0, strict: bool = True, high: float | None = None, unit: str = ""
) -> float:
    """``value`` as a float, checked: a real number (:func:`real_number`; else a TypeError), finite,
    above ``low`` (at least ``low`` with ``strict=False``; any with None) and at most ``high`` where
    given (else a ValueError), each naming ``name`` with its ``unit`` (e.g. ``" [s]"``)."""
    x = real_number(value)
    if x is None:
        raise TypeError(f"{name} must be a number{unit}, got {value!r}")
    above = low is None or (x > low if strict else x >= low)
    if not (math.isfinite(x) and above and (high is None or x <= high)):
        least = "" if low is None else f" and {'>' if strict else '>='} {low:g}"
        most = "" if high is None else f" and at most {high:g}"
        raise ValueError(f"{name} must be finite{least}{most}{unit}, got {shown(value)}")
    return x


def json_ready(row: dict[str, Any]) -> dict[str, Any]:
    """``row`` as :func:`json_value` makes any value JSON-ready (a result's ``as_dict``)."""
    return {k: json_value(v) for k, v in row.items()}


def json_value(data: Any) -> Any:
    """``data`` with each float that is not finite, at any depth of its dicts, lists and tuples, as
    None: JSON has no inf or NaN (``json.dumps`` writes ``Infinity``, which strict parsers refuse)."""
    if isinstance(data, float):
        return data if math.isfinite(data) else None
    if isinstance(data, dict):
        return json_ready(data)
    if isinstance(data, (list, tuple)):
        items = [json_value(v) for v in data]
        return tuple(items) if type(data) is tuple else items
    return data


def check_count(name: str, value: object) -> int:
    """``value`` as an int >= 1 (a count: runs, readings per bin); a ValueError naming ``name``
    otherwise (a bool, 2.5 or 0 were taken, or failed as "'float' object cannot be interpreted as
    an integer")."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be a whole number >= 1, got {value!r}")
    return int(value)


def check_seed(seed: object, bits: int = 64) -> int:
    """``seed`` as an int in [0, 2^bits) (numpy's PCG64 and the core's generators take no other;
    scipy's optimisers, numpy's legacy generator, take 32 bits); a ValueError otherwise (numpy's
    own for -1 was "expected non-negative integer")."""
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or not 0 <= seed < 2**bits:
        raise ValueError(f"seed must be an integer in [0, 2**{bits}), got {seed!r}")
    return int(seed)


def require_flag(name: str, value: object) -> None:
    """A TypeError unless ``value`` is a bool: a switch given as text ("no") read as True."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {value!r}")


def _prefix(context: str) -> str:
    return f"{context}: " if context else ""


def require_finite(name: str, values: FloatArray, *, context: str = "") -> None:
    """A ValueError naming the first value of ``values`` that is not finite (the core's words): its
    index (``rate[3]``, of an array of more dimensions ``rate[1, 2]``; a 0-d array: ``rate``)."""
    bad = np.flatnonzero(~np.isfinite(values))
    if len(bad):
        where = tuple(int(k) for k in np.unravel_index(bad[0], np.shape(values)))
        label = f"{name}[{', '.join(map(str, where))}]" if where else name
        raise ValueError(f"{_prefix(context)}{label} is {values[where]}: samples must be finite (drop or fill them first)")


def first_infinite(values: FloatArray) -> int | None:
    """The index of the first infinite value of ``values``, or None (NaN is no infinity: a value
    unknown there, where the caller allows one)."""
    bad = np.flatnonzero(np.isinf(values))
    return int(bad[0]) if len(bad) else None


def require_increasing(name: str, t: FloatArray, *, context: str = "") -> None:
    """A ValueError naming the first time of ``t`` that is not after the one before it, and what to
    do: sort them, or what explains the step (:func:`~gyrocore._time_steps.why_times_step_back`)."""
    back = np.flatnonzero(np.diff(t) <= 0)
    if len(back):
        i = int(back[0]) + 1
        raise ValueError(
            f"{_prefix(context)}{name} must strictly increase: {name}[{i}] = {t[i]} follows {t[i - 1]} "
            + (why_times_step_back(t, i, float(t[i - 1])) or "(sort them and drop duplicate times)")
        )


def require_series(t_name: str, t: FloatArray, name: str, values: FloatArray, *, context: str = "") -> None:
    """Values at times: equal lengths, every value finite, times strictly increasing; a
    ValueError naming ``context``, the array and the first offending index otherwise."""
    if len(t) != len(values):
        raise ValueError(f"{_prefix(context)}{name} has {len(values)} samples but {t_name} has {len(t)}")
    require_finite(t_name, t, context=context)
    require_finite(name, values, context=context)
    require_increasing(t_name, t, context=context)


def require_choice(what: str, value: object, choices: Iterable[str]) -> None:
    """Refuse ``value`` unless it is one of ``choices``: ``unknown <what> 'x' (did you mean
    'y'?); choose one of ...``, the one form of every such error."""
    names = tuple(choices)
    if not isinstance(value, str):  # a 1-element array of "whole" compared equal, and passed
        raise TypeError(f"{what} must be a name, one of {', '.join(names)}; got {type(value).__name__} {value!r}")
    if value not in names:
        raise ValueError(f"unknown {what} {value!r}{did_you_mean(value, names)}; choose one of {', '.join(names)}")


def require_options(what: str, options: Iterable[str], names: Iterable[str]) -> None:
    """Refuse a keyword ``options`` passes on that is none of ``names``, the options of ``what``
    (the function that takes them): a TypeError naming it, a likely meant one, and the choices.
    Passed on, a typo was Python's "from_gnss() got an unexpected keyword argument 'min_sped'",
    naming a function the caller never called."""
    known = tuple(names)
    unknown = [k for k in options if k not in known]
    if unknown:
        said = ", ".join(f"{k!r}{did_you_mean(k, known)}" for k in unknown)
        raise TypeError(f"unknown option(s) {said} of {what}; choose from {', '.join(known)}")


def keyword_options(function: Callable[..., Any]) -> tuple[str, ...]:
    """The names of ``function``'s keyword-only parameters, the options a caller may pass on."""
    return tuple(p.name for p in inspect.signature(function).parameters.values() if p.kind is p.KEYWORD_ONLY)


def require_version(what: str, found: object, reads: int, where: str = "") -> None:
    """Refuse a saved file whose ``"version"`` (``found``) is not the one this gyrocore ``reads``
    (``true`` is not 1, though Python finds them equal): a later one was written by a newer
    gyrocore, whose user upgrades; a missing or malformed one is named as such. ``what`` is the
    file's kind (``parameter file``); ``where`` goes before the message (the file's name)."""
    if found != reads or isinstance(found, bool):
        raise ValueError(where + _version_error(what, found, reads))


def _version_error(what: str, found: object, reads: int) -> str:
    if isinstance(found, int) and not isinstance(found, bool) and found > reads:
        return (f"{what} version {found}, written by a newer gyrocore; this one reads version {reads}: upgrade "
                "gyrocore to read it, or write the file again with this one")
    if found is None:
        return f"{what} without a \"version\" (this gyrocore writes and reads version {reads})"
    return f"{what} version {found!r}; this gyrocore reads version {reads}"


def did_you_mean(value: object, choices: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the one of ``choices`` that ``value`` is a likely typo, another
    case or the start of (``recomended``, ``HDR``, ``lowpas_tau``, ``sigma`` for ``sigma_deg``), to
    follow the name in an error; empty when none or several are as close. Every "unknown name"
    error of the package says it the same way, also the extension's (which calls this)."""
    if not isinstance(value, str) or not value:
        return ""
    lowered = {c.lower(): c for c in choices}
    typed = value.lower()
    starts = [c for c in lowered if c.startswith(typed)]
    if len(starts) == 1:
        best = lowered[starts[0]]
    else:
        ranked = sorted(((difflib.SequenceMatcher(None, typed, c).ratio(), c) for c in lowered), reverse=True)
        # 0.8: a typo of one or two letters in a name; --bias-window and --up-window share 0.75
        if not ranked or ranked[0][0] < 0.8 or (len(ranked) > 1 and ranked[1][0] == ranked[0][0]):
            return ""  # nothing close, or two as close (hdr_c: hdr_c1 or hdr_c2?)
        best = lowered[ranked[0][1]]
    return f" (did you mean {best!r}?)" if best != value else ""


def public_dir(module: str) -> Callable[[], list[str]]:
    """The ``__dir__`` of the module named ``module`` (PEP 562), which ``dir()`` and tab completion
    list: its ``__all__`` and its underscored names (which completion hides), not the names it
    imports for itself (``np``, ``Any``) nor the modules loaded as parts of it."""
    def names() -> list[str]:
        namespace = vars(sys.modules[module])
        return sorted(set(namespace["__all__"]) | {name for name in namespace if name.startswith("_")})
    return names

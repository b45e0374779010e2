"""Units of a file, and a check that the values read look like the units they were read in.

Timestamps come in ``s``, ``ms``, ``us`` or ``ns`` and rates in ``rad/s`` or ``deg/s``; the readers
convert them to s and rad/s. :class:`UnitCheck` then names the option that would fix values that
look like another unit (rates in deg/s read as rad/s, an epoch in ms read as s, ...).
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._arrays import FloatArray, durations_in_seconds, warn_coarse_times, warn_merged_counts
from .._checks import INTERVAL_LIMIT, SUBSET_SIZE, typical_interval, unit_problems

if TYPE_CHECKING:
    from .read_options import ReadOptions

#: Time units of a file, as counts per second.
TIME_UNITS = {"s": 1.0, "ms": 1e3, "us": 1e6, "ns": 1e9}
#: Rate units of a file.
RATE_UNITS = ("rad/s", "deg/s")
#: How a header may write each unit, normalised by :func:`normal_unit` (lower case; no spaces, ``*``,
#: ``.`` or ``^``), e.g. ``#timestamp [ns]``, ``w_RS_S_x [rad s^-1]``, ``gyro_z_dps``, ``t_ms``.
HEADER_TIME_UNITS = {
    **dict.fromkeys(("s", "sec", "secs", "second", "seconds"), "s"),
    **dict.fromkeys(("ms", "msec", "millisecond", "milliseconds"), "ms"),
    **dict.fromkeys(("us", "\u00b5s", "\u03bcs", "usec", "microsecond", "microseconds"), "us"),
    **dict.fromkeys(("ns", "nsec", "nanosecond", "nanoseconds"), "ns"),
}
HEADER_RATE_UNITS = {
    **dict.fromkeys(("rad/s", "rads-1", "rad/sec", "radps", "rad_s"), "rad/s"),
    **dict.fromkeys(("deg/s", "degs-1", "deg/sec", "degps", "dps", "\u00b0/s", "deg_s"), "deg/s"),
}
#: A unit in brackets or parentheses at the end of a column name: ``t [s]``, ``rate (deg/s)``.
_BRACKETED = re.compile(r"^(?P<base>.*?)\s*(?:\[(?P<square>[^\]]*)\]|\((?P<round>[^)]*)\))$")
#: A yaw rate that never exceeds this [deg/s] over a whole log is more likely in rad/s.
SMALL_RATE_DPS = 3.0
#: A median interval below this [s] (above 10 kHz) suggests timestamps in a larger unit.
SHORT_INTERVAL = 1e-4
#: Timestamps beyond this [s] (the year 5138) are an epoch in ms, us or ns.
EPOCH_LIMIT = 1e11
#: Unix epoch seconds of the years 2001 to 2096: whole-number times there are seconds, not ms.
EPOCH_SECONDS = (1e9, 4e9)
#: How the problem that names another time unit begins.
_TIME_PROBLEM = "timestamps look like"
#: Intervals are judged on this many first samples, whatever the chunks are.
HEAD_SAMPLES = 1 << 16


class UnitCheck:
    """Checks that a stream of samples looks like the units it was read in.

    Feed it every chunk (in SI units, after conversion); :meth:`problems` then lists what looks like
    another unit. Intervals are judged on the first :data:`HEAD_SAMPLES` samples (however they
    were chunked); rates on the whole stream, since a log may begin with a long rest: large ones
    as :func:`gyrocore.process` judges an array, on a regular subset of the stream's rates (kept
    only where they are read in rad/s), small ones on the largest ``|rate|``.
    """

    def __init__(self, options: ReadOptions) -> None:
        self._options = options
        self._first: list[str] | None = None
        self._head: list[FloatArray] = []  # the first samples' times, until judged
        self._head_samples = 0
        self._max_rate = 0.0
        self._last_time: float | None = None
        self._intervals = 0
        self._gaps = 0  # intervals longer than INTERVAL_LIMIT
        # every ``_stride``-th rate of the stream (a regular subset of bounded size, the stride
        # doubled as it fills): a 500 Hz log in deg/s whose turns began after its first 131 s
        # (HEAD_SAMPLES) was never told of its unit. Kept only for a log read in rad/s, the one
        # unit they can show to be another's (a log in deg/s is never told it is in deg/s).
        self._judges_rates = options.rate_unit == "rad/s"
        self._subset: list[FloatArray] = []
        self._stride = 1
        self._seen = 0
        self._kept = 0

    def update(self, t: FloatArray, rate: FloatArray) -> None:
        """Account for one chunk (t [s], rate [rad/s])."""
        largest = np.max(np.abs(rate), initial=0.0, where=np.isfinite(rate))
        self._max_rate = max(self._max_rate, float(largest))
        if self._judges_rates:
            self._keep_subset(rate)
        if len(t):
            edges = t if self._last_time is None else np.concatenate(([self._last_time], t))
            self._intervals += len(edges) - 1
            # Times that are not finite (inf - inf) are the core's error right after this, which
            # names the sample: numpy's "invalid value" warning before it would only confuse. An
            # interval of such a time is no gap, so that it never reads as a unit's fault.
            with np.errstate(invalid="ignore"):
                d = np.diff(edges)
                self._gaps += int(np.count_nonzero(np.isfinite(d) & (d > INTERVAL_LIMIT)))
            self._last_time = float(t[-1])
        if self._first is None:
            self._head.append(t[:HEAD_SAMPLES])
            self._head_samples += len(t)
            if self._head_samples >= HEAD_SAMPLES:
                self._judge_head()

    def _keep_subset(self, rate: FloatArray) -> None:
        """Keep the rates of the stream's samples ``0, s, 2 s, ...`` (``s``: the stride), at most
        about 2 :data:`~gyrocore._checks.SUBSET_SIZE` of them, whatever the chunks."""
        kept = np.array(rate[(-self._seen) % self._stride :: self._stride])
        if len(kept):  # a chunk between two samples of the stride adds none (kept empty, they grew with the log)
            self._subset.append(kept)
        self._seen += len(rate)
        self._kept += len(kept)  # counted, not summed over the list: a long log's list is long
        while self._kept > 2 * SUBSET_SIZE:
            whole = np.concatenate(self._subset)[::2]
            self._subset, self._kept, self._stride = [whole], len(whole), self._stride * 2

    def problems(self) -> list[str]:
        """What looks like another unit, with the option that would fix it."""
        if self._first is None:
            self._judge_head()
        problems = []
        if self._judges_rates and self._subset:
            # the check of gyrocore.process (it judges rates only when given one timestamp)
            rates = np.concatenate(self._subset)
            problems += [f"{p}; or use rate_unit='deg/s' (--rate-unit deg/s)" for p in unit_problems(rates[:1], rates)]
        problems += self._first or []
        max_dps = math.degrees(self._max_rate)
        small = self._first is not None and max_dps < SMALL_RATE_DPS and not self._options.static
        # a unit the file's header states is its own word, not a guess: a still recording in deg/s
        # reads small rates, and the option the warning named contradicted the header (an error)
        if self._options.rate_unit == "deg/s" and small and not _header_states_deg(self._options):
            problems.append(
                f"rates look like rad/s, not deg/s: |rate| never exceeds {max_dps:.3g} deg/s, which only a "
                f"sensor that never turned reads; if the log is in rad/s, use rate_unit='rad/s' (--rate-unit rad/s)"
            )
        return problems

    def error(self) -> str | None:
        """Why the stream cannot be a gyro log in the units it was read in, or None: every interval
        is longer than a gap (a log in ns read as s has nothing but gaps)."""
        if self._intervals == 0 or self._gaps < self._intervals:
            return None
        if self._first is None:
            self._judge_head()
        fix = self.time_fix() or f"give the unit of the time column with --time-unit ({', '.join(TIME_UNITS)})"
        return f"each of the {self._intervals} intervals is longer than {INTERVAL_LIMIT:g} s, a gap: {fix}"

    def time_fix(self) -> str | None:
        """The problem that says which time unit the timestamps look like, if one does (so an
        error about a timestamp can name the option that fixes it)."""
        if self._first is None:
            self._judge_head()
        return next((p for p in self._first or [] if p.startswith(_TIME_PROBLEM)), None)

    def _judge_head(self) -> None:
        """Judge the first samples (at most :data:`HEAD_SAMPLES`, whatever the chunks were), once
        they hold an interval."""
        if self._head_samples < 2:
            return
        t = np.concatenate(self._head)[:HEAD_SAMPLES]
        self._first, self._head = self._first_chunk_problems(t), []

    def _first_chunk_problems(self, t: FloatArray) -> list[str]:
        o = self._options
        problems = []
        unit = o.time_unit or "s"
        t0 = abs(float(t[0]))
        interval = typical_interval(t) if len(t) > 1 else 0.0  # one gap does not make it look like ms
        rest = ""
        if t0 > EPOCH_LIMIT:
            # an epoch read in too small a unit: which unit puts it between 1973 and 2286?
            counts = t0 * TIME_UNITS[unit]
            fits = [u for u, k in TIME_UNITS.items() if 1e8 <= counts / k <= 1e10]
            why = f"t[0] = {t[0]:.6g} s is after the year 5000"
        elif interval > 0 and not SHORT_INTERVAL <= interval <= INTERVAL_LIMIT:
            counts = interval * TIME_UNITS[unit]
            fits = [u for u, k in TIME_UNITS.items() if SHORT_INTERVAL <= counts / k <= INTERVAL_LIMIT]
            why = f"the median interval is {interval:.3g} s, a {1 / interval:.3g} Hz gyro"
        elif self._whole_ms(t, interval):
            fits = ["ms"]
            why = f"whole numbers {interval:g} apart, a {1 / interval:g} Hz gyro in s or a {1000 / interval:g} Hz one in ms"
            rest = "; for a gyro that does run so slowly, give time_unit='s' (--time-unit s) or a header t [s]"
        else:
            fits = []
        if fits:
            problems.append(
                f"{_TIME_PROBLEM} {' or '.join(fits)}, not {unit}: {why}; "
                f"use time_unit='{fits[0]}' (--time-unit {fits[0]}){rest}"
            )
        return problems

    def _whole_ms(self, t: FloatArray, interval: float) -> bool:
        """Whether the times ``t`` [s] look like ms read as s: whole numbers 1 or 2 apart (a 1 kHz
        or 500 Hz gyro in ms reads as a 1 Hz or 0.5 Hz one in s, within the intervals judged
        sound), read in s for want of a unit, and not Unix epoch seconds (2001 to 2096)."""
        if not getattr(self._options, _ASSUMED_TIME_UNIT, False) or interval not in (1.0, 2.0):
            return False
        return not EPOCH_SECONDS[0] <= abs(float(t[0])) <= EPOCH_SECONDS[1] and bool(np.all(t == np.round(t)))


def _header_states_deg(options: ReadOptions) -> bool:
    """Whether the rate column's name (or a gyro column's) states deg/s (``gyro_z_dps``, ``wz [deg/s]``)."""
    columns = options.gyro_cols if options.gyro_cols is not None else (options.rate,)
    return any(rate_unit_named(split_unit(c)[1] or "") == "deg/s" for c in columns)


def normal_unit(unit: str) -> str:
    return re.sub(r"[\s*.^]", "", unit.lower())


def time_unit_named(text: str) -> str:
    """``text`` as one of :data:`TIME_UNITS` where it is a spelling a header may state (``sec``,
    ``msec``, ``nanoseconds``), else as given (and then refused where it is checked): the option
    took only ``s`` where a header read ``t_sec``."""
    return HEADER_TIME_UNITS.get(normal_unit(text), text) if isinstance(text, str) else text


def rate_unit_named(text: str) -> str:
    """``text`` as one of :data:`RATE_UNITS` where it is a spelling a header may state (``dps``,
    ``deg/sec``, ``°/s``), else as given, as :func:`time_unit_named`."""
    return HEADER_RATE_UNITS.get(normal_unit(text), text) if isinstance(text, str) else text


def is_unit(text: str) -> bool:
    """Whether ``text`` is a time or rate unit as a header writes it, alone (``s``, ``[deg/s]``,
    ``(ms)``): what a row of units under a header holds."""
    m = _BRACKETED.match(text.strip())
    unit = normal_unit(text if m is None or m["base"] else (m["square"] if m["square"] is not None else m["round"]))
    return unit in HEADER_TIME_UNITS or unit in HEADER_RATE_UNITS


def split_unit(column: str) -> tuple[str, str | None]:
    """A column name without the unit it states, and that unit as written (None if it states none).

    ``#timestamp [ns]`` -> ``("timestamp", "ns")``; ``gyro_z_dps`` -> ``("gyro_z", "dps")``;
    ``gyro_z_deg_s`` -> ``("gyro_z", "deg_s")``; ``t`` -> ``("t", None)``. A ``_suffix`` counts as a
    unit only if it is one (``gyro_z`` has none); a number in square brackets is an array's element,
    not a unit (PX4's ``gyro_rad[2]`` -> ``("gyro_rad[2]", None)``).
    """
    name = column.strip().lstrip("#").strip()
    m = _BRACKETED.match(name)
    if m and m["base"] and not (m["square"] or "").strip().isdigit():  # gyro_rad[2] is an array's element
        return m["base"], (m["square"] if m["square"] is not None else m["round"]).strip()
    for words in (2, 1):  # a unit of two words first: gyro_z_deg_s is in deg_s, not in s
        base, *suffix = name.rsplit("_", words)
        unit = normal_unit("_".join(suffix))
        if len(suffix) == words and base and (unit in HEADER_TIME_UNITS or unit in HEADER_RATE_UNITS):
            return base, "_".join(suffix)
    return name, None


def _header_column(path: Path, header: list[str], wanted: str, option: str) -> str:
    """The header name of column ``wanted``: itself, or the one column that is ``wanted`` with a
    unit (``t`` finds ``t [s]`` or ``t_ms``). A missing column is left to the reader to report."""
    if wanted in header:
        return wanted
    matches = [h for h in header if split_unit(h)[0] == wanted]
    if len(matches) > 1:
        raise ValueError(
            f"{path}: column {wanted!r} matches {', '.join(map(repr, matches))}; give the whole name ({option})"
        )
    return matches[0] if matches else wanted


def _stated_unit(path: Path, column: str, given: str | None, option: str, default: str) -> tuple[str, bool]:
    """The unit of ``column``: the one given, else the one its name states, else ``default``; and
    whether it is ``default`` for want of the other two."""
    kind = "time" if option == "--time-unit" else "rate"
    table, choices = (HEADER_TIME_UNITS, TIME_UNITS) if kind == "time" else (HEADER_RATE_UNITS, RATE_UNITS)
    written = split_unit(column)[1]
    if written is None:
        return given or default, given is None
    stated = table.get(normal_unit(written))
    # a known unit of the other kind in a ``_suffix`` is part of the name (``t_dps`` is no time unit)
    if stated is None and written == column.rpartition("_")[2]:
        return given or default, given is None
    where = f"{path}: column {column!r} states the unit {written!r}"
    if stated is None and given is None:
        raise ValueError(
            f"{where}, which is not a {kind} unit gyrocore reads ({', '.join(choices)}): convert the column, "
            f"or read it as one of those with {option}"
        )
    if stated is not None and given is not None and given != stated:
        raise ValueError(f"{where} but {option} {given} was given: leave out {option} (or correct the header)")
    unit = given or stated
    assert unit is not None  # one was given, or the name states one (else the first error above)
    return unit, False


def header_options(path: Path, header: list[str] | None, options: ReadOptions) -> ReadOptions:
    """``options`` with the time and rate columns named as in ``header`` and their units taken from
    the header where it states them (and no unit was given); for a file without column names
    (``header`` None) the units given, else s and rad/s.

    Raises:
        ValueError: a header unit gyrocore does not read (naming the option to give instead), a unit
            given that contradicts the header, or a column name that matches several columns.
    """
    if header is None:
        return replace(options, time_unit=options.time_unit or "s", rate_unit=options.rate_unit or "rad/s")
    time = _header_column(path, header, options.time, "--time-col")
    time_unit, assumed = _stated_unit(path, time, options.time_unit, "--time-unit", "s")
    if options.gyro_cols is None:
        rate = _header_column(path, header, options.rate, "--rate-col")
        rate_unit = _stated_unit(path, rate, options.rate_unit, "--rate-unit", "rad/s")[0]
        return _assumed(replace(options, time_col=time, rate_col=rate, time_unit=time_unit, rate_unit=rate_unit),
                        assumed)
    gyro = _header_columns(path, header, options.gyro_cols, "--gyro-cols")
    units = [_stated_unit(path, c, options.rate_unit, "--rate-unit", "rad/s")[0] for c in gyro]
    if len(set(units)) > 1:
        read = ", ".join(f"{c!r} as {u}" for c, u in zip(gyro, units))
        raise ValueError(f"{path}: the gyro columns read in different units ({read}): give each its unit in the header")
    accel = None if options.accel_cols is None else _header_columns(path, header, options.accel_cols, "--accel-cols")
    return _assumed(
        replace(options, time_col=time, gyro_cols=gyro, accel_cols=accel, time_unit=time_unit, rate_unit=units[0]),
        assumed,
    )


#: The reader's note on :class:`ReadOptions` (an attribute, not a field: no option a user gives):
#: the time unit is ``s`` only because neither an option nor the header gave one.
_ASSUMED_TIME_UNIT = "_assumed_time_unit"


def _assumed(options: ReadOptions, assumed: bool) -> ReadOptions:
    """``options`` noted as read in seconds only for want of a unit (a ``replace`` leaves it out)."""
    object.__setattr__(options, _ASSUMED_TIME_UNIT, assumed)  # frozen: set as __post_init__ sets its forms
    return options


def _header_columns(path: Path, header: list[str], wanted: tuple[str, str, str], option: str) -> tuple[str, str, str]:
    """The header names of the three columns ``wanted`` (see :func:`_header_column`)."""
    x, y, z = (_header_column(path, header, c, option) for c in wanted)
    return (x, y, z)


def seconds_from_counts(raw: np.ndarray, per_second: float) -> FloatArray:
    """Timestamps [s] from counts of a unit; division (not multiplication by 1e-3) rounds once.
    Durations (timedelta64 in .npy and .npz files) carry their own unit; datetime64 times are
    their durations since the Unix epoch (a view: the counts are the same)."""
    if raw.dtype.kind == "M":
        raw = raw.view(raw.dtype.str.replace("M8", "m8"))
    if raw.dtype.kind == "m":
        return np.asarray(durations_in_seconds("the time column", raw), dtype=np.float64)
    warn_coarse_times(raw, per_second)
    t = np.asarray(raw, dtype=np.float64)
    if per_second == 1.0:
        return t
    t = t / per_second
    warn_merged_counts(raw, t, per_second)
    return t

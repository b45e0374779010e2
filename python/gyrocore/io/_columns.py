"""What the format readers and the writer share: finding the named columns, column data as numpy
arrays, and pyarrow's lazy import done where an interrupt is not lost."""

from __future__ import annotations

import functools
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .. import _signals
from .._arrays import FloatArray
from .._checks import warn
from .units import HEADER_TIME_UNITS, normal_unit, split_unit

if TYPE_CHECKING:
    import pyarrow as pa


#: What to do about a missing column of gyro data: the reading options name another.
CHOOSE_COLUMNS = "choose with time_col/rate_col, --time-col/--rate-col"
#: What to do with columns aligned by runs of spaces, which no one delimiter separates.
ALIGNED = ("its columns aligned with runs of spaces, which no delimiter separates (--delimiter ' ' reads empty "
           "columns between them): convert the file, e.g. awk -v OFS=, '{$1=$1; print}' old.csv > new.csv")


def column_positions(
    path: Path,
    header: list[str],
    columns: tuple[str, ...],
    choose: str = CHOOSE_COLUMNS,
    *,
    where: str = "",
    times: tuple[str, ...] = (),
) -> dict[str, int]:
    """Where each of ``columns`` is in ``header`` (column, field or array names of ``path``);
    ``choose`` says what to do about a missing one; ``where`` is the header's place in an error
    (``"line 1: "`` in a CSV file; a Parquet file or an archive has no lines); ``times`` are the
    columns whose type is a time (a Parquet timestamp), which look like the time whatever their name.

    Raises:
        ValueError: a column is missing or appears more than once.
    """
    missing = [c for c in columns if c not in header]
    if missing and choose == CHOOSE_COLUMNS and _heading_table(header):
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)}; it has {', '.join(map(str, header))}, "
                         "the columns of a heading table gyrocore writes: give the log it was made from (inputs that "
                         "reach an earlier run's output folder: leave that folder out), or for a gyro's log of these "
                         f"columns {CHOOSE_COLUMNS}")
    if missing:
        with_unit = [split_unit(str(h)) for h in header if split_unit(str(h))[1] is not None]
        short = f"; a name may leave out its unit, e.g. {with_unit[0][0]}" if with_unit else ""
        # a space last: it may be part of a name, but one field cannot hold both of a log's columns
        found = [d for d in ",;\t| " if len(header) == 1 and d in str(header[0]).strip()]
        if found:
            shown = "a tab" if found[0] == "\t" else repr(found[0])
            # the reading options (--delimiter) are the gyro's: another file given them was told to use one
            given = (f"give the file's delimiter (delimiter={found[0]!r}, {delimiter_option(found[0])})"
                     if choose == CHOOSE_COLUMNS
                     else f"such a file is read comma-separated: separate its fields with ',' (not {shown})")
            short = f"; the header line is one field, with {shown} in it: {given}"
            if found[0] == " " and "  " in str(header[0]).strip():  # --delimiter ' ' would split it into empty names
                short = f"; the header line is one field, {ALIGNED}"
        if choose == CHOOSE_COLUMNS and not found:  # the one field is the whole header line, no column
            short += _look_like(header, missing, times)
        if any(not str(h).strip() for h in header):  # "it has , gyro_z": a column no option can name
            short += ("; a column without a name (as pandas' df.to_csv() writes an unnamed index) cannot be chosen: "
                      "name it, e.g. df.to_csv(path, index_label='t')")
        if header and all(is_number(str(h).strip(" \t")) for h in header):  # "it has 0, 0.1" left the cause to guess
            names = [*columns[: len(header)], *(f"col{k + 1}" for k in range(len(columns), len(header)))]
            short += (f"; its first line holds numbers, not column names: the file has no header line; add one "
                      f"as its first line, e.g. {','.join(names)}")
        listed = ", ".join(str(h) or "''" for h in header)  # an unnamed column shown, not an empty place
        raise ValueError(
            f"{path}: missing column(s) {', '.join(missing)}; it has {listed or 'none'} "
            f"({choose}{short})"
        )
    twice = [c for c in columns if header.count(c) > 1]
    if twice:
        raise ValueError(f"{path}: {where}column(s) {', '.join(twice)} appear more than once")
    return {c: header.index(c) for c in columns}


def _heading_table(header: list[str]) -> bool:
    """Whether ``header`` names the columns of a heading table gyrocore writes (a heading, and
    nothing but the writer's columns): the hint to choose a rate column led to processing an
    output again, its corrected rate taken for the gyro's."""
    from .writer import FIX_COLUMNS, OUTPUT_COLUMNS  # the writer imports this module

    names = {split_unit(str(h))[0] for h in header}
    return "heading" in names and names <= {*OUTPUT_COLUMNS, *FIX_COLUMNS}


def delimiter_option(delimiter: str) -> str:
    """The command line's option that reads a file separated by ``delimiter`` (``--delimiter tab``)."""
    return f"--delimiter {'tab' if delimiter == chr(9) else repr(delimiter)}"


#: How a header may state the SI units of the columns of a file of other data than the gyro's
#: (a reference, odometry, heading fixes), for :func:`in_si_units`.
SECONDS = tuple(u for u, si in HEADER_TIME_UNITS.items() if si == "s")
RADIANS = ("rad", "radian", "radians")
METRES = ("m", "metre", "metres", "meter", "meters")
METRES_PER_SECOND = ("m/s", "ms-1")


def in_si_units(path: Path, header: list[str], units: dict[str, tuple[str, tuple[str, ...]]]) -> list[str]:
    """``header`` with each name that states the unit of a column of ``units`` (``{"t": ("s",
    SECONDS)}``: the unit and its spellings) named without it: ``t [s]`` is ``t``. A name that
    states another unit is an error: it is not converted (``heading [deg]`` was a missing column
    ``heading``, the hint to leave the unit out of the name, and the degrees then read as radians).
    """
    bare = []
    for name in header:
        base, given = split_unit(name)
        if base in units and given is not None:
            unit, spellings = units[base]
            if normal_unit(given) not in spellings:
                how = " (numpy.radians for degrees)" if unit == "rad" else ""
                raise ValueError(f"{path}: column {name!r} is in {given}, not {unit}: convert it to {unit}{how} "
                                 f"and name it {base} or {base} [{unit}]")
            name = base
        bare.append(name)
    return bare


#: Header names (lower case, letters and digits only) that say "time" and "yaw rate" in the words
#: loggers use: an IMU's ``timestamp``, ``time_ns``, ``gz``, ``wz``, EuRoC's ``w_RS_S_z``, ``yaw_rate``,
#: a one-axis gyro's ``rate`` or ``gyro`` (``rate(deg/s)``: its unit is left out before the match).
_LIKE = {
    "t": re.compile(r".*(time|stamp).*|t|ts|sec|secs|seconds"),
    "gyro_z": re.compile(r"(gyr|gyro|gyroscope|g|w|omega|angular|angvel|angularvelocity|rot)[a-z0-9]*z|.*yawrate.*"
                         r"|rate|turnrate|angularrate|gyro|gyroscope"),
}
#: Names that are a time and nothing else, preferred where several names look like a time.
_TIME_WORDS = frozenset(("t", "ts", "time", "times", "timestamp", "stamp", "sec", "secs", "seconds"))
_OPTION = {"t": ("time_col", "--time-col"), "gyro_z": ("rate_col", "--rate-col")}


def is_number(text: str) -> bool:
    """Whether pyarrow reads ``text`` (trimmed of spaces and tabs) as a float. Python's float() also
    takes ``1_000``, digits beyond ASCII (``\u0663``) and other white space around (a no-break
    space), which pyarrow refuses: taken for numbers, the search passed the bad value by."""
    if "_" in text or not text.isascii() or text.strip() != text:
        return False
    try:
        float(text)
    except ValueError:
        return False
    return True


def _look_like(header: list[str], missing: list[str], times: tuple[str, ...] = ()) -> str:
    """The options that name the one column of ``header`` that looks like each missing default
    column (a time, a yaw rate), as a hint in Python's words and the command line's; empty where
    none or several do. A column of ``times`` looks like the time by its type: pandas names an
    unnamed DatetimeIndex ``__index_level_0__``, which no name pattern should take for a time."""
    said, typed, axes = [], [], ""
    bases = {split_unit(str(h))[0] for h in header}  # the names without their units, as the reader matches them
    for column in (c for c in missing if c in _LIKE):
        like = [b for b in bases if _LIKE[column].fullmatch(re.sub(r"[^a-z0-9]", "", _axis_named(b).lower()))]
        if column == "t":
            like += [b for b in times if b not in like]
            plain = [b for b in like if re.sub(r"[^a-z0-9]", "", b.lower()) in _TIME_WORDS]
            if len(plain) == 1:  # PX4's timestamp beside its accelerometer_timestamp_relative
                like = plain
        if len(like) == 1:
            keyword, option = _OPTION[column]
            said.append(f"{keyword}={like[0]!r}")
            typed.append(f"{option} {_quoted(like[0])}")
            if column == "gyro_z":
                axes = _three_axes(like[0], bases)
        elif column == "gyro_z" and not like and {"x", "y", "z"} <= bases:
            # a phone app's gyro file (Sensor Logger's time, seconds_elapsed, z, y, x): bare axis names
            # say nothing of a gyro, so this is said apart from the names that look like one
            axes = ("; its x, y, z may be a gyro's axes: rate_col='z' (--rate-col z) for a sensor z up (a phone "
                    "lying flat), else gyro_cols='x,y,z' and the axis that points up (--gyro-cols x,y,z --up AXIS)")
    if not said:
        return axes
    one = len(said) == 1
    return f"; {', '.join(said)} ({' '.join(typed)}) look{'s' if one else ''} like {'it' if one else 'them'}{axes}"


#: An element of an array logged as columns, ``gyro_rad[0]`` to ``gyro_rad[2]`` (PX4's ulog2csv): its
#: x, y and z axes.
_ELEMENT = re.compile(r"(?P<array>.+)\[\s*(?P<index>[012])\s*\]")


def _axis_named(name: str) -> str:
    """``name`` with an array's element 0, 1 or 2 written as its axis (``gyro_rad[2]`` as
    ``gyro_radz``), so that an array of three axes is matched as its axes' names are."""
    m = _ELEMENT.fullmatch(name)
    return name if m is None else m["array"] + "xyz"[int(m["index"])]


def _three_axes(z: str, bases: set[str]) -> str:
    """Where the gyro's z column ``z`` has its x and y beside it, the three-axis options: the z axis
    is the yaw rate only of a sensor mounted z up (EuRoC's x axis points up, a phone's z only
    when it lies flat), which the header cannot tell."""
    element = _ELEMENT.fullmatch(z)
    if element is not None:
        xyz = [f"{element['array']}[{i}]" for i in (0, 1)]
    else:
        cut = z.lower().rfind("z")
        xyz = [z[:cut] + a + z[cut + 1:] for a in ("x", "y")]
    if not all(name in bases for name in xyz):
        return ""
    cols = ",".join([*xyz, z])
    return (f"; where z does not point up, give the three axes and the axis that does: gyro_cols={cols!r}, "
            f"up='x' for x up (--gyro-cols {_quoted(cols)} --up x), or accel_cols to measure up")


def _quoted(name: str) -> str:
    """``name`` as typed on a command line: quoted where the shell would split or read it."""
    return name if re.fullmatch(r"[\w.+-]+", name) else repr(name)


def warn_own_time_unit(path: Path, column: str, kind: str, unit: str, given: str) -> None:
    """Warn that the time unit the user gave (``given``) is not used: the time column's type
    (``kind``, a timestamp or duration) carries its own, ``unit``, and the user expects the option
    to act."""
    if unit != given:
        warn(f"{path}: column {column} is a {kind} with its own unit ({unit}): time_unit {given!r} "
             "(--time-unit) is not used")


def first_null(array: pa.Array) -> int | None:
    """Index of the first null of a pyarrow array, or None."""
    if array.null_count == 0:
        return None
    return int(np.flatnonzero(np.asarray(array.is_null()))[0])


def concat(parts: list[np.ndarray]) -> FloatArray:
    """The pieces of a column, read chunk after chunk, as one contiguous float64 array."""
    return np.ascontiguousarray(np.concatenate(parts) if parts else np.empty(0), dtype=np.float64)


@functools.cache
def import_pyarrow_lazy_modules() -> None:
    """Make pyarrow import pandas now (or find it missing), before any data is read or written.

    pyarrow does it on its first conversion between its arrays and numpy and discards whatever
    that import raises, so a Ctrl-C or SIGTERM arriving then would be lost and the run would go on
    (:mod:`gyrocore._signals`). Done here, such a signal still raises KeyboardInterrupt. Without
    pyarrow (an install without the ``io`` extra) there is nothing to do.
    """
    try:
        import pyarrow as pa
    except ImportError:
        return

    with _signals.not_swallowed():
        pa.record_batch([np.zeros(1)], names=["x"]).column(0).to_numpy()

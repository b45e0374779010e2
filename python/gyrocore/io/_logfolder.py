"""The log-folder layout: ``gyro.csv`` (t, gyro_z), ``reference.csv`` (t, heading, x, y),
``odometry.csv`` (t, speed), ``fixes.csv`` (t, heading, sigma: heading fixes) and ``meta.json`` (the ``stationary`` rest window, and whatever else
describes the log).

``gyro.csv`` is read like any CSV input; this module reads the rest. Only ``gyro.csv`` is required.
"""

from __future__ import annotations

import difflib
import math
import os
from pathlib import Path
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import FloatArray
from .._checks import warn
from ..window import RestWindowError, in_log_clock
from ._columns import METRES, METRES_PER_SECOND, RADIANS, SECONDS, in_si_units
from ._csvfile import CsvLayout, csv_layout, read_csv_columns
from ._jsonfile import json_kind, read_json
from ._paths import check_file, has_file

if TYPE_CHECKING:
    from ..fixes import Fixes

#: The gyro samples of a log folder; a folder with this file is a log folder.
GYRO_CSV = "gyro.csv"
#: A log folder's heading fixes, used by the processing entry points when present.
FIXES_CSV = "fixes.csv"
#: A log folder's own GNSS receiver log (comma_seg40's): fused only where ``--fixes`` names it.
GNSS_CSV = "gnss.csv"
#: The other files of a log folder, each optional.
META_JSON, REFERENCE_CSV, ODOMETRY_CSV = "meta.json", "reference.csv", "odometry.csv"


def is_log_folder(path: Path) -> bool:
    """Whether the folder ``path`` is a log folder: it has ``gyro.csv``, or something of that name
    (a folder, a link that cannot be followed), which reading the log then names."""
    return os.path.lexists(path / GYRO_CSV)


def lacks_gyro(path: Path) -> bool:
    """Whether ``path`` is a folder with a log folder's other files but no ``gyro.csv``: a log
    folder without its samples, not a folder of logs whose CSV files are the logs."""
    others = (META_JSON, REFERENCE_CSV, ODOMETRY_CSV, FIXES_CSV)
    return path.is_dir() and not is_log_folder(path) and any((path / name).is_file() for name in others)


def warn_gyro_alone(path: Path) -> None:
    """Warn when ``path`` is a log folder's ``gyro.csv`` given alone: read as a plain file, it loses
    the folder's rest window, odometry and reference beside it (the sample log's gyro.csv found 21
    "rests" on its straight roads, where the folder took its 60 s rest)."""
    beside = [name for name in (META_JSON, ODOMETRY_CSV, REFERENCE_CSV, FIXES_CSV) if (path.parent / name).is_file()]
    if path.name == GYRO_CSV and beside:
        warn(f"{path}: the gyro of the log folder {path.parent}, read as a file alone, without the "
             f"{', '.join(beside)} beside it; give the folder ({path.parent}) to read the log with them")
    elif path.name in _NOT_GYRO and (path.parent / GYRO_CSV).is_file():
        # read as a log it failed on a missing gyro_z column, as if the file were a broken log
        warn(f"{path}: the {_NOT_GYRO[path.name]} of the log folder {path.parent}, not its gyro ({GYRO_CSV}); "
             f"give the folder ({path.parent}) to read the log")


#: A log folder's files that hold no gyro samples, and what each holds.
_NOT_GYRO = {REFERENCE_CSV: "reference heading", ODOMETRY_CSV: "odometry", FIXES_CSV: "heading fixes",
             GNSS_CSV: "GNSS receiver log"}


def read_meta(folder: Path) -> tuple[dict[str, Any], tuple[float, float] | None]:
    """``meta.json`` (empty without the file) and its rest window ``(t0, t1)`` [s] (or None); its
    ``name``, when not null, must be text (it names the log in tables and its plot's file)."""
    path = folder / META_JSON
    meta = _read_json(path)
    name = meta.get("name")
    if name is not None and not (isinstance(name, str) and name.strip()):
        raise ValueError(f"{path}: name must be the log's name as text (or null: the folder's name), got {name!r}")
    _warn_misspelled(path, meta)
    return meta, _rest_window(path, meta.get("stationary"))


#: The keys of meta.json that gyrocore reads; any other is the user's (a log's notes, its source).
META_KEYS = ("name", "stationary")
#: The reading options (:class:`gyrocore.io.ReadOptions`) a meta.json might be expected to set, and
#: does not: a ``"rate_unit": "deg/s"`` there left a gyro in deg/s read as rad/s without a word.
_READING_OPTIONS = ("time_col", "rate_col", "time_unit", "rate_unit", "topic", "delimiter", "gyro_cols", "accel_cols",
                    "up", "up_window")


def _warn_misspelled(path: Path, meta: dict[str, Any]) -> None:
    """Warn of a key that looks like a misspelled key gyrocore reads (``stationery``,
    ``Stationary``: another case, or a letter or two apart) where that key is missing: the log was
    read without its rest window, without a word. Other keys are the user's and are left alone,
    also one that a key of gyrocore's starts with (a GNSS base ``station``)."""
    for key in meta:
        option = key.replace("-", "_").lower()
        if option in _READING_OPTIONS:
            unit = (f", or state it in {GYRO_CSV}'s header (t [s], gyro_z [deg/s])" if option.endswith("_unit") else "")
            warn(f"{path}: the key {key!r} is not read: a log folder's {META_JSON} gives its rest window "
                 f"('stationary') and name; {option} is a reading option: give it to the command "
                 f"(--{option.replace('_', '-')}) or to read_log ({option}=){unit}")
            continue
        for meant in (k for k in META_KEYS if k not in meta and abs(len(k) - len(key)) <= 2):
            if difflib.SequenceMatcher(None, key.lower(), meant).ratio() >= 0.8:
                warn(f"{path}: the key {key!r} is not read (did you mean {meant!r}?); gyrocore reads "
                     f"{' and '.join(map(repr, META_KEYS))} (the rest window [t0, t1] in seconds, and the log's name)")


def read_reference(folder: Path) -> dict[str, FloatArray]:
    """``reference.csv`` (:func:`read_reference_file`); empty without the file."""
    path = folder / REFERENCE_CSV
    return read_reference_file(path) if has_file(path) else {}


def read_odometry(folder: Path) -> dict[str, FloatArray]:
    """Columns t and speed of ``odometry.csv``; empty without the file. A t or speed that is not
    finite, or a time that does not come after the one before it, is an error naming its line."""
    path = folder / ODOMETRY_CSV
    if not has_file(path):
        return {}
    layout = si_layout(path, _ODOMETRY_UNITS)
    odometry = read_csv_columns(path, ("t", "speed"), what="an odometry file", layout=layout)
    _require_samples(path, layout, odometry, ("t", "speed"), "the odometry")
    return odometry


def read_fixes(folder: Path) -> Fixes | None:
    """``fixes.csv`` (t, heading, sigma: :func:`gyrocore.fixes.read_fixes_csv`); None without it."""
    from ..fixes import read_fixes_csv  # it reads through this package

    path = folder / FIXES_CSV
    return read_fixes_csv(path) if has_file(path) else None


def has_track(where: str, columns: Iterable[str], names: tuple[str, str] = ("x", "y")) -> bool:
    """Whether a reference holds positions: both columns ``names`` (x and y [m]). One without
    the other warns: dead reckoning and the closed-path check are then left out, and the user
    should know why."""
    have = set(columns)
    present = [name for name in names if name in have]
    if len(present) == 1:
        other = names[1] if present[0] == names[0] else names[0]
        warn(f"{where}: column {present[0]} without {other}: the reference's positions are left out "
             "(its heading is still used)")
    return len(present) == 2


def read_reference_file(path: str | Path) -> dict[str, FloatArray]:
    """A reference heading given apart from its log: a CSV file like ``reference.csv``, with
    columns t [s] and heading [rad], and x and y [m] where it has both.

    A t or heading that is not a finite number is an error naming its line. An x or y that is
    empty or not finite leaves the positions out, with a warning naming its line: the heading is
    still scored, while dead reckoning and the closed-path check need every position.
    """
    path = Path(path)  # gyrocore.io exports it: a path given as text was "'str' object has no attribute 'is_file'"
    check_file(path)
    layout = si_layout(path, _REFERENCE_UNITS)
    # a log file with its own reference given as one: it said "drive.csv has the columns t, heading, x, y"
    if "heading" not in layout.header and "heading_true" in layout.header:
        raise ValueError(f"{path}: no column heading, and its heading_true makes it a log with its own reference (what "
                         "gyrocore simulate writes): give it as the log, whose heading_true is read with it; a "
                         "reference file has the columns t, heading [rad] and, where known, x, y [m]")
    track = ("x", "y") if has_track(str(path), layout.header) else ()
    ref = read_csv_columns(path, ("t", "heading", *track), what="a reference", optional=track, layout=layout)
    _require_samples(path, layout, ref, ("t", "heading"), "a reference")
    for name in track:
        where = _not_finite(path, layout, ref, name, "empty or nan")  # an empty position is read as NaN
        if where is not None:
            warn(f"{where}; the reference's positions are left out (its heading is still used)")
            return {"t": ref["t"], "heading": ref["heading"]}
    return ref


#: The units a reference's and an odometry file's columns may state in their names (``t [s]``,
#: ``heading [rad]``, ``speed [m/s]``), as a fixes.csv's: any other is refused, not converted.
_REFERENCE_UNITS = {"t": ("s", SECONDS), "heading": ("rad", RADIANS), "x": ("m", METRES), "y": ("m", METRES)}
_ODOMETRY_UNITS = {"t": ("s", SECONDS), "speed": ("m/s", METRES_PER_SECOND)}


def si_layout(path: Path, units: dict[str, tuple[str, tuple[str, ...]]]) -> CsvLayout:
    """The layout of the CSV file ``path`` with its names of ``units`` read without their
    (SI) units (:func:`in_si_units`): a gyro.csv's ``t [s]`` was read, its reference's refused."""
    layout = csv_layout(path, ",")
    return CsvLayout(in_si_units(path, layout.header, units), layout.header_lines)


def _require_samples(path: Path, layout: CsvLayout, table: dict[str, FloatArray], names: tuple[str, ...], what: str) -> None:
    """Refuse a value of the columns ``names`` of the CSV file ``path`` that is not finite, and a
    time ``t`` that does not come after the one before it, naming the file, line and column
    (``what`` is whose samples they are: "a reference"). Checked later, on the arrays, the error
    named only an index (``speed[3] is nan``), and the log rather than this file."""
    for name in names:
        where = _not_finite(path, layout, table, name, "nan")
        if where is not None:
            raise ValueError(f"{where}; {what}'s {' and '.join(names)} must be finite numbers: fill it in or drop the line")
    t = table["t"]
    back = np.flatnonzero(np.diff(t) <= 0)
    if len(back):
        k = int(back[0]) + 1
        raise ValueError(f"{path}: line {layout.line(k)}, column {layout.header.index('t') + 1} (t): {t[k]:.17g} does not come "
                         f"after {t[k - 1]:.17g} on line {layout.line(k - 1)}; {what}'s times must strictly increase: "
                         "sort the file and drop repeated times")


def _not_finite(path: Path, layout: CsvLayout, columns: dict[str, FloatArray], name: str, nan: str) -> str | None:
    """Where the first value of column ``name`` that is not finite is, and what it is (a NaN
    said as ``nan``), or None (row k is ``layout.line(k)``, as :func:`read_csv_columns` reads)."""
    bad = np.flatnonzero(~np.isfinite(columns[name]))
    if len(bad) == 0:
        return None
    value = columns[name][bad[0]]
    what = nan if np.isnan(value) else str(value)
    return f"{path}: line {layout.line(int(bad[0]))}, column {layout.header.index(name) + 1} ({name}): {what}"


def from_stationary(folder: str | Path, error: RestWindowError) -> str:
    """``error``, about the rest window of the log folder ``folder``, naming its source first:
    its ``meta.json``'s ``stationary`` (a window in another time base, e.g. [0, 1e12] for a log in
    epoch seconds, was blamed on the log alone), and the log's span in the clock it is written in."""
    return f"{Path(folder) / META_JSON} (stationary): {in_log_clock(str(error), error.span)}"


def _rest_window(path: Path, window: Any) -> tuple[float, float] | None:
    """meta.json's ``stationary``: ``[t0, t1]`` [s] or null."""
    if window is None:
        return None
    if not (
        isinstance(window, list)
        and len(window) == 2
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(_as_float(v)) for v in window)
        and window[0] < window[1]  # an empty window [5, 5] passed here, then failed unnamed (Log's own check)
    ):
        raise ValueError(f"{path}: stationary must be [t0, t1] in seconds (finite, t0 < t1) or null, got {window!r}")
    return float(window[0]), float(window[1])


def _as_float(value: int | float) -> float:
    """``value`` as a float; an integer too long for one (JSON has no limit) is infinite."""
    try:
        return float(value)
    except OverflowError:
        return math.inf


def _read_json(path: Path) -> dict[str, Any]:
    if not has_file(path):
        return {}
    meta = read_json(path)
    if not isinstance(meta, dict):
        raise ValueError(f'{path}: expected a JSON object ({{"stationary": ..., "name": ...}}), got {json_kind(meta)}')
    return meta

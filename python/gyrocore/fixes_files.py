"""Heading fixes read from files: a log folder's ``fixes.csv`` (t [s], heading [rad, CCW from
east], sigma [rad]) and a ``gnss.csv`` like comma_seg40's (t, speed [m/s], bearing [deg, CW from
north]), every value checked and a bad one named by its file, line and column. Re-exported by
:mod:`gyrocore.fixes`."""

from __future__ import annotations

import re
from pathlib import Path

from ._arrays import FloatArray
from ._checks import keyword_options, require_options
from .fixes import Fixes, check_all, from_gnss
from .io._columns import RADIANS, SECONDS, in_si_units
from .io._csvfile import CsvLayout, csv_layout, read_csv_columns
from .io._paths import check_file
from .io.units import split_unit


def read_gnss_csv(path: str | Path, **options: float) -> Fixes:
    """Fixes from a ``gnss.csv`` like comma_seg40's (t, speed [m/s], bearing [deg, clockwise from
    north]), through :func:`from_gnss` (its options pass on)."""
    require_options("read_gnss_csv (from_gnss's)", options, keyword_options(from_gnss))  # before the file is read
    path = Path(path)
    check_file(path)  # a named pipe was waited on for ever, a folder was "missing"
    return _gnss_csv(path, csv_layout(path, ","), **options)


def _gnss_csv(path: Path, layout: CsvLayout, **options: float) -> Fixes:
    """:func:`read_gnss_csv` of a file checked (:func:`check_file`) whose ``layout`` is read."""
    # a name may state its unit, as in a fixes.csv (t [s], speed [m/s], bearing [deg] was refused)
    names = _fix_columns(path, layout.header, _GNSS_UNITS, _GNSS_HEADER)
    # an empty bearing is none, as nan is (a receiver at rest logs no course): from_gnss drops it
    cols = _read_rows(path, tuple(names.values()), optional=(names["bearing"],))
    try:
        return from_gnss(cols[names["t"]], cols[names["bearing"]], cols[names["speed"]], **options)
    except ValueError as e:
        where = {"t": names["t"], "speed": names["speed"], "bearing_deg": names["bearing"]}
        raise ValueError(_at_line(path, layout, where, e)) from None


def read_fixes_csv(path: str | Path) -> Fixes:
    """A log folder's ``fixes.csv``: t [s], heading [rad, CCW from east], sigma [rad] (a column
    name may state its unit, if it is that one: ``t [s]``, ``heading [rad]``). Every fix is
    checked as it is read: a bad one is an error naming the file, line and column."""
    path = Path(path)
    check_file(path)  # a named pipe was waited on for ever, a folder was "missing"
    return _fixes_csv(path, csv_layout(path, ","))


def _fixes_csv(path: Path, layout: CsvLayout) -> Fixes:
    """:func:`read_fixes_csv` of a file checked (:func:`check_file`) whose ``layout`` is read."""
    names = _fix_columns(path, layout.header, _FIX_UNITS, _FIXES_HEADER)
    cols = _read_rows(path, tuple(names.values()))
    try:
        return check_all(Fixes(*(cols[names[c]] for c in FIXES_COLUMNS)))._warn_if_vague()
    except ValueError as e:
        raise ValueError(_at_line(path, layout, names, e)) from None


#: The columns of the two fix files :func:`read_fixes_file` reads.
FIXES_COLUMNS, GNSS_COLUMNS = ("t", "heading", "sigma"), ("t", "speed", "bearing")
#: The units a ``fixes.csv`` column may state in its name (``t [s]``, ``heading (rad)``), as
#: :func:`gyrocore.io.units.split_unit` reads them; any other unit is refused, not converted.
_FIX_UNITS = {"t": ("s", SECONDS), "heading": ("rad", RADIANS), "sigma": ("rad", RADIANS)}
_FIXES_HEADER = (f"a fixes.csv has the header {','.join(FIXES_COLUMNS)}: t [s] on the gyro's clock, heading [rad, "
                 "counter-clockwise from east], sigma [rad] (a name may state its unit: t [s], heading [rad])")
#: The units a ``gnss.csv`` column may state in its name, as :data:`_FIX_UNITS`.
_GNSS_UNITS = {"t": ("s", SECONDS), "speed": ("m/s", ("m/s",)), "bearing": ("deg", ("deg", "degree", "degrees", "°"))}
_GNSS_HEADER = (f"a gnss.csv has the header {','.join(GNSS_COLUMNS)}: t [s], speed [m/s] over ground, bearing [deg, "
                "clockwise from north] (a name may state its unit: speed [m/s], bearing [deg])")


def _fix_columns(path: Path, header: list[str], units: dict[str, tuple[str, tuple[str, ...]]],
                 expected: str) -> dict[str, str]:
    """The header name of each column of ``units`` (a fixes.csv's or a gnss.csv's) in ``header``:
    the name itself or with its unit; a column missing, given twice or in another unit is an error
    saying what is ``expected``."""
    bare = in_si_units(path, header, units)
    names = {}
    for wanted in units:
        found = [h for h, b in zip(header, bare) if b == wanted]
        if len(found) != 1:
            problem = "no column" if not found else f"{len(found)} columns"
            raise ValueError(f"{path}: {problem} {wanted}; {expected}; its header is {','.join(header)}")
        names[wanted] = found[0]
    return names


def _read_rows(path: Path, columns: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict[str, FloatArray]:
    """The named columns of a fixes file, which must have a row: a file of no fix is refused, as a
    gyro file of no sample is, rather than fusing nothing. An empty value of an ``optional``
    column is NaN."""
    cols = read_csv_columns(path, columns, what="a fixes file", optional=optional)
    if len(cols[columns[0]]) == 0:
        raise ValueError(f"{path}: no row after the header line, so no fix; add the fixes (one per line) or "
                         "remove the file")
    return cols


#: How an error about one row begins: the filter's (and :class:`Fixes`') ``fix N: column = value``,
#: or :func:`from_gnss`'s ``column[N] is value`` and ``column must strictly increase: column[N] =``.
ROW_ERROR = re.compile(r"fix (\d+): (\w+) = |(?:\w+ must strictly increase: )?(\w+)\[(\d+)\] (?:is|=) ")


def _at_line(path: Path, layout: CsvLayout, names: dict[str, str], error: ValueError) -> str:
    """``error``, about row N of the file ``path``, with the line and column of its value in front
    (row N is ``layout.line(N)``, after the header; blank lines are refused by the reader). ``names``
    maps the column an error names to the header's name, for the errors whose N is the file's row."""
    m = ROW_ERROR.match(str(error))
    column = None if m is None else names.get(m[2] or m[3])
    if m is None or column is None:
        return f"{path}: {error}"
    return f"{path}: line {layout.line(int(m[1] or m[4]))}, column {layout.header.index(column) + 1} ({column}): {error}"


def read_fixes_file(path: str | Path) -> Fixes:
    """A fixes file, by its header: ``fixes.csv``'s columns (t, heading [rad, CCW from east],
    sigma [rad], :func:`read_fixes_csv`) or comma_seg40's ``gnss.csv`` (t, speed [m/s], bearing
    [deg, CW from north], through :func:`read_gnss_csv` with its defaults)."""
    path = Path(path)
    check_file(path)  # a folder or a pipe given as the fixes is named as such, not "missing"
    layout = csv_layout(path, ",")
    header = layout.header
    if header and header[0].startswith(("$", "!")) and len(header[0]) in (6, 7):  # $GPRMC, !AIVDM: a talker and type
        raise ValueError(f"{path}: NMEA 0183 sentences ({header[0]},...), not a CSV file of fixes; their times are UTC: "
                         "read them with gyrocore.fixes.read_nmea, shift the times onto the gyro's clock, and write "
                         f"them as a fixes.csv ({','.join(FIXES_COLUMNS)}) or give them to process (fixes=)")
    if set(FIXES_COLUMNS) <= {split_unit(h)[0] for h in header}:
        return _fixes_csv(path, layout)  # checked once, its header read once
    if set(GNSS_COLUMNS) <= {split_unit(h)[0] for h in header}:
        return _gnss_csv(path, layout)
    raise ValueError(f"{path}: a fixes file has the columns {', '.join(FIXES_COLUMNS)} (t [s], headings in rad, CCW "
                     f"from east) or {', '.join(GNSS_COLUMNS)} (a gnss.csv); its header has {', '.join(sorted(header))}")

"""KITTI raw OXTS folders read as logs: a drive's ``oxts/`` folder (or the drive folder that holds
it), with ``timestamps.txt`` (one ``2011-09-30 13:16:05.640352090`` per frame), ``data/`` (one
file ``0000000000.txt`` ... per frame, a line of 30 numbers) and ``dataformat.txt`` (the 30 field
names, in the order of :data:`FIELDS`).

The log is read as the shared KITTI logs were converted (``data/real/kitti_*/meta.json``):

* gyro: ``wz`` [rad/s], the OXTS RT3003's angular rate about the vehicle's z axis, counter-clockwise
  positive (``rate_col='wu'`` takes the rate about the earth's up axis instead);
* time [s]: the first frame's seconds of day (the recording PC's clock) plus the elapsed time,
  both counted in integer nanoseconds and divided once, so no timestamp is rounded twice;
* reference: heading = ``yaw`` (0 = east, counter-clockwise positive), wrapped to (-pi, pi]; x, y
  [m] east and north of the first frame, equirectangular about it (R = 6378137 m);
* odometry: speed = ``vf``, the OXTS's forward speed parallel to the earth's surface [m/s].

The folders are small (10 Hz, a few thousand frames), so each reading reads the whole folder.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from .._arrays import FloatArray
from .._checks import warn
from ._paths import check_file

if TYPE_CHECKING:
    from .read_options import ReadOptions
    from .source import GyroSource

#: The kind of a :class:`~gyrocore.io.source.GyroSource` read from an OXTS folder.
KIND = "kitti oxts"
#: The OXTS folder of a KITTI raw drive, and its files.
OXTS, TIMESTAMPS, DATA, DATAFORMAT = "oxts", "timestamps.txt", "data", "dataformat.txt"
#: The 30 fields of an OXTS data line, in order (KITTI raw's dataformat.txt; pykitti's
#: ``OxtsPacket`` names the same fields in the same order, posacc and velacc as pos_accuracy and
#: vel_accuracy).
FIELDS = ("lat", "lon", "alt", "roll", "pitch", "yaw", "vn", "ve", "vf", "vl", "vu", "ax", "ay", "az", "af", "al",
          "au", "wx", "wy", "wz", "wf", "wl", "wu", "posacc", "velacc", "navstat", "numsats", "posmode", "velmode",
          "orimode")
#: The fields that are a yaw rate [rad/s]: about the vehicle's z axis (the default, what the shared
#: KITTI logs hold) and about the earth's up axis.
RATE_FIELDS = ("wz", "wu")
#: The fields the reference and odometry are made of.
TRACK_FIELDS = ("yaw", "lat", "lon", "vf")
#: The earth's radius of the equirectangular projection [m] (WGS 84's equatorial radius).
EARTH_RADIUS = 6378137.0

_STAMP = re.compile(r"\d{4}-\d{2}-\d{2} \d{2}:\d{2}:\d{2}(\.\d{1,9})?")
_NS_PER_S = 1_000_000_000


def oxts_folder(path: Path) -> Path | None:
    """The OXTS folder that the folder ``path`` is, or holds as ``oxts/`` (a drive folder), or
    None. An OXTS folder has ``timestamps.txt`` and ``data/``, and ``dataformat.txt`` or the name
    ``oxts``: a camera's or the lidar's folder (``image_00``, ``velodyne_points``) has the first
    two and neither of the others."""
    for folder in (path, path / OXTS):
        if (folder / TIMESTAMPS).is_file() and (folder / DATA).is_dir() and (
                (folder / DATAFORMAT).is_file() or folder.name == OXTS):
            return folder
    return None


def sensor_folder_hint(path: Path) -> str:
    """A hint for a KITTI raw sensor folder that holds no OXTS data (``image_02``,
    ``velodyne_points``: ``timestamps.txt`` and ``data/``) given as a log; else empty."""
    if (path / TIMESTAMPS).is_file() and (path / DATA).is_dir():
        return (f"; it looks like a KITTI raw sensor folder ({TIMESTAMPS}, {DATA}/), and gyrocore reads the drive's "
                f"GPS/IMU: give its {OXTS} folder ({path.parent / OXTS}) or the drive folder ({path.parent})")
    return ""


def log_name(path: Path, folder: Path) -> str:
    """The log's name: the drive folder's (``2011_09_30_drive_0034_sync``), also where the
    ``oxts`` folder itself is given."""
    drive = folder.resolve().parent if folder.name == OXTS else folder.resolve()
    return drive.name or path.name


def frame_count(folder: Path) -> int:
    """The frames in ``timestamps.txt`` (its lines to the last that is not blank)."""
    return len(_stamp_lines(folder / TIMESTAMPS))


def oxts_options(path: Path, options: ReadOptions) -> ReadOptions:
    """``options`` for an OXTS folder: its rate is a field of :data:`RATE_FIELDS` (``wz`` unless
    ``rate_col`` names ``wu``), its times are in the file's own unit. A time column or a unit
    given (for a batch's CSV files) is not used, with a warning; three-axis options are refused."""
    if options.three_axis:
        raise ValueError(f"{path}: a KITTI OXTS folder's yaw rate is its field wz (or wu: rate_col='wu', --rate-col wu), "
                         "already about the vehicle's up axis: leave out gyro_cols, accel_cols and up")
    rate = options.rate_col or RATE_FIELDS[0]
    if rate not in RATE_FIELDS:
        raise ValueError(f"{path}: rate_col {rate!r} (--rate-col) is no yaw rate of a KITTI OXTS folder: give "
                         f"{' or '.join(RATE_FIELDS)} (wz about the vehicle's z axis, the default; wu about the "
                         "earth's up axis)")
    for name, value, own in (("time_col", options.time_col, None), ("time_unit", options.time_unit, "s"),
                             ("rate_unit", options.rate_unit, "rad/s")):
        if value is not None and value != own:
            warn(f"{path}: {name} {value!r} (--{name.replace('_', '-')}) is not used: a KITTI OXTS folder's times are "
                 f"read from {TIMESTAMPS} and its rates are in rad/s")
    return replace(options, time_col="t", rate_col=rate, time_unit="s", rate_unit="rad/s")


class Frames(NamedTuple):
    """An OXTS folder read once: its times [s] and, per frame, the fields a log takes (the rate
    fields and the track's) and the line of its data file they were read from."""

    t: FloatArray
    values: FloatArray
    lines: np.ndarray


#: The fields :class:`Frames` keeps, in its columns' order.
KEPT = (*RATE_FIELDS, *TRACK_FIELDS)


def read_frames(folder: Path) -> Frames:
    """Every frame of an OXTS folder, each data file read and its 30 numbers parsed once.

    Raises:
        ValueError: naming the file and line: a dataformat.txt whose fields differ from
            :data:`FIELDS`, a timestamp that does not parse or does not come after the one before
            it, a count of data files other than the timestamps', a data line without 30
            numbers, a value that is no number.
    """
    _check_dataformat(folder / DATAFORMAT)
    t = _times(folder / TIMESTAMPS)
    files = _data_files(folder, len(t))
    kept = [FIELDS.index(name) for name in KEPT]
    values, lines = np.empty((len(files), len(kept)), dtype=np.float64), np.empty(len(files), dtype=np.int64)
    for row, path in enumerate(files):
        lines[row], numbers = _data_line(path)
        values[row] = [numbers[k] for k in kept]
    return Frames(t, values, lines)


def frames_of(src: GyroSource) -> Frames:
    """The source's folder read once (:func:`read_frames`), for its gyro's chunks and its
    reference and odometry alike (each had read every data file again)."""
    if "oxts" not in src.read_once:
        src.read_once["oxts"] = read_frames(src.data_path)
    frames: Frames = src.read_once["oxts"]
    return frames


def fields_of(folder: Path, frames: Frames, names: tuple[str, ...]) -> dict[str, FloatArray]:
    """The fields ``names`` of ``frames``, each value finite: one that is not is named by its
    file, line and column."""
    columns = {name: frames.values[:, KEPT.index(name)] for name in names}
    for name, column in columns.items():
        bad = np.flatnonzero(~np.isfinite(column))
        if len(bad):
            k = int(bad[0])
            path = folder / DATA / f"{k:010d}.txt"
            number = int(frames.lines[k])
            token = path.read_text(encoding="utf-8", errors="replace").splitlines()[number - 1].split()[FIELDS.index(name)]
            raise ValueError(f"{path}: line {number}, column {FIELDS.index(name) + 1} ({name}): {token} is not a finite "
                             "number")
    return columns


def oxts_tables(src: GyroSource) -> tuple[dict[str, FloatArray], dict[str, FloatArray]]:
    """The reference (t, heading, x, y) and odometry (t, speed) of an OXTS folder's source."""
    frames = frames_of(src)
    t, v = frames.t, fields_of(src.data_path, frames, TRACK_FIELDS)
    heading = np.where(v["yaw"] <= -np.pi, v["yaw"] + 2 * np.pi, v["yaw"])
    heading = np.where(heading > np.pi, heading - 2 * np.pi, heading)  # (-pi, pi], as a reference.csv holds it
    lat0, lon0 = np.radians(v["lat"][0]), np.radians(v["lon"][0])
    x = EARTH_RADIUS * np.cos(lat0) * (np.radians(v["lon"]) - lon0)
    y = EARTH_RADIUS * (np.radians(v["lat"]) - lat0)
    return {"t": t, "heading": heading, "x": x, "y": y}, {"t": t, "speed": v["vf"]}


def oxts_chunks(src: GyroSource, rows: int, columns: tuple[str, ...]) -> Iterator[tuple[np.ndarray, list[np.ndarray], float, int]]:
    """The OXTS folder's times [s] and fields ``columns``, at most ``rows`` frames at a time (the
    reader of :meth:`GyroSource.chunks <gyrocore.io.GyroSource.chunks>`)."""
    frames = frames_of(src)
    t, values = frames.t, fields_of(src.data_path, frames, columns)
    for start in range(0, len(t), rows):
        stop = min(start + rows, len(t))
        yield t[start:stop], [values[c][start:stop] for c in columns], 1.0, stop


def _check_dataformat(path: Path) -> None:
    """A dataformat.txt (``lat:   latitude of the oxts-unit (deg)``, one field a line) that lists
    other fields, or in another order, than :data:`FIELDS` is refused: the data lines would be
    read by the wrong names. Without the file, the standard order is read (as pykitti does)."""
    if not os.path.lexists(path):
        return
    check_file(path)
    names = []
    for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
        if line.strip():
            names.append((number, line.split(":", 1)[0].strip().lstrip("-#* ").lower()))  # "- lat:" as a readme lists it
    for (number, name), field in zip(names, FIELDS):
        if name != field:
            raise ValueError(f"{path}: line {number}: field {name!r} where KITTI raw's OXTS format has {field!r} "
                             f"(its fields: {' '.join(FIELDS)}); gyrocore reads that format alone")
    if len(names) != len(FIELDS):
        raise ValueError(f"{path}: {len(names)} fields, and KITTI raw's OXTS format has {len(FIELDS)} "
                         f"({' '.join(FIELDS)}); gyrocore reads that format alone")


def _stamp_lines(path: Path) -> list[str]:
    """The lines of ``timestamps.txt``, blank ones at its end left out."""
    check_file(path)
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    while lines and not lines[-1].strip():
        lines.pop()
    return lines


def _times(path: Path) -> FloatArray:
    """The times [s] of ``timestamps.txt``: the first frame's nanoseconds of day plus each
    frame's nanoseconds after it, in integers, divided once (a float of the whole date, 1.3e18
    ns, resolves 256 ns only)."""
    lines = _stamp_lines(path)
    if not lines:
        raise ValueError(f"{path}: no timestamps (one line per frame: 2011-09-30 13:16:05.640352090)")
    for number, line in enumerate(lines, 1):
        if not _STAMP.fullmatch(line.strip()):
            _bad_stamp(path, number, line)
    try:
        stamps = np.array([line.strip().replace(" ", "T") for line in lines], dtype="datetime64[ns]")
    except ValueError:  # a date or time out of range (month 13, hour 25): the line is found again one by one
        for number, line in enumerate(lines, 1):
            try:
                np.datetime64(line.strip().replace(" ", "T"), "ns")
            except ValueError:
                _bad_stamp(path, number, line)
        raise
    ns = stamps.astype(np.int64)
    back = np.flatnonzero(np.diff(ns) <= 0)
    if len(back):
        k = int(back[0]) + 1
        what = "repeats" if ns[k] == ns[k - 1] else "goes back from"
        more = f" ({len(back)} such lines in all)" if len(back) > 1 else ""
        raise ValueError(f"{path}: line {k + 1}: {lines[k].strip()} {what} {lines[k - 1].strip()} on line {k}{more}; "
                         "timestamps must strictly increase. KITTI raw's extract (unsynced) OXTS data has repeated "
                         "timestamps: read the drive's sync data, or mend the timestamps first (and keep one data "
                         "file per line)")
    day = stamps[0].astype("datetime64[D]").astype("datetime64[ns]").astype(np.int64)
    return np.asarray((ns - day) / _NS_PER_S, dtype=np.float64)


def _bad_stamp(path: Path, number: int, line: str) -> None:
    """Raise the error of a timestamp line that does not parse (a blank one: a frame KITTI lost)."""
    if not line.strip():
        raise ValueError(f"{path}: line {number}: blank, where a frame's timestamp belongs (some KITTI raw drives lost "
                         "frames so); each line must hold one, like 2011-09-30 13:16:05.640352090")
    raise ValueError(f"{path}: line {number}: {line.strip()[:60]!r} is not a timestamp like "
                     "2011-09-30 13:16:05.640352090 (date, time of day to the nanosecond)")


def _data_files(folder: Path, count: int) -> list[Path]:
    """The data files of the ``count`` frames (``data/0000000000.txt`` on), each there."""
    data = folder / DATA
    with os.scandir(data) as entries:
        found = {entry.name: entry.is_file() for entry in entries if entry.name.endswith(".txt")}
    names = sorted(found)
    expected = [f"{k:010d}.txt" for k in range(count)]
    if names != expected:
        missing = sorted(set(expected) - set(names))
        extra = sorted(set(names) - set(expected))
        said = "; ".join(part for part in (f"{missing[0]} is missing" if missing else "",
                                           f"{extra[0]} is not a frame's" if extra else "") if part)
        raise ValueError(f"{data}: {len(names)} data files, and {folder / TIMESTAMPS} has {count} timestamps ({said}): "
                         f"one file per line, {expected[0] if expected else '0000000000.txt'} on; a folder whose "
                         "files and timestamps differ cannot tell which time is whose")
    for name in names:  # one look at each (from the listing): a stat of each file took a third of the reading
        if not found[name]:
            check_file(data / name)  # names what stands there: a folder, a broken link
    return [data / name for name in names]


def _data_line(path: Path) -> tuple[int, list[float]]:
    """A data file's one line of 30 numbers: its line number and the numbers (each one read, that
    a file cut short or garbled is named, not read as other fields)."""
    text = path.read_text(encoding="utf-8", errors="replace").splitlines()
    lines = [(number, line) for number, line in enumerate(text, 1) if line.strip()]
    if len(lines) != 1:
        raise ValueError(f"{path}: {len(lines)} lines of numbers; an OXTS data file holds one frame, one line of "
                         f"{len(FIELDS)} numbers")
    number, tokens = lines[0][0], lines[0][1].split()
    if len(tokens) != len(FIELDS):
        raise ValueError(f"{path}: line {number}: {len(tokens)} numbers, and an OXTS data line has {len(FIELDS)} "
                         f"({' '.join(FIELDS)})")
    values = []
    for k, token in enumerate(tokens):
        try:
            values.append(float(token))
        except ValueError:
            raise ValueError(f"{path}: line {number}, column {k + 1} ({FIELDS[k]}): {token[:40]!r} is not a number") from None
    return number, values

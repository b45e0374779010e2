"""Whole logs in memory: :func:`read_log` and the :class:`Log` it returns.

A log is read chunk after chunk like any input (:mod:`gyrocore.io.source`), checked for units that
look wrong, and joined; a log folder adds its reference, odometry and rest window.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import FloatArray, as_window, float_fields, one_line
from .._checks import NoUsableReading, require_flag, warn
from .._gyrocore import SampleError
from ..pipeline import (
    HeadingResult,
    has_bias_source,
    preset_params,
    process,
    uses_static_bias,
)
from ..rests import speed_on
from ..wholelog import WHOLE_OPTIONS
from ..window import RestWindowError, in_log_clock
from ._columns import concat
from ._kitti import KIND as KITTI_KIND
from ._kitti import oxts_tables
from ._logfolder import from_stationary, has_track, read_fixes, read_odometry, read_reference
from .source import SPEED_COLUMN, GyroSource, finite_speed, open_source
from .units import UnitCheck

if TYPE_CHECKING:
    from ..fixes import Fixes, FixesLike


#: The per-sample series of a :class:`Log`, by field name.
_SERIES = ("t", "rate", "t_ref", "heading_ref", "x_ref", "y_ref", "t_odometry", "speed")
#: The unit of each series that is a quantity, not a time (durations and dates refused in it).
_UNITS = {"rate": "rad/s", "heading_ref": "rad", "x_ref": "m", "y_ref": "m", "speed": "m/s"}


@dataclass(frozen=True, repr=False, eq=False)
class Log:
    """One recorded drive: gyro samples, and the reference and odometry where the log has them.

    Units: s, rad/s, rad, m, m/s; headings counter-clockwise positive.
    """

    name: str
    t: FloatArray
    rate: FloatArray
    t_ref: FloatArray | None = None
    heading_ref: FloatArray | None = None
    x_ref: FloatArray | None = None
    y_ref: FloatArray | None = None
    t_odometry: FloatArray | None = None
    speed: FloatArray | None = None
    stationary: tuple[float, float] | None = None
    """Rest window ``(t0, t1)`` at the start, in the log's time base, or None."""
    meta: dict[str, Any] = field(default_factory=dict)
    fixes: Fixes | None = None
    """Heading fixes (a log folder's ``fixes.csv``), or None."""
    path: str | None = None
    """Where :func:`read_log` read the log, as given (two log folders may share meta.json's name),
    or None for a log built in memory."""
    _source: GyroSource | None = field(default=None, init=False, repr=False, compare=False)
    # the file read, whose lines an error about a sample names; not an argument, so that
    # ``dataclasses.replace`` with other samples leaves it out rather than naming wrong lines

    def __post_init__(self) -> None:
        """Each series as a read-only float64 numpy array of the log's own: a pandas Series indexes
        by label, so ``t[0]`` and ``t[-1]`` of one cut from a table (``df.loc[df.t > 10, "t"]``)
        failed. The caller's arrays were kept as they were, so that a change of one after the log
        was made (or through ``log.rate``) changed the log's heading without a word: a writable
        array is copied (10^7 samples of t and rate: 40-50 ms, 160 MB), a read-only one taken as it
        is (:func:`~gyrocore._arrays.frozen_array`), and a write through ``log.t`` fails.
        A ``speed`` without ``t_odometry`` is one per gyro sample (as :func:`gyrocore.process` takes
        it); series that belong together are checked to match, and ``stationary`` to be a window."""
        float_fields(self, _SERIES, frozen=True, units=_UNITS)
        if self.speed is not None and self.t_odometry is None and len(self.speed) == len(self.t):
            object.__setattr__(self, "t_odometry", self.t)  # its own times: the gyro's (frozen: set as float_fields sets)
        for times, values in (("t", ("rate",)), ("t_ref", ("heading_ref", "x_ref", "y_ref")), ("t_odometry", ("speed",))):
            self._check_series(times, values)
        if self.stationary is not None:
            self._check_stationary()

    def _check_series(self, times: str, names: tuple[str, ...]) -> None:
        """Each series of ``names`` as long as its times ``times``, and none without them."""
        n = None if getattr(self, times) is None else len(getattr(self, times))
        for name in names:
            values = getattr(self, name)
            if values is None or (n is not None and len(values) == n):
                continue
            if n is None:
                hint = " (or one per gyro sample, as long as t)" if name == "speed" else ""
                raise ValueError(f"log {self.name}: {name} given without {times}: give its times as {times}{hint}")
            raise ValueError(f"log {self.name}: {name} has {len(values)} samples but {times} has {n}: give one per time")
        if n is not None and times != "t" and all(getattr(self, name) is None for name in names):
            raise ValueError(f"log {self.name}: {times} given without {' or '.join(names)}")

    def _check_stationary(self) -> None:
        """``stationary`` is two finite times, the first before the second, kept as two floats: a
        pandas Series (``df.t.iloc[[i, j]]``) is read by position (kept as given, its ``[1]`` was a
        look-up by label, a KeyError in ``repr``)."""
        try:
            window = as_window("stationary", self.stationary)
        except ValueError:
            raise ValueError(f"log {self.name}: stationary = {one_line(self.stationary)}: give the rest window as "
                             "(start, end) [s] in the log's time base, start before end") from None
        object.__setattr__(self, "stationary", window)  # frozen: set as float_fields sets

    def __repr__(self) -> str:
        """A summary (the arrays run to millions of samples)."""
        if len(self.t) == 0:
            return f"Log({self.name!r}, empty)"
        parts = [f"{len(self.t)} samples", f"{self.duration:.6g} s from t = {self.t[0]:.3f} s"]
        if self.t_ref is not None:
            parts.append(f"reference {len(self.t_ref)} samples" + (" with track" if self.has_track else ""))
        if self.t_odometry is not None:
            parts.append(f"odometry {len(self.t_odometry)} samples")
        if self.fixes is not None:
            parts.append(f"{len(self.fixes)} heading fixes")
        if self.stationary is not None:
            t0 = float(self.t[0])
            parts.append(f"rest +{self.stationary[0] - t0:.6g} .. +{self.stationary[1] - t0:.6g} s")
        return f"Log({self.name!r}: {', '.join(parts)})"

    @property
    def duration(self) -> float:
        """Duration of the gyro record [s]."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    def reference(self) -> tuple[FloatArray, FloatArray]:
        """The reference heading: ``(t_ref, heading_ref)``.

        Raises:
            ValueError: the log has none (a log folder without reference.csv, or a bare file).
        """
        if self.t_ref is None or self.heading_ref is None:
            # a caller with the reference in a file of its own was told only where a log's own would be
            raise ValueError(f"log {self.name}: no reference heading (a log folder's reference.csv, a file's heading_true "
                             "column; one apart: dataclasses.replace(log, t_ref=..., heading_ref=...), e.g. the t and "
                             "heading of gyrocore.io.read_reference_file)")
        return self.t_ref, self.heading_ref

    @property
    def has_track(self) -> bool:
        """Whether the log has reference positions (x, y in reference.csv)."""
        return self.t_ref is not None and self.x_ref is not None and self.y_ref is not None

    def track(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The reference positions: ``(t_ref, x_ref, y_ref)`` [s, m, m].

        Raises:
            ValueError: the log has none.
        """
        if self.t_ref is None or self.x_ref is None or self.y_ref is None:
            raise ValueError(f"log {self.name}: no reference positions (x, y in reference.csv)")
        return self.t_ref, self.x_ref, self.y_ref

    def speed_on_gyro_times(self) -> FloatArray | None:
        """The odometry speed [m/s] interpolated onto the gyro's times (NaN outside the odometry's
        span), or None without odometry."""
        if self.t_odometry is None or self.speed is None:
            return None
        if np.array_equal(self.t_odometry, self.t):
            # a file's speed column, one value per sample: nothing to interpolate, and an empty
            # value (NaN) is a speed unknown there, as on the command line (interpolation refuses it)
            return self.speed
        return speed_on(self.t, self.t_odometry, self.speed, where=f"log {self.name}: odometry speed")

    def process(
        self,
        preset: str = "recommended",
        *,
        mode: str = "whole",
        use_speed: bool = True,
        fixes: FixesLike | None = None,
        use_fixes: bool = True,
        fusion: dict[str, float] | None = None,
        **overrides: Any,
    ) -> HeadingResult:
        """Run a preset on this log (see :func:`gyrocore.process` for ``mode``, ``fixes`` and
        ``fusion``).

        The static bias comes from the rest window of meta.json unless given; in whole mode,
        without either, from every rest found in the log, with the odometry's speed unless
        ``use_speed`` is False. The result's ``bias_source`` and ``rests`` say which. Heading
        fixes: ``fixes`` if given, else the log's own (``fixes.csv``) unless ``use_fixes`` is False.
        A switch that is no bool (``use_speed="no"`` read as True) is a TypeError.
        """
        require_flag("use_speed", use_speed)
        require_flag("use_fixes", use_fixes)
        speed: dict[str, Any] = {}
        if use_speed and mode == "whole":
            speed["speed"] = self.speed_on_gyro_times()
        elif use_speed and self.speed is not None and tracks_rests(preset, overrides):
            # the odometry at its own times: the tracker interpolates it, and knows no speed outside it
            speed.update(speed=self.speed, speed_t=self.t_odometry)
        given = fixes if fixes is not None else self.fixes if use_fixes else None
        with self._naming_sample():
            if self.stationary is None or not uses_static_bias(preset) or has_bias_source(overrides):
                return process(self.t, self.rate, preset, mode=mode, fixes=given, fusion=fusion, **speed, **overrides)
            with self._naming_stationary():
                return process(
                    self.t, self.rate, preset, mode=mode, bias_window=self.stationary, fixes=given, fusion=fusion,
                    **speed, **overrides,
                )

    @contextmanager
    def _naming_sample(self) -> Iterator[None]:
        """Re-raise the :class:`~gyrocore.SampleError` of a bad sample (a NaN reading, a time going
        back) of a log read from a file naming the file and its line, in the words of ``gyrocore
        process FILE`` (:meth:`GyroSource.locate`): the index alone left a user to count lines.
        A log with no usable reading at all is named by its file (or its name)."""
        try:
            yield
        except NoUsableReading as e:
            where = f"log {self.name}" if self._source is None else str(self._source.data_path)
            raise ValueError(f"{where}: {e}") from None
        except SampleError as e:
            if self._source is None:
                raise
            check = UnitCheck(self._source.options)
            check.update(self.t, self.rate)
            e.log_message = getattr(e, "log_message", str(e))  # type: ignore[attr-defined]  # named again alike
            e.args = (self._source.locate(e, check.time_fix()),)
            raise

    @contextmanager
    def _naming_stationary(self) -> Iterator[None]:
        """Re-raise a :class:`RestWindowError` about the log's own rest window (:attr:`stationary`)
        naming where that window came from, its meta.json or the log: the pipeline's error names
        the window alone, and a window in another time base was blamed on the log."""
        try:
            yield
        except RestWindowError as e:
            where = f"log {self.name}: {in_log_clock(str(e), e.span)} (the rest window is the log's stationary)"
            raise RestWindowError(where if self.path is None else from_stationary(self.path, e)) from None


def tracks_rests(preset: str, overrides: dict[str, Any]) -> bool:
    """Whether ``preset`` with ``overrides`` runs the core's rest tracker (whole mode's options,
    which causal mode refuses with its own message, left out)."""
    return bool(preset_params(preset, **{k: v for k, v in overrides.items() if k not in WHOLE_OPTIONS})["track_rests"])


#: The columns of a file that hold the drive's truth at each sample, as ``gyrocore simulate``
#: writes it: the reference heading [rad, counter-clockwise], and the positions [m].
TRUTH_COLUMNS = {"heading": "heading_true", "x": "x", "y": "y"}


def _file_tables(src: GyroSource, t: FloatArray) -> tuple[dict[str, FloatArray], dict[str, FloatArray]]:
    """A file's reference and odometry at its own samples' times, from its columns (one pass):
    the heading of :data:`TRUTH_COLUMNS` (with the positions where it has both) and the speed of
    :data:`~gyrocore.io.source.SPEED_COLUMN`, each empty without its column."""
    # positions only beside a heading: a three-axis gyro's columns may be named x, y [rad/s]
    track = (TRUTH_COLUMNS["x"], TRUTH_COLUMNS["y"]) if src.extra_columns((TRUTH_COLUMNS["heading"],)) else ()
    columns = src.optional_columns((TRUTH_COLUMNS["heading"], *track, SPEED_COLUMN))
    ref: dict[str, FloatArray] = {}
    if TRUTH_COLUMNS["heading"] in columns:
        heading = columns[TRUTH_COLUMNS["heading"]]
        bad = np.flatnonzero(~np.isfinite(heading))
        if len(bad):  # scoring named it heading[k], an index, not where in the file it is
            k = int(bad[0])
            what = "empty or nan" if np.isnan(heading[k]) else str(heading[k])
            raise ValueError(f"{src.data_path}: {src.where(k)}, column {TRUTH_COLUMNS['heading']}: {what}; a reference's "
                             "t and heading must be finite numbers: fill it in or drop that sample")
        ref = {"t": t, "heading": heading}
        if has_track(str(src.path), columns, (TRUTH_COLUMNS["x"], TRUTH_COLUMNS["y"])):
            ref.update(x=columns[TRUTH_COLUMNS["x"]], y=columns[TRUTH_COLUMNS["y"]])
    odo = {"t": t, "speed": finite_speed(src, columns[SPEED_COLUMN])} if SPEED_COLUMN in columns else {}
    return ref, odo


def read_log(path: str | Path, *, use_fixes: bool = True, **options: Any) -> Log:
    """Read a whole log into memory: a log folder (with its reference, odometry and fixes) or any file
    :func:`open_source` reads (``options``: the :class:`ReadOptions` fields; a CSV or Parquet
    file's ``speed`` column [m/s] is the log's speed, as a folder's odometry, and its
    ``heading_true`` column [rad] (with ``x``, ``y`` [m]) its reference, as ``gyrocore simulate``
    writes them). ``use_fixes=False`` leaves a log folder's ``fixes.csv`` unread (a command that
    does not use it is not stopped by a bad one; a value that is no bool is a TypeError).

    Raises ValueError for a malformed input, naming the file and where, for one without samples,
    and when every interval is a gap (timestamps in another unit).
    Warns (:class:`gyrocore.InputWarning`) when the values look like another unit.

    Example:
        >>> import gyrocore
        >>> log = gyrocore.read_log("../shared/data/real/f110_ds3")  # doctest: +SKIP
        >>> log = gyrocore.read_log("drive.csv", time_col="time", time_unit="ms", rate_unit="deg/s")  # doctest: +SKIP
    """
    require_flag("use_fixes", use_fixes)
    if not isinstance(path, (str, os.PathLike)):  # a table in memory: "expected str, bytes or os.PathLike object"
        raise TypeError(f"read_log reads a file or log folder by its path, got {type(path).__name__}: samples in "
                        "memory go to gyrocore.process(t, rate), or with their reference to gyrocore.Log(name, t, "
                        "rate, t_ref=..., heading_ref=...)")
    src = open_source(path, **options)
    check = UnitCheck(src.options)
    ts, rates = [], []
    for chunk in src.chunks(1 << 20):
        check.update(chunk.t, chunk.rate)
        ts.append(chunk.t)
        rates.append(chunk.rate)
    if sum(map(len, ts)) == 0:
        raise ValueError(f"{src.data_path}: no samples")
    error = check.error()
    if error is not None:
        raise ValueError(f"{src.data_path}: {error}")
    for problem in check.problems():
        warn(f"{src.data_path}: {problem}")
    ref: dict[str, FloatArray] = {}
    odo: dict[str, FloatArray] = {}
    fixes = None
    t = concat(ts)
    if src.kind == "log folder":
        ref, odo = read_reference(src.path), read_odometry(src.path)
        fixes = read_fixes(src.path) if use_fixes else None
    elif src.kind == KITTI_KIND:
        ref, odo = oxts_tables(src)
    else:
        ref, odo = _file_tables(src, t)
    rate = concat(rates)
    for series in (t, rate, *ref.values(), *odo.values()):  # read here, no one else's: the log takes them uncopied
        series.flags.writeable = False
    log = Log(
        name=src.name,
        t=t,
        rate=rate,
        t_ref=ref.get("t"),
        heading_ref=ref.get("heading"),
        x_ref=ref.get("x"),
        y_ref=ref.get("y"),
        t_odometry=odo.get("t"),
        speed=odo.get("speed"),
        stationary=src.stationary,
        meta=src.meta,
        fixes=fixes,
        path=str(path),
    )
    object.__setattr__(log, "_source", src)
    return log

"""Three-axis input: the yaw rate is the gyro's component along the vertical, ``gyro . up``.

``up`` (a unit vector in the sensor frame) is given as an axis (``x``, ``-y``, ...) or a vector,
or measured: at rest an accelerometer reads the specific force, which points up, so the mean of
its readings over the rest window is up. The projection runs per sample in the core
(:func:`gyrocore._gyrocore.project_up`, ``gyrocore::Up``), chunk after chunk.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from pathlib import Path
import numpy as np

from .._arrays import FloatArray
from .._checks import real_number
from .._gyrocore import project_up
from ..window import Window, time_range

#: ``up`` measured from the accelerometer over the rest window.
MEASURED = "accel"
#: The sensor axes ``up`` may name.
AXES: dict[str, tuple[float, float, float]] = {
    "x": (1.0, 0.0, 0.0),
    "y": (0.0, 1.0, 0.0),
    "z": (0.0, 0.0, 1.0),
}
#: Standard gravity [m/s^2]: what an accelerometer at rest reads.
GRAVITY = 9.80665
#: The least mean specific force [m/s^2] accepted as gravity at rest: half of it. Less is free
#: fall, motion that cancels gravity, or readings in another unit (g), whose direction cannot be
#: trusted to be up.
LEAST_GRAVITY = GRAVITY / 2
#: How ``up`` is written: an axis with an optional sign, three numbers, or the measured one.
UP_HELP = "x, y, z, -x, -y, -z, a vector X,Y,Z (normalised), or accel (the accelerometer at rest)"

#: ``up`` as :class:`ReadOptions` keeps it.
UpValue = str | tuple[float, float, float]


def parse_up_window(value: object) -> tuple[float, float] | Window:
    """``up_window`` as the reader takes it: a :class:`Window`, two numbers [s], or two bounds as
    the command line writes them (``("+0", "+20")``: after the first sample), which the error of
    an empty window suggests; numpy compared text with the times and failed deep in the reader.

    Raises:
        TypeError: not two numbers or two bounds as text.
    """
    if isinstance(value, Window):
        return value
    pair = list(value) if isinstance(value, (tuple, list, np.ndarray)) else []
    if len(pair) == 2 and all(isinstance(v, str) for v in pair):
        return Window.parse(pair, "up_window (--up-window)")
    t0, t1 = (real_number(v) for v in pair) if len(pair) == 2 else (None, None)
    if t0 is not None and t1 is not None:
        return t0, t1
    raise TypeError(f"up_window must be two times [s], (t0, t1), or two bounds as text, ('+0', '+20') for the "
                    f"first 20 s, got {value!r}")


def parse_up(value: str | Sequence[float]) -> UpValue:
    """``up`` as :class:`ReadOptions` keeps it: :data:`MEASURED` or a vector (not normalised).

    Raises:
        ValueError: not an axis, three finite numbers not all zero, nor :data:`MEASURED`.
    """
    if isinstance(value, str):
        text = value.strip().lower()
        if text == MEASURED:
            return MEASURED
        sign, axis = (-1.0, text[1:]) if text.startswith("-") else (1.0, text.lstrip("+"))
        if axis in AXES:
            x, y, z = AXES[axis]
            return (sign * x, sign * y, sign * z)
        parts: Sequence[str | float] = text.split(",")
    else:
        parts = list(value)
    try:
        vector = tuple(float(p) for p in parts)
    except (TypeError, ValueError):
        vector = ()
    if len(vector) != 3:
        raise ValueError(f"up {value!r}: give {UP_HELP}")
    if not all(math.isfinite(c) for c in vector):  # 1e400 reads as infinity
        raise ValueError(f"up {value!r}: its components must be finite numbers")
    try:  # the core's rule: finite and of some length
        project_up(np.empty(0), np.empty(0), np.empty(0), (vector[0], vector[1], vector[2]))
    except ValueError as e:
        raise ValueError(f"up {value!r}: {e}") from None
    return (vector[0], vector[1], vector[2])


def three_names(value: str | Sequence[str], option: str) -> tuple[str, str, str]:
    """Three column names, given as a sequence or as one text ``gx,gy,gz``."""
    names = [n.strip() for n in (value.split(",") if isinstance(value, str) else value)]
    if len(names) != 3 or not all(names) or len(set(names)) != 3:
        raise ValueError(f"{option} {value!r}: give three different column names (x, y and z axes), e.g. gx,gy,gz")
    return (names[0], names[1], names[2])


def project(values: Sequence[np.ndarray], up: tuple[float, float, float]) -> FloatArray:
    """The rate along ``up`` of the three gyro axes ``values`` (NaN where an axis is NaN)."""
    x, y, z = (np.ascontiguousarray(v, dtype=np.float64) for v in values)
    return project_up(x, y, z, up)


def measure_up(
    path: Path, window: Window | tuple[float, float], samples: Iterator[tuple[FloatArray, list[np.ndarray]]]
) -> tuple[float, float, float]:
    """The mean accelerometer reading over the rest window: up, in the sensor frame.

    ``samples`` yields (t [s], [ax, ay, az]) chunk after chunk from the start of the file; it is
    read only up to the window's end.

    Raises:
        ValueError: no finite accelerometer reading in the window, or a mean below
            :data:`LEAST_GRAVITY` (free fall, or not m/s^2), naming the file and the window.
    """
    total = np.zeros(3)
    count = 0
    first = last = math.nan
    bounds: tuple[float, float] | None = None
    for t, accel in samples:
        if len(t) == 0:
            continue
        if bounds is None:
            first = float(t[0])
            bounds = window.resolve(first) if isinstance(window, Window) else window
        last = float(t[-1])
        a = np.column_stack([np.asarray(v, dtype=np.float64) for v in accel])
        inside = (t >= bounds[0]) & (t <= bounds[1]) & np.isfinite(a).all(axis=1)
        total += a[inside].sum(axis=0)
        count += int(inside.sum())
        if last > bounds[1]:
            break
    shown = str(window) if isinstance(window, Window) else f"{window[0]:.10g} .. {window[1]:.10g} s"
    where = f"{path}: the rest window {shown}, over which up is measured,"
    if count == 0:
        span = "the log has no samples" if bounds is None else time_range(first, last, plus_t=True)  # up_window takes +T
        raise ValueError(f"{where} holds no accelerometer reading ({span}); give another window, or --up / up=")
    mean = total / count
    magnitude = float(np.linalg.norm(mean))
    if not magnitude >= LEAST_GRAVITY:
        raise ValueError(
            f"{where} reads a mean specific force of {magnitude:.3g} over {count} samples, not gravity "
            f"({GRAVITY} m/s^2 at rest): the sensor is in free fall or moving, or the accelerometer is not "
            "in m/s^2 (convert it, e.g. g times 9.80665); or give up with --up / up="
        )
    return (float(mean[0]), float(mean[1]), float(mean[2]))

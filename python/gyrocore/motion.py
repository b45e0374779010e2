"""True planar motion as a function of continuous time, and the papers' motion profiles.

A :class:`Motion` is a yaw rate and a forward speed that are piecewise linear between knots, so the
heading (their integral) is exact at any time, and one motion can be sampled at any rate. Position
is integrated on the knots (0.05 s apart at most) and interpolated. Units: s, rad/s, rad, m, m/s;
counter-clockwise positive; the heading starts at 0 and is continuous.

Profiles:

- :func:`hdr_figure3`: the HDR paper's Figure 3 and 5 drive: straight with a slight 0.1 Hz swerve,
  curving at 2 deg/s from 660 s to 680 s, then straight again.
- :func:`car`: a car drive of straight stretches, swaying, curves, 90-degree turns and stops, in the
  road mixes of the HDR paper's Tables II and IV (:data:`ROAD_MIXES`, :data:`TABLE_II_DRIVES`).
- :func:`square_path`: the FOG paper's 4x4 m bi-directional square path (0.4 m/s, 30 deg/s turns).
- :func:`rotary_table`: the FOG paper's rotary-table runs, 360 deg cw then ccw at 30 deg/s.
- :func:`robot_run`: the Hong & Park robot run: 160 s, the first 20 s calibration motion, up to 2 m/s.

For example, a square path ends where it began, heading as it started:

    >>> import numpy as np, gyrocore.motion as motion
    >>> m = motion.square_path(runs=1)
    >>> truth = m.sample(np.array([0.0, m.duration]))
    >>> [round(float(np.degrees(h)), 9) for h in truth.heading]
    [0.0, 0.0]

The modules: :mod:`.motion_model` (the motion and the builder of profiles), :mod:`.motion_roads`
(the HDR paper's drives), :mod:`.motion_lab` (the FOG and Hong & Park papers' motions); every
public name is here.
"""

from __future__ import annotations

from ._checks import public_dir
from .motion_lab import robot_run, rotary_table, square_path
from .motion_model import GRID, MAX_DURATION, Motion, Segment, Truth
from .motion_roads import (
    ROAD_MIXES,
    ROADS,
    TABLE_II_DRIVES,
    TABLE_IV_DRIVES,
    DriveSpec,
    Road,
    car,
    hdr_figure3,
)

__all__ = [
    "GRID", "MAX_DURATION", "ROADS", "ROAD_MIXES", "TABLE_II_DRIVES", "TABLE_IV_DRIVES", "DriveSpec", "Motion", "Road",
    "Segment", "Truth", "car", "hdr_figure3", "robot_run", "rotary_table", "square_path",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

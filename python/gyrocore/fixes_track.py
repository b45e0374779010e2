"""Heading fixes from a track of positions, for logs that record where the vehicle was (x/y, or
latitude/longitude) but not its course.

Between two positions the vehicle moved along the chord, so the chord's direction is its course
at the middle of the interval (exactly so on a circle driven at constant speed, to second order
in the interval otherwise). Each pair of consecutive positions gives one fix at the middle of
their times. Two position errors of ``position_sigma`` [m] each move the chord's direction by
about ``sqrt(2) * position_sigma / distance`` [rad], so a fix's sigma grows as the distance
between the positions shrinks; below ``min_speed`` the chord is mostly noise (a vehicle at rest
has no course) and the pair gives no fix. Like course over ground, this assumes the vehicle moves
the way it points (no side slip, forward gear).

Units: s, m, rad (headings counter-clockwise from east, as the logs' ``reference.csv``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import READ_GNSS, FloatArray, as_float_array, no_path_for_arrays
from ._checks import check_number, keyword_options, require_finite, require_increasing, require_options, warn
from .fixes import Fixes, warn_no_fix


#: Mean Earth radius [m] (IUGG), for :func:`from_latlon`'s local plane.
EARTH_RADIUS = 6_371_008.8
#: The largest latitude [deg] :func:`from_latlon` takes, 11 km from a pole. Nearer, a step's
#: longitude difference grows to a sizeable angle (180 deg for one across the pole), and laying it
#: out east at its middle latitude no longer gives its course; the course from east, which the
#: fixes are, turns by the step's longitude difference times the sine of the latitude as it goes.
MAX_LATITUDE = 89.9
_POLAR_KM = EARTH_RADIUS * math.radians(90.0 - MAX_LATITUDE) / 1000.0
#: The largest position [m] :func:`from_positions` takes (7 times the Sun's distance): beyond it a
#: position is corrupt (an infinite one was left out as if unknown, and 1e300 gave a fix as
#: confident as any, its chord hardly affected by the position's error).
MAX_POSITION = 2.0**40


@no_path_for_arrays("gyrocore.fixes.from_positions", READ_GNSS)
def from_positions(t: ArrayLike, x: ArrayLike, y: ArrayLike, *, position_sigma: float = 1.0,
                   min_speed: float = 2.0, min_sigma_deg: float = 0.5) -> Fixes:
    """Fixes from positions ``x`` (east) and ``y`` (north) [m] at strictly increasing times ``t``
    [s]: the direction of each step, at its middle time, with ``sigma = hypot(min_sigma,
    sqrt(2) * position_sigma / distance)`` [rad]. Steps slower than ``min_speed`` [m/s] and steps
    with a position unknown (NaN) are left out, and a position that is infinite or beyond
    +-:data:`MAX_POSITION` is an error naming it; positions that give no fix at all warn why (an
    :class:`~gyrocore.InputWarning` with the step speeds seen)."""
    tt, xx, yy = (as_float_array(name, a) for name, a in (("t", t), ("x", x), ("y", y)))
    if not (len(tt) == len(xx) == len(yy)):
        raise ValueError(f"t, x and y must have one length, got {len(tt)}, {len(xx)} and {len(yy)}")
    position_sigma, min_speed, min_sigma_deg = (check_number(name, value) for name, value in (
        ("position_sigma", position_sigma), ("min_speed", min_speed), ("min_sigma_deg", min_sigma_deg)))
    require_finite("t", tt, context="positions")
    require_increasing("t", tt, context="positions")
    for name, values in (("x", xx), ("y", yy)):
        with np.errstate(invalid="ignore"):
            far = np.flatnonzero(np.abs(values) > MAX_POSITION)  # NaN: a position unknown there
        if len(far):  # an infinite one was left out as if unknown, 1e300 gave a confident fix
            i = int(far[0])
            raise ValueError(f"positions: {name}[{i}] is {values[i]}: beyond +-2^40 m; a position is in metres (NaN "
                             "where it is unknown): drop or repair the sample")
    dt, dx, dy = np.diff(tt), np.diff(xx), np.diff(yy)
    distance = np.hypot(dx, dy)
    with np.errstate(invalid="ignore"):
        keep = np.isfinite(distance) & (distance >= min_speed * dt)
    if len(tt) == 1:  # a course is the step between two positions
        warn("1 position gives no heading fix: a fix is the course of the step between two positions")
    elif len(tt) and not keep.any():
        known = np.isfinite(distance)
        warn_no_fix(f"{len(tt)} positions", distance[known] / dt[known], min_speed)
    middle = 0.5 * (tt[:-1] + tt[1:])
    sigma = np.hypot(math.radians(min_sigma_deg), math.sqrt(2.0) * position_sigma / distance[keep])
    return Fixes(middle[keep], np.arctan2(dy[keep], dx[keep]), sigma)


@no_path_for_arrays("gyrocore.fixes.from_latlon", READ_GNSS)
def from_latlon(t: ArrayLike, lat_deg: ArrayLike, lon_deg: ArrayLike, **options: float) -> Fixes:
    """:func:`from_positions` for latitude and longitude [deg] on a sphere: each step between two
    positions is laid out east (x) and north (y) at its own middle latitude, so a fix's course is
    the step's local one wherever the drive goes (a plane tangent at the first position alone
    skews the east-west scale by the cosine of the latitude travelled since: 0.46 deg on a
    north-east course 100 km north of it at 45 deg). ``options`` go to :func:`from_positions`.

    Latitudes lie within +-:data:`MAX_LATITUDE` (89.9 deg; nearer a pole the local east/north
    layout of a step breaks down) and longitudes within -180 and 180 deg or 0 and 360 (each step's
    longitude difference is wrapped, so either convention, and a track across the antimeridian or
    across 0 deg in the second, gives the same fixes); a ValueError names the first that does not.
    NaN is a position unknown there: the steps to and from it give no fix.

    No fix from a track whose every latitude lies within +-pi/2 and longitude within +-pi warns
    that they look like radians (read as degrees, a drive in radians moves 57 times too little
    for a course)."""
    require_options("from_latlon (from_positions's)", options, keyword_options(from_positions))
    lat, lon = as_float_array("lat_deg", lat_deg), as_float_array("lon_deg", lon_deg)
    if len(lat) != len(lon):
        raise ValueError(f"lat_deg and lon_deg must have one length, got {len(lat)} and {len(lon)}")
    _check_latlon(lat, lon)
    finite = np.flatnonzero(np.isfinite(lat) & np.isfinite(lon))
    if len(finite) == 0:
        raise ValueError("no finite latitude and longitude: no position to take a course from")
    phi, lam = np.radians(lat), np.radians(lon)
    # each step's longitude difference wrapped into (-pi, pi], so a track across the antimeridian
    # stays whole, and scaled by the cosine of the step's middle latitude
    east = EARTH_RADIUS * np.cos(0.5 * (phi[1:] + phi[:-1])) * np.angle(np.exp(1j * np.diff(lam)))
    # positions whose consecutive differences are those steps (a step to or from a position that
    # is not finite gives no fix, and adds nothing here)
    x = np.concatenate(([0.0], np.cumsum(np.where(np.isfinite(east), east, 0.0))))
    x[~(np.isfinite(lat) & np.isfinite(lon))] = np.nan
    y = EARTH_RADIUS * (phi - phi[finite[0]])
    fixes = from_positions(t, x, y, **options)
    if not len(fixes) and _look_like_radians(lat[finite], lon[finite]):
        warn("the latitudes and longitudes look like radians (every |lat| <= pi/2 and |lon| <= pi, "
             "as degrees open sea near 0 N 0 E): from_latlon takes degrees; convert with numpy.degrees")
    return fixes


def _check_latlon(lat: FloatArray, lon: FloatArray) -> None:
    """A ValueError naming the first latitude beyond +-:data:`MAX_LATITUDE` (or beyond +-90, no
    latitude) and the first longitude beyond +-360 (in neither convention); NaN is a position
    unknown there."""
    with np.errstate(invalid="ignore"):
        near_pole, far = np.flatnonzero(np.abs(lat) > MAX_LATITUDE), np.flatnonzero(np.abs(lon) > 360.0)
    if len(near_pole):
        i = int(near_pole[0])
        if abs(lat[i]) > 90.0:
            raise ValueError(f"lat_deg[{i}] is {lat[i]}: a latitude lies within -90 and 90 deg")
        raise ValueError(
            f"lat_deg[{i}] is {lat[i]}: within {_POLAR_KM:.0f} km of a pole, east and north turn with every "
            "step's longitude, so a step's local east/north layout (and a course from east) breaks down "
            f"there; from_latlon takes latitudes within +-{MAX_LATITUDE} deg"
        )
    if len(far):
        i = int(far[0])
        raise ValueError(f"lon_deg[{i}] is {lon[i]}: a longitude lies within -180 and 180 deg (or 0 and 360)")


def _look_like_radians(lat: FloatArray, lon: FloatArray) -> bool:
    """Every latitude within +-pi/2 and longitude within +-pi: radians, or a track within 175 km of
    0 N 0 E (open sea)."""
    return bool(np.all(np.abs(lat) <= math.pi / 2) and np.all(np.abs(lon) <= math.pi))

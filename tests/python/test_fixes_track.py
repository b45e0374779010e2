"""Heading fixes from a track of positions (gyrocore.fixes.from_positions, from_latlon): exact on
a circle, the sigma and the slow steps, named errors, and a real KITTI track fused with its MEMS twin."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import gyrocore
from gyrocore import fixes, fixes_track

from .conftest import real_log_path


def test_a_chord_of_a_circle_driven_at_constant_speed_points_along_the_middle_tangent() -> None:
    t = np.sort(np.random.default_rng(1).uniform(0.0, 60.0, 200))   # irregular times
    radius, omega = 50.0, 0.2                                       # 10 m/s, counter-clockwise
    x, y = radius * np.cos(omega * t), radius * np.sin(omega * t)
    f = fixes.from_positions(t, x, y)
    assert len(f) == len(t) - 1 - int(np.sum(np.diff(t) * radius * omega < 2.0 * np.diff(t)))
    middle = 0.5 * (t[:-1] + t[1:])
    np.testing.assert_allclose(f.t, middle)
    tangent = omega * middle + math.pi / 2
    assert np.max(np.abs(np.angle(np.exp(1j * (f.heading - tangent))))) < 1e-9


def test_sigma_grows_as_the_step_shrinks_and_slow_or_unknown_steps_give_no_fix() -> None:
    t = np.arange(6.0)
    x = np.array([0.0, 10.0, 15.0, 16.0, np.nan, 30.0])   # steps of 10, 5, 1 m, then a gap in the track
    f = fixes.from_positions(t, x, np.zeros(6), position_sigma=0.5, min_speed=2.0, min_sigma_deg=0.5)
    np.testing.assert_array_equal(f.t, [0.5, 1.5])
    np.testing.assert_array_equal(f.heading, [0.0, 0.0])
    expected = np.hypot(math.radians(0.5), math.sqrt(2.0) * 0.5 / np.array([10.0, 5.0]))
    np.testing.assert_allclose(f.sigma, expected)
    backwards = fixes.from_positions(t, -x, np.zeros(6))
    np.testing.assert_allclose(np.abs(backwards.heading), math.pi)


def test_latitude_and_longitude_give_the_course_counter_clockwise_from_east() -> None:
    t = np.arange(10.0)
    north = fixes.from_latlon(t, 48.0 + 1e-4 * t, np.full(10, 11.0))   # about 11 m/s north
    np.testing.assert_allclose(north.heading, math.pi / 2, atol=1e-9)
    east = fixes.from_latlon(t, np.full(10, 48.0), 11.0 + 1e-4 * t)
    np.testing.assert_allclose(east.heading, 0.0, atol=1e-9)
    across = fixes.from_latlon(t, np.full(10, 0.0), (179.9995 + 1e-4 * t + 180.0) % 360.0 - 180.0)
    assert len(across) == 9
    np.testing.assert_allclose(across.heading, 0.0, atol=1e-9)   # eastward across the antimeridian


@pytest.mark.parametrize("bearing_deg", [45.0, 100.0, 330.0])
def test_a_long_drive_at_one_course_gives_that_course_far_from_its_start(bearing_deg: float) -> None:
    # A vehicle holding one course follows a rhumb line: latitude moves with the distance's north
    # part, longitude with the Mercator latitude (psi = ln tan(pi/4 + phi/2)) times tan(bearing).
    # 20 m/s for two hours from 45 N, over 140 km in all; a NaN position midway drops two steps.
    theta = math.radians(bearing_deg)  # clockwise from north
    t = np.arange(0.0, 7200.0, 1.0)
    phi = math.radians(45.0) + 20.0 * t * math.cos(theta) / fixes_track.EARTH_RADIUS
    psi = np.log(np.tan(math.pi / 4 + phi / 2))
    lam = math.radians(7.0) + math.tan(theta) * (psi - psi[0])
    lat, lon = np.degrees(phi), np.degrees(lam)
    lat[3600] = np.nan
    track = fixes.from_latlon(t, lat, lon)
    assert len(track) == len(t) - 3
    expected = math.atan2(math.cos(theta), math.sin(theta))  # counter-clockwise from east
    error = np.degrees(np.abs(np.angle(np.exp(1j * (track.heading - expected)))))
    assert error.max() < 1e-4, error.max()  # the tangent plane at the start: 0.3-0.5 deg off


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: fixes.from_positions([0.0, 1.0], [0.0], [0.0, 1.0]), "t, x and y must have one length, got 2, 1 and 2"),
        (lambda: fixes.from_positions([0.0, 1.0, 1.0], [0, 5, 9], [0, 0, 0]), r"positions: t must strictly increase: t\[2\] = 1.0 follows 1.0"),
        (lambda: fixes.from_positions([0.0, np.nan], [0, 5], [0, 0]), r"positions: t\[1\] is nan: samples must be finite"),
        (lambda: fixes.from_positions([0.0, 1.0], [0, 5], [0, 0], position_sigma=0.0), "position_sigma must be finite and > 0"),
        (lambda: fixes.from_latlon([0.0, 1.0], [10.0, 95.0], [0.0, 0.0]), r"lat_deg\[1\] is 95.0"),
        (lambda: fixes.from_latlon([0.0, 1.0, 2.0], [89.0, 89.95, 90.5], [0.0, 0.0, 0.0]),
         r"lat_deg\[1\] is 89.95: within 11 km of a pole, .* from_latlon takes latitudes within \+-89.9 deg"),
        (lambda: fixes.from_latlon([0.0, 1.0, 2.0], [10.0, 10.0, 10.0], [0.0, 360.0, 400.0]),
         r"lon_deg\[2\] is 400.0: a longitude lies within -180 and 180 deg \(or 0 and 360\)"),
        (lambda: fixes.from_latlon([0.0, 1.0], [np.nan, np.nan], [0.0, 0.0]), "no finite latitude and longitude"),
    ],
)
def test_bad_tracks_are_named(call: object, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        call()  # type: ignore[operator]


def test_a_track_that_gives_no_fix_says_why() -> None:
    t = np.arange(10.0)
    with pytest.warns(gyrocore.InputWarning, match=r"no heading fix from 10 positions: every speed is below min_speed "
                                                   r"= 2 m/s \(speeds from 1 to 1 m/s\)"):
        assert len(fixes.from_positions(t, t, np.zeros(10))) == 0


def test_latitudes_and_longitudes_in_radians_are_told_to_be_degrees() -> None:
    t = np.arange(60.0)
    lat, lon = 48.0 + 1e-4 * t, np.full(60, 11.0)   # about 11 m/s north
    with pytest.warns(gyrocore.InputWarning) as caught:
        assert len(fixes.from_latlon(t, np.radians(lat), np.radians(lon))) == 0
    messages = [str(w.message) for w in caught]
    assert "no heading fix from 60 positions: every speed is below min_speed" in messages[0]
    assert "look like radians" in messages[1] and "from_latlon takes degrees; convert with numpy.degrees" in messages[1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(fixes.from_latlon(t, lat, lon)) == 59


def test_a_real_track_fixes_its_mems_twin() -> None:
    # KITTI 0018's reference track (OXTS positions, 10 Hz), one position a second, as the only
    # heading source of the twin's simulated MEMS gyro (0.5 deg/s bias, 2 % scale error; raw
    # integration 70.6 deg).
    log = gyrocore.read_log(real_log_path("kitti_2011_09_30_0018_mems"))
    t, x, y = log.track()
    f = fixes.from_positions(t[::10], x[::10], y[::10], position_sigma=0.1)
    reference = np.interp(f.t, log.t_ref, np.unwrap(log.heading_ref))
    assert np.median(np.abs(np.angle(np.exp(1j * (f.heading - reference))))) < math.radians(0.5)
    for mode, limit in (("causal", 1.5), ("smoothed", 1.0)):
        fused = fixes.fuse(log.t, log.rate, f, mode=mode)
        e_psi = gyrocore.heading_errors(log.t, fused.heading, log.t_ref, log.heading_ref, absolute=True).e_psi_deg
        assert e_psi < limit, (mode, e_psi)


def test_a_track_near_a_pole_is_refused_where_its_steps_lose_their_course() -> None:
    # 4.4 m from the north pole, a step across it (8.9 m, north then south) was laid out as 14 m east
    t = np.arange(3.0)
    with pytest.raises(ValueError, match=r"lat_deg\[0\] is 89.99996: within 11 km of a pole"):
        fixes.from_latlon(t, [89.99996, 89.99996, 89.99996], [0.0, 180.0, 0.0])
    with pytest.raises(ValueError, match=r"lat_deg\[2\] is -90.0: within 11 km of a pole"):
        fixes.from_latlon(t, [-89.0, -89.5, -90.0], [0.0, 0.0, 0.0])
    # up to the limit a track's fixes are the course of its steps
    lat = 89.9 - 1e-4 * t
    assert np.degrees(fixes.from_latlon(t, lat, np.zeros(3)).heading) == pytest.approx([-90.0, -90.0])


def test_longitudes_from_0_to_360_give_the_fixes_of_those_from_minus_180() -> None:
    t = np.arange(5.0)
    lat = np.full(5, 10.0)
    lon = np.array([359.9998, 359.9999, 0.0, 0.0001, 0.0002])
    wrapped = fixes.from_latlon(t, lat, lon)
    assert len(wrapped) == 4
    np.testing.assert_allclose(wrapped.heading, fixes.from_latlon(t, lat, np.where(lon > 180, lon - 360, lon)).heading,
                               atol=1e-9)

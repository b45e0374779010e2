"""A file's name given where a call takes arrays, as the command line takes files: every public call
of arrays says what it takes and how a file is read, given the name alone or with the rest."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import gyrocore
import gyrocore.allan
import gyrocore.calibration
import gyrocore.deadreckon
import gyrocore.evaluate
import gyrocore.fixes
import gyrocore.sim

LOG = "a log file or folder is read with gyrocore.read_log(path), and its arrays ({}) are given here"
CALIBRATE = " (on the command line: gyrocore calibrate FILE)"

#: call, its name as said, the arrays it takes as said, the way on as said
CALLS: list[tuple[Callable[..., Any], str, str, str]] = [
    (gyrocore.fuse, "gyrocore.fuse", "t [s], rate [rad/s] and fixes", "a log folder is read with gyrocore.read_log(path), its fixes"),
    (gyrocore.fixes.Fusion().process, "gyrocore.fixes.Fusion.process", "t [s] and rate [rad/s]", "gyrocore process FILE --fixes FIXES)"),
    (gyrocore.fixes.from_gnss, "gyrocore.fixes.from_gnss", "t [s], bearing_deg [deg] and speed [m/s]", "gyrocore.fixes.read_nmea(path)"),
    (gyrocore.fixes.from_positions, "gyrocore.fixes.from_positions", "t [s], x [m] and y [m]", "gyrocore.fixes.read_nmea(path)"),
    (gyrocore.fixes.from_latlon, "gyrocore.fixes.from_latlon", "t [s], lat_deg [deg] and lon_deg [deg]", "read_gnss_csv(path)"),
    (gyrocore.allan.deviation, "gyrocore.allan.deviation", "rate [rad/s] and dt [s]", LOG.format("log.rate, and its sample interval as dt")),
    (gyrocore.allan.deviation_from_timestamps, "gyrocore.allan.deviation_from_timestamps", "t [s] and rate [rad/s]", "gyrocore allan FILE"),
    (gyrocore.calibration.static_bias, "gyrocore.calibration.static_bias", "t [s] and rate [rad/s]", LOG.format("log.t, log.rate") + CALIBRATE),
    (gyrocore.calibration.detect_rest, "gyrocore.calibration.detect_rest", "t [s] and rate [rad/s]", CALIBRATE),
    (gyrocore.calibration.rest_windows, "gyrocore.calibration.rest_windows", "t [s] and rate [rad/s]", CALIBRATE),
    (gyrocore.calibration.rotary_table, "gyrocore.calibration.rotary_table", "t [s] and rate [rad/s]", CALIBRATE),
    (gyrocore.calibration.heading_reference, "gyrocore.calibration.heading_reference",
     "t [s], rate_measured [rad/s], t_ref [s] and heading_ref [rad]", LOG.format("log.t, log.rate, log.t_ref, log.heading_ref")),
    (gyrocore.calibration.time_offset, "gyrocore.calibration.time_offset",
     "t [s], rate_measured [rad/s], t_ref [s] and heading_ref [rad]", LOG.format("log.t, log.rate, log.t_ref, log.heading_ref")),
    (gyrocore.calibration.rate_reference, "gyrocore.calibration.rate_reference", "rate_measured [rad/s] and rate_reference [rad/s]", CALIBRATE),
    (gyrocore.calibration.bias_temperature_table, "gyrocore.calibration.bias_temperature_table",
     "t [s], rate [rad/s] and temperature", CALIBRATE),
    (gyrocore.integrate, "gyrocore.integrate", "t [s] and rate [rad/s]", LOG.format("log.t, log.rate")),
    (gyrocore.downsample, "gyrocore.downsample", "t [s] and rate [rad/s]", LOG.format("log.t, log.rate")),
    (gyrocore.heading_errors, "gyrocore.heading_errors", "t [s], heading [rad], t_ref [s] and heading_ref [rad]",
     "(on the command line: gyrocore evaluate FOLDER)"),
    (gyrocore.evaluate.return_orientation_error, "gyrocore.evaluate.return_orientation_error", "t [s] and heading [rad]", "read_log"),
    (gyrocore.sim.gnss_fixes, "gyrocore.sim.gnss_fixes", "t_ref [s] and heading_ref [rad]", LOG.format("log.t_ref, log.heading_ref")),
    (gyrocore.deadreckon.dead_reckon, "gyrocore.deadreckon.dead_reckon", "t_speed [s], speed [m/s], t_heading [s] and heading [rad]",
     "log.t_odometry, log.speed"),
    (gyrocore.process, "gyrocore.process", "t [s] and rate [rad/s]", "then processed with its .process(preset)"),
]


@pytest.mark.parametrize(("call", "name", "takes", "way"), CALLS, ids=[c[1] for c in CALLS])
@pytest.mark.parametrize("given", ["drive.csv", Path("logs/drive1")])
def test_a_file_given_alone_is_told_what_the_call_takes_and_how_the_file_is_read(
    call: Callable[..., Any], name: str, takes: str, way: str, given: str | Path
) -> None:
    # alone it met Python's own "fuse() missing 2 required positional arguments: 'rate' and 'fixes'"
    first = next(iter(__import__("inspect").signature(call).parameters))
    said = f"{first} = {given!r}: a file's name, not a sequence of numbers; {name} takes {takes}; "
    with pytest.raises(TypeError) as alone:
        call(given)
    assert str(alone.value).startswith(said) and way in str(alone.value)
    with pytest.raises(TypeError, match=re.escape(said)):  # by keyword too
        call(**{first: given})

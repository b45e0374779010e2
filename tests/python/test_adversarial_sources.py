"""Inputs found by adversarial testing of the heading-fix sources, ROS bags, log folders and the
tune command: each was a bare Python error naming another function, a misleading message or a
value taken without a word, and is now refused or warned about in words that name it."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from gyrocore import fixes

T = np.arange(10.0)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda path: fixes.read_gnss_csv(path / "gnss.csv", min_sped=1.0),
         "unknown option(s) 'min_sped' (did you mean 'min_speed'?) of read_gnss_csv (from_gnss's); choose from "
         "min_speed, speed_sigma, min_sigma_deg"),
        (lambda path: fixes.read_nmea(path / "gnss.nmea", min_sped=1.0),
         "unknown option(s) 'min_sped' (did you mean 'min_speed'?) of read_nmea (from_gnss's)"),
        (lambda path: fixes.from_latlon(T, np.full(10, 45.0), T * 1e-3, speed_sigma=1.0),
         "unknown option(s) 'speed_sigma' of from_latlon (from_positions's); choose from position_sigma, min_speed, "
         "min_sigma_deg"),
        (lambda path: fixes.fuse(T, np.zeros(10), ([3.0], [0.5], [0.1]), gat=3.0),
         "unknown fusion setting(s) gat (did you mean 'gate'?); choose from"),
    ],
    ids=["read_gnss_csv", "read_nmea", "from_latlon", "fuse"],
)
def test_an_unknown_option_passed_on_is_named_with_the_function_called(
    tmp_path: Path, call: object, message: str
) -> None:
    """``read_gnss_csv(path, min_sped=1)`` was ``from_gnss() got an unexpected keyword argument
    'min_sped'`` (``from_latlon``: ``from_positions() ...``), a function the caller never called,
    with no hint; ``fuse(..., gat=3)`` suggested nothing."""
    (tmp_path / "gnss.csv").write_text("t,speed,bearing\n0,5,10\n1,5,20\n")
    (tmp_path / "gnss.nmea").write_text("$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\n")
    with pytest.raises(TypeError, match="^" + re.escape(message)):
        call(tmp_path)  # type: ignore[operator]

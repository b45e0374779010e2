"""NMEA logs as loggers record them: a log that opens in the last minute before midnight with its
date advanced early (gyrocore.fixes.read_nmea)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gyrocore import InputWarning
from gyrocore.fixes import read_nmea

from .test_fixes_nmea import nmea, rmc

pynmea2 = pytest.importorskip("pynmea2")

#: 1994-03-23 00:00:00 UTC, the day of rmc()'s date 230394.
DAY0 = 764380800.0



def test_a_log_opening_with_its_date_advanced_early_is_not_a_day_late(tmp_path: Path) -> None:
    # a receiver dating by GPS time, its log opening 10 s before midnight UTC with the next day's
    # date already: every fix was put a day late, 23:59:50 on the 24th and 00:00:00 on the 25th
    times = [f"2359{s:02d}" for s in range(50, 60)] + [f"0000{s:02d}" for s in range(30)]
    path = nmea(tmp_path, *(rmc(time, date="240394") for time in times))
    with pytest.warns(InputWarning, match=r"drive.nmea: 10 RMC sentence\(s\) have a date field off the day their "
                                          r"time of day runs on to \(the first: line 1\), the receiver advancing it "
                                          r"early"):
        np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 86390.0 + np.arange(40))
    # fewer sentences after midnight than before it read as a date field late, as in a log of no
    # such opening; and one that catches up was late
    for dates in (["240394"] * 15, ["240394"] * 12 + ["250394"] * 3):
        path = nmea(tmp_path, *(rmc(time, date=date) for time, date in zip(times, dates)))
        with pytest.warns(InputWarning, match=r"drive.nmea: \d RMC sentence\(s\) have a date field off the day"):
            np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 86400.0 + 86390.0 + np.arange(15))

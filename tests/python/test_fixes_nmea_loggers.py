"""NMEA logs beyond a receiver's course: true headings (HDT, a dual-antenna receiver's or a
gyrocompass's) timed by the RMC or ZDA before them, a logger's timestamp before each sentence, and
a log that opens in the last minute before midnight with its date advanced early
(gyrocore.fixes.read_nmea)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from gyrocore import InputWarning
from gyrocore.fixes import read_nmea

from .test_fixes_nmea import nmea, rmc

pynmea2 = pytest.importorskip("pynmea2")

#: 1994-03-23 00:00:00 UTC, the day of rmc()'s date 230394; 12:00:00 of it.
DAY0 = 764380800.0
NOON = DAY0 + 43200.0


def hdt(heading: str, talker: str = "GP") -> str:
    """An HDT sentence with a valid checksum: a true heading [deg, clockwise from north]."""
    return str(pynmea2.HDT(talker, "HDT", (heading, "T")))


def zda(time: str, day: str = "23") -> str:
    """A ZDA sentence of ``day`` March 1994 at ``time`` (hhmmss)."""
    return str(pynmea2.ZDA("GP", "ZDA", (f"{time}.00", day, "03", "1994", "00", "00")))


def heading_deg(fixes_heading: np.ndarray) -> np.ndarray:
    """Bearings [deg, clockwise from north, 0 to 360] of headings [rad, counter-clockwise from east]."""
    return np.round(np.degrees(math.pi / 2 - fixes_heading) % 360.0, 9)


def test_hdt_headings_are_fixes_at_rest_timed_by_the_rmc_before_them(tmp_path: Path) -> None:
    # HDT was skipped: a dual-antenna receiver at rest (speed 0, no course) gave no fix at all
    lines = [line for i, talker in enumerate(("GP", "GN", "HE"))
             for line in (rmc(f"12000{i}", speed="000.0", course=""), hdt(f"{10 + 100 * i:05.1f}", talker))]
    fixes = read_nmea(nmea(tmp_path, *lines))
    np.testing.assert_array_equal(fixes.t, NOON + np.arange(3))
    np.testing.assert_array_equal(heading_deg(fixes.heading), [10.0, 110.0, 210.0])
    np.testing.assert_allclose(fixes.sigma, math.radians(0.5))  # HDT_SIGMA_DEG, whatever the speed
    assert read_nmea(nmea(tmp_path, *lines), hdt_sigma_deg=0.2).sigma == pytest.approx([math.radians(0.2)] * 3)


def test_an_epochs_hdt_takes_the_place_of_its_course_as_source_chooses(tmp_path: Path) -> None:
    # epoch 0 has a course and an HDT (different, to tell them apart), epoch 1 a course only,
    # epoch 2 an HDT at rest only
    path = nmea(tmp_path, rmc("120000", course="090.0"), hdt("080.0"), rmc("120001", course="090.0"),
                rmc("120002", speed="000.0", course=""), hdt("070.0"))
    chosen = {source: read_nmea(path, source=source) for source in ("auto", "hdt", "course")}
    np.testing.assert_array_equal(chosen["auto"].t, NOON + np.arange(3))
    np.testing.assert_array_equal(heading_deg(chosen["auto"].heading), [80.0, 90.0, 70.0])
    assert chosen["auto"].sigma[0] == chosen["auto"].sigma[2] == pytest.approx(math.radians(0.5))
    assert chosen["auto"].sigma[1] > math.radians(0.5)  # a course's, of its speed
    np.testing.assert_array_equal(chosen["hdt"].t, NOON + np.array([0.0, 2.0]))
    np.testing.assert_array_equal(heading_deg(chosen["hdt"].heading), [80.0, 70.0])
    np.testing.assert_array_equal(chosen["course"].t, NOON + np.arange(2))
    np.testing.assert_array_equal(heading_deg(chosen["course"].heading), [90.0, 90.0])
    with pytest.raises(ValueError, match=r"source must be one of 'auto', 'hdt', 'course', got 'gyro'"):
        read_nmea(path, source="gyro")
    with pytest.raises(ValueError, match=r"hdt_sigma_deg must be finite and > 0 \[deg\], got 0"):
        read_nmea(path, hdt_sigma_deg=0)
    with pytest.raises(TypeError, match=r"unknown option\(s\) 'hdt_sigma' \(did you mean 'hdt_sigma_deg'\?\)"):
        read_nmea(path, hdt_sigma=0.2)


def test_a_log_of_hdt_and_zda_alone_gives_fixes(tmp_path: Path) -> None:
    # a gyrocompass's HDT with a receiver's ZDA for the time, no RMC: a heading each second
    lines = [line for i in range(5) for line in (zda(f"12000{i}"), hdt(f"{30 * i:05.1f}", "HE"),
                                                 hdt(f"{30 * i + 1:05.1f}", "HE"))]
    with pytest.warns(InputWarning, match=r"5 HDT sentence\(s\) follow another of their epoch and are skipped"):
        fixes = read_nmea(nmea(tmp_path, *lines))
    np.testing.assert_array_equal(fixes.t, NOON + np.arange(5))
    np.testing.assert_array_equal(heading_deg(fixes.heading), 30.0 * np.arange(5))
    # a ZDA and an RMC of one epoch time its HDT alike
    fixes = read_nmea(nmea(tmp_path, rmc("120000", course=""), zda("120000"), hdt("045.0"), zda("120001"),
                           rmc("120001", course=""), hdt("046.0")))
    np.testing.assert_array_equal(fixes.t, NOON + np.arange(2))
    # a ZDA's date field late after midnight runs on into the next day, as an RMC's does
    path = nmea(tmp_path, zda("235959"), hdt("045.0"), zda("000000"), hdt("046.0"), zda("000001", "24"), hdt("047.0"))
    with pytest.warns(InputWarning, match=r"drive.nmea: 1 ZDA sentence\(s\) have a date field off the day"):
        np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 86399.0 + np.arange(3))


def test_hdt_that_no_epoch_times_is_skipped_with_a_warning(tmp_path: Path) -> None:
    # an HDT before any timed sentence, and one after a void RMC (not of the valid epoch before it)
    empty_zda = str(pynmea2.ZDA("GP", "ZDA", ("", "", "", "", "", "")))  # a receiver without the time yet
    path = nmea(tmp_path, hdt("010.0"), rmc("120000", speed="000.0", course=""), hdt("020.0"),
                rmc("120001", status="V"), hdt("030.0"), empty_zda, hdt("040.0"))
    with pytest.warns(InputWarning, match=r"drive.nmea: 3 HDT sentence\(s\) come before any valid RMC or ZDA, or "
                                          r"after a void RMC, and are skipped: .* \(the first: line 1\)"):
        fixes = read_nmea(path)
    np.testing.assert_array_equal(fixes.t, [NOON])
    np.testing.assert_array_equal(heading_deg(fixes.heading), [20.0])
    # a log of HDT alone has no time: no fix, saying why
    with pytest.warns(InputWarning, match=r"of its 2 sentences, none is RMC; 2 are HDT: 2 come before any valid RMC "
                                          r"or ZDA, .*; fixes come from valid RMC sentences with a course \(or the "
                                          r"VTG after one\), or HDT or THS of an epoch with a valid RMC or ZDA"):
        assert len(read_nmea(nmea(tmp_path, hdt("010.0"), hdt("020.0")))) == 0
    with pytest.warns(InputWarning, match=r"of its 2 sentences, none is HDT or THS; fixes come"):
        assert len(read_nmea(nmea(tmp_path, rmc("120000"), rmc("120001")), source="hdt")) == 0


@pytest.mark.parametrize(("heading", "error"), [("abc", r"line 2: an HDT sentence whose fields cannot be read"),
                                                ("400.0", r"line 2: the HDT heading '400.0' is no bearing of 0 to 360"),
                                                ("-1.0", r"line 2: the HDT heading '-1.0' is no bearing")])
def test_an_hdt_heading_that_is_no_bearing_names_its_line(tmp_path: Path, heading: str, error: str) -> None:
    with pytest.raises(ValueError, match=r"drive.nmea: " + error):
        read_nmea(nmea(tmp_path, rmc("120000"), hdt(heading)))


def test_an_hdt_without_a_heading_or_a_checksum(tmp_path: Path) -> None:
    # an empty heading (no heading solution) is no fix; one cut short is refused as an RMC is
    fixes = read_nmea(nmea(tmp_path, rmc("120000", course="090.0"), hdt("")))
    np.testing.assert_array_equal(heading_deg(fixes.heading), [90.0])
    with pytest.raises(ValueError, match=r"line 2: an HDT sentence without its checksum"):
        read_nmea(nmea(tmp_path, rmc("120000"), hdt("080.0").split("*")[0]))


@pytest.mark.parametrize("prefix", ["1634567890.123 ", "2021-10-18T12:00:00.123Z,", "[12:00:00.123] "],
                         ids=["unix-seconds", "iso-time", "bracketed-time"])
def test_a_loggers_timestamp_before_each_sentence_is_skipped(tmp_path: Path, prefix: str) -> None:
    # a serial logger's or a ROS dump's time before each sentence: "line 1: not an NMEA sentence"
    lines = [rmc(f"12000{i}") for i in range(3)] + [hdt("080.0")]
    fixes = read_nmea(nmea(tmp_path, *(prefix + line for line in lines)))
    np.testing.assert_array_equal(fixes.t, NOON + np.arange(3))  # the sentences' own times
    np.testing.assert_array_equal(heading_deg(fixes.heading), [84.4, 84.4, 80.0])
    # the checksum is still checked, from the $ on
    lines[1] = lines[1][:-1] + ("0" if lines[1][-1] != "0" else "1")
    with pytest.raises(ValueError, match=r"line 2: not an NMEA sentence .*checksum does not match"):
        read_nmea(nmea(tmp_path, *(prefix + line for line in lines)))
    # a line without $ or ! is still no sentence
    with pytest.raises(ValueError, match=r"line 2: not an NMEA sentence"):
        read_nmea(nmea(tmp_path, prefix + rmc("120000"), prefix + "GPRMC,1,2,3"))


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

"""NMEA logs as receivers write them: midnight UTC with the date field late, times that step back
or repeat, the leap second, mode indicators of no measurement, VTG's own fields, sentences cut
short, and the course convention and clock of the fixes read (gyrocore.fixes.read_nmea)."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import InputWarning
from gyrocore.fixes import read_nmea

from .test_fixes_nmea import nmea, rmc

pynmea2 = pytest.importorskip("pynmea2")

#: 1994-03-23 00:00:00 UTC, the day of rmc()'s date 230394.
DAY0 = 764380800.0


def vtg(course: str = "054.7", *, magnetic: str = "034.4", knots: str = "005.5", kmh: str = "010.2",
        mode: tuple[str, ...] = ()) -> str:
    """A VTG sentence with a valid checksum (``mode``: its mode indicator, NMEA 2.3 on)."""
    return str(pynmea2.VTG("GP", "VTG", (course, "T", magnetic, "M", knots, "N", kmh, "K", *mode)))


@pytest.mark.parametrize("dates", [("230394", "230394", "240394", "240394"), ("230394", "230394", "230394", "240394"),
                                   ("230394", "230394", "230394", "230394")],
                         ids=["date-advances", "date-one-late", "date-never-advances"])
def test_a_log_across_midnight_utc_runs_on_into_the_next_day(tmp_path: Path, dates: tuple[str, ...]) -> None:
    # a date field advanced a sentence late put 00:00:00 a day back, and the sort moved it first:
    # a fix 86398 s before the others, outside any gyro's span, the rest out of step
    times = ("235958", "235959", "000000", "000001")
    path = nmea(tmp_path, *(rmc(time, date=date) for time, date in zip(times, dates)))
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 86398.0 + np.arange(4))
    late = sum(date == "230394" for date in dates[2:])  # the sentences after midnight dated the day before
    assert [str(w.message).split(": ", 1)[1][:2] for w in said] == ([f"{late} "] if late else [])
    # a VTG after midnight gives the course of the epoch just before it, on the next day
    path = nmea(tmp_path, rmc("235959", course=""), vtg("000.0"), rmc("000000", course="", date=dates[2]),
                vtg("090.0"))
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        fixes = read_nmea(path)
    assert len(said) == (dates[2] == "230394")  # the one sentence after midnight, dated the day before
    np.testing.assert_array_equal(fixes.t, [DAY0 + 86399.0, DAY0 + 86400.0])
    np.testing.assert_allclose(fixes.heading, [math.pi / 2, 0.0], atol=1e-12)


def test_a_time_that_steps_back_names_its_line(tmp_path: Path) -> None:
    # it was sorted into place without a word: two logs run together, or a corrupt time, became
    # one drive
    path = nmea(tmp_path, rmc("120005"), rmc("120006"), rmc("120001"))
    with pytest.raises(ValueError, match=r"drive.nmea: line 3: the time steps back, from 1994-03-23 12:00:06 \(line "
                                         r"2\) to 1994-03-23 12:00:01 UTC"):
        read_nmea(path)


def test_mode_indicators_of_no_measurement_give_no_fix(tmp_path: Path) -> None:
    # status A with mode N (data not valid), E (the receiver's dead reckoning through an outage)
    # or M (manual input) gave a fix as confident as a measured one
    path = nmea(tmp_path, *(rmc(f"12000{i}", mode=(mode,)) for i, mode in enumerate("ADNEM")), rmc("120005"))
    np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 43200.0 + np.array([0.0, 1.0, 5.0]))
    path = nmea(tmp_path, rmc("120000", course=""), vtg(mode=("N",)), rmc("120001", course=""), vtg(mode=("A",)))
    np.testing.assert_array_equal(read_nmea(path).t, [DAY0 + 43201.0])
    with pytest.warns(InputWarning, match=r"of its 2 sentences, 2 are RMC: 1 void \(status V\), 1 of mode N, E, M or S"):
        assert len(read_nmea(nmea(tmp_path, rmc(status="V"), rmc(mode=("N",))))) == 0


def test_a_receivers_simulator_mode_gives_no_fix(tmp_path: Path) -> None:
    # status A with mode S (the receiver's own simulator, NMEA 2.3 on) gave fixes of no vehicle's
    # motion, as sure as measured ones
    path = nmea(tmp_path, rmc("120000", mode=("S",)), rmc("120001", course=""), vtg(mode=("S",)), rmc("120002"))
    np.testing.assert_array_equal(read_nmea(path).t, [DAY0 + 43202.0])
    with pytest.warns(InputWarning, match=r"of its 1 sentences, 1 are RMC: 1 of mode N, E, M or S \(no measurement\)"):
        assert len(read_nmea(nmea(tmp_path, rmc(mode=("S",))))) == 0


def test_a_vtg_after_a_void_rmc_gives_no_earlier_epoch_its_course(tmp_path: Path) -> None:
    # the VTG of a void epoch gave its course to the valid epoch before, one second earlier
    path = nmea(tmp_path, rmc("120000", course=""), vtg("", magnetic=""), rmc("120001", status="V"), vtg("180.0"))
    with pytest.warns(InputWarning, match="no heading fix"):
        assert len(read_nmea(path)) == 0


def test_a_vtg_speed_in_knots_alone_is_read(tmp_path: Path) -> None:
    # a VTG whose km/h field was empty gave no fix, its speed in knots unread
    fixes = read_nmea(nmea(tmp_path, rmc("120000", course=""), vtg("090.0", knots="010.0", kmh="")))
    np.testing.assert_allclose(fixes.heading, [0.0], atol=1e-12)
    np.testing.assert_allclose(fixes.sigma, [math.hypot(math.radians(0.5), 0.2 / (10.0 * 1852.0 / 3600.0))])


@pytest.mark.parametrize(("variation", "magnetic", "true"), [(("003.1", "E"), "034.4", 37.5),
                                                             (("003.1", "W"), "034.4", 31.3),
                                                             (("005.0", "E"), "358.0", 3.0),
                                                             (("005.0", "W"), "002.0", 357.0)],
                         ids=["east", "west", "east-past-north", "west-past-north"])
def test_a_vtg_magnetic_course_is_made_true_by_the_rmc_variation(tmp_path: Path, variation: tuple[str, str],
                                                                 magnetic: str, true: float) -> None:
    # a VTG with its true course empty gave no fix, where its RMC gave the variation (NMEA 0183:
    # an easterly variation subtracts from the true course, so true = magnetic + east, - west)
    fixes = read_nmea(nmea(tmp_path, rmc("120000", course="", variation=variation), vtg("", magnetic=magnetic)))
    assert len(fixes) == 1
    np.testing.assert_allclose(np.angle(np.exp(1j * (fixes.heading - math.radians(90.0 - true)))), 0.0, atol=1e-9)


def test_a_vtg_magnetic_course_without_a_variation_is_skipped_saying_what_to_do(tmp_path: Path) -> None:
    unknown = {"variation": ("", "")}
    said = r"1 VTG give a magnetic course only, and the RMC of their epoch no magnetic variation .*: their epochs"
    with pytest.warns(InputWarning, match=r"1 without a course; " + said + r" are skipped; set the receiver to write "
                                          r"the true course in VTG, or the magnetic variation in RMC"):
        assert len(read_nmea(nmea(tmp_path, rmc("120000", course="", **unknown), vtg("", magnetic="034.4")))) == 0
    # among fixes it was skipped without a word
    path = nmea(tmp_path, rmc("120000"), rmc("120001", course="", **unknown), vtg("", magnetic="034.4"))
    with pytest.warns(InputWarning, match=r"drive.nmea: 1 VTG sentence\(s\) give a magnetic course only, and the RMC"):
        assert len(read_nmea(path)) == 1
    # a variation that is no angle is the RMC's line
    path = nmea(tmp_path, rmc("120000"), rmc("120001", course="", variation=("x", "E")), vtg("", magnetic="034.4"))
    with pytest.raises(ValueError, match=r"drive.nmea: line 2: the RMC's magnetic variation \('x', 'E'\) is no angle"):
        read_nmea(path)


@pytest.mark.parametrize("fields", [("054.7", "T", "005.5", "N", "010.2", "K"),
                                    ("054.7", "T", "005.5", "N", "010.2", "K", "A"),
                                    ("054.7", "034.4", "005.5", "010.2"),
                                    ("054.7", "", "034.4", "", "005.5", "", "010.2", "", "A")],
                         ids=["magnetic-pair-left-out", "magnetic-pair-left-out-with-mode", "before-nmea-2",
                              "letters-left-empty"])
def test_a_vtg_is_read_by_its_unit_letters(tmp_path: Path, fields: tuple[str, ...]) -> None:
    # without the magnetic pair the knots were read as a magnetic course and the km/h as knots (a
    # speed 1.85 times too high, a sigma too small); the letterless VTG of NMEA 0183 before
    # version 2 gave no fix, without a word
    fixes = read_nmea(nmea(tmp_path, rmc("120000", course=""), str(pynmea2.VTG("GP", "VTG", fields))))
    np.testing.assert_allclose(fixes.heading, [math.radians(90.0 - 54.7)], atol=1e-12)
    np.testing.assert_allclose(fixes.sigma, [math.hypot(math.radians(0.5), 0.2 / (10.2 / 3.6))], rtol=1e-12)


def test_a_date_advanced_early_before_midnight_is_put_on_its_day(tmp_path: Path) -> None:
    # a receiver that takes its date from GPS time stamps the next day's date on the last seconds
    # before midnight UTC: 00:00:00 stepped a day back from 23:59:59, "the time steps back"
    times, dates = ("235958", "235959", "000000", "000001"), ("230394", "240394", "240394", "240394")
    path = nmea(tmp_path, *(rmc(time, date=date) for time, date in zip(times, dates)))
    with pytest.warns(InputWarning, match=r"drive.nmea: 1 RMC sentence\(s\) have a date field off the day their "
                                          r"time of day runs on to \(the first: line 2\), the receiver advancing it "
                                          r"early"):
        np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 86398.0 + np.arange(4))
    # 18 s early (GPS time's lead on UTC), at 1 Hz
    times = [f"2359{s:02d}" for s in range(40, 60)] + ["000000", "000001"]
    path = nmea(tmp_path, *(rmc(time, date="240394" if i >= 2 else "230394") for i, time in enumerate(times)))
    with pytest.warns(InputWarning, match=r"18 RMC sentence\(s\) have a date field off the day"):
        np.testing.assert_array_equal(read_nmea(path).t, DAY0 + 86380.0 + np.arange(22))
    # a genuine step back is still one
    path = nmea(tmp_path, rmc("235959", date="230394"), rmc("235958", date="240394"))
    with pytest.raises(ValueError, match=r"line 2: the time steps back, from 1994-03-23 23:59:59 \(line 1\) to "
                                         r"1994-03-23 23:59:58 UTC"):
        read_nmea(path)
    # further from midnight the next day's date is a gap in the log, taken as written
    for time in ("120001", "235800"):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            fixes = read_nmea(nmea(tmp_path, rmc("120000", date="230394"), rmc(time, date="240394")))
        assert fixes.t[1] == DAY0 + 86400.0 + int(time[:2]) * 3600 + int(time[2:4]) * 60 + int(time[4:])


def test_a_sentence_without_its_checksum_names_its_line(tmp_path: Path) -> None:
    # pynmea2 takes a sentence without one: an RMC cut in its date ("230394" to "2303") was dated
    # 2 March 2003, a fix nine years on; one cut in its course took the digits left
    whole = rmc("120001")
    for cut in (whole[:whole.index("230394") + 4], whole.split("*")[0]):
        path = nmea(tmp_path, rmc("120000"), cut, rmc("120002"))
        with pytest.raises(ValueError, match=r"drive.nmea: line 2: an RMC sentence without its checksum \(\*hh; "):
            read_nmea(path)
    with pytest.raises(ValueError, match=r"line 2: an VTG sentence without its checksum"):
        read_nmea(nmea(tmp_path, rmc("120000", course=""), vtg().split("*")[0]))


def test_a_last_line_cut_off_without_a_line_end_is_skipped(tmp_path: Path) -> None:
    # a log stopped while it was written: its last line is what there is of a sentence
    for cut in (rmc("120002")[:30], rmc("120002")[:-1]):
        path = tmp_path / "drive.nmea"
        path.write_text(f"{rmc('120000')}\n{rmc('120001')}\n{cut}")
        with pytest.warns(InputWarning, match=r"drive.nmea: line 3, the last, is cut off without a line end"):
            assert len(read_nmea(path)) == 2
        path.write_text(f"{rmc('120000')}\n{cut}\n{rmc('120001')}")  # within the file: an error
        with pytest.raises(ValueError, match=r"drive.nmea: line 2: "):
            read_nmea(path)


def test_a_time_repeated_with_other_values_keeps_its_first(tmp_path: Path) -> None:
    # the last sentence of a time was kept without a word: a 5 Hz receiver writing whole seconds
    # has its first at the time, the others up to 0.8 s after it
    path = nmea(tmp_path, rmc("120000", course="000.0"), rmc("120000", course="090.0"), rmc("120001"),
                rmc("120001"))
    with pytest.warns(InputWarning, match=r"drive.nmea: 1 RMC sentence\(s\) repeat the time of an earlier one with "
                                          r"another course or speed \(the first: line 2\)"):
        fixes = read_nmea(path)
    np.testing.assert_array_equal(fixes.t, DAY0 + 43200.0 + np.arange(2))
    assert fixes.heading[0] == pytest.approx(math.pi / 2)


def test_the_leap_second_is_skipped_with_a_warning(tmp_path: Path) -> None:
    # 23:59:60 was an error that refused the whole log ("combine() argument 2 must be datetime.time")
    path = nmea(tmp_path, rmc("235959", date="311216"), rmc("235960", date="311216"), rmc("000000", date="010117"))
    with pytest.warns(InputWarning, match=r"1 RMC sentence\(s\) in the leap second 23:59:60 UTC are skipped"):
        assert list(read_nmea(path).t) == [1483228799.0, 1483228800.0]


def test_talkers_rates_and_directions_read_as_written(tmp_path: Path) -> None:
    # GPS, multi-constellation, GLONASS, Galileo and BeiDou talkers at 10 Hz, driving north, east,
    # south and west: headings counter-clockwise from east
    talkers, bearings = ("GP", "GN", "GL", "GA", "BD", "GB"), ("000.0", "090.0", "180.0", "270.0")
    lines = [str(pynmea2.RMC(talkers[i % 6], "RMC", (f"1200{i // 10:02d}.{i % 10}0", "A", "4807.038", "N", "01131.000",
                                                     "E", "010.0", bearings[i % 4], "230394", "", "")))
             for i in range(24)]
    fixes = read_nmea(nmea(tmp_path, *lines))
    np.testing.assert_allclose(fixes.t - fixes.t[0], 0.1 * np.arange(24), atol=1e-6)
    expected = np.tile([math.pi / 2, 0.0, -math.pi / 2, math.pi], 6)
    np.testing.assert_allclose(np.angle(np.exp(1j * (fixes.heading - expected))), 0.0, atol=1e-12)


def test_fixes_in_utc_seconds_say_how_to_put_them_on_the_gyros_clock() -> None:
    # the warning said to give the fixes on the gyro's clock, not how
    t = np.arange(0.0, 30.0, 0.01)
    utc = gyrocore.fixes.from_gnss(1.7e9 + np.arange(30.0), np.zeros(30), np.full(30, 10.0))
    said = r"from fixes in UTC \(Unix\) seconds, as read_nmea gives them, subtract the UTC time at which the gyro's clock"
    with pytest.warns(InputWarning, match=r"none of the 30 heading fixes fall within .*" + said):
        gyrocore.fixes.fuse(t, np.zeros_like(t), utc)
    with pytest.warns(InputWarning, match=r"after the last gyro sample .*" + said):
        gyrocore.fixes.Fusion().process(t, np.zeros_like(t), utc)


def test_a_serial_log_with_binary_messages_among_its_sentences_is_read(tmp_path: Path) -> None:
    # a u-blox serial log (UBX messages between the sentences, their bytes split into lines by the
    # line ends among them, a sentence after one on its line) was refused at its first binary line
    rng = np.random.default_rng(7)
    ubx = [b"\xb5b\x01\x07" + rng.integers(0, 256, int(n)).astype(np.uint8).tobytes()
           for n in rng.integers(20, 400, 100)]
    body = b"".join(message + f"{rmc(f'1200{i:02d}', course='')}\r\n{vtg()}\r\n".encode()
                    for i, message in enumerate(ubx[:50])) + b"".join(ubx[50:])
    path = tmp_path / "drive.ubx"
    path.write_bytes(body)
    with pytest.warns(InputWarning, match=r"drive.ubx: binary data from line 1 on, a receiver's binary messages "
                                          r"\(u-blox UBX\) among its sentences: \d+ line\(s\) of it"):
        fixes = read_nmea(path)
    np.testing.assert_array_equal(fixes.t, DAY0 + 43200.0 + np.arange(50))
    np.testing.assert_allclose(fixes.heading, np.radians(90.0 - 54.7))
    # a text log's line of no sentence, before any binary data, is still an error
    path.write_bytes(f"{rmc('120000')}\nQe])\n".encode() + body)
    with pytest.raises(ValueError, match=r"drive.ubx: line 2: not an NMEA sentence"):
        read_nmea(path)

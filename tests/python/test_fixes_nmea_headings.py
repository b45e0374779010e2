"""NMEA true headings at the time of their own epoch (gyrocore.fixes.read_nmea): a receiver that
writes each epoch's HDT before its RMC (``$GPHDT, $GPRMC, $GPVTG`` each second) had every heading
timed by the epoch before, a second late; the log's own order is told from its pattern, and where
it cannot be, the HDT is of the time before it with a warning. THS (u-blox's true heading, with a
mode indicator) is read as HDT is."""

from __future__ import annotations

import math
import warnings
from functools import reduce
from pathlib import Path

import numpy as np
import pytest

from gyrocore import InputWarning
from gyrocore.fixes import read_nmea

from .test_fixes_nmea import nmea, rmc
from .test_fixes_nmea_loggers import NOON, hdt, heading_deg, zda
from .test_fixes_nmea_receivers import vtg

pynmea2 = pytest.importorskip("pynmea2")

#: A car turning at 10 deg/s, an epoch a second: its heading at 12:00:0k is 10 k deg.
TURN = 10.0


def bursts(order: str, seconds: int = 6, heading: str = "HDT") -> list[str]:
    """The sentences of a turning car's receiver, a burst each second: ``order`` the place of the
    heading sentence in it, ``"before"`` (HDT, RMC, VTG) or ``"after"`` (RMC, VTG, HDT); the course
    and the heading of each second alike."""
    lines = []
    for k in range(seconds):
        course = f"{TURN * k:05.1f}"
        timed = [rmc(f"12000{k}", course=course), vtg(course)]
        sentence = hdt(course) if heading == "HDT" else ths(course)
        lines += [sentence, *timed] if order == "before" else [*timed, sentence]
    return lines


def ths(heading: str, mode: str = "A") -> str:
    """A THS sentence, its checksum worked out here (pynmea2 has no THS class of its own)."""
    body = f"GNTHS,{heading},{mode}"
    return f"${body}*{reduce(lambda a, c: a ^ ord(c), body, 0):02X}"


def read_quietly(path: Path, **options: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The fixes' times, bearings [deg] and sigmas of ``path``, read without a warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fixes = read_nmea(path, **options)  # type: ignore[arg-type]
    return fixes.t, heading_deg(fixes.heading), fixes.sigma


@pytest.mark.parametrize("order", ["before", "after"])
def test_each_hdt_is_of_its_own_bursts_epoch(tmp_path: Path, order: str) -> None:
    # HDT before the RMC of its burst was timed by the RMC before it: each heading a second late,
    # 10 deg off in the turn, without a word
    t, bearing, sigma = read_quietly(nmea(tmp_path, *bursts(order)))
    np.testing.assert_array_equal(t, NOON + np.arange(6))
    np.testing.assert_array_equal(bearing, TURN * np.arange(6))
    np.testing.assert_allclose(sigma, math.radians(0.5))  # all of them HDT's, none a course's


def test_a_log_begun_or_stopped_in_a_burst(tmp_path: Path) -> None:
    # begun in a burst of HDT before RMC: its first VTG is of an epoch before the log, which the
    # log's start says nothing of; its end does
    lines = bursts("before")
    t, bearing, _ = read_quietly(nmea(tmp_path, *lines[2:]))
    np.testing.assert_array_equal(t, NOON + np.arange(1, 6))
    np.testing.assert_array_equal(bearing, TURN * np.arange(1, 6))
    # HDT after the RMC, begun in a burst: the first HDT is of an epoch before the log, skipped
    lines = bursts("after")
    with pytest.warns(InputWarning, match=r"drive.nmea: 1 HDT sentence\(s\) come before any valid RMC or ZDA, or "
                                          r"after a void RMC, and are skipped: .* \(the first: line 2\)"):
        fixes = read_nmea(nmea(tmp_path, *lines[1:]))
    np.testing.assert_array_equal(fixes.t, NOON + np.arange(1, 6))
    np.testing.assert_array_equal(heading_deg(fixes.heading), TURN * np.arange(1, 6))
    # stopped while its last line was written: that line's burst says nothing either (its end,
    # an HDT-less VTG, read as bursts that end before their HDT)
    path = tmp_path / "drive.nmea"
    path.write_text("".join(f"{line}\n" for line in lines) + rmc("120006", course="060.0") + "\n" + vtg()[:12])
    with pytest.warns(InputWarning, match=r"line 20, the last, is cut off"):
        fixes = read_nmea(path)
    np.testing.assert_array_equal(fixes.t, NOON + np.arange(7))
    np.testing.assert_array_equal(heading_deg(fixes.heading), TURN * np.arange(7))
    assert np.degrees(fixes.sigma[-1]) > 0.5  # the last epoch's course: its HDT never came


def test_an_hdt_before_a_void_rmc_is_skipped_where_hdt_comes_first(tmp_path: Path) -> None:
    lines = bursts("before")
    lines[4] = rmc("120001", status="V")  # epoch 1 has no fix: its HDT (line 4) is of no time
    with pytest.warns(InputWarning, match=r"drive.nmea: 1 HDT sentence\(s\) come after the last valid RMC or ZDA, "
                                          r"or before a void RMC, and are skipped: .* \(the first: line 4\)"):
        fixes = read_nmea(nmea(tmp_path, *lines))
    np.testing.assert_array_equal(fixes.t, NOON + np.array([0.0, 2.0, 3.0, 4.0, 5.0]))
    np.testing.assert_array_equal(heading_deg(fixes.heading), TURN * np.array([0, 2, 3, 4, 5]))


def test_an_hdt_among_an_epochs_rmc_and_zda_is_of_that_epoch(tmp_path: Path) -> None:
    lines = [line for k in range(4) for line in (zda(f"12000{k}"), hdt(f"{TURN * k:05.1f}"), rmc(f"12000{k}"))]
    t, bearing, _ = read_quietly(nmea(tmp_path, *lines))
    np.testing.assert_array_equal(t, NOON + np.arange(4))
    np.testing.assert_array_equal(bearing, TURN * np.arange(4))


@pytest.mark.parametrize(("case", "why"), [
    ("mixed", r"its HDT sentences are not one to each epoch's sentences"),
    ("once", r"it has a single epoch"),
    ("once-of-several", r"its HDT sentences are not one to each epoch's sentences"),
    ("ends-disagree", r"its first and last epochs disagree")])
def test_an_order_that_cannot_be_told_takes_the_time_before_with_a_warning(tmp_path: Path, case: str,
                                                                           why: str) -> None:
    before, after = bursts("before"), bursts("after")
    lines = {"mixed": before[:6] + after[6:12] + before[12:],  # HDT H0 H1 before, H2 H3 after, H4 H5 before
             "once": after[:3],
             "once-of-several": after[:3] + [line for line in after[3:] if not line.startswith("$GPHDT")],
             "ends-disagree": before[1:]}[case]  # from the first RMC on: it opens as bursts of HDT after
    with pytest.warns(InputWarning, match=r"drive.nmea: whether the HDT sentences come before or after the RMC or "
                                          r"ZDA of their epoch cannot be told from the log \(" + why + r".*\): each is "
                                          r"taken at the time of the valid RMC or ZDA before it"):
        fixes = read_nmea(nmea(tmp_path, *lines))
    hdt_fixes = np.isclose(fixes.sigma, math.radians(0.5))
    if case == "mixed":  # each HDT of the time before it (H0 of none), and of two in one epoch the first
        np.testing.assert_array_equal(fixes.t[hdt_fixes], NOON + np.array([0.0, 2.0, 3.0, 4.0]))
        np.testing.assert_array_equal(heading_deg(fixes.heading[hdt_fixes]), TURN * np.array([1, 2, 3, 5]))
    elif case == "ends-disagree":
        np.testing.assert_array_equal(fixes.t[hdt_fixes], NOON + np.arange(5))
        np.testing.assert_array_equal(heading_deg(fixes.heading[hdt_fixes]), TURN * np.arange(1, 6))
    else:
        np.testing.assert_array_equal(fixes.t[hdt_fixes], [NOON])


def test_ths_is_read_as_hdt(tmp_path: Path) -> None:
    # $GNTHS was a sentence of a type pynmea2 does not know, skipped: no heading fix from it
    for order in ("before", "after"):
        t, bearing, sigma = read_quietly(nmea(tmp_path, *bursts(order, heading="THS")))
        np.testing.assert_array_equal(t, NOON + np.arange(6))
        np.testing.assert_array_equal(bearing, TURN * np.arange(6))
        np.testing.assert_allclose(sigma, math.radians(0.5))
    path = nmea(tmp_path, *bursts("after", heading="THS"))
    assert read_nmea(path, hdt_sigma_deg=0.2).sigma == pytest.approx([math.radians(0.2)] * 6)
    np.testing.assert_array_equal(heading_deg(read_nmea(path, source="hdt").heading), TURN * np.arange(6))
    assert read_nmea(path, source="course").sigma[0] > math.radians(0.5)  # the courses alone


def test_ths_modes(tmp_path: Path) -> None:
    # E (dead reckoning) is taken and counted; M, S and V are no measurement, skipped and counted
    modes = "AEMSVA"
    lines = [line for k, mode in enumerate(modes)
             for line in (rmc(f"12000{k}", speed="000.0", course=""), ths(f"{TURN * k:05.1f}", mode))]
    with pytest.warns(InputWarning) as caught:
        fixes = read_nmea(nmea(tmp_path, *lines))
    said = [str(w.message) for w in caught]
    assert any(s.endswith("THS sentences of no measured heading are skipped: 1 of mode M (manual input), 1 of mode "
                          "S (simulator), 1 of mode V (not valid)") for s in said), said
    assert any("1 THS sentence(s) are of mode E, estimated: the receiver's dead reckoning" in s for s in said), said
    np.testing.assert_array_equal(fixes.t, NOON + np.array([0.0, 1.0, 5.0]))
    np.testing.assert_array_equal(heading_deg(fixes.heading), [0.0, 10.0, 50.0])
    # a log of THS of no measurement alone says why it gives no fix
    with pytest.warns(InputWarning, match=r"no heading fix from .*: of its 4 sentences, 2 are RMC: 2 without a "
                                          r"course; 2 are THS: 2 of THS mode M, S or V \(no measurement\); "):
        assert len(read_nmea(nmea(tmp_path, *lines[4:8]))) == 0


def test_a_ths_that_is_damaged_names_its_line(tmp_path: Path) -> None:
    bad = ths("045.0")[:-1] + ("0" if ths("045.0")[-1] != "0" else "1")
    with pytest.raises(ValueError, match=r"drive.nmea: line 2: not an NMEA sentence .*checksum does not match"):
        read_nmea(nmea(tmp_path, rmc("120000"), bad))
    with pytest.raises(ValueError, match=r"drive.nmea: line 2: an THS sentence without its checksum"):
        read_nmea(nmea(tmp_path, rmc("120000"), ths("045.0").split("*")[0]))
    with pytest.raises(ValueError, match=r"drive.nmea: line 2: the THS heading '400.0' is no bearing of 0 to 360"):
        read_nmea(nmea(tmp_path, rmc("120000"), ths("400.0")))

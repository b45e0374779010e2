"""Heading fixes from NMEA 0183 sentences (pynmea2, the ``nmea`` extra): the course over ground and
speed of a receiver's RMC sentences, or of the VTG sentence after one (its values read by their
unit letters; a magnetic course made true by the RMC's magnetic variation), through
:func:`gyrocore.fixes.from_gnss`; and the true heading of HDT and THS sentences (a dual-antenna
receiver's or a gyrocompass's), at the time of the RMC or ZDA of their epoch
(:mod:`.fixes_nmea_headings`; the times: :mod:`.fixes_nmea_time`).

A file is read line by line, in the order written, and a line that cannot be used is an error
naming the file and the line: one that is no sentence (a bad checksum, a line longer than any
sentence), an RMC, VTG, HDT, THS or ZDA without its checksum (a sentence cut short reads as one
of other values), one whose date, time, course, speed or heading is not a value (pynmea2 hands such
a field back as its text), an RMC or ZDA whose time steps back, and one whose magnetic variation,
needed to make a VTG's magnetic course true, is no angle. A logger's timestamp before a sentence
is skipped. The last line, cut off without a line end (a log stopped mid-write), is skipped after
a warning instead. A serial log, with a receiver's binary messages
(u-blox UBX) among its sentences, is read from its first binary data on as such: a sentence after
binary data on its line is read, and a line of no sentence skipped, with a warning counting them.
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from ._checks import check_number, keyword_options, require_options, shown, warn
from ._extras import require
from .fixes import Fixes, from_gnss, heading_of_bearing
from .fixes_files import ROW_ERROR
from .io._csvfile import refuse_not_text
from .io._paths import check_file
from .fixes_nmea_headings import Headings, ths_class
from .fixes_nmea_time import EARLY_DATE, Clock, in_leap_second

#: Metres per second in a knot and in a km/h (NMEA's speed units).
KNOT, KMH = 1852.0 / 3600.0, 1.0 / 3.6

#: The longest line taken for a sentence [characters]. NMEA 0183 caps a sentence at 82, and
#: proprietary ones run a little longer; a longer line is binary data or a file without line
#: breaks, refused before it is read whole into memory.
MAX_LINE = 4096

#: Mode indicators (NMEA 2.3 on, the last field of RMC and VTG) of a course that is no measurement,
#: which receivers write with status A: N (data not valid), E (estimated: the receiver's dead
#: reckoning, its last course carried through an outage), M (manual input) and S (simulator: the
#: receiver's own simulated fixes, of no vehicle's motion).
NO_FIX_MODES = ("N", "E", "M", "S")

#: The default standard deviation of an HDT heading [deg]. A dual-antenna receiver's heading error
#: falls as its baseline grows: NovAtel gives 0.40 deg at 0.5 m, 0.20 deg at 1 m and 0.08 deg at
#: 2 m (OEM7 manual, "Importance of Antenna Location for ALIGN"); 0.5 deg covers a short baseline
#: of 0.5 m with some margin for multipath. Give a smaller one for a longer baseline, a larger one
#: for a ship's gyrocompass.
HDT_SIGMA_DEG = 0.5
#: Where the heading of an epoch comes from (``source``): its HDT where it has one and its course
#: otherwise, HDT alone, or the course alone.
SOURCES = ("auto", "hdt", "course")

#: The unit letters of a VTG's values: true and magnetic course, speed in knots and in km/h.
_VTG_UNITS = ("T", "M", "N", "K")

#: The start of a sentence on a line: a logger's time before it is skipped.
_START = re.compile(r"[$!]")
#: Text up to the last character that no NMEA sentence has (they are printable ASCII): binary data
#: read as text, a receiver's binary messages among its sentences.
_BINARY = re.compile(r".*[^\t\x20-\x7e]", re.DOTALL)
#: A sentence with its checksum, near the start of a file: a serial log may begin with binary data
#: before it, and is no binary file.
_SENTENCE = re.compile(rb"[$!][A-Z][A-Z0-9]{4,5},[\x20-\x7e]*\*[0-9A-Fa-f]{2}")


def read_nmea(path: str | Path, *, source: str = "auto", hdt_sigma_deg: float = HDT_SIGMA_DEG,
              **options: float) -> Fixes:
    """Fixes from NMEA 0183 sentences: course over ground and speed of valid RMC sentences, at
    their UTC date and time as Unix seconds; a VTG sentence supplies the course (and speed, in
    km/h or else knots) of the valid RMC epoch just before it where that RMC had none. Other
    sentences are skipped (those pynmea2 does not know too), as are RMC and VTG whose mode
    indicator is N, E, M or S (:data:`NO_FIX_MODES`).

    An HDT sentence (``$GPHDT,123.4,T``: a dual-antenna receiver's or a gyrocompass's true
    heading, valid at any speed) is a fix of sigma ``hdt_sigma_deg`` (:data:`HDT_SIGMA_DEG`), and
    so is a THS (``$GNTHS,123.45,A``, u-blox's) of mode A, or E (dead reckoning: taken, counted
    in a warning); one of mode M, S or V is skipped, counted. It has no time of its own: it is of
    the epoch of the burst of sentences it was written in, timed by its valid RMC or ZDA. Whether
    the log writes it after that time (``$GPRMC, $GPVTG, $GPHDT``) or before it (``$GPHDT,
    $GPRMC, $GPVTG``) is told from the log's pattern (:meth:`.fixes_nmea_headings.Headings.times`);
    where it cannot be, it is of the RMC or ZDA before it, with a warning. Of several HDT of one
    epoch the one nearest its time is kept; one of no epoch with a time is skipped, a warning
    counting them. ``source`` chooses between an epoch's HDT and its course: ``"auto"`` the HDT
    where the epoch has one and the course otherwise, ``"hdt"`` HDT alone, ``"course"`` the
    course alone (HDT skipped); THS counts as HDT.

    A VTG's values are read by their unit letters (T, M, N, K; NMEA 0183's VTG before version 2,
    without them, by place); one with a magnetic course alone is made true by the magnetic
    variation of its RMC (true = magnetic + variation east, - west), and where that RMC gives none
    it is skipped with a warning.

    Sentences are taken in the order written: an RMC (or ZDA) time of day that wraps past
    midnight while its date field has not yet advanced is of the next day, and one in the last
    :data:`EARLY_DATE` seconds before midnight dated a day after the sentence before it (the date
    advanced early) is of that sentence's day, a warning counting the sentences so moved either
    way. A log that opens in that last minute with the next day's date already, and keeps it
    through midnight, is put a day back as a whole where more of its sentences follow that
    midnight than precede it (the reading that takes fewer date fields for wrong). A time
    that steps back otherwise is an error naming its line; of RMC sentences repeating one time
    the first is kept (a warning counts those that differ from it); one in the leap second
    23:59:60 is skipped with a warning.

    A line that is no sentence, an RMC, VTG, HDT, THS or ZDA without a checksum, or one whose
    fields are not values is an error naming the file and line, as is a file of no sentence; a
    last line cut off without a line end is skipped with a warning, and so, from the first binary
    data on (a serial log's binary messages among its sentences), is a line of no sentence, a
    sentence after binary data on its line read. Text before the first ``$`` or ``!`` of a line
    (a logger's timestamp: ``1634567890.123 $GPRMC,...``, ``[12:00:00.123] $GPRMC,...``) is
    skipped, the sentence and its checksum read from there on. Sentences that give no fix warn
    with their counts (void RMC, RMC without a course, HDT of no epoch, THS of no measurement; a
    log of GGA, GNS or GLL positions alone says what to do). The times are UTC: shift them onto the gyro's clock before
    fusing. ``options`` go to :func:`gyrocore.fixes.from_gnss`.
    """
    # before the file is read
    require_options("read_nmea (from_gnss's)", options, keyword_options(read_nmea) + keyword_options(from_gnss))
    if source not in SOURCES:
        raise ValueError(f"source must be one of {', '.join(map(repr, SOURCES))}, got {shown(source)}")
    sigma = math.radians(check_number("hdt_sigma_deg", hdt_sigma_deg, unit=" [deg]"))
    pynmea2 = require("pynmea2", "reading NMEA sentences")
    path = Path(path)
    check_file(path)  # a named pipe (a receiver's live output) was waited on for ever
    epochs = _Epochs(pynmea2, path)
    for number, text, ended in _sentences(path):
        epochs.take(number, text, ended)
    return epochs.fixes(source, sigma, options)


class _Epochs:
    """The course and speed, and the true heading, of each epoch of one file's sentences, taken in
    the order written."""

    def __init__(self, pynmea2: Any, path: Path) -> None:
        self.pynmea2, self.path = pynmea2, path
        self.epochs: dict[float, tuple[float, float, int]] = {}  # time -> course [deg], speed [m/s], line
        self.tally: Counter[str] = Counter()
        self.headings = Headings(path, self.tally)  # the HDT and THS headings, timed once the file is read
        self.last: float | None = None  # the epoch of the valid RMC just before: a VTG's
        self.clock = Clock(path)  # the times of the dated sentences (RMC, ZDA)
        self.readers = {pynmea2.RMC: self._rmc, pynmea2.VTG: self._vtg, pynmea2.HDT: self._heading,
                        ths_class(pynmea2): self._heading, pynmea2.ZDA: self._zda}
        # the magnetic variation of the valid RMC just before (its fields 10 and 11) and its line: a
        # VTG's magnetic course is made true by it
        self.variation: tuple[str, str, int] = ("", "", 0)
        self.repeat: int | None = None  # the line of the first RMC repeating a time with other values
        self.binary: int | None = None  # the first line of binary data: a serial log from there on
        self.skipped = 0  # the last line of it skipped

    def take(self, number: int, text: str, ended: bool) -> None:
        """Takes the sentence ``text`` of line ``number``, which ``ended`` with a line end; a
        ValueError names the line. From the first line of binary data on, the file is a serial log:
        a line is read from its last ``$`` after any binary data, and one of no sentence is skipped
        (a binary message's bytes between two line ends may all be printable). Before it, a line is
        read from its first ``$`` or ``!``: a logger writes its own time before each sentence."""
        binary = _BINARY.match(text)
        if binary is not None and self.binary is None:
            self.binary = number
        if self.binary is not None:
            start = text.rfind("$", 0 if binary is None else binary.end())  # a binary message may hold a $
            if start != 0:
                self._skip(number)
            if start < 0:
                return
            text = text[start:]
        elif (sentence := _START.search(text)) is not None:  # a line without either stays an error as it is
            text = text[sentence.start():]
        self.tally["sentences"] += 1
        try:
            msg = self.pynmea2.parse(text)
        except self.pynmea2.SentenceTypeError:
            return  # a sentence whose checksum holds but whose type pynmea2 does not know has no course for it
        except self.pynmea2.ParseError as e:
            # pynmea2 adds the line to its words: a long line of no sentence filled the error with
            # up to 4096 characters of it
            reason = e.args[0] if e.args else str(e)  # pynmea2's (message, data)
            reason = reason[0] if isinstance(reason, tuple) and reason else reason
            return self._unusable(number, ended, f"not an NMEA sentence ({reason}: {shown(text, 100)})")
        reader = self.readers.get(type(msg))
        if reader is None:
            # a position without a course: counted, to say what to do with a log of them alone
            self.tally["positions"] += isinstance(msg, (self.pynmea2.GGA, self.pynmea2.GNS, self.pynmea2.GLL))
            return
        if "*" not in text:  # pynmea2 takes a sentence without one: "084.4,230394" cut to "084.4,2303" dated 2003
            return self._unusable(number, ended, f"an {msg.sentence_type} sentence without its checksum (*hh; "
                                  f"{shown(text, 100)}): cut short, its values cannot be trusted")
        try:
            reader(msg, number)
        except (ValueError, TypeError) as e:
            if str(e).startswith(str(self.path)):  # a time that steps back: its error names the line already
                raise
            raise ValueError(f"{self.path}: line {number}: an {msg.sentence_type} sentence whose fields cannot be "
                             f"read ({e}); remove or repair the line") from None

    def _unusable(self, number: int, ended: bool, problem: str) -> None:
        """The error of line ``number``, which is no sentence gyrocore can use (``problem``); in a
        serial log, the line skipped; the last line cut off without a line end (a log stopped while
        it was written), a warning."""
        if self.binary is not None:
            return self._skip(number)
        if ended:
            raise ValueError(f"{self.path}: line {number}: {problem}; remove or repair the line")
        self.headings.cut_off = True  # the log stopped in a burst: its last epoch says nothing of their order
        warn(f"{self.path}: line {number}, the last, is cut off without a line end and is skipped: {problem}")

    def _skip(self, number: int) -> None:
        """Counts line ``number`` of a serial log as skipped, once."""
        if self.skipped != number:
            self.tally["binary"] += 1
            self.skipped = number

    def _rmc(self, msg: Any, number: int) -> None:
        self.tally["RMC"] += 1
        self.last = None  # a VTG after a void RMC is of that epoch, which has no fix
        if msg.status != "A":
            self.tally["void"] += 1
        elif msg.mode_indicator in NO_FIX_MODES:
            self.tally["mode"] += 1
        elif in_leap_second(msg):
            self.tally["leap"] += 1
        elif not (msg.datestamp and msg.timestamp):
            self.tally["undated"] += 1
        else:
            self.last = t = self.clock.time(msg, number)
            self.variation = (msg.mag_variation or "", msg.mag_var_dir or "", number)
            if msg.true_course is None or msg.spd_over_grnd is None:
                self.tally["courseless"] += 1
            else:
                self._add(t, float(msg.true_course), float(msg.spd_over_grnd) * KNOT, number)
        self.headings.marker(self.tally["sentences"], self.last)  # the time of its epoch's headings

    def _vtg(self, msg: Any, number: int) -> None:
        true, magnetic, knots, kmh, mode = _vtg_fields(msg.data)
        # a log that opens with a VTG opens in a burst: the rest of an epoch whose RMC came before it
        self.headings.opened_with_vtg |= self.tally["sentences"] == 1
        if self.last is None or self.last in self.epochs or mode in NO_FIX_MODES:
            return
        if true:
            course = float(true)
        elif not magnetic:
            return
        elif (variation := self._variation()) is None:
            self.tally["magnetic"] += 1  # warned of, with what to do
            return
        else:
            course = (float(magnetic) + variation) % 360.0
        # the speed in km/h, or else in knots (the km/h field left empty)
        speed = next((float(value) * unit for value, unit in ((kmh, KMH), (knots, KNOT)) if value), None)
        if speed is not None:
            self.epochs[self.last] = (course, speed, number)

    def _variation(self) -> float | None:
        """The magnetic variation [deg] of the epoch's RMC, east positive (true = magnetic +
        variation east, - west: NMEA 0183's easterly variation subtracts from the true course),
        or None where its fields leave it unknown; a value that is no angle is an error naming
        the RMC's line."""
        value, side, line = self.variation
        if not (value and side):
            return None
        try:
            degrees = float(value)
        except ValueError:
            degrees = math.nan
        if not (0.0 <= degrees <= 180.0 and side in ("E", "W")):
            raise ValueError(f"{self.path}: line {line}: the RMC's magnetic variation ({value!r}, {side!r}) is no "
                             "angle of 0 to 180 degrees E or W, and the VTG after it gives a magnetic course only, "
                             "which it makes true; remove or repair the line")
        return degrees if side == "E" else -degrees

    def _zda(self, msg: Any, number: int) -> None:
        """A ZDA's date and time time the headings of its epoch (a log of a gyrocompass's HDT and ZDA
        has no RMC); one without them, or in a leap second, leaves its epoch untimed."""
        dated = None not in (msg.timestamp, msg.day, msg.month, msg.year) and not in_leap_second(msg)
        self.headings.marker(self.tally["sentences"], self.clock.time(msg, number) if dated else None)

    def _heading(self, msg: Any, number: int) -> None:
        """An HDT's or THS's true heading, timed by its epoch's RMC or ZDA once the file is read."""
        self.headings.take(msg, self.tally["sentences"], number)

    def _add(self, t: float, course: float, speed: float, number: int) -> None:
        """The epoch at ``t``, unless an RMC gave that time already (its first is kept)."""
        had = self.epochs.get(t)
        if had is None:
            self.epochs[t] = (course, speed, number)
        elif had[:2] != (course, speed):
            self.tally["repeats"] += 1
            self.repeat = number if self.repeat is None else self.repeat

    def fixes(self, source: str, sigma: float, options: dict[str, float]) -> Fixes:
        """The fixes of the epochs taken, in time order: an epoch's HDT heading, of ``sigma`` [rad],
        or its course through :func:`from_gnss` with ``options``, as ``source`` chooses."""
        if not self.tally["sentences"]:
            raise ValueError(f"{self.path}: no NMEA sentence, so no fix; give a file of RMC (and VTG) or HDT sentences")
        shift = self.clock.shift()  # a log that opened with its date field advanced early: a day back
        headings = {} if source == "course" else self.headings.times()
        self._warn_skipped()
        if headings:  # else said with the other reasons for no fix
            self.headings.warn()
        epochs = {} if source == "hdt" else {t: e for t, e in self.epochs.items() if t not in headings}
        if not (epochs or headings):
            self._warn_no_epoch(source)
        times = list(epochs)  # in time order: a step back was refused
        course, speed, lines = (np.array([epochs[k][i] for k in times], dtype=float) for i in range(3))
        try:
            by_course = from_gnss(np.array(times, dtype=float) + shift, course, speed, **options)
        except ValueError as e:
            # from_gnss names a sample by its index in time order: the file names its line
            m = ROW_ERROR.match(str(e))
            if m is None or m[4] is None:
                raise
            raise ValueError(f"{self.path}: line {int(lines[int(m[4])])}: {e}") from None
        if not headings:
            return by_course
        t = np.concatenate((by_course.t, np.array(list(headings), dtype=float) + shift))
        heading = np.concatenate((by_course.heading, heading_of_bearing(np.array([h for h, _ in headings.values()]))))
        order = np.argsort(t, kind="stable")  # no time is both: an epoch's HDT took the place of its course
        return Fixes(t[order], heading[order], np.concatenate((by_course.sigma, np.full(len(headings), sigma)))[order])

    def _warn_skipped(self) -> None:
        """Warns of lines skipped: a serial log's binary data, and RMC sentences that were fixes of their own (those
        repeating a time with other values, and those in a leap second)."""
        if self.tally["binary"]:
            warn(f"{self.path}: binary data from line {self.binary} on, a receiver's binary messages (u-blox UBX) "
                 f"among its sentences: {self.tally['binary']} line(s) of it, or of no sentence after it, are skipped, "
                 "and a sentence after it on its line is read")
        if self.tally["repeats"]:
            warn(f"{self.path}: {self.tally['repeats']} RMC sentence(s) repeat the time of an earlier one with another "
                 f"course or speed (the first: line {self.repeat}), and the first of each time is kept: a receiver "
                 "faster than its time's resolution (5 Hz in whole seconds) or repeating a time writes them")
        if self.clock.moved:
            clock = self.clock
            warn(f"{self.path}: {clock.moved} {clock.moved_kinds()} sentence(s) have a date field off the day their "
                 f"time of day runs on to (the first: line {clock.first_moved}), the receiver advancing it early, in "
                 f"the last {EARLY_DATE:.0f} s before midnight UTC, or late, after it: they are put on that day")
        if self.tally["magnetic"] and self.epochs:  # else said with the other reasons for no fix
            warn(f"{self.path}: {self.tally['magnetic']} VTG sentence(s) give a magnetic course only, {_MAGNETIC}")
        if self.tally["leap"]:
            warn(f"{self.path}: {self.tally['leap']} RMC sentence(s) in the leap second 23:59:60 UTC are skipped: Unix "
                 "seconds have no such second, and the fixes after it are a second behind a clock that ran through it")

    def _warn_no_epoch(self, source: str) -> None:
        """Warns that the sentences gave no course or HDT heading, with the counts that say why."""
        tally = self.tally
        if source == "hdt":
            why = "none is HDT or THS"
        elif not tally["RMC"]:
            why = "none is RMC"
            if tally["positions"]:
                why += (f"; {tally['positions']} are GGA, GNS or GLL, positions without a course: set the receiver to "
                        "write RMC (and VTG), or take the course of each step between positions with "
                        "gyrocore.fixes.from_latlon")
        else:
            counts = {"void (status V)": tally["void"], "of mode N, E, M or S (no measurement)": tally["mode"],
                      "without a date or time": tally["undated"], "without a course": tally["courseless"]}
            why = f"{tally['RMC']} are RMC: " + ", ".join(f"{n} {what}" for what, n in counts.items() if n)
            if tally["magnetic"]:
                why += f"; {tally['magnetic']} VTG give a magnetic course only, {_MAGNETIC}"
        if tally["HDT"]:
            headings = self.headings
            counts = {headings.untimed_words(): tally["untimed"], "without a heading": tally["headingless"],
                      "of THS mode M, S or V (no measurement)": headings.skipped_modes(),
                      "skipped by source='course'": tally["HDT"] if source == "course" else 0}
            why = (why if source != "hdt" else "") + f"; {tally['HDT']} are {headings.kinds_said()}: " + ", ".join(
                f"{n} {what}" for what, n in counts.items() if n)
        warn(f"no heading fix from {self.path}: of its {tally['sentences']} sentences, {why.lstrip('; ')}; fixes come "
             "from valid RMC sentences with a course (or the VTG after one), or HDT or THS of an epoch with a valid RMC or ZDA")


#: What is done with a VTG's magnetic course where its RMC gives no variation, and what to do.
_MAGNETIC = ("and the RMC of their epoch no magnetic variation (fields 10 and 11) to make it true: their epochs are "
             "skipped; set the receiver to write the true course in VTG, or the magnetic variation in RMC")


def _vtg_fields(data: list[str]) -> tuple[str, str, str, str, str]:
    """A VTG's true course, magnetic course, speed in knots and in km/h, and mode indicator, as
    written ("" where empty), each value by the unit letter after it (T, M, N, K): receivers that
    leave out the magnetic pair (``054.7,T,005.5,N,010.2,K``) shift the others along, where
    pynmea2 reads by place and took the knots for a magnetic course and the km/h for knots. A
    letter left empty is that of its place in the standard layout, and a VTG of four values and
    no letter is NMEA 0183's before version 2, read by place."""
    if len(data) == 4 and not set(data) & set(_VTG_UNITS):
        true, magnetic, knots, kmh = data
        return true, magnetic, knots, kmh, ""
    values = dict.fromkeys(_VTG_UNITS, "")
    for place, (value, unit) in enumerate(zip(data[0::2], data[1::2])):
        unit = unit or (_VTG_UNITS[place] if place < len(_VTG_UNITS) else "")
        if unit in values:
            values[unit] = value
    return values["T"], values["M"], values["N"], values["K"], data[-1] if len(data) % 2 else ""


def _sentences(path: Path) -> Iterator[tuple[int, str, bool]]:
    """(line number, text, ended with a line end) of each line of ``path`` that is not blank; a
    line longer than :data:`MAX_LINE` is an error, raised before more of it is read. A byte-order
    mark is not part of the first line, and bytes that are not UTF-8 become U+FFFD (no sentence
    has them)."""
    with path.open("rb") as raw:  # a UTF-16, gzip or binary file: its bytes were echoed in the error
        first = raw.readline(MAX_LINE + 1)
        # a serial log may begin with a receiver's binary messages: a sentence in its first 64 KiB
        # shows it is one, and its binary data is skipped
        if not _SENTENCE.search(first + raw.read(65536)):
            refuse_not_text(path, first, "NMEA file")
    with path.open(encoding="utf-8-sig", errors="replace") as f:
        number = 0
        while line := f.readline(MAX_LINE + 1):
            number += 1
            if len(line.rstrip("\r\n")) > MAX_LINE:
                raise ValueError(f"{path}: line {number}: longer than {MAX_LINE} characters, so not an NMEA sentence "
                                 "(at most 82): is it an NMEA log?")
            if line.strip():
                yield number, line.strip(), line.endswith("\n")

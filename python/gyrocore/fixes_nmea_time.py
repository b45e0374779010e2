"""The times of an NMEA log's dated sentences (RMC, ZDA) for :func:`gyrocore.fixes.read_nmea`: a
date field and a time of day each, read in the order written, on one clock that runs on across
midnight UTC where a receiver advances the date field late or early, and refuses a time that
steps back."""

from __future__ import annotations

import datetime
import re
from pathlib import Path
from typing import Any

#: Seconds in a day, and the fall of a sentence's time of day under one date that is midnight UTC
#: passed (the receiver advanced the date field a sentence or more late): more than half a day.
DAY = 86_400.0
HALF_DAY = DAY / 2
#: The last seconds before midnight UTC in which a sentence dated a day after the epoch before it
#: is of that epoch's day: a receiver that takes its date from GPS time (18 s ahead of UTC since
#: 2017) advances the date field early. Further from midnight the next day's date is a gap in
#: the log, taken as written.
EARLY_DATE = 60.0

#: A time in the leap second 23:59:60 UTC, which pynmea2 hands back as its text.
LEAP_SECOND = re.compile(r"235960(\.\d*)?")


def in_leap_second(msg: Any) -> bool:
    """Whether the sentence ``msg``'s time is in a leap second: Unix seconds have no 23:59:60, and
    it would be read as the next 00:00:00."""
    return isinstance(msg.timestamp, str) and LEAP_SECOND.fullmatch(msg.timestamp) is not None


class Clock:
    """The times [Unix s] of one file's dated sentences, in the order written."""

    def __init__(self, path: Path) -> None:
        self.path = path
        # the last dated sentence: its date field, time of day [s], time [s] and line; and the days
        # added to the times of its date field (one after midnight with the date not yet advanced,
        # minus one before it with the date advanced early: see days_off)
        self.last: tuple[datetime.date, float, float, int] | None = None
        self.lag = 0.0
        self.moved = 0  # the sentences put on another day than their date field's, the first's line, their types
        self.first_moved: int | None = None
        self.kinds: set[str] = set()
        # a log that opens in the last EARLY_DATE s before midnight has no sentence before it to
        # show an early date field: the sentences before its first midnight (their count and the
        # first's line), and whether the date field then stood still through midnight, as a late
        # one does until it catches up (or never) and an early one for good (see shift)
        self.opening: list[int] | None = None
        self.opening_kinds: set[str] = set()
        self.before_midnight, self.held = True, False

    def time(self, msg: Any, number: int) -> float:
        """The time [s] of the dated sentence ``msg`` of line ``number``: its date field is taken
        where it agrees with its time of day, and put right where it is a day off it (see
        :func:`days_off`); a time that falls otherwise is an error naming the line."""
        t = float(msg.datetime.timestamp())  # first: a field that is not a date or a time raises a TypeError
        date, clock = msg.datestamp, msg.timestamp
        of_day = 3600.0 * clock.hour + 60.0 * clock.minute + clock.second + clock.microsecond / 1e6
        last = self.last
        if last is None and of_day >= DAY - EARLY_DATE:
            self.opening = [0, number]
        off = None if last is None else days_off(last[0], last[1], date, of_day)
        self.lag = 0.0 if off is None else self.lag + off * DAY
        if last is not None and self.before_midnight and midnight_passed(last[1], of_day):
            self.before_midnight = False  # the log's first midnight: its date field standing still?
            self.held = self.opening is not None and off == 1 and self.lag == DAY
        self.held = self.held and self.lag == DAY  # a date field that caught up was late
        if self.opening is not None and self.before_midnight:
            self.opening[0] += 1
            self.opening_kinds.add(msg.sentence_type)
        if self.lag:
            self.moved += 1
            self.first_moved = number if self.first_moved is None else self.first_moved
            self.kinds.add(msg.sentence_type)
        t += self.lag
        if last is not None and t < last[2]:
            raise ValueError(f"{self.path}: line {number}: the time steps back, from {utc(last[2])} (line {last[3]}) "
                             f"to {utc(t)} UTC; sentences are read in the order written: remove the lines of the "
                             "earlier time, or read two logs one at a time")
        self.last = (date, of_day, t, number)
        return t

    def moved_kinds(self) -> str:
        """The types of the sentences moved: ``"RMC"``, ``"RMC and ZDA"``."""
        return " and ".join(sorted(self.kinds))

    def shift(self) -> float:
        """What to add to every time taken [s], once the log is read: a day back where it opened in
        the last :data:`EARLY_DATE` s before midnight and its date field never advanced after it,
        else 0. Such a log reads two ways: a date field advanced early, before the first sentence,
        and right from midnight on; or one that stood still at midnight (late, or never advancing)
        and wrong from there on. The reading that takes fewer date fields for wrong is kept: early
        where more sentences follow that midnight than precede it (the rest of a log against at
        most a minute of it), late otherwise, as a log of no such opening is read. The moved
        sentences are then those before that midnight."""
        if not (self.held and self.opening is not None and self.moved > self.opening[0]):
            return 0.0
        self.moved, self.first_moved, self.kinds = self.opening[0], self.opening[1], self.opening_kinds
        return -DAY


def midnight_passed(of_day_before: float, of_day: float) -> bool:
    """Whether the time of day fell from ``of_day_before`` to ``of_day`` [s] by more than half a day:
    midnight UTC passed between two sentences (a receiver gets its time of day right)."""
    return of_day_before - of_day > HALF_DAY


def days_off(date_before: datetime.date, of_day_before: float, date: datetime.date, of_day: float) -> int | None:
    """The days by which the date field ``date`` of a sentence at ``of_day`` [s] is off the day its
    time of day runs on to from the sentence before it (``date_before``, ``of_day_before``), the
    time of day being what a receiver gets right: the day advances where midnight passed. 1 where
    the date field has not advanced with it (late); -1 where it has advanced and the time of day
    has not, within :data:`EARLY_DATE` of midnight (early); 0 where the two agree, and None where
    the date field steps otherwise (a gap in the log, taken as written)."""
    passed = int(midnight_passed(of_day_before, of_day))
    step = (date - date_before).days
    if step == passed:
        return 0
    if (step, passed) == (0, 1) or ((step, passed) == (1, 0) and of_day >= DAY - EARLY_DATE):
        return passed - step
    return None


def utc(t: float) -> str:
    """Unix seconds ``t`` as an ISO UTC date and time."""
    return datetime.datetime.fromtimestamp(t, datetime.timezone.utc).isoformat(sep=" ")[:-6]

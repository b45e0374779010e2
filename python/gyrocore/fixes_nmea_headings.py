"""The true headings of an NMEA log (HDT, THS) for :func:`gyrocore.fixes.read_nmea`, each at the
time of its epoch.

A heading sentence has no time of its own: it is of the epoch of the burst of sentences the
receiver wrote it in, and that burst's RMC or ZDA times it. Receivers differ in where they write
it: after the time (``$GPRMC, $GPVTG, $GPHDT`` each second) or before it (``$GPHDT, $GPRMC,
$GPVTG``). Read always as of the time before it, a heading of the second kind was an epoch late,
without a word (a car turning at 10 deg/s: 10 deg off at 1 Hz). The order is told from the log's
own pattern once it is read (:meth:`Headings.times`): where every epoch's sentences hold one
heading between its time and the next epoch's, a log that begins and ends with whole bursts
shows it at either end: a heading before the first time is of a log whose bursts begin with it,
and a heading after the last time of one whose bursts end with it.
"""

from __future__ import annotations

import functools
from bisect import bisect_right
from collections import Counter
from decimal import Decimal
from pathlib import Path
from typing import Any, NamedTuple

from ._checks import warn

#: Where an epoch's heading sentences sit against its RMC or ZDA: after it (timed by the RMC or ZDA
#: before them, the rule where the log cannot tell) or before it (timed by the one after them).
AFTER, BEFORE = "after", "before"

#: THS mode indicators (NMEA 0183 4.1's true heading and status) of a heading taken: A autonomous,
#: and E estimated, the receiver's dead reckoning carrying its heading through an outage of its
#: antennas (taken, as a heading it keeps with its own gyro for seconds, and counted in a warning:
#: it is not the dual-antenna measurement, and drifts as that gyro does). The others, M manual
#: input, S simulator and V not valid, are no measurement and are skipped, counted in a warning.
THS_TAKEN = ("A", "E")
#: What each THS mode indicator is, for the warnings.
THS_MODES = {"A": "autonomous", "E": "estimated (dead reckoning)", "M": "manual input", "S": "simulator",
             "V": "not valid"}


@functools.cache
def ths_class(pynmea2: Any) -> type:
    """pynmea2's class of THS sentences (``$GNTHS,123.45,A*hh``: the true heading [deg] and a mode
    indicator, as u-blox receivers write it), defined here where pynmea2 has none: pynmea2 registers
    a TalkerSentence subclass by its class name, so that its ``parse`` reads THS as any sentence it
    knows, its checksum checked; without it THS was a sentence of unknown type, skipped."""
    known = getattr(pynmea2, "THS", None)
    if known is not None:
        return known  # type: ignore[no-any-return]

    class THS(pynmea2.TalkerSentence):  # type: ignore[misc]
        """True heading and status: heading [deg], mode indicator (A, E, M, S, V)."""

        fields = (("Heading", "heading", Decimal), ("Mode indicator", "mode"))

    return THS


class _Epoch(NamedTuple):
    """The RMC and ZDA sentences of one epoch, written one after another with one time: the index
    of the first and of the last among the log's sentences, and the time [s] (None: a void RMC, or
    one or a ZDA without a usable time)."""

    first: int
    last: int
    t: float | None


def _places(epochs: list[_Epoch], indices: list[int]) -> list[tuple[int, bool]]:
    """Where each sentence of ``indices`` (of the log) is among the ``epochs``: the index of the
    epoch before it (-1 before the first), and whether it is among that epoch's RMC and ZDA."""
    starts = [e.first for e in epochs]
    places = []
    for index in indices:
        k = bisect_right(starts, index) - 1
        places.append((k, k >= 0 and index <= epochs[k].last))
    return places


class Headings:
    """The heading sentences of one NMEA log and the RMC and ZDA sentences that time them, noted in
    the order written and put together once the whole log is read (:meth:`times`)."""

    def __init__(self, path: Path, tally: Counter[str]) -> None:
        self.path, self.tally = path, tally
        self.markers: list[tuple[int, float | None]] = []  # each RMC's and ZDA's sentence index and time
        self.sentences: list[int] = []  # the sentence index of each heading sentence, taken or not
        self.taken: list[tuple[int, float, int]] = []  # sentence index, heading [deg], line: those taken
        self.kinds: set[str] = set()  # HDT, THS
        self.modes: Counter[str] = Counter()  # THS mode indicators of headings skipped, and E (taken)
        self.opened_with_vtg = False  # the log's first sentence a VTG: the rest of a burst begun before it
        self.cut_off = False  # the log's last line cut off: it stopped in a burst
        self.order = AFTER
        self.unknown = ""  # why the order cannot be told, where there are headings to time
        self.untimed: int | None = None  # the line of the first heading of no epoch

    def marker(self, index: int, t: float | None) -> None:
        """An RMC or ZDA, sentence ``index`` of the log, of time ``t`` [s] (None: of no usable time)."""
        self.markers.append((index, t))

    def take(self, msg: Any, index: int, number: int) -> None:
        """The heading sentence ``msg`` (HDT, THS), sentence ``index`` of the log and on line
        ``number``; a heading that is no bearing is an error naming the line."""
        kind = msg.sentence_type
        self.kinds.add(kind)
        self.sentences.append(index)
        self.tally["HDT"] += 1
        if msg.heading is None:  # not "not heading": 0 (north) is a heading
            self.tally["headingless"] += 1  # a receiver without a heading solution leaves the field empty
            return
        heading = float(msg.heading)
        if not 0.0 <= heading <= 360.0:
            raise ValueError(f"{self.path}: line {number}: the {kind} heading {msg.data[0]!r} is no bearing of 0 to "
                             "360 degrees; remove or repair the line")
        if kind == "THS" and msg.mode != "A":
            self.modes[msg.mode or "(empty)"] += 1
            if msg.mode not in THS_TAKEN:
                return
        self.taken.append((index, heading, number))

    def times(self) -> dict[float, tuple[float, int]]:
        """The heading [deg] and line of each epoch's time [s] that has one: each heading is of the
        epoch of the RMC or ZDA before it or after it, as :meth:`_order` tells, and of several of
        one epoch the one nearest its time is kept, the others counted; one of no epoch with a
        time is skipped, counted."""
        epochs = self._epochs()
        self.order, self.unknown = self._order(epochs)
        nearest: dict[float, tuple[int, float, int]] = {}  # time -> distance in sentences, heading, line
        places = _places(epochs, [index for index, _, _ in self.taken])
        for (index, heading, number), (k, among) in zip(self.taken, places):
            k += not among and self.order == BEFORE
            epoch = epochs[k] if 0 <= k < len(epochs) else None
            if epoch is None or epoch.t is None:
                self.tally["untimed"] += 1
                self.untimed = number if self.untimed is None else self.untimed
                continue
            distance = max(epoch.first - index, index - epoch.last, 0)
            had = nearest.get(epoch.t)
            if had is not None:
                self.tally["hdt_repeats"] += 1
                if had[0] <= distance:
                    continue
            nearest[epoch.t] = (distance, heading, number)
        return {t: (heading, number) for t, (_, heading, number) in nearest.items()}

    def _epochs(self) -> list[_Epoch]:
        """The epochs of the RMC and ZDA sentences, in the order written: those written one after
        another with one time (a receiver's RMC and ZDA of an epoch) are one."""
        epochs: list[_Epoch] = []
        for index, t in self.markers:
            if epochs and t is not None and epochs[-1].t == t:
                epochs[-1] = epochs[-1]._replace(last=index)
            else:
                epochs.append(_Epoch(index, index, t))
        return epochs

    def _order(self, epochs: list[_Epoch]) -> tuple[str, str]:
        """Where the log writes an epoch's heading against its RMC or ZDA (:data:`AFTER`,
        :data:`BEFORE`), and why it cannot be told ("" where it can, or where it does not matter).

        It is told where every epoch's sentences, from its time to the next's, hold one heading
        (more of them than not: a receiver leaves a heading out now and then): a heading before the
        log's first time then says that the log's bursts begin with it, none that they begin with
        the time, and a heading after its last time that they end with it, none that they end
        before it. An end that is not a burst's says nothing: a log that opens with a VTG (the rest
        of an epoch whose RMC came before the log), or whose last line is cut off (stopped while
        written). Where the two ends say different things (a log begun or stopped in a burst,
        the one indistinguishable from the other), or the pattern is another, it cannot be told,
        and the headings are of the time before them. Headings written faster than the epochs
        (several in every epoch: a gyrocompass's) are of the time before them too, as a
        gyrocompass's are written after the time that they follow."""
        if not (self.taken and epochs):
            return AFTER, ""
        between = Counter(k for k, among in _places(epochs, self.sentences) if not among)
        if not between:  # every heading among its epoch's RMC and ZDA: of that epoch, whatever the order
            return AFTER, ""
        counts = [between[k] for k in range(len(epochs) - 1)]
        if counts and min(counts) >= 2:
            return AFTER, ""
        if not counts or max(counts) > 1 or 2 * counts.count(1) <= len(counts):
            return AFTER, (f"its {self.kinds_said()} sentences are not one to each epoch's sentences, from its time to "
                           "the next's" if len(epochs) > 1 else "it has a single epoch")
        said = (None if self.opened_with_vtg else BEFORE if between[-1] else AFTER,
                None if self.cut_off else AFTER if between[len(epochs) - 1] else BEFORE)
        ends = {end for end in said if end is not None}
        if len(ends) == 1:
            return ends.pop(), ""
        return AFTER, ("its first and last epochs disagree, one of them cut off by the log's start or end" if ends
                       else "both its first and last epochs are cut off by the log's start and end")

    def kinds_said(self) -> str:
        """The heading sentences of the log: ``"HDT"``, ``"THS"``, ``"HDT or THS"``."""
        return " or ".join(sorted(self.kinds)) or "HDT"

    def untimed_words(self) -> str:
        """What is done with headings of no epoch, and why."""
        if self.order == BEFORE:
            return ("come after the last valid RMC or ZDA, or before a void RMC, and are skipped: a heading has no "
                    "time of its own, and this log writes each epoch's before its RMC or ZDA")
        return ("come before any valid RMC or ZDA, or after a void RMC, and are skipped: a heading has no time of "
                "its own, and takes that of the valid RMC or ZDA before it")

    def warn(self) -> None:
        """Warns of headings skipped or of modes counted, and of an order that cannot be told."""
        kinds = self.kinds_said()
        if self.unknown:
            warn(f"{self.path}: whether the {kinds} sentences come before or after the RMC or ZDA of their epoch "
                 f"cannot be told from the log ({self.unknown}): each is taken at the time of the valid RMC or ZDA "
                 "before it, as a receiver that writes them after its time has it; one that writes them before (a "
                 "burst of $GPHDT, $GPRMC, ...) has them then an epoch late")
        if self.tally["untimed"]:
            warn(f"{self.path}: {self.tally['untimed']} {kinds} sentence(s) {self.untimed_words()} (the first: line "
                 f"{self.untimed})")
        if self.tally["hdt_repeats"]:
            side = "precede" if self.order == BEFORE else "follow"
            warn(f"{self.path}: {self.tally['hdt_repeats']} {kinds} sentence(s) {side} another of their epoch and are "
                 "skipped: a heading has no time of its own, and the one nearest its epoch's time (a valid RMC or "
                 "ZDA) is kept; a gyrocompass writes HDT faster than a receiver its time")
        skipped = {mode: n for mode, n in self.modes.items() if mode not in THS_TAKEN}
        if skipped:
            said = ", ".join(f"{n} of mode {mode} ({THS_MODES.get(mode, 'no mode of THS')})"
                             for mode, n in sorted(skipped.items()))
            warn(f"{self.path}: THS sentences of no measured heading are skipped: {said}")
        if self.modes["E"]:
            warn(f"{self.path}: {self.modes['E']} THS sentence(s) are of mode E, estimated: the receiver's dead "
                 "reckoning carrying its heading through an outage of its antennas, drifting as its gyro does; they "
                 "are taken, of sigma hdt_sigma_deg as the others")

    def skipped_modes(self) -> int:
        """The THS sentences skipped for their mode indicator (M, S, V, or another)."""
        return sum(n for mode, n in self.modes.items() if mode not in THS_TAKEN)

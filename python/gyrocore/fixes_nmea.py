"""Heading fixes from NMEA 0183 sentences (pynmea2, the ``nmea`` extra): the course over ground and
speed of a receiver's RMC sentences, or of the VTG sentence after one, through
:func:`gyrocore.fixes.from_gnss`.

A file is read line by line, and a line that cannot be used is an error naming the file and the
line: one that is no sentence (a bad checksum, binary data, a line longer than any sentence), and
one whose date, time, course or speed is not a value (pynmea2 hands such a field back as its text).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from ._checks import keyword_options, require_options, shown, warn
from ._extras import require
from .fixes import Fixes, from_gnss
from .fixes_files import ROW_ERROR
from .io._csvfile import refuse_not_text
from .io._paths import check_file

#: Metres per second in a knot and in a km/h (NMEA's speed units).
KNOT, KMH = 1852.0 / 3600.0, 1.0 / 3.6

#: The longest line taken for a sentence [characters]. NMEA 0183 caps a sentence at 82, and
#: proprietary ones run a little longer; a longer line is binary data or a file without line
#: breaks, refused before it is read whole into memory.
MAX_LINE = 4096


def read_nmea(path: str | Path, **options: float) -> Fixes:
    """Fixes from NMEA 0183 sentences: course over ground and speed of valid RMC sentences, at
    their UTC date and time as Unix seconds; a VTG sentence supplies the course of the RMC/GGA
    epoch just before it where that RMC had none. Other sentences are skipped (those pynmea2 does
    not know too); a line that is no sentence, or whose fields are not values, is an error naming
    the file and line, as is a file of no sentence; sentences that give no fix warn with their
    counts (void RMC, RMC without a course). The times are UTC: shift them onto the gyro's clock before fusing. ``options`` go to
    :func:`gyrocore.fixes.from_gnss`.
    """
    require_options("read_nmea (from_gnss's)", options, keyword_options(from_gnss))  # before the file is read
    pynmea2 = require("pynmea2", "reading NMEA sentences")
    path = Path(path)
    check_file(path)  # a named pipe (a receiver's live output) was waited on for ever
    epochs: dict[float, tuple[float, float, int]] = {}  # time -> course [deg], speed [m/s], line
    tally: Counter[str] = Counter()
    last: float | None = None
    for number, text in _sentences(path):
        tally["sentences"] += 1
        try:
            msg = pynmea2.parse(text)
        except pynmea2.SentenceTypeError:
            continue  # a sentence whose checksum holds but whose type pynmea2 does not know has no course for it
        except pynmea2.ParseError as e:
            # pynmea2 adds the line to its words: a line of binary data (a receiver's UBX messages
            # among its sentences) filled the error with up to 4096 bytes of it
            reason = e.args[0] if e.args else str(e)  # pynmea2's (message, data)
            reason = reason[0] if isinstance(reason, tuple) and reason else reason
            raise ValueError(f"{path}: line {number}: not an NMEA sentence ({reason}: {shown(text, 100)}); remove or "
                             "repair the line") from None
        try:
            last = _read(pynmea2, msg, last, number, epochs, tally)
        except (ValueError, TypeError) as e:
            raise ValueError(f"{path}: line {number}: an {msg.sentence_type} sentence whose fields cannot be read "
                             f"({e}); remove or repair the line") from None
    if not tally["sentences"]:
        raise ValueError(f"{path}: no NMEA sentence, so no fix; give a file of RMC (and VTG) sentences")
    if not epochs:
        _warn_no_epoch(path, tally)
    times = sorted(epochs)
    course, speed, lines = (np.array([epochs[k][i] for k in times], dtype=float) for i in range(3))
    try:
        return from_gnss(np.array(times, dtype=float), course, speed, **options)
    except ValueError as e:
        # from_gnss names a sample by its index in time order: the file names its line
        m = ROW_ERROR.match(str(e))
        if m is None or m[4] is None:
            raise
        raise ValueError(f"{path}: line {int(lines[int(m[4])])}: {e}") from None


def _sentences(path: Path) -> Iterator[tuple[int, str]]:
    """(line number, text) of each line of ``path`` that is not blank; a line longer than
    :data:`MAX_LINE` is an error, raised before more of it is read. A byte-order mark is not
    part of the first line, and bytes that are not UTF-8 become U+FFFD (no sentence has them)."""
    with path.open("rb") as raw:  # a UTF-16, gzip or binary file: its bytes were echoed in the error
        refuse_not_text(path, raw.readline(MAX_LINE + 1), "NMEA file")
    with path.open(encoding="utf-8-sig", errors="replace") as f:
        number = 0
        while line := f.readline(MAX_LINE + 1):
            number += 1
            if len(line.rstrip("\r\n")) > MAX_LINE:
                raise ValueError(f"{path}: line {number}: longer than {MAX_LINE} characters, so not an NMEA sentence "
                                 "(at most 82): is it an NMEA log?")
            if line.strip():
                yield number, line.strip()


def _read(pynmea2: Any, msg: Any, last: float | None, number: int, epochs: dict[float, tuple[float, float, int]],
          tally: Counter[str]) -> float | None:
    """Takes the course of ``msg`` into ``epochs`` (at line ``number``); returns the time of the
    epoch a VTG after it belongs to. A field that is not a value raises ValueError or TypeError."""
    if isinstance(msg, pynmea2.RMC):
        tally["RMC"] += 1
        if msg.status != "A":
            tally["void"] += 1
        elif not (msg.datestamp and msg.timestamp):
            tally["undated"] += 1
        else:
            last = msg.datetime.timestamp()
            if msg.true_course is not None and msg.spd_over_grnd is not None:
                epochs[last] = (float(msg.true_course), float(msg.spd_over_grnd) * KNOT, number)
            else:
                tally["courseless"] += 1
    elif isinstance(msg, pynmea2.VTG) and last is not None and last not in epochs:
        if msg.true_track is not None and msg.spd_over_grnd_kmph is not None:
            epochs[last] = (float(msg.true_track), float(msg.spd_over_grnd_kmph) * KMH, number)
    return last


def _warn_no_epoch(path: Path, tally: Counter[str]) -> None:
    """Warns that the sentences of ``path`` gave no course, with the counts that say why."""
    if not tally["RMC"]:
        why = "none is RMC"
    else:
        counts = {"void (status V)": tally["void"], "without a date or time": tally["undated"],
                  "without a course": tally["courseless"]}
        why = f"{tally['RMC']} are RMC: " + ", ".join(f"{n} {what}" for what, n in counts.items() if n)
    warn(f"no heading fix from {path}: of its {tally['sentences']} sentences, {why}; fixes come from valid RMC "
         "sentences with a course (or the VTG after one)")

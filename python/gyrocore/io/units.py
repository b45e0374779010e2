"""Units of a file, and a check that the values read look like the units they were read in.

Timestamps come in ``s``, ``ms``, ``us`` or ``ns`` and rates in ``rad/s`` or ``deg/s``; the readers
convert them to s and rad/s. :class:`UnitCheck` then names the option that would fix values that
look like another unit (rates in deg/s read as rad/s, an epoch in ms read as s, ...).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._arrays import FloatArray
from .._checks import INTERVAL_LIMIT, unit_problems

if TYPE_CHECKING:
    from .source import ReadOptions

#: Time units of a file, as counts per second.
TIME_UNITS = {"s": 1.0, "ms": 1e3, "us": 1e6, "ns": 1e9}
#: Rate units of a file.
RATE_UNITS = ("rad/s", "deg/s")
#: A yaw rate that never exceeds this [deg/s] over a whole log is more likely in rad/s.
SMALL_RATE_DPS = 3.0
#: A mean interval below this [s] (above 10 kHz) suggests timestamps in a larger unit.
SHORT_INTERVAL = 1e-4
#: Timestamps beyond this [s] (the year 5138) are an epoch in ms, us or ns.
EPOCH_LIMIT = 1e11
#: Intervals and large rates are judged on this many first samples, whatever the chunks are.
HEAD_SAMPLES = 1 << 16


class UnitCheck:
    """Checks that a stream of samples looks like the units it was read in.

    Feed it every chunk (in SI units, after conversion); :meth:`problems` then lists what looks like
    another unit. Intervals and large rates are judged on the first :data:`HEAD_SAMPLES` samples
    (however they were chunked); small rates on the largest ``|rate|`` of the whole stream,
    since a log may begin with a long rest.
    """

    def __init__(self, options: ReadOptions) -> None:
        self._options = options
        self._first: list[str] | None = None
        self._head: list[tuple[FloatArray, FloatArray]] = []  # the first samples, until judged
        self._head_samples = 0
        self._max_rate = 0.0

    def update(self, t: FloatArray, rate: FloatArray) -> None:
        """Account for one chunk (t [s], rate [rad/s])."""
        largest = np.max(np.abs(rate), initial=0.0, where=np.isfinite(rate))
        self._max_rate = max(self._max_rate, float(largest))
        if self._first is None:
            self._head.append((t[:HEAD_SAMPLES], rate[:HEAD_SAMPLES]))
            self._head_samples += len(t)
            if self._head_samples >= HEAD_SAMPLES:
                self._judge_head()

    def problems(self) -> list[str]:
        """What looks like another unit, with the option that would fix it."""
        if self._first is None:
            self._judge_head()
        problems = list(self._first or [])
        max_dps = math.degrees(self._max_rate)
        small = self._first is not None and max_dps < SMALL_RATE_DPS and not self._options.static
        if self._options.rate_unit == "deg/s" and small:
            problems.append(
                f"rates look like rad/s, not deg/s: |rate| never exceeds {max_dps:.3g} deg/s, which only a "
                f"sensor that never turned reads; if the log is in rad/s, use rate_unit='rad/s' (--rate-unit rad/s)"
            )
        return problems

    def _judge_head(self) -> None:
        """Judge the first samples (at most :data:`HEAD_SAMPLES`, whatever the chunks were), once
        they hold an interval."""
        if self._head_samples < 2:
            return
        t = np.concatenate([h[0] for h in self._head])[:HEAD_SAMPLES]
        rate = np.concatenate([h[1] for h in self._head])[:HEAD_SAMPLES]
        self._first, self._head = self._first_chunk_problems(t, rate), []

    def _first_chunk_problems(self, t: FloatArray, rate: FloatArray) -> list[str]:
        o = self._options
        problems = []
        if o.rate_unit == "rad/s":
            # unit_problems judges rates only when given one timestamp
            problems += [f"{p}; or use rate_unit='deg/s' (--rate-unit deg/s)" for p in unit_problems(t[:1], rate)]
        unit = o.time_unit
        t0 = abs(float(t[0]))
        mean_dt = float(t[-1] - t[0]) / (len(t) - 1) if len(t) > 1 else 0.0
        if t0 > EPOCH_LIMIT:
            # an epoch read in too small a unit: which unit puts it between 1973 and 2286?
            counts = t0 * TIME_UNITS[unit]
            fits = [u for u, k in TIME_UNITS.items() if 1e8 <= counts / k <= 1e10]
            why = f"t[0] = {t[0]:.6g} s is after the year 5000"
        elif mean_dt > 0 and not SHORT_INTERVAL <= mean_dt <= INTERVAL_LIMIT:
            counts = mean_dt * TIME_UNITS[unit]
            fits = [u for u, k in TIME_UNITS.items() if SHORT_INTERVAL <= counts / k <= INTERVAL_LIMIT]
            why = f"the mean interval is {mean_dt:.3g} s, a {1 / mean_dt:.3g} Hz gyro"
        else:
            fits = []
        if fits:
            problems.append(
                f"timestamps look like {' or '.join(fits)}, not {unit}: {why}; "
                f"use time_unit='{fits[0]}' (--time-unit {fits[0]})"
            )
        return problems

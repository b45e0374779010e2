"""The heading change across a log's longest gap, for the report of a file: a gap is integrated
across (bridged, or reset), which turns the heading by whatever rate its two ends read times its
length, and a user who reads "1 gap(s), the longest 1000.04 s" alone did not see the turn that
was made up there (52 rad across 1000 s of a parked car's bias)."""

from __future__ import annotations

import math

import numpy as np

from ._arrays import FloatArray


class LongestGap:
    """The longest interval between samples of a log given in blocks, and the change of the
    output heading across it: the two rows on either side of it, as written."""

    def __init__(self) -> None:
        self.interval = 0.0
        self.turn = math.nan
        self._last: tuple[float, float] | None = None  # (t, heading) of the last sample of the block before

    def update(self, t: FloatArray, heading: FloatArray, gapped: bool = True) -> None:
        """Take the next block's times and the headings computed for them; ``gapped``: whether the
        pipeline met a gap in it (without one, its longest interval cannot be the longest gap,
        and the block is not searched)."""
        if len(t) == 0:
            return
        if gapped and self._last is not None:  # the interval from the block before to this one
            self._take(float(t[0]) - self._last[0], float(heading[0]) - self._last[1])
        if gapped and len(t) > 1:
            dt = np.diff(t)
            k = int(np.argmax(dt))
            self._take(float(dt[k]), float(heading[k + 1] - heading[k]))
        self._last = (float(t[-1]), float(heading[-1]))

    def _take(self, interval: float, turn: float) -> None:
        if interval > self.interval:
            self.interval, self.turn = interval, turn

    def turn_across(self, longest_gap: float) -> float | None:
        """The heading change [rad] across the gap the pipeline reports as the longest, or None
        where the longest interval seen is another one (a skipped sample's row is in the output
        but not among the pipeline's intervals): said only when it is exactly that gap's."""
        return self.turn if longest_gap > 0 and self.interval == longest_gap and math.isfinite(self.turn) else None


def gap_turn_text(turn: float | None) -> str:
    """The words of :meth:`LongestGap.turn_across` after the longest gap's length ("" without one)."""
    if turn is None:
        return ""
    return f", across which the heading changes by {abs(turn):.4f} rad ({math.degrees(abs(turn)):.2f} deg)"

"""What a run of the heading-fix filter warns of, where its fixes look wrong as a whole: fixes
outside the gyro's time span (another clock), most of them rejected by the outlier gate, and
fixes re-admitted after a run of rejections; a whole log's run (:func:`gyrocore.fixes.fuse`,
whole mode's fix stage) warns of all of them, a stream (:class:`gyrocore.fixes.Fusion`) of the
gate's on its totals."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ._arrays import FloatArray
from ._checks import warn
from .fixes_check import warn_disagreement
from .fixes_stream import ON_GYRO_CLOCK

if TYPE_CHECKING:
    from .fixes import Fixes


def warn_whole_log(t: FloatArray, rate: FloatArray, fixes: Fixes, counts: Mapping[str, int]) -> None:
    """A whole log's warnings about its ``fixes``, fused with the gyro's ``t`` and ``rate`` into
    ``counts``: fixes outside the gyro's span, fixes that disagree with the gyro between them
    (:func:`gyrocore.fixes_check.warn_disagreement`), most of them rejected by the gate, and any
    re-admitted after a run of rejections."""
    warn_outside(t, fixes)
    warn_disagreement(t, rate, fixes)
    warn_rejected(counts)
    warn_readmitted(counts)


#: A whole log's run warns when fewer than this share of its fixes fall within the gyro's time
#: span: fixes on another clock (UTC seconds against seconds since boot) all fall outside it,
#: and are skipped without changing the heading.
MIN_SHARE_INSIDE = 0.1


def warn_outside(t: FloatArray, fixes: Fixes) -> None:
    """Warns (:class:`~gyrocore.InputWarning`) when ``fixes`` were given for a whole log's gyro
    times ``t`` but none, or under :data:`MIN_SHARE_INSIDE` of them, fall within ``t``'s span.
    Both are checked (finite, in time order)."""
    if not len(fixes) or not len(t):
        return
    inside = int(np.count_nonzero((fixes.t >= t[0]) & (fixes.t <= t[-1])))
    if inside >= MIN_SHARE_INSIDE * len(fixes):
        return
    warn(f"{'none' if inside == 0 else f'only {inside}'} of the {len(fixes)} heading fixes fall within the gyro's "
         f"time span (gyro {t[0]:.3f} to {t[-1]:.3f} s, fixes {fixes.t[0]:.3f} to {fixes.t[-1]:.3f} s), and a fix "
         f"outside it is not used: {ON_GYRO_CLOCK}")


#: A whole log's run warns when the outlier gate rejects more than this share of the fixes it
#: reached, and at least :data:`MIN_REJECTED`: a good receiver's fixes pass it (the gate rejects
#: 0.1 % of them), while headings in degrees, times or rates in another unit, or a compass bearing
#: given as a heading are rejected one after another, and the heading is then the gyro's alone.
MAX_SHARE_REJECTED = 0.5
MIN_REJECTED = 5


def warn_rejected(counts: Mapping[str, int]) -> bool:
    """Warns (:class:`~gyrocore.InputWarning`) when the outlier gate rejected most of the fixes a
    run reached (:data:`MAX_SHARE_REJECTED`), saying what usually causes it; says whether it did."""
    rejected, reached = counts["rejected"], counts["applied"] + counts["rejected"]
    if rejected < MIN_REJECTED or rejected <= MAX_SHARE_REJECTED * reached:
        return False
    warn(f"the outlier gate rejected {rejected} of the {reached} heading fixes it reached: they disagree with the "
         f"heading the gyro carries between them, so the heading is mostly the gyro's alone. {_CAUSES}")
    return True


def warn_readmitted(counts: Mapping[str, int]) -> bool:
    """Warns (:class:`~gyrocore.InputWarning`) when the filter re-admitted fixes after a run of
    rejections (``readmit_after``): the heading was taken back to the fixes, but what made the
    filter surer than they allow is still there. Says whether it warned."""
    readmitted = counts.get("readmitted", 0)
    if not readmitted:
        return False
    warn(f"{readmitted} time(s) the gate rejected every heading fix for readmit_after seconds and the filter took "
         f"them in again, its heading having drifted away from them. {_CAUSES}")
    return True


#: What usually makes the gate reject good fixes one after another.
_CAUSES = ("Check the units: fix headings in rad, counter-clockwise from east (not degrees, not a compass bearing: "
           "from_gnss converts one), fix and gyro times in seconds on one clock (a receiver's latency subtracted), the "
           "rate in rad/s; each fix's sigma its real error (a sigma stated too small, or a fix given twice, rejects the "
           "fixes after it); a gyro whose bias is far beyond initial_bias_sigma needs a larger one; and where the "
           "heading drifts between fixes more than arw allows, a larger arw: it must cover every error of the rate "
           "between fixes, the gyro's noise (gyrocore.allan's N) and the rate's lag or interpolated stretches too, "
           "which fixes far tighter than the gyro reveal (a KITTI drive's 10 Hz rate with 0.1 deg fixes: arw near "
           "1e-2 rad/sqrt(s), its gyro's N below 1e-4)")

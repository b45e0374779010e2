"""A SIMULATED GNSS receiver: heading fixes from a reference track (not measured), for drives
that have a reference but no receiver (:func:`gnss_fixes`, also ``gyrocore.sim.gnss_fixes``)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._arrays import FloatArray, as_float_array, as_window, no_path_for_arrays, read_the_log
from ._checks import check_number, check_seed, real_number, require_radians, require_series
from .evaluate_metrics import find_gaps

if TYPE_CHECKING:
    from .fixes import Fixes


#: The most fixes :func:`gnss_fixes` makes: more than a 100 Hz receiver gives in a day (8.6e6);
#: a rate of 1e9 Hz over a minute asked for 6e10 and did not end.
MAX_FIXES = 1e7
#: The range of the simulated fixes' noise [deg]: from the core's smallest fix sigma (1e-12 rad),
#: which it refuses below, to 60 deg. A heading's error wraps at +-180 deg, which leaves the
#: noise's standard deviation below the sigma the fixes state: 0.5 % below at 60 deg, 7 % at 90
#: (83.7 deg), 43 % at 180 (103.5 deg, where half a turn was allowed).
SIGMA_DEG = (math.degrees(1e-12), 60.0)


@no_path_for_arrays("gyrocore.sim.gnss_fixes", read_the_log("log.t_ref, log.heading_ref"))
def gnss_fixes(t_ref: ArrayLike, heading_ref: ArrayLike, *, seed: int, rate_hz: float = 1.0,
               sigma_deg: float = 1.0, outages: Sequence[tuple[float, float]] | None = ()) -> Fixes:
    """SIMULATED heading fixes of a GNSS receiver following a reference track (not measured).

    A fix every ``1 / rate_hz`` seconds from the reference's first time, its heading the reference
    (unwrapped and linearly interpolated, rad, counter-clockwise from east) plus white Gaussian
    noise of ``sigma_deg`` (at most 60 deg: :data:`SIGMA_DEG`), which is also the fix's sigma;
    none inside any of the ``outages`` ``(start, end)`` [s, on the reference's clock; None or () for
    none], nor inside a gap of the reference (an interval over 10 times its median,
    :func:`gyrocore.evaluate.find_gaps`), which tells nothing of the turns made in it. Same
    arguments, same fixes (numpy's PCG64 seeded with ``seed``). The reference is finite, its times
    strictly increasing: a ValueError names its first sample that is not; a heading in degrees (a
    wrap by 360) is a ``UnitError``, as the scoring's.
    """
    from .fixes import Fixes

    t, heading = as_float_array("t_ref", t_ref), as_float_array("heading_ref", heading_ref, unit="rad")
    # checked before unwrapping: one NaN heading made every later fix NaN, times out of order
    # made no fix, and lengths apart failed inside numpy.interp
    require_series("t_ref", t, "heading_ref", heading, context="the reference")
    # as the scoring's Reference: one in degrees made fixes 55 deg off, each stating its sigma
    require_radians("the reference heading", t, heading)
    psi = np.unwrap(heading)
    if len(t) < 2:
        raise ValueError("the reference needs at least two samples")
    rate_hz = check_number("rate_hz", rate_hz)
    given = real_number(sigma_deg)  # text failed in Python's words, True was 1 deg
    if given is None or not SIGMA_DEG[0] <= given <= SIGMA_DEG[1]:
        raise ValueError(f"sigma_deg must be in [{SIGMA_DEG[0]:.3g}, {SIGMA_DEG[1]:g}] deg (beyond, the noise wraps at "
                         f"+-180 deg and is no longer the sigma), got {sigma_deg!r}")
    count = (t[-1] - t[0]) * rate_hz
    if count > MAX_FIXES:
        raise ValueError(f"{count:.3e} fixes requested ({t[-1] - t[0]:g} s at {rate_hz:g} Hz): more than "
                         f"{MAX_FIXES:.0e}; is the rate in Hz?")
    # a span of whole periods lost its last fix to rounding (2.1 s at 10 Hz gave 20.999999999999996):
    # a count within 1e-12 (relative) of a whole number is that number, its last fix put on the
    # reference's last time rather than an ulp past it
    tf = np.minimum(t[0] + np.arange(int(count * (1.0 + 1e-12)) + 1) / rate_hz, t[-1])
    # none inside a gap of the reference (as its scoring finds them): interpolated across one, the
    # fixes missed every turn in it (40 s over a 270 deg turn: errors to 180 deg, each stating sigma)
    k = np.minimum(np.searchsorted(t, tf, side="right") - 1, len(t) - 2)
    keep = ~(find_gaps(t)[k] & (tf > t[k]) & (tf < t[k + 1]))
    for window in _windows(outages):
        keep &= ~inside_outage(tf, window)
    rng = np.random.Generator(np.random.PCG64(check_seed(seed)))
    sigma = math.radians(given)
    noisy = np.interp(tf, t, psi) + sigma * rng.standard_normal(len(tf))
    # not Fixes.of, whose warning on vague sigmas takes them for degrees written as radians: this
    # sigma was given in degrees, by name, and converted here
    return Fixes(tf[keep], np.angle(np.exp(1j * noisy[keep])), np.full(int(keep.sum()), sigma))


def _windows(outages: Sequence[tuple[float, float]] | None) -> list[tuple[float, float]]:
    """The outages as checked ``(start, end)`` pairs; None is none. A number failed in Python's
    words (``'int' object is not iterable``), one ``(start, end)`` given alone as "cannot unpack"."""
    if outages is None:
        return []
    try:
        given = list(outages)
    except TypeError:
        raise TypeError(f"outages must be (start, end) pairs in seconds, e.g. ((100, 160),), or () for none; "
                        f"got {outages!r}") from None
    return [as_window("an outage", outage) for outage in given]


def inside_outage(times: FloatArray, window: tuple[float, float]) -> NDArray[np.bool_]:
    """Which ``times`` [s] lie in the outage ``window`` ``[start, end)``, a time within rounding of
    an edge (8 ulps of the clock) taken as on it: the fix or reference sample due at the start is
    in the outage and the one due at the end is not, however the edges were summed. ``(42879.24 +
    50.3) + 49.9`` is an ulp above ``42879.24 + 100.2``: the fix and the reference sample due at
    that end fell inside the outage, which left out a fix too many and scored a sample past it."""
    start, end = window
    return (times >= start - edge_rounding(start)) & (times < end - edge_rounding(end))


def edge_rounding(edge: float) -> float:
    """How near an outage's ``edge`` [s] a time is taken as on it [s]: 8 ulps of the clock there
    (1.2e-10 s on a clock of 1e5 s, 1.9e-6 s on one of 1.7e9 s)."""
    return 8.0 * float(np.spacing(abs(edge)))

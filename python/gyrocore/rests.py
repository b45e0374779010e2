"""Rest tracking (``track_rests=True``): the rests a drive makes, found as it streams, each one
re-measuring the static bias through a one-state Kalman filter (see rust/src/rest_tracker.rs and
docs/rest_tracking.md).

This module holds the Python side: the speed a caller gives (per gyro sample, or a series at its own
times such as a log folder's ``odometry.csv``, interpolated onto the gyro's), the rests as
:class:`Rest` records, and :func:`bias_walk`, the filter's process noise from a gyro's Allan
parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray, as_float_array


@dataclass(frozen=True)
class Rest:
    """One rest the tracker found (times in the log's own clock)."""

    start: float
    """Start of the part measured [s] (the rest without its first and last detection block)."""
    end: float
    """End of the part measured [s]."""
    bias: float
    """Mean reading over it [rad/s]: the bias it measured."""
    std_error: float
    """Standard error of that mean [rad/s] (batch means of its blocks, at least the white-noise error)."""
    accepted: bool
    """False when the filter's gate refused it (too far from the bias for its standard errors)."""
    filtered: float
    """The filtered bias after this rest [rad/s]: what the pipeline subtracts from then on."""


def bias_walk(*, rate_random_walk: float, bias_instability: float, horizon: float = 60.0) -> float:
    """The random-walk intensity ``q`` [rad^2/s^3] of the bias from Allan parameters: ``K^2`` from
    the rate random walk K [rad/s/sqrt(s)], plus the bias instability's floor ``(0.664 B)^2``
    [B in rad/s] spread over ``horizon`` seconds (a flicker bias wanders by about its floor over
    the time between stops; a random walk is the filter's one-state stand-in for it)."""
    for name, value in (("rate_random_walk", rate_random_walk), ("bias_instability", bias_instability)):
        if not (math.isfinite(value) and value >= 0):
            raise ValueError(f"{name} must be finite and >= 0, got {value}")
    if not (math.isfinite(horizon) and horizon > 0):
        raise ValueError(f"horizon must be finite and > 0 [s], got {horizon}")
    from .allan import FLICKER_FLOOR  # allan imports the pipeline, which imports this module

    return rate_random_walk**2 + (FLICKER_FLOOR * bias_instability) ** 2 / horizon


def _first_bad(name: str, values: FloatArray) -> None:
    """A ValueError naming the first non-finite value of ``values``, if any."""
    bad = ~np.isfinite(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name}[{i}] is {values[i]}: speeds must be finite (drop or fill them first)")


def speed_at(t: FloatArray, speed: ArrayLike, speed_t: ArrayLike | None = None) -> FloatArray:
    """The speed [m/s] at each gyro time ``t``: ``speed`` itself (one per sample), or, with its own
    strictly increasing times ``speed_t``, interpolated linearly; NaN (no speed: the tracker judges
    those samples by the rate) outside ``speed_t``'s span. Errors name the offending index."""
    s = as_float_array("speed", speed)
    _first_bad("speed", s)
    if speed_t is None:
        if len(s) != len(t):
            raise ValueError(
                f"speed has {len(s)} samples but t has {len(t)}: give one speed per gyro sample, "
                "or the speed's own times as speed_t"
            )
        return s
    return speed_on(t, speed_t, s, where="speed")


def speed_on(t: FloatArray, t_speed: ArrayLike, speed: ArrayLike, *, where: str = "speed") -> FloatArray:
    """A speed series at its own times, interpolated linearly onto the gyro's times ``t``.

    Outside the series' span the speed is unknown (NaN), so no rest is taken from there.

    Raises:
        ValueError: lengths differ, a time or speed is not finite, or the times do not strictly
            increase (naming ``where`` and the index).
    """
    ts, vs = as_float_array(f"{where} times", t_speed), as_float_array(where, speed)
    if len(ts) != len(vs):
        raise ValueError(f"{where}: {len(ts)} times but {len(vs)} speeds")
    for label, a in (("time", ts), ("speed", vs)):
        bad = np.flatnonzero(~np.isfinite(a))
        if len(bad):
            raise ValueError(f"{where}: {label} at index {bad[0]} is {a[bad[0]]}; speeds must be finite")
    steps = np.flatnonzero(np.diff(ts) <= 0)
    if len(steps):
        i = int(steps[0]) + 1
        raise ValueError(f"{where}: times must strictly increase, but index {i} ({ts[i]}) follows {ts[i - 1]}")
    if len(ts) == 0:
        return np.full(len(t), np.nan)
    return np.asarray(np.interp(t, ts, vs, left=np.nan, right=np.nan), dtype=np.float64)


def pieces(t: FloatArray, min_duration: float) -> list[slice]:
    """The block cut where ``t`` passes multiples of ``4 * min_duration`` from its start: the core
    keeps the latest 8 rests, and rests end at least ``min_duration`` apart, so no piece ends more
    than it keeps."""
    if len(t) == 0:
        return [slice(0, 0)]
    span = 4.0 * min_duration
    count = int((t[-1] - t[0]) // span)
    cuts = np.searchsorted(t, t[0] + span * np.arange(1, count + 1)).tolist() if count else []
    edges = [0, *cuts, len(t)]
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:]) if b > a] or [slice(0, 0)]


def found(inner: Any) -> int:
    """How many rests the core pipeline ``inner`` has found (0 without rest tracking)."""
    tracker = inner.rest_tracker()
    return 0 if tracker is None else int(tracker[2])


def new_rests(inner: Any, before: int, origin: float) -> list[Rest]:
    """The rests the core found since it had found ``before``, with times from ``origin`` [s] (the
    first sample's time) on."""
    _, _, found, latest = inner.rest_tracker()
    new = found - before
    if new > len(latest):
        raise RuntimeError(f"{new} rests ended in one piece but the core keeps {len(latest)}")
    return [
        Rest(origin + a, origin + b, bias, error, accepted, filtered)
        for a, b, bias, error, accepted, filtered in latest[len(latest) - new :]
    ]


def run(
    inner: Any,
    t: FloatArray,
    rate: FloatArray,
    temp: FloatArray | None,
    index_offset: int,
    flags: tuple[bool, bool],
    speed: FloatArray | None,
    origin: float,
) -> tuple[Any, FloatArray, FloatArray | None, FloatArray | None, list[Rest]]:
    """A chunk through a copy of the core pipeline ``inner`` in :func:`pieces`, collecting every
    rest that ends (the outputs are those of one call: the core is chunk-invariant). Returns the
    advanced copy, the outputs and the rests; on an error ``inner`` is as it was."""
    work = inner.__copy__()
    outs, found_now = [], []
    for part in pieces(t, work.params()["rest_min_duration"]):
        before = found(work)
        temp_p, speed_p = (None if a is None else a[part] for a in (temp, speed))
        offset = index_offset + (part.start or 0)
        outs.append(work.process(t[part], rate[part], temp_p, offset, flags, speed_p))
        found_now += new_rests(work, before, origin)

    def joined(k: int) -> FloatArray | None:
        parts = [a for o in outs if (a := o[k]) is not None]
        return np.concatenate(parts) if len(parts) == len(outs) else None

    heading: FloatArray = np.concatenate([o[0] for o in outs])
    return work, heading, joined(1), joined(2), found_now

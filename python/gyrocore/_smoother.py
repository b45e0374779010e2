"""The bias of a whole log from its rests: a Rauch-Tung-Striebel smoother of a random-walk bias.

The bias ``b(t)`` is modelled as a random walk, ``Var[b(t + dt) - b(t)] = walk**2 * dt`` (the
gyro's rate random walk ``K`` of IEEE 952, ``walk`` in rad/s/sqrt(s)); each rest ``k`` measures
``b`` at its middle ``t_k`` with variance ``R_k``, its standard error squared. A forward Kalman
filter over the rests (with a diffuse prior: the first rest starts it) and the RTS backward pass
give the bias at every rest from all of them; between two rests the smoothed bias is linear in
time (the mean of a Brownian bridge between the smoothed end points), and before the first and
after the last it is constant, growing less certain with the distance. A rest measured far less
precisely than its neighbours, relative to how far the bias can walk between them, barely moves
the estimate; with ``walk = 0`` the bias is the inverse-variance weighted mean of the rests.

Units: s, rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import _gyrocore
from ._arrays import FloatArray

#: A rest's variance never counts as below this [rad^2/s^2] (a noiseless or quantized gyro reads
#: one value throughout a rest: a standard error of 0 would make the filter divide by nothing).
MIN_VARIANCE = 1e-24


@dataclass(frozen=True, eq=False)
class SmoothedBias:
    """The smoothed bias at the rests' middles, and from there at any time.

    Attributes:
        times: the rests' middles [s], increasing.
        mean: the smoothed bias at each [rad/s].
        variance: its variance [rad^2/s^2].
        cross: the covariance of the smoothed bias at neighbouring rests (one fewer than ``times``).
        walk: the random walk's strength [rad/s/sqrt(s)].
    """

    times: FloatArray
    mean: FloatArray
    variance: FloatArray
    cross: FloatArray
    walk: float

    def at(self, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The smoothed bias [rad/s] and its standard error [rad/s] at the times ``t``."""
        ta = np.asarray(t, dtype=np.float64)
        return self.mean_at(ta), np.sqrt(self.variance_at(ta))

    def mean_at(self, t: ArrayLike) -> FloatArray:
        """The smoothed bias [rad/s] at the times ``t``: linear between two rests, constant before
        the first and after the last."""
        return np.asarray(np.interp(np.asarray(t, dtype=np.float64), self.times, self.mean), dtype=np.float64)

    def variance_at(self, t: ArrayLike) -> FloatArray:
        """The smoothed bias's variance [rad^2/s^2] at the times ``t``, computed a slice at a time
        (a whole log's temporaries would each be as large as the log)."""
        ta = np.asarray(t, dtype=np.float64)
        out = np.empty(ta.shape)
        flat, into = ta.reshape(-1), out.reshape(-1)
        for i in range(0, len(flat), _SLICE):
            into[i : i + _SLICE] = self._variance(flat[i : i + _SLICE])
        return out

    def _variance(self, ta: FloatArray) -> FloatArray:
        q = self.walk**2
        n = len(self.times)
        if n == 1:
            return np.asarray(self.variance[0] + q * np.abs(ta - self.times[0]), dtype=np.float64)
        k = np.clip(np.searchsorted(self.times, ta, side="right") - 1, 0, n - 2)
        t0, t1 = self.times[k], self.times[k + 1]
        w = np.clip((ta - t0) / (t1 - t0), 0.0, 1.0)
        variance = (1 - w) ** 2 * self.variance[k] + w**2 * self.variance[k + 1] + 2 * w * (1 - w) * self.cross[k]
        # the bridge's own spread between two rests, and the walk beyond the first or last
        inside = np.clip(ta, t0, t1)
        variance += q * (inside - t0) * (t1 - inside) / (t1 - t0)
        variance += q * (np.maximum(self.times[0] - ta, 0.0) + np.maximum(ta - self.times[-1], 0.0))
        return np.maximum(variance, 0.0)


#: Samples per slice in :meth:`SmoothedBias.variance_at` (its temporaries stay in the cache).
_SLICE = 1 << 15


def smooth(times: ArrayLike, values: ArrayLike, std_errors: ArrayLike, walk: float) -> SmoothedBias:
    """The RTS smoother of a random-walk bias measured at ``times`` (increasing) as ``values`` with
    standard errors ``std_errors``.

    Raises:
        ValueError: no measurement, times not increasing, or ``walk`` negative or not finite.
    """
    ts, z = np.asarray(times, dtype=np.float64), np.asarray(values, dtype=np.float64)
    r = np.maximum(np.asarray(std_errors, dtype=np.float64) ** 2, MIN_VARIANCE)
    if len(ts) == 0:
        raise ValueError("no rest to smooth")
    if (np.diff(ts) <= 0).any():
        raise ValueError("the rests' times must increase")
    if not (np.isfinite(walk) and walk >= 0):
        raise ValueError(f"bias_walk must be finite and >= 0, got {walk}")
    n = len(ts)
    filtered, filtered_var, predicted_var = _forward(ts, z, r, walk**2)
    mean, variance, cross = filtered.copy(), filtered_var.copy(), np.empty(n - 1)
    for k in range(n - 2, -1, -1):
        g = filtered_var[k] / predicted_var[k + 1]
        mean[k] = filtered[k] + g * (mean[k + 1] - filtered[k])
        variance[k] = filtered_var[k] + g * g * (variance[k + 1] - predicted_var[k + 1])
        cross[k] = g * variance[k + 1]
    return SmoothedBias(ts, mean, variance, cross, float(walk))


def _forward(
    ts: FloatArray, z: FloatArray, r: FloatArray, q: float, backward: bool = False
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The Kalman filter over the rests (times increasing), from the first to the last, or the last
    to the first where ``backward``: the filtered mean and variance at each rest, and the variance
    predicted there from the rests filtered before it (infinite at the first: the diffuse prior, the
    first rest alone). The core's loop (``gyrocore::bias_walk``, the rest tracker's update): it runs
    once per rest in every round of refusals."""
    return _gyrocore.filter_rests(ts, z, r, q, MIN_VARIANCE, backward)


def leave_one_out(times: FloatArray, values: FloatArray, std_errors: FloatArray, walk: float) -> FloatArray:
    """Each rest's normalized innovation against the smoother of the others: ``(z_k - b_k) /
    sqrt(R_k + Var b_k)``, with ``b_k`` the bias the other rests give at ``t_k``.

    For a random walk, the bias at ``t_k`` given the other rests combines the filter forward over
    the rests before ``k`` with the filter backward over those after it, each predicted to
    ``t_k`` (the two-filter form of the smoother): two passes for all ``k``, not a smoother per
    rest, so that refusing outliers among many rests stays linear per round."""
    return np.array(LeaveOneOut(times, values, std_errors, walk).scores, dtype=np.float64)


class LeaveOneOut:
    """:func:`leave_one_out`'s scores of rests that are left out one at a time (:meth:`remove`,
    whole mode's refusal of outliers, the worst first), bit for bit those of :func:`leave_one_out`
    over the rests kept.

    A rest left out changes the forward filter only after it and the backward filter only before
    it, and each only until its state (mean and variance) is again what it was, bit for bit: from
    there on every later step is the same. Each refusal so filters the rests near it (about 1200
    of 13,334 each way over a long drive, docs/performance.md; fewer the farther the bias walks
    between rests), not all of them: a pass over all of them per refusal took most of whole
    mode's time where thousands are refused. A filter
    restarted inside the rests starts from the state of the rest before it, given as a first rest
    of that mean and variance at its time: the diffuse prior takes it as it is, and the steps after
    it are the full pass's own.
    """

    def __init__(self, times: FloatArray, values: FloatArray, std_errors: FloatArray, walk: float) -> None:
        self.n = len(times)
        if self.n < 2:
            raise ValueError("leaving one rest out needs at least two rests")
        self.q = walk**2
        #: one row each: times, values, variances, scores, then the forward and the backward
        #: filter's filtered mean, its variance and the variance predicted (the first n columns)
        self._rows = np.empty((10, self.n))
        self._rows[0], self._rows[1] = times, values
        self._rows[2] = np.maximum(np.asarray(std_errors, dtype=np.float64) ** 2, MIN_VARIANCE)
        self._rows[4:7] = _forward(self.times, self.values, self.r, self.q)
        self._rows[7:10] = _forward(self.times, self.values, self.r, self.q, backward=True)
        self._score(0, self.n)

    @property
    def scores(self) -> FloatArray:
        """Each kept rest's score, in order (a view, changed by :meth:`remove`)."""
        return self._rows[3, :self.n]

    @property
    def times(self) -> FloatArray:
        return self._rows[0, :self.n]

    @property
    def values(self) -> FloatArray:
        return self._rows[1, :self.n]

    @property
    def r(self) -> FloatArray:
        return self._rows[2, :self.n]

    @property
    def ahead(self) -> FloatArray:
        return self._rows[4:7, :self.n]

    @property
    def behind(self) -> FloatArray:
        return self._rows[7:10, :self.n]

    def remove(self, k: int) -> None:
        """Leave out the rest at ``k`` (of those kept, in order); :attr:`scores` follows."""
        if self.n <= 2:
            raise ValueError("leaving one rest out needs at least two rests")
        self._rows[:, k:self.n - 1] = self._rows[:, k + 1:self.n]
        self.n -= 1
        end = self._refilter(k, backward=False)
        first = self._refilter(k - 1, backward=True)
        # a rest's score reads the forward filter at the rest before it and the backward one at
        # the rest after it
        self._score(max(first - 1, 0), min(end + 1, self.n))

    def _refilter(self, k: int, backward: bool) -> int:
        """Filter again from the rest at ``k`` on (toward the start where ``backward``), from the
        state of its neighbour on the side already filtered, until the state is the old one; the
        end of the changed stretch: one past its last rest, or (``backward``) its first rest."""
        n, step = self.n, -1 if backward else 1
        state = self.behind if backward else self.ahead
        length = 256
        while 0 <= k < n:
            stop = max(k - length + 1, 0) if backward else min(k + length, n)
            part = slice(stop, k + 1) if backward else slice(k, stop)
            rests = self._rows[:3, part]
            before = k - step
            if 0 <= before < n:  # the neighbour's state as a first rest (see the class doc)
                joined = (self.times[before], state[0, before], state[1, before])
                rests = np.column_stack((rests, joined) if backward else (joined, rests))
            new = np.array(_forward(rests[0], rests[1], rests[2], self.q, backward))
            if 0 <= before < n:
                new = new[:, :-1] if backward else new[:, 1:]
            same = np.flatnonzero((new[0] == state[0, part]) & (new[1] == state[1, part]))
            if len(same):  # from here on, as before
                at = int(same[-1] if backward else same[0])
                kept = slice(at, None) if backward else slice(None, at + 1)
                state[:, part][:, kept] = new[:, kept]
                return part.start + at if backward else part.start + at + 1
            state[:, part] = new
            k, length = stop - 1 if backward else stop, 2 * length
        return 0 if backward else n

    def _score(self, lo: int, hi: int) -> None:
        """The scores of the rests ``lo`` to ``hi - 1``, from the two filters."""
        n = self.n
        ahead_var, behind_var = self.ahead[2, lo:hi], self.behind[2, lo:hi]
        # the prediction at each rest from one side: the filtered mean of the rest before it (0
        # where there is none: its variance is infinite)
        ahead = self.ahead[0, max(lo - 1, 0):hi - 1]
        behind = self.behind[0, lo + 1:min(hi + 1, n)]
        ahead = np.concatenate(([0.0], ahead)) if lo == 0 else ahead
        behind = np.concatenate((behind, [0.0])) if hi == n else behind
        with np.errstate(divide="ignore", invalid="ignore"):
            info = 1.0 / ahead_var + 1.0 / behind_var  # 0 from a side with no rest (infinite variance)
            variance = 1.0 / info
            mean = variance * (np.where(np.isinf(ahead_var), 0.0, ahead / ahead_var)
                               + np.where(np.isinf(behind_var), 0.0, behind / behind_var))
        self.scores[lo:hi] = (self.values[lo:hi] - mean) / np.sqrt(self.r[lo:hi] + variance)

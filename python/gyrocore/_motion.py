"""Whether a gyro stood still: the checks behind two warnings. An Allan deviation of a record in
motion is the motion's, and a static bias measured over a window in which the gyro turned is off
by the turn. Both compare the readings with their white noise, estimated from the first
differences (robustly: slow motion barely moves them, while it moves the readings' spread and
their means)."""

from __future__ import annotations

import math

import numpy as np

from ._arrays import FloatArray
from ._checks import usable, warn

#: The means compared by :func:`moving_share` span this long [s]: long enough to average the
#: noise down, short enough that a turn or a swerve changes them.
MOTION_BLOCK = 0.5
#: A record whose share of such means that differ from the one before by more than
#: :data:`MOTION_SIGMAS` standard errors is at least this is warned about as moving. Measured
#: (:func:`moving_share`): records at rest 0 (broad_10's and broad_11's rests, simulated CRS03
#: gyros of 10 minutes to 4 hours), at most 0.002 (simulated XV-3500 gyros) and 0.015 to 0.021
#: (the simulated FOG, whose bias instability shows at half a second); the 18 real drives 0.30
#: (comma_seg40, often stopped) to 0.74 (f110_ds1).
MOTION_SHARE = 0.1
MOTION_SIGMAS = 5.0
#: A rest window whose readings spread more than this many times their white noise, and by more
#: than :data:`REST_EXCESS` beyond it, is warned about. Measured: the real logs' given and found
#: rests (with the speed and from the rate alone) 0.71 to 2.50 times and at most 0.15 deg/s beyond; simulated CRS03 drives' rests at 100,
#: 10 and 1 Hz (averaged) at most 1.51 times and 0.22 deg/s beyond (bias instability and drift
#: also spread a rest's readings, most where averaging has taken the white noise away); the first
#: 5 s of the real drives 1.7 (a car still stopped) to 44 times and 0.2 to 37 deg/s beyond.
REST_SPREAD = 4.0
REST_EXCESS = math.radians(0.5)
#: The first differences :func:`white_noise` reads at most: its median absolute deviation is then
#: within about 0.5 % of all of them.
NOISE_STEPS = 100_000
#: Fewer readings than this do not tell a rest from a turn.
MIN_READINGS = 10


def white_noise(rate: FloatArray) -> float:
    """The readings' white noise [their unit], from the median absolute deviation of their first
    differences (each the difference of two noises: sqrt(2) times one), of at most
    :data:`NOISE_STEPS` of them spread over the record; 0 for fewer than two readings or readings
    that rarely change from one to the next (a coarsely quantised gyro)."""
    if len(rate) < 2:
        return 0.0
    # all of a 10^8-sample record's differences took 1.9 s, a third of its Allan deviation
    at = np.linspace(0, len(rate) - 2, min(len(rate) - 1, NOISE_STEPS)).astype(np.int64)
    steps = rate[at + 1] - rate[at]
    return float(np.median(np.abs(steps - np.median(steps)))) / 0.6745 / math.sqrt(2.0)


def moving_share(rate: FloatArray, dt: float) -> float | None:
    """The share of the record's consecutive :data:`MOTION_BLOCK` means that differ by more than
    :data:`MOTION_SIGMAS` standard errors of its white noise; None for a record of under 10 such
    means or one whose white noise reads 0 (:func:`white_noise`)."""
    n = max(4, int(round(MOTION_BLOCK / dt)))
    blocks = len(rate) // n
    noise = white_noise(rate)
    if blocks < 10 or noise == 0.0:
        return None
    means = rate[: blocks * n].reshape(blocks, n).mean(axis=1)
    return float(np.mean(np.abs(np.diff(means)) > MOTION_SIGMAS * noise * math.sqrt(2.0 / n)))


def warn_if_moving(rate: FloatArray, dt: float) -> None:
    """Warn when the record looks like a gyro in motion: its Allan deviation is then the motion's
    (a car's f110_ds1 read as a rate random walk of 2.9 rad/s^2/sqrt(Hz), 10^7 times a MEMS gyro's)."""
    share = moving_share(rate, dt)
    if share is not None and share >= MOTION_SHARE:
        warn(f"the gyro seems to move: {share:.0%} of its {MOTION_BLOCK:g} s means differ from the one before by more "
             f"than {MOTION_SIGMAS:g} times their noise (at rest: under {MOTION_SHARE:.0%}); the Allan deviation then "
             "shows the motion, not the sensor's noise: record the gyro at rest, or analyse a rest alone "
             "(gyrocore allan --window T0 T1, or a slice of t and rate)")


def spread(rate: FloatArray) -> tuple[float, float] | None:
    """The readings' standard deviation over their white noise (about 1 at rest, as a rest reads
    its bias and noise alone) and how far it lies beyond it [rad/s, in quadrature]; None for fewer
    than :data:`MIN_READINGS` readings or a white noise of 0."""
    noise = white_noise(rate)
    if len(rate) < MIN_READINGS or noise == 0.0:
        return None
    sd = float(np.std(rate))
    return sd / noise, math.sqrt(max(sd * sd - noise * noise, 0.0))


#: How the warning of :func:`warn_if_turning` begins, for a caller that passes it on alone.
TURNING = "the rest window"

#: What to do with rates in deg/s read as rad/s, wherever they came from: ``rate_unit`` is an
#: option of the readers only, and ``gyrocore.process`` given arrays refused it as an unknown
#: parameter when a warning told its caller to give it.
DEG_PER_S_FIX = "convert arrays with numpy.radians, or read the file with rate_unit='deg/s', --rate-unit deg/s"


#: A bias beyond this [rad/s, 28.6 deg/s] is no gyro's at rest (MEMS zero-rate offsets reach
#: about 20 deg/s, the real logs' 1.4): a rest window that reads more holds rates in deg/s read
#: as rad/s (a car's stop at 1.4 deg/s read 81 deg/s), or the gyro turned steadily in it.
REST_LEVEL = 0.5


def warn_if_turning(window: tuple[float, float], rate: FloatArray, bias: float) -> None:
    """Warn when the readings of the rest ``window`` spread far beyond their noise: the gyro
    turned in it, and the ``bias`` measured there [rad/s] is off by the turn (f110_ds1's first
    5 s, given as its rest, read 40.7 deg/s); else when ``bias`` is beyond :data:`REST_LEVEL`."""
    measured = spread(rate)
    if measured is not None and measured[0] > REST_SPREAD and measured[1] > REST_EXCESS:
        warn(f"{TURNING} [{window[0]}, {window[1]}] s does not look like a rest: its readings spread "
             f"{measured[0]:.3g} times their sample-to-sample noise, {math.degrees(measured[1]):.3g} deg/s beyond it (at "
             f"rest: about once, and at most {math.degrees(REST_EXCESS):g} deg/s beyond), so the gyro turned in it and its "
             f"bias, {math.degrees(bias):.5g} deg/s, holds the turn: give a window in which the gyro stands still")
    elif abs(bias) > REST_LEVEL:
        warn(f"{TURNING} [{window[0]}, {window[1]}] s reads a bias of {bias:.4g} rad/s ({math.degrees(bias):.4g} deg/s), "
             f"beyond any gyro's at rest (more than {REST_LEVEL:g} rad/s): rates in deg/s read as rad/s (then "
             f"{DEG_PER_S_FIX}), or the gyro turned in it (then give a window in which it stands still)")


#: The readings of a streamed rest window :class:`WindowWatch` keeps at most (8 MB): a window of
#: an hour at 1 kHz is checked on its first 1000 s, and memory stays flat however long it is.
WATCHED = 1_000_000


class WindowWatch:
    """The readings of a causal pipeline's rest window, kept as its chunks stream by (up to
    :data:`WATCHED`), and checked by :func:`warn_if_turning` once the window is over: the core
    measures the window's bias itself, chunk by chunk, and saw no turn in it."""

    def __init__(self) -> None:
        # One buffer that doubles as it fills, so that a chunk costs its own readings whatever came
        # before: a list of every chunk's readings, counted again for each chunk, took 1.35 ms a
        # chunk of one sample 80 s into a window at 1 kHz (108 s for the window), and its arrays
        # took 280 bytes a reading. None once checked.
        self._buffer: FloatArray | None = np.empty(0)
        self._count = 0

    @property
    def checked(self) -> bool:
        """Whether the window was checked (or there is none to watch)."""
        return self._buffer is None

    @property
    def readings(self) -> list[FloatArray] | None:
        """The readings kept (one array, in a list as a pickle holds them), or None once checked."""
        return None if self._buffer is None else [self._buffer[: self._count]]

    @classmethod
    def restored(cls, readings: list[FloatArray] | None) -> WindowWatch:
        """A watch that holds ``readings`` (None: the window was checked), as a pickle kept it."""
        watch = cls()
        if readings is None:
            watch._buffer = None
        else:
            watch._keep(np.concatenate(readings) if readings else np.empty(0))
        return watch

    def add(self, window: tuple[float, float], t: FloatArray, rate: FloatArray) -> None:
        """Keep the readings of the chunk ``(t, rate)`` inside ``window`` that the core takes."""
        if self._buffer is not None:
            self._keep(rate[(t >= window[0]) & (t <= window[1]) & usable(rate)])

    def _keep(self, inside: FloatArray) -> None:
        """Append ``inside`` to the buffer, up to :data:`WATCHED` readings in all."""
        assert self._buffer is not None
        inside = inside[: max(WATCHED - self._count, 0)]
        end = self._count + len(inside)
        if end > len(self._buffer):
            grown = np.empty(min(max(end, 2 * len(self._buffer)), WATCHED))
            grown[: self._count] = self._buffer[: self._count]
            self._buffer = grown
        self._buffer[self._count:end] = inside
        self._count = end

    def close(self, window: tuple[float, float], bias: float) -> None:
        """The window is over: check its readings (once)."""
        if self._buffer is not None:
            warn_if_turning(window, self._buffer[: self._count], bias)
            self._buffer = None

"""The points a long line is drawn through: as many as a plot's pixels show."""

from __future__ import annotations

import numpy as np

from ._arrays import FloatArray

#: A line of :func:`gyrocore.evaluate_plot.plot_log` is drawn through at most twice this many
#: points (the plot is 1000 pixels wide): every sample of a long log's 7 methods, drawn twice, took
#: 21.5 s and 2.9 GB resident for 4*10^6 samples, where scoring them took 5.5 s and 838 MB.
PLOT_BINS = 4000


def envelope(y: FloatArray) -> np.ndarray:
    """The indices of ``y`` a line is drawn through: at most 2 :data:`PLOT_BINS` (and the last few
    samples), each bin of consecutive samples by its lowest and its highest, in their order, so
    that the line covers what the line through every sample covers at the plot's resolution."""
    size = -(-len(y) // PLOT_BINS)
    if size <= 2:
        return np.arange(len(y))
    whole = len(y) // size * size
    bins = y[:whole].reshape(-1, size)
    low, high = bins.argmin(axis=1), bins.argmax(axis=1)
    first = np.arange(0, whole, size)
    return np.concatenate((np.column_stack((first + np.minimum(low, high), first + np.maximum(low, high))).ravel(),
                           np.arange(whole, len(y))))

"""A bias-versus-temperature look-up table from rests at several temperatures (FOG section 2)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .._arrays import READ_WITH_TEMPERATURES, no_path_for_arrays
from .._checks import check_count, check_number
from .inputs import check_series, check_temperature
from .rest import time_weights
from .result import BiasTable


@no_path_for_arrays("gyrocore.calibration.bias_temperature_table", READ_WITH_TEMPERATURES)
def bias_temperature_table(
    t: ArrayLike,
    rate: ArrayLike,
    temperature: ArrayLike,
    *,
    bin_width: float = 1.0,
    min_samples: int = 10,
) -> BiasTable:
    """Bias versus temperature from a record at rest (FOG section 2, its Figure 2).

    Readings [rad/s] are grouped into temperature bins ``bin_width`` degC wide; each bin with at
    least ``min_samples`` readings gives one entry: its mean temperature and its time-weighted
    mean reading (as :func:`static_bias`). The record must be at rest throughout (cut it to the
    rest first); the temperature should change slowly (a warm-up after power-on).

    Raises:
        SampleError: a temperature that is not finite or beyond +-2^20 degC (the pipeline's
            limit), naming the sample.
        ValueError: bad samples otherwise, or fewer than two bins with ``min_samples`` readings.
    """
    ta, ra = check_series(t, rate, minimum=1)
    temp = check_temperature(temperature, len(ta))
    check_number("bin_width", bin_width, unit=" [degC]")
    check_count("min_samples", min_samples)  # 0 kept bins of no reading
    w = time_weights(ta - ta[0])
    w[0] = w[1] if len(w) > 1 else 1.0
    position = np.floor((temp - temp.min()) / bin_width)
    if not np.isfinite(position).all():
        raise ValueError(
            f"bin_width = {bin_width:g} degC is too small for temperatures spanning {np.ptp(temp):.6g} degC"
        )
    # The bins that hold readings, numbered 0, 1, ... in temperature order: memory follows the
    # readings, not the span of temperatures over the bin width.
    _, k = np.unique(position, return_inverse=True)
    nb = int(k.max()) + 1
    counts = np.bincount(k, minlength=nb)
    wsum = np.bincount(k, w, nb)
    keep = (counts >= min_samples) & (wsum > 0)
    if counts.max() < min_samples:  # the span may be wide: each reading fell in a bin of a few
        raise ValueError(
            f"no temperature bin of {bin_width:g} degC holds {min_samples} readings (the fullest holds "
            f"{counts.max()}): give a wider bin_width or a smaller min_samples"
        )
    if keep.sum() < 2:
        raise ValueError(
            f"fewer than 2 temperature bins of {bin_width:g} degC hold {min_samples} readings: the temperature "
            f"spans only {np.ptp(temp):.3g} degC"
        )
    bias = np.bincount(k, w * ra, nb) / np.where(wsum > 0, wsum, 1.0)
    mean_t = np.bincount(k, w * temp, nb) / np.where(wsum > 0, wsum, 1.0)
    var = np.bincount(k, w * (ra - bias[k]) ** 2, nb) / np.where(wsum > 0, wsum, 1.0)
    stderr = np.sqrt(var / np.maximum(counts, 1))
    idx = np.flatnonzero(keep)
    order = idx[np.argsort(mean_t[idx])]
    return BiasTable(
        temperatures=tuple(float(v) for v in mean_t[order]),
        biases=tuple(float(v) for v in bias[order]),
        stderr=tuple(float(v) for v in stderr[order]),
        counts=tuple(int(v) for v in counts[order]),
    )

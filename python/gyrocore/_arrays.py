"""Conversion of user arrays to what the Rust core reads: 1-D, contiguous float64."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def as_float_array(name: str, values: ArrayLike) -> FloatArray:
    """Return ``values`` as a 1-D contiguous float64 array, copying only when needed.

    Raises TypeError for non-numeric data and ValueError for a wrong shape.
    """
    a = np.asarray(values)
    if a.dtype == np.bool_ or not (
        np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)
    ):
        raise TypeError(f"{name} must hold real numbers, got dtype {a.dtype}")
    if a.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}")
    return np.ascontiguousarray(a, dtype=np.float64)

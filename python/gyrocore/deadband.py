"""What the threshold filter (Hong eq 12: ``|r_m| < r_thres -> 0``) lets through of a rate in
Gaussian noise: the reason a dead band removes a small residual bias only when the noise is well
below the threshold.

A reading ``x = b + w``, with ``w`` Gaussian of rms ``sigma``, leaves the dead band as
``y = x`` where ``|x| >= r_thres`` and 0 elsewhere. Its expected value, with
``a = (r_thres - b) / sigma`` and ``c = (-r_thres - b) / sigma``, is

    E[y] = b (Q(a) + Phi(c)) + sigma (phi(a) - phi(c))

(``phi``, ``Phi`` the standard normal density and distribution, ``Q = 1 - Phi``). For a bias much
smaller than the noise, ``E[y] = leak * b`` with ``leak = 2 Q(k) + 2 k phi(k)``, ``k = r_thres /
sigma``: at ``k = 1`` (the XV3500 at 0.3 deg/s) 80 % of a residual bias passes and is integrated
into the heading; at ``k = 3`` (the pipeline's ``threshold_sigmas = 3``), 3 %.

Only the distribution of one sample matters, so these hold for correlated (low-passed) noise too,
with ``sigma`` the rms of one sample (:attr:`gyrocore.sim.GyroSpec.noise_rms_dps`).

    >>> round(bias_leak(noise_rms=1.0, threshold=1.0), 3)
    0.801
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray, as_float_array, refuse_masked
from ._checks import check_number, public_dir, require_finite
from ._extras import require

__all__ = ["bias_leak", "expected_output"]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


def _cdf(x: FloatArray | float, what: str) -> FloatArray:
    """The standard normal distribution, for ``what`` (named if scipy is missing); scipy (the
    ``fit`` extra) is imported here, not with the
    package, because the command line's start (and the moment it owns Ctrl-C) waited 0.7 s for it."""
    ndtr = require("scipy.special", what).ndtr
    probability: FloatArray = ndtr(x)
    return probability


def _pdf(x: FloatArray | float) -> FloatArray:
    """The standard normal density."""
    density: FloatArray = np.exp(-0.5 * np.square(x)) / np.sqrt(2.0 * np.pi)
    return density


def _check(noise_rms: float, threshold: float) -> None:
    # text was numpy's bare "ufunc 'isfinite' not supported", and True a noise of 1
    check_number("noise_rms", noise_rms)
    check_number("threshold", threshold, strict=False)


def expected_output(rate: ArrayLike, noise_rms: float, threshold: float) -> FloatArray:
    """The expected output of the dead band (Hong eq 12) for a true ``rate`` (any shape) plus
    Gaussian noise of rms ``noise_rms``, in the units of the arguments. A rate that is not finite
    is a ValueError naming its index."""
    _check(noise_rms, threshold)
    refuse_masked("rate", rate)  # the masked values were used as data
    # the package's checks of an array, in any shape: text was numpy's "could not convert string to float"
    b = as_float_array("rate", np.ravel(rate), unit="rad/s").reshape(np.shape(rate))
    require_finite("rate", b)  # NaN came back as the expected output, without a word
    # a rate or threshold many noise levels wide overflows a, c or their squares to infinity, where
    # the distribution (0 or 1) and the density (0) are their exact limits: no warning is due
    with np.errstate(over="ignore"):
        a = (threshold - b) / noise_rms
        c = (-threshold - b) / noise_rms
        what = "the dead band's expected output"
        out: FloatArray = b * (_cdf(-a, what) + _cdf(c, what)) + noise_rms * (_pdf(a) - _pdf(c))
    return out


def bias_leak(noise_rms: float, threshold: float) -> float:
    """The fraction of a small bias (``|b|`` much below ``noise_rms``) that passes the dead band
    on average: the slope of :func:`expected_output` at 0, ``2 Q(k) + 2 k phi(k)`` with
    ``k = threshold / noise_rms``. 1 without a threshold; it falls below 0.5 only above
    ``k = 1.54``."""
    _check(noise_rms, threshold)
    k = threshold / noise_rms
    if math.isinf(k):  # a threshold of 1e300 over a noise of 1e-300: inf * phi(inf) gave NaN, not "none passes"
        return 0.0
    return float(2.0 * _cdf(-k, "the dead band's bias leak") + 2.0 * k * _pdf(k))

"""Equivalent degrees of freedom of an Allan-family variance and its chi-squared confidence interval.

Greenhall & Riley, "Uncertainty of stability variances based on finite differences" (PTTI 2003), the
method Stable32 uses; :mod:`gyrocore.allan` re-exports the public names.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._arrays import FloatArray, as_float_array
from ._checks import check_count, check_number
from ._extras import require

#: Two-sided confidence of one standard deviation, erf(1/sqrt(2)) (Stable32's 0.683).
ONE_SIGMA = math.erf(1.0 / math.sqrt(2.0))


#: (a0, a1) of their Table 1 (modified variances, d = 2) and Table 2 (unmodified, d = 2 and 3),
#: for the rate-noise exponents supported here: 1/edf = (a0 - a1/r)/r for long records.
_TABLES = {
    0: {"modified": (1.033, 0.607), 2: (2.0 / 3.0, 1.0 / 3.0), 3: (7.0 / 9.0, 1.0 / 2.0)},
    -1: {"modified": (1.048, 0.534), 2: (0.852, 0.375), 3: (0.997, 0.617)},
    -2: {"modified": (1.302, 0.535), 2: (1.079, 0.368), 3: (1.033, 0.607)},
}
_J_MAX = 100


def _sw(t: NDArray[np.float64], alpha: int) -> NDArray[np.float64]:
    """Their eq 7, the generalized autocovariance of phase noise with exponent ``alpha`` (up to a
    constant); ``_sx`` without a filter asks for ``alpha + 2``."""
    a = np.abs(t)
    with np.errstate(divide="ignore", invalid="ignore"):
        log = np.where(a > 0, np.log(np.where(a > 0, a, 1.0)), 0.0)
    if alpha == 2:
        return -a
    if alpha == 1:
        return t**2 * log
    if alpha == 0:
        return a**3
    if alpha == -1:
        return t**4 * log
    if alpha == -2:
        return a**5
    if alpha == -3:
        return t**6 * log
    if alpha == -4:
        return a**7
    raise ValueError(f"unsupported noise exponent {alpha}")


def _sx(t: NDArray[np.float64], f: float, alpha: int) -> NDArray[np.float64]:
    """Their eq 8: ``sw`` after the averaging filter of length 1/F (F = inf: no filter)."""
    if math.isinf(f):
        return _sw(t, alpha + 2)
    return f * f * (2.0 * _sw(t, alpha) - _sw(t - 1.0 / f, alpha) - _sw(t + 1.0 / f, alpha))


def _sz(t: NDArray[np.float64], f: float, alpha: int, d: int) -> NDArray[np.float64]:
    """Their eq 9: ``sx`` after the d-th difference, sum_k (-1)^k C(2d, d+k) sx(t + k)."""
    out = np.zeros_like(t)
    for k in range(-d, d + 1):
        out += (-1) ** abs(k) * math.comb(2 * d, d + k) * _sx(t + k, f, alpha)
    return out


def _basic_sum(j: int, m_terms: float, s: float, f: float, alpha: int, d: int) -> float:
    """Their eq 10."""
    idx = np.arange(1, j, dtype=np.float64)
    inner = float(np.sum(2.0 * (1.0 - idx / m_terms) * _sz(idx / s, f, alpha, d) ** 2))
    first = float(_sz(np.zeros(1), f, alpha, d)[0] ** 2)
    last = (1.0 - j / m_terms) * float(_sz(np.array([j / s]), f, alpha, d)[0] ** 2)
    return first + last + inner


def equivalent_dof(alpha: int, d: int, m: int, n: int, *, overlapping: bool, modified: bool) -> float:
    """Equivalent degrees of freedom of a variance estimate (Greenhall & Riley 2003, their
    section 4 algorithm): ``alpha`` the rate-noise exponent (0, -1, -2), ``d`` the difference
    order (2 Allan, 3 Hadamard), ``m`` the averaging factor, ``n`` phase samples (whole numbers
    >= 1: m = 0 divided by zero, m = -1 or 2.5 gave a number)."""
    m, n = check_count("m", m), check_count("n", n)
    if alpha not in _TABLES or d not in (2, 3) or (modified and d != 2):
        raise ValueError(f"no EDF for alpha = {alpha}, d = {d}, modified = {modified}")
    f = 1.0 if modified else float(m)  # filter factor
    s = float(m) if overlapping else 1.0  # stride factor
    length = m / f + m * d  # span of the filter on the phase
    if n < length:
        raise ValueError(f"{n} phase samples are too few for m = {m}")
    m_terms = 1.0 + math.floor(s * (n - length) / m)
    j = int(min(m_terms, (d + 1) * s))
    r = m_terms / s
    if modified:
        if j <= _J_MAX:
            inv = _basic_sum(j, m_terms, s, 1.0, alpha, d) / (_sz(np.zeros(1), 1.0, alpha, d)[0] ** 2 * m_terms)
        elif r > d + 1:
            a0, a1 = _TABLES[alpha]["modified"]
            inv = (a0 - a1 / r) / r
        else:
            inv = _basic_sum(_J_MAX, _J_MAX, _J_MAX / r, 1.0, alpha, d) / (
                _sz(np.zeros(1), 1.0, alpha, d)[0] ** 2 * _J_MAX
            )
    else:
        if j <= _J_MAX:
            fm = float(m) if m * (d + 1) <= _J_MAX else math.inf
            inv = _basic_sum(j, m_terms, s, fm, alpha, d) / (_sz(np.zeros(1), fm, alpha, d)[0] ** 2 * m_terms)
        elif r > d + 1:
            a0, a1 = _TABLES[alpha][d]
            inv = (a0 - a1 / r) / r
        else:
            inv = _basic_sum(_J_MAX, _J_MAX, _J_MAX / r, math.inf, alpha, d) / (
                _sz(np.zeros(1), math.inf, alpha, d)[0] ** 2 * _J_MAX
            )
    return float(1.0 / inv)


def confidence_interval(
    dev: ArrayLike, edf: ArrayLike, confidence: float = ONE_SIGMA
) -> tuple[FloatArray, FloatArray]:
    """Chi-squared interval of a deviation with ``edf`` degrees of freedom (NIST SP 1065 eq 45):
    ``dev * sqrt(edf / chi2_{(1+c)/2})`` .. ``dev * sqrt(edf / chi2_{(1-c)/2})``.

    Raises:
        ValueError: ``dev`` and ``edf`` of different lengths, a ``dev`` that is not finite and >= 0,
            an ``edf`` that is not finite and > 0 (naming the first), or ``confidence`` outside (0, 1).
        TypeError: arrays or a ``confidence`` that are not real numbers.
    """
    chi2 = require("scipy.stats", "the Allan deviation").chi2  # scipy's only use here

    # Checked: one edf for two deviations was broadcast over both, and an edf of 0, -1 or NaN gave
    # NaN bounds (a confidence of 1 an infinite one) without a word.
    d, e = as_float_array("dev", np.atleast_1d(dev)), as_float_array("edf", np.atleast_1d(edf))
    if len(d) != len(e):
        raise ValueError(f"dev has {len(d)} values but edf has {len(e)}: give one edf per deviation")
    for name, values, ok in (("dev", d, d >= 0), ("edf", e, e > 0)):
        bad = np.flatnonzero(~(np.isfinite(values) & ok))
        if len(bad):
            raise ValueError(f"{name}[{bad[0]}] = {values[bad[0]]}: must be finite and {'>=' if name == 'dev' else '>'} 0")
    if not 0.0 < check_number("confidence", confidence) < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    if np.ndim(dev) == 0 and np.ndim(edf) == 0:  # one deviation given as a number: one back, as before
        d, e = d.reshape(()), e.reshape(())
    tail = (1.0 - confidence) / 2.0
    return d * np.sqrt(e / chi2.ppf(1.0 - tail, e)), d * np.sqrt(e / chi2.ppf(tail, e))

"""Heading error metrics of the papers: E_psi (HDR eq 15), NE_psi (HDR eq 16), the mean and standard
deviation of the absolute error (Hong Table 1), final and maximum error."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import as_float_array


@dataclass(frozen=True)
class HeadingErrors:
    """Heading error against a reference, in degrees (compared at the reference's times)."""

    e_psi_deg: float
    """Average absolute heading error E_psi (HDR eq 15)."""
    ne_psi_deg_per_min: float
    """E_psi per minute of duration, NE_psi (HDR eq 16)."""
    mean_error_deg: float
    """Mean absolute error (Hong Table 1's mean error; equal to E_psi)."""
    std_error_deg: float
    """Standard deviation of the absolute error (Hong Table 1)."""
    final_error_deg: float
    """Signed error at the last compared reference time."""
    max_error_deg: float
    """Largest absolute error."""
    duration_min: float
    """Compared duration T_d [min]."""
    n: int
    """Number of reference samples compared."""

    def as_dict(self) -> dict[str, float]:
        """The metrics as a plain dict (for JSON)."""
        return asdict(self)


def unwrap(heading: ArrayLike) -> np.ndarray:
    """Continuous heading [rad] from one wrapped to (-pi, pi]."""
    return np.unwrap(as_float_array("heading", heading))


def heading_errors(
    t: ArrayLike, heading: ArrayLike, t_ref: ArrayLike, heading_ref: ArrayLike
) -> HeadingErrors:
    """Compare an estimated heading with a reference heading.

    The estimate (continuous, rad) is linearly interpolated at the reference's times inside its
    own time span; the reference (rad, may be wrapped) is unwrapped. Both are aligned at the first
    compared reference time (only relative heading is meaningful), and E_psi averages the absolute
    difference over the reference samples (HDR eq 15), NE_psi divides it by the duration in minutes
    (eq 16).
    """
    t = as_float_array("t", t)
    heading = as_float_array("heading", heading)
    t_ref = as_float_array("t_ref", t_ref)
    ref = unwrap(heading_ref)
    if len(t) != len(heading) or len(t_ref) != len(ref):
        raise ValueError("t/heading and t_ref/heading_ref must have equal lengths")
    if len(t) < 2:
        raise ValueError("need at least two heading samples to compare")
    inside = (t_ref >= t[0]) & (t_ref <= t[-1])
    if inside.sum() < 2:
        raise ValueError("the reference has fewer than two samples inside the heading's time span")
    tr, ref = t_ref[inside], ref[inside]
    est = np.interp(tr, t, heading)
    err = np.degrees((est - est[0]) - (ref - ref[0]))
    abs_err = np.abs(err)
    duration_min = (tr[-1] - tr[0]) / 60.0
    e_psi = float(abs_err.mean())
    return HeadingErrors(
        e_psi_deg=e_psi,
        ne_psi_deg_per_min=e_psi / duration_min if duration_min > 0 else math.nan,
        mean_error_deg=e_psi,
        std_error_deg=float(abs_err.std()),
        final_error_deg=float(err[-1]),
        max_error_deg=float(abs_err.max()),
        duration_min=float(duration_min),
        n=int(len(tr)),
    )

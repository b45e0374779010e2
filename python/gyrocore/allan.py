"""Allan deviation of gyro data and the noise parameters read from it.

The curve is IEEE Std 952-1997 Annex C's (Hong & Park section 2.1 read their gyro's angle random
walk and bias instability from it): the rate averaged over ``tau`` seconds, differenced between
adjacent intervals. The sums run in Rust on all cores, O(N) per averaging time over the angle
(the integral of the rate, computed once), so a day of 1 kHz data takes about a second.

Units: for a rate in rad/s the deviation is in rad/s; the angle random walk ``N`` is in
rad/s/sqrt(Hz) (= rad/sqrt(s)), the bias instability ``B`` in rad/s, the rate random walk ``K`` in
rad/s^2/sqrt(Hz) (= rad/s/sqrt(s)); each parameter also carries the customary degree units.

Confidence intervals are chi-squared intervals with the equivalent degrees of freedom of
Greenhall & Riley ("Uncertainty of stability variances based on finite differences", PTTI 2003),
the method Stable32 uses; the noise type they assume is white rate noise (``noise_alpha=0``,
the angle-random-walk regime) unless told otherwise.

    >>> import numpy as np, gyrocore.allan as allan
    >>> rate = np.random.default_rng(1).normal(0.0, 0.01, 100_000)  # white noise, dt = 0.01 s
    >>> r = allan.deviation(rate, 0.01)
    >>> bool(abs(r.adev[0] / (0.01 * np.sqrt(0.01) / np.sqrt(r.taus[0])) - 1) < 0.01)
    True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._checks import public_dir
from ._extras import require
from .allan_curve import (
    GAP_FACTOR,
    MAX_OVERSAMPLING,
    AllanResult,
    Kind,
    TauSpec,
    deviation,
    deviation_from_timestamps,
    phase_deviation,
)
from .allan_edf import ONE_SIGMA, confidence_interval, equivalent_dof
from .allan_noise import (
    FLICKER_FLOOR,
    NoiseParameter,
    NoiseParameters,
    NoiseSettings,
    noise_parameters,
    settings_from_noise,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = [
    "FLICKER_FLOOR", "GAP_FACTOR", "MAX_OVERSAMPLING", "ONE_SIGMA", "AllanResult", "Kind", "NoiseParameter",
    "NoiseParameters", "NoiseSettings", "TauSpec", "confidence_interval", "deviation", "deviation_from_timestamps",
    "equivalent_dof", "noise_parameters", "phase_deviation", "plot", "settings_from_noise",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


def plot(
    result: AllanResult,
    *,
    parameters: NoiseParameters | None = None,
    ax: Axes | None = None,
    unit: str = "rad/s",
    label: str | None = None,
) -> Axes:
    """Log-log plot of the deviation with its confidence interval; with ``parameters``, the
    slope -1/2 (N), floor (0.664 B) and slope +1/2 (K) lines over the ranges they came from.
    Needs matplotlib (``pip install gyrocore[plot]``); returns the axes. Raises ValueError for a
    curve that is 0 at every tau (constant readings), which log axes cannot show."""
    if result.flat_zero:  # matplotlib drew empty axes, warning only that it could not log-scale
        raise ValueError("the deviation is 0 at every tau (constant readings): a log-log plot has nothing to draw")
    plt = require("matplotlib.pyplot", "plotting an Allan deviation")
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 4.8))
    err = np.vstack([result.adev - result.adev_low, result.adev_high - result.adev])
    ax.errorbar(result.taus, result.adev, yerr=err, fmt="o-", ms=3, capsize=2,
                label=label or f"{result.kind} deviation")
    if parameters is not None:
        span = np.array([result.taus[0], result.taus[-1]])
        if parameters.arw is not None:
            ax.plot(span, parameters.arw.value / np.sqrt(span), "--",
                    label=f"N = {parameters.arw.value_deg:.3g} deg/sqrt(h)")
        if parameters.bias_instability is not None:
            bound = "<=" if "upper bound" in parameters.bias_instability.method else "="
            ax.plot(span, [FLICKER_FLOOR * parameters.bias_instability.value] * 2, ":",
                    label=f"0.664 B, B {bound} {parameters.bias_instability.value_deg:.3g} deg/h")
        if parameters.rrw is not None:
            ax.plot(span, parameters.rrw.value * np.sqrt(span / 3.0), "-.",
                    label=f"K = {parameters.rrw.value_deg:.3g} deg/h/sqrt(h)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("averaging time tau [s]")
    ax.set_ylabel(f"deviation [{unit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax

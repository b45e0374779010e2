"""Heading against a reference, scored with the papers' metrics, and methods compared on logs.

Metrics: E_psi (HDR eq 15), NE_psi (HDR eq 16), the mean and standard deviation of the absolute
error (Hong Table 1), final and maximum error, the return orientation error of a closed path (FOG
section 4.1) and the improvement factor over plain integration (HDR Table II). :func:`compare` runs
every method on every log and writes plots of heading and error against time.

Units: radians inside, degrees in the fields named ``*_deg``; times in seconds.
"""

from __future__ import annotations

# in the order of their definitions: the API page lists the names in the order they are imported
from ._checks import public_dir
from .evaluate_metrics import (
    GAP_FACTOR,
    HeadingErrors,
    unwrap,
    find_gaps,
    Reference,
    heading_errors,
    improvement,
    return_orientation_error,
)
from .evaluate_compare import (
    Method,
    log_bias,
    Score,
    CLOSED_FRACTION,
    is_closed_path,
    score,
    compare,
    named_error,
    Failed,
    format_table,
    format_bias_sources,
)
from .evaluate_plot import plot_log, plot_path

__all__ = [
    "CLOSED_FRACTION", "GAP_FACTOR", "Failed", "HeadingErrors", "Method", "Reference", "Score", "compare",
    "find_gaps", "format_bias_sources", "format_table", "heading_errors", "improvement", "is_closed_path",
    "log_bias", "named_error", "plot_log", "plot_path", "return_orientation_error", "score", "unwrap",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

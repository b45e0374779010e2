"""Whole mode's own options (:class:`Options`: ``bias_walk``, ``min_rest``, ``bias_sigmas``,
``hdr_bound_walk``) and the checks of which mode takes what, shared by :mod:`gyrocore.wholelog`,
:mod:`gyrocore.batch` and tuning.

Units: s, rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ._checks import MAX_READING, real_number, require_choice, shown
from ._rests import MIN_REST

#: The ways to process a whole log: ``whole`` (bias from every rest, known from the first sample)
#: or ``causal`` (what a streaming :class:`gyrocore.Pipeline` gives, sample after sample).
MODES = ("whole", "causal")
#: What a warning that no bias is known says a command-line user can give.
BIAS_OPTIONS_HINT = "(on the command line: --bias-window, --bias-duration or --bias-dps)"
#: Default random walk of the bias between rests [rad/s/sqrt(s)], chosen by leave-one-log-out on
#: the real logs (docs/whole_log.md). A gyro whose rate random walk ``K`` is known
#: (:func:`gyrocore.allan.noise_parameters`) can give it as ``bias_walk=K``.
BIAS_WALK = 1e-4
#: Default walk of the bias's uncertainty that HDR's bound (``hdr_bound_sigmas``) grows with away
#: from the rests [rad/s/sqrt(s)]: how far HDR may correct, not the bias's own walk; the value
#: ``recommended`` was fitted with (docs/whole_log.md).
HDR_BOUND_WALK = 1e-3
#: The keywords whole mode takes besides the pipeline's parameters (:class:`Options`).
WHOLE_OPTIONS = ("bias_walk", "min_rest", "bias_sigmas", "hdr_bound_walk")
#: Default of :attr:`Options.bias_sigmas`, chosen by leave-one-log-out (docs/whole_log.md).
BIAS_SIGMAS = 5.0


def check_mode(mode: str) -> None:
    """Refuse a mode that is not one of :data:`MODES`."""
    require_choice("mode", mode, MODES)


def refuse_whole_options(si: dict[str, Any]) -> None:
    """Refuse, in causal mode, what only whole mode uses (:data:`WHOLE_OPTIONS`)."""
    given = [name for name in WHOLE_OPTIONS if si.get(name) is not None]
    if given:
        raise ValueError(
            f"{', '.join(given)}: used by mode='whole' only (the causal pipeline does not look for rests); "
            "leave it out or process the whole log (without --causal)"
        )


def refuse_tracking(si: dict[str, Any]) -> None:
    """Refuse, in whole mode, the core's causal rest tracker: whole mode already takes the bias
    from every rest of the log."""
    if si.get("track_rests"):
        raise ValueError(
            "track_rests follows the bias as a stream goes; whole mode already takes it from every "
            "rest of the log: leave track_rests out, or pass mode='causal' (--causal)"
        )


def untracked(si: dict[str, Any]) -> dict[str, Any]:
    """``si`` with the preset's own rest tracker off: whole mode takes the bias from the whole log,
    and the tracker, which follows it as a stream goes, gives way."""
    return {**si, "track_rests": False}


@dataclass(frozen=True)
class Options:
    """What whole mode takes besides the pipeline's parameters (keywords of :func:`gyrocore.process`).

    Attributes:
        bias_walk: the bias's random walk between rests [rad/s/sqrt(s)].
        min_rest: the shortest rest found in the log that is used [s].
        bias_sigmas: found rests whose mean is within this many standard errors of 0 leave the
            bias at 0.
        hdr_bound_walk: the walk of the bias's uncertainty that HDR's bound grows with away from
            the rests [rad/s/sqrt(s)].
    """

    bias_walk: float = BIAS_WALK
    min_rest: float = MIN_REST
    bias_sigmas: float = BIAS_SIGMAS
    hdr_bound_walk: float = HDR_BOUND_WALK

    @classmethod
    def pop(cls, si: dict[str, Any]) -> Options:
        """The options in ``si`` (removed from it), checked."""
        given = {name: si.pop(name) for name in WHOLE_OPTIONS if si.get(name) is not None}
        for name, value in given.items():  # a numpy float32 was refused as no number
            high = MAX_READING if name.endswith("_walk") else math.inf  # a rate's limit: 1e300 overflowed the smoother
            if (x := real_number(value)) is None or not (math.isfinite(x) and 0 <= x <= high):
                most = f" and at most 2^20 = {MAX_READING:.0f}" if high < math.inf else ""
                raise ValueError(f"invalid parameter {name} = {shown(value)}: must be a finite number >= 0{most}")
            given[name] = x
        for name in WHOLE_OPTIONS:
            si.pop(name, None)
        return cls(**given)

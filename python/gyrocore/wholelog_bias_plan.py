"""Whole mode's plan of a log's bias (:class:`BiasPlan`): where it comes from, the bias at each
time, the pipeline that runs the corrected readings, and the dead band and HDR bound scaled by the
rests' noise. :mod:`gyrocore.wholelog` makes the plan."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from ._arrays import FloatArray
from ._checks import collected, usable
from ._smoother import SmoothedBias
from .pipeline import HeadingResult, Pipeline, preset_params
from .rests import Rest


@dataclass(frozen=True, eq=False)
class BiasPlan:
    """Where whole mode takes the bias from, before the first sample is processed.

    Attributes:
        source: one line saying so (for reports).
        rests: every rest measured, in time order; those with ``refused`` set were not used.
        overrides: what the pipeline then runs with (``bias=0`` when the smoothed bias is
            subtracted from the rate, and the explicit dead band and HDR bound).
        smoothed: the smoothed bias, or None (a given bias, or none).
        warning: what the user should know (no rest found), or None.
    """

    source: str
    rests: tuple[Rest, ...] = ()
    overrides: dict[str, Any] = field(default_factory=dict)
    smoothed: SmoothedBias | None = None
    warning: str | None = None
    given_error: float = 0.0
    """A given rest window's standard error [rad/s]: :attr:`bias_error` where there is no ``bound``."""
    bound: SmoothedBias | None = None
    """The used rests' bias smoothed with the walk of HDR's bound (``hdr_bound_walk``), or None (a
    given rest window, or no rest)."""
    times: FloatArray | None = None
    """The log's times, over which :attr:`bias_error` is the root mean square of ``bound``'s
    standard error (None: over the rests' middles)."""

    @cached_property
    def bias_error(self) -> float:
        """The bias's standard error that HDR's bound (``hdr_bound_sigmas``) scales with, root mean
        square over the log [rad/s] (0 without rests).

        Computed on first use, by :meth:`scaled` for a configuration with that bound: over every
        sample of a long log it is about a third of whole mode's time, which a configuration
        without one does not pay. Whether there is one is known only from the parameters that
        finally run, not from the plan's preset (a tuning run plans a log once and lays each
        evaluation's fitted values over the preset's)."""
        if self.bound is None:
            return self.given_error
        variance = self.bound.variance_at(self.times) if self.times is not None else self.bound.variance
        return math.sqrt(float(np.mean(variance)))

    def bias(self, t: FloatArray) -> FloatArray | float:
        """The bias to subtract at the times ``t`` [rad/s] (0 without rests)."""
        if self.smoothed is None:
            return 0.0
        constant = self._constant()
        return self.smoothed.mean_at(t) if constant is None else constant

    def pipeline(self, preset: str) -> Pipeline:
        """The pipeline this plan runs, on the readings of :meth:`corrected`. A bias that is one
        number over the whole log goes to the core as ``bias=`` (the overrides say ``bias=0``): it
        subtracts it as the first operation on each reading, as ``rate - bias`` would (and
        ``x - 0.0`` is ``x``), with no pass over the rate and no copy of it."""
        constant = self._constant()
        if constant is None:
            return Pipeline(preset, **self.overrides)
        with collected([]):  # a bias no gyro has at rest was said of the window that measured it
            return Pipeline(preset, **{**self.overrides, "bias": constant})

    def corrected(self, t: FloatArray, rate: FloatArray) -> FloatArray:
        """The readings at the times ``t`` as :meth:`pipeline` takes them: ``rate`` less the bias
        where it varies over the log, else ``rate`` itself (none, or the core's ``bias=``)."""
        if self.smoothed is None or self._constant() is not None:
            return rate
        bias = self.smoothed.mean_at(t)
        corrected = np.subtract(rate, bias, out=bias)  # no second array as long as the log
        # a reading the core refuses (or holds, or skips) goes to it as the log has it: its error
        # names the value in the file ("rate[500] = 10000000"), not that value less a bias
        unusable = ~usable(rate)
        corrected[unusable] = rate[unusable]
        return corrected

    def _constant(self) -> float | None:
        """The bias when it is one number over the whole log (exactly one rest's mean, as
        ``bias=`` would give), else None (it varies, or there is none to subtract)."""
        if self.smoothed is None or len(self.smoothed.times) > 1:
            return None
        return float(self.smoothed.mean[0])

    @property
    def used(self) -> tuple[Rest, ...]:
        """The rests whose bias was used."""
        return tuple(r for r in self.rests if r.refused is None)

    def scaled(self, preset: str, si: dict[str, Any], params: Mapping[str, Any] | None = None) -> dict[str, float]:
        """The explicit dead band and HDR bound a noise-scaled ``preset`` with ``si`` gets on this
        log: ``threshold_sigmas`` times the used rests' pooled noise (root mean square weighted by
        readings), ``hdr_bound_sigmas`` times the smoothed bias's standard error (none without a rest).
        ``params``: ``preset_params(preset, **si)`` where the caller has it (a tuning run builds
        the preset's once and lays each evaluation's fitted values over them)."""
        used = self.used
        if not used:
            return {}
        if params is None:
            params = preset_params(preset, **si)
        out: dict[str, float] = {}
        if params.get("threshold_sigmas") is not None:
            noise = math.sqrt(float(np.average([r.noise**2 for r in used], weights=[r.samples for r in used])))
            out["threshold"] = params["threshold_sigmas"] * noise
        if params.get("hdr_bound_sigmas") is not None:
            out["hdr_max_correction"] = params["hdr_bound_sigmas"] * self.bias_error
        return out

    def with_scaled(self, preset: str, si: dict[str, Any]) -> BiasPlan:
        """This plan with :meth:`scaled`'s dead band and HDR bound among its overrides."""
        return replace(self, overrides={**self.overrides, **self.scaled(preset, si)})

    def result(self, result: HeadingResult) -> HeadingResult:
        """``result`` saying where its bias came from."""
        return replace(result, bias_source=self.source, rests=self.rests)

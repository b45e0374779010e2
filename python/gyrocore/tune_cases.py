"""The drives a method is tuned and tested on (simulated, from logs, and the "do no harm" drives of a
gyro without bias) and a parameter set's scores on them; :mod:`gyrocore.tune` re-exports the public
names."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from functools import cached_property
from typing import Any, Mapping, Sequence

import numpy as np

from . import motion, sim, wholelog
from ._arrays import FloatArray
from ._checks import check_count, check_number, require_flag
from ._rests import measure_rest
from .evaluate import HeadingErrors, Reference, log_bias
from .io import Log
from .pipeline import HeadingResult, Pipeline, uses_static_bias


#: :meth:`Case.from_reference_rate`'s regular grid holds at most this many points per reference
#: sample (memory follows the samples, not the span of their times).
MAX_GRID_PER_SAMPLE = 10


@dataclass(frozen=True, repr=False, eq=False)
class Case:
    """One drive to tune or test on: gyro samples, a reference heading and the static-bias source.

    ``bias`` holds the pipeline overrides that give the static bias (a rest window, a fixed bias or
    a leading duration); presets without a static bias ignore it.
    """

    name: str
    t: FloatArray
    rate: FloatArray
    reference: Reference
    bias: Mapping[str, Any]
    baseline: str = "raw"
    """The preset that harm is measured against (see the module doc)."""
    plan: wholelog.BiasPlan | None = None
    """Whole mode's bias of a real log (:meth:`from_log`), or None: ``bias`` alone gives it."""

    @classmethod
    def from_drive(cls, name: str, drive: sim.Drive, baseline: str = "raw") -> "Case":
        """A simulated drive: the measured rate against the true heading, bias from its rest."""
        return cls(name, drive.t, drive.rate_measured, Reference(drive.t, drive.heading_true),
                   {"bias_window": drive.stationary}, baseline)

    @classmethod
    def from_log(
        cls, log: Log, *, bias_duration: float | None = None, mode: str = "whole", use_speed: bool = True
    ) -> "Case":
        """A real log against its reference. In whole mode (the mode of ``gyrocore evaluate`` and
        :meth:`gyrocore.Log.process`) the bias is the whole log's (:mod:`gyrocore.wholelog`: its
        rest window or ``bias_duration``, else every rest found, with the odometry's speed unless
        ``use_speed`` is False), planned once here, so that every evaluation runs the pipeline alone
        and gives what ``log.process(preset, use_speed=use_speed, **overrides)`` gives. In causal
        mode, as :func:`gyrocore.evaluate.log_bias` says."""
        require_flag("use_speed", use_speed)
        t_ref, heading_ref = log.reference()
        reference = Reference(t_ref, heading_ref)
        if mode == "causal":
            bias, _ = log_bias(log, bias_duration=bias_duration)
            if log.stationary is not None:  # refused here, before the fit, as whole mode and evaluate refuse it
                with log._naming_stationary():
                    measure_rest([(log.t, log.rate)], log.stationary, "given: bias_window")
            return cls(log.name, log.t, log.rate, reference, bias)
        wholelog.check_mode(mode)
        speed = log.speed_on_gyro_times() if use_speed else None
        given = log_bias(log, bias_duration=bias_duration)[0] if log.stationary is not None or bias_duration is not None else {}
        with log._naming_stationary():
            plan = wholelog.plan_log("static_bias", given, log.t, log.rate, speed, wholelog.Options())
        return cls(log.name, log.t, log.rate, reference, {"bias": 0.0}, plan=plan)

    @classmethod
    def from_reference_rate(cls, log: Log) -> "Case":
        """The log's reference as a gyro without bias (the accuracy bar's "reference's own rate"),
        scored against the reference, with harm measured against plain integration. Its static
        bias is given as 0, as for a gyro known to have none: the reference need not be at rest
        in the log's rest window (f110_ds3's turns at -0.15 deg/s there).

        The unwrapped reference heading is interpolated onto a regular grid at its median interval
        and differenced; each rate stands at the middle of its interval. On a regular grid the
        trapezoid rule then integrates these rates back to the reference exactly, where
        derivatives at irregular reference times would not (f110_ds3's jittered times would add
        tens of degrees)."""
        t_ref, heading_ref = log.reference()
        if len(t_ref) < 2:
            raise ValueError(f"log {log.name}: a reference heading needs two samples for a rate, got {len(t_ref)}")
        step = float(np.median(np.diff(t_ref)))
        points = (t_ref[-1] - t_ref[0]) / step
        if points > MAX_GRID_PER_SAMPLE * len(t_ref):  # a jump of the clock would ask for a grid over it
            raise ValueError(
                f"log {log.name}: the reference spans {t_ref[-1] - t_ref[0]:.6g} s, {points:.3g} of its median "
                f"intervals ({step:.3g} s) for {len(t_ref)} samples: it has a gap or a jump of its clock; "
                "cut the log at it"
            )
        grid = t_ref[0] + step * np.arange(int(points) + 1)
        heading = np.interp(grid, t_ref, np.unwrap(heading_ref))
        t, rate = grid[:-1] + 0.5 * step, np.diff(heading) / step
        return cls(f"{log.name} (reference rate)", t, rate, Reference(t_ref, heading_ref), {"bias": 0.0})

    def heading(
        self, preset: str, overrides: Mapping[str, Any], params: Mapping[str, Any] | None = None
    ) -> HeadingResult:
        """The heading of this drive with ``preset`` and ``overrides``; ``params``:
        ``preset_params(preset, **overrides)`` where the caller has it (whole mode's dead band and
        HDR bound scale with them: :meth:`gyrocore.wholelog.BiasPlan.scaled`)."""
        if not uses_static_bias(preset):
            return Pipeline(preset, **overrides).process(self.t, self.rate)
        if self.plan is None:
            return Pipeline(preset, **overrides, **self.bias).process(self.t, self.rate)
        scaled = self.plan.scaled(preset, dict(overrides), params)
        return Pipeline(preset, **{**overrides, **scaled}, **self.bias).process(self.t, self._whole_rate)

    @cached_property
    def _whole_rate(self) -> FloatArray:
        """The rate less whole mode's bias (:attr:`plan`), computed once."""
        assert self.plan is not None
        return self.rate - self.plan.bias(self.t)

    def score(
        self, preset: str, overrides: Mapping[str, Any], params: Mapping[str, Any] | None = None
    ) -> HeadingErrors:
        """Heading errors of ``preset`` with ``overrides`` on this drive (``params``: see :meth:`heading`)."""
        r = self.heading(preset, overrides, params)
        return self.reference.errors(r.t, r.heading)

    @cached_property
    def _plain(self) -> dict[str, HeadingErrors]:
        return {}

    def plain(self, preset: str) -> HeadingErrors:
        """Heading errors of ``preset`` with its own parameters, computed once per preset: the
        comparisons that every score of this drive is set against."""
        if preset not in self._plain:
            self._plain[preset] = self.score(preset, {})
        return self._plain[preset]

    @property
    def raw(self) -> HeadingErrors:
        """Heading errors of plain integration."""
        return self.plain("raw")

    @property
    def baseline_errors(self) -> HeadingErrors:
        """Heading errors of the baseline that harm is measured against."""
        return self.plain(self.baseline)

    def harm_deg(self, preset: str, overrides: Mapping[str, Any]) -> float:
        """How much worse than the baseline ``preset`` makes E_psi here [deg]."""
        return self.score(preset, overrides).e_psi_deg - self.baseline_errors.e_psi_deg

    def __repr__(self) -> str:
        minutes = (self.t[-1] - self.t[0]) / 60
        return f"Case({self.name!r}, n={len(self.t)}, duration={minutes:.1f} min, bias={dict(self.bias)})"


def simulated_cases(
    drives: Sequence[motion.DriveSpec],
    *,
    rate_hz: float = 10.0,
    sensor_name: str | sim.GyroSpec = "crs03",
    first_seed: int = 0,
    time_scale: float = 1.0,
    baseline: str = "raw",
) -> list[Case]:
    """Simulated car drives (:func:`gyrocore.sim.car_drive`), one per drive spec (its road mix and
    duration, e.g. :data:`gyrocore.motion.TABLE_II_DRIVES`), seeds from ``first_seed``.

    ``time_scale`` shortens (or lengthens) every drive, for quick runs.
    """
    return [
        Case.from_drive(
            f"{d.name} (sim {d.mix}, seed {first_seed + i})",
            sim.car_drive(d.minutes * 60.0 * time_scale, rate_hz, seed=first_seed + i, mix=d.mix,
                          sensor_name=sensor_name),
            baseline,
        )
        for i, d in enumerate(drives)
    ]


#: Road mixes of the harm drives: long gentle curves, much of it below Table III's turn switch.
HARM_MIXES = ("curvy_highway", "highway", "suburbs")


def perfect_gyro(rate_hz: float) -> sim.GyroSpec:
    """A gyro without bias, drift, noise or scale error, sampling at ``rate_hz``."""
    return sim.GyroSpec(name="perfect gyro", rate_hz=rate_hz)


def unbiased_gyro(rate_hz: float) -> sim.GyroSpec:
    """The CRS03's white noise (its angle random walk and bandwidth) and nothing else: no bias,
    drift or scale error."""
    crs03 = sim.SENSORS["crs03"]
    return sim.GyroSpec(name="unbiased noisy gyro", rate_hz=rate_hz, arw_deg_per_sqrt_h=crs03.arw_deg_per_sqrt_h,
                        bandwidth_hz=min(crs03.bandwidth_hz, rate_hz))


def harm_cases(
    *,
    minutes: float = 20.0,
    rate_hz: float = 10.0,
    mixes: Sequence[str] = HARM_MIXES,
    per_mix: int = 2,
    first_seed: int = 1000,
    noisy: bool = False,
) -> list[Case]:
    """Do-no-harm drives on ``per_mix`` drives of each road mix of ``mixes`` (default: long gentle
    curves), seeds from ``first_seed``: a perfect gyro against plain integration, or, ``noisy``, an
    unbiased gyro with noise (:func:`unbiased_gyro`) against static bias removal. Each option of
    the wrong kind is refused by name (``noisy="no"`` was True, ``per_mix=-1`` no drive, ``mixes=
    "highway"`` its letters)."""
    require_flag("noisy", noisy)
    per_mix = check_count("per_mix", per_mix)
    minutes = check_number("minutes", minutes)
    if isinstance(mixes, str):
        raise TypeError(f"mixes={mixes!r}: give a sequence of road mixes, e.g. ({mixes!r},), not one string")
    gyro, baseline = (unbiased_gyro(rate_hz), "static_bias") if noisy else (perfect_gyro(rate_hz), "raw")
    return simulated_cases(
        [motion.DriveSpec(f"{gyro.name}, {mix}", minutes, mix, "do no harm") for mix in mixes for _ in range(per_mix)],
        rate_hz=rate_hz,
        sensor_name=gyro,
        first_seed=first_seed,
        baseline=baseline,
    )


# ---------------------------------------------------------------------------------------------
# Scores


@dataclass(frozen=True)
class CaseScore:
    """A parameter set's errors on one drive, with plain integration's and the harm baseline's."""

    case: str
    e_psi_deg: float
    ne_psi_deg_per_min: float
    raw_e_psi_deg: float
    baseline_e_psi_deg: float
    static_bias_e_psi_deg: float

    @property
    def harm_deg(self) -> float:
        """E_psi minus the baseline's [deg] (positive: worse than the baseline)."""
        return self.e_psi_deg - self.baseline_e_psi_deg

    def as_dict(self) -> dict[str, Any]:
        """The score as a plain dict (for JSON), with ``harm_deg``."""
        return {**asdict(self), "harm_deg": self.harm_deg}


def score_cases(
    cases: Sequence[Case], preset: str, overrides: Mapping[str, Any], params: Mapping[str, Any] | None = None
) -> tuple[CaseScore, ...]:
    """Score ``preset`` with ``overrides`` on each case (``params``: see :meth:`Case.heading`)."""
    out = []
    for c in cases:
        e = c.score(preset, overrides, params)
        out.append(CaseScore(c.name, e.e_psi_deg, e.ne_psi_deg_per_min, c.raw.e_psi_deg, c.baseline_errors.e_psi_deg,
                             c.plain("static_bias").e_psi_deg))
    return tuple(out)


def mean_ne_psi(scores: Sequence[CaseScore]) -> float:
    """The mean NE_psi [deg/min] of HDR section 5.3 (the bottom line of Table II)."""
    return float(np.mean([s.ne_psi_deg_per_min for s in scores]))


def mean_log_ratio(scores: Sequence[CaseScore]) -> float:
    """The mean over drives of log(E_psi / E_psi of static-bias removal): scale-free, so that a
    drive of 100 deg counts no more than one of 0.5 deg; negative where the method beats
    static-bias removal (the accuracy bar, on logs whose errors span 0.4-116 deg)."""
    return float(np.mean([math.log(s.e_psi_deg / s.static_bias_e_psi_deg) for s in scores]))


#: What :func:`gyrocore.tune.tune` minimises: the paper's mean NE_psi (:func:`mean_ne_psi`) or
#: the mean log ratio to static-bias removal (:func:`mean_log_ratio`).
OBJECTIVES = ("ne_psi", "log_ratio")


def harm_excess(scores: Sequence[CaseScore], limit_deg: float) -> float:
    """Sum over harm drives of how far the harm exceeds ``limit_deg`` [deg], a number >= 0 as
    :func:`gyrocore.tune.tune` takes it (a NaN limit gave 0: no harm, whatever the drives)."""
    limit_deg = check_number("limit_deg", limit_deg, strict=False, unit=" [deg]")
    return float(sum(max(0.0, s.harm_deg - limit_deg) for s in scores))

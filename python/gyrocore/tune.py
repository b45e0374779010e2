"""Fit a method's parameters over a set of training drives, as the HDR paper did by hand (section 5.3).

The objective is the mean NE_psi (HDR eq 16) over the training drives, minimised by a scipy
optimiser in log-parameter space within bounds, with a fixed seed and a bounded number of
evaluations (the Rust pipeline makes one evaluation of a 20-minute drive about a millisecond).
A "do no harm" constraint keeps the method from making a gyro without bias worse: on each harm
drive the method's E_psi may exceed its baseline's by at most ``harm_limit_deg``; every degree
beyond that costs :data:`HARM_WEIGHT` deg/min of objective. The baseline is plain integration for
a perfect gyro (no bias, drift or noise), and static bias removal for a gyro with noise but no
bias (whose rest window gives a bias estimate off by its noise, which no later stage causes).

The result is a :class:`ParameterSet`: a base preset plus SI overrides, written as a versioned JSON
preset file that ``gyrocore evaluate --params FILE`` and ``gyrocore.Pipeline(preset, **overrides)``
accept.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from . import motion, sim, wholelog
from ._arrays import FloatArray
from ._extras import require
from .evaluate import HeadingErrors, Method, Reference, log_bias
from .io import Log
from .pipeline import BIAS_SOURCES, HeadingResult, Pipeline, parameters, preset_params, uses_static_bias

#: Version of the preset-file format written by :meth:`ParameterSet.write`.
FORMAT_VERSION = 1
FORMAT_NAME = "gyrocore-params"

#: Objective cost [deg/min] per degree that a harm drive's E_psi exceeds the limit.
HARM_WEIGHT = 10.0

#: Search bounds of the tunable parameters, SI (rad/s, s, 1). Wide: from well below to well above
#: Table III (i_c 7.4e-4 rad/s, tau 0.75 s, Theta_w 9.8e-3 rad/s, c1 0.16, c2 1.8) and Hong &
#: Park's threshold (5.2e-3 rad/s).
BOUNDS: dict[str, tuple[float, float]] = {
    "hdr_increment": (1e-5, 1e-2),
    "lowpass_tau": (0.05, 10.0),
    "hdr_turn_threshold": (1e-3, 0.2),
    "hdr_c1": (1e-3, 10.0),
    "hdr_c2": (0.1, 5.0),
    "threshold": (1e-4, 0.05),
    "threshold_sigmas": (0.01, 5.0),
    "hdr_bound_sigmas": (0.1, 20.0),
    "hdr_max_correction": (1e-6, 1e-2),
}

_HDR_PARAMETERS = ("hdr_increment", "lowpass_tau", "hdr_turn_threshold", "hdr_c1", "hdr_c2")


def default_parameters(preset: str) -> tuple[str, ...]:
    """The parameters tuned by default for ``preset``: HDR's five and the threshold where used."""
    params = preset_params(preset)
    names: tuple[str, ...] = _HDR_PARAMETERS if params["hdr"] else ()
    if params["threshold"] > 0 or not params["hdr"]:
        names += ("threshold",)
    return names


# ---------------------------------------------------------------------------------------------
# Parameter sets (preset files)


def validate(preset: str, overrides: Mapping[str, Any]) -> None:
    """Raise ValueError unless the core accepts ``overrides`` on ``preset`` (it checks every value
    when a pipeline is built)."""
    Pipeline(preset, **overrides, bias=0.0)



@dataclass(frozen=True)
class ParameterSet:
    """A base preset with parameter overrides (SI names and units, see :func:`gyrocore.parameters`).

    ``Pipeline(ps.preset, **ps.overrides)`` runs it; the static bias is not part of a parameter set
    (it belongs to each log: its rest window, or a bias duration).
    """

    name: str
    preset: str
    overrides: Mapping[str, Any]
    tuning: Mapping[str, Any] = field(default_factory=dict)
    """How the set was found (training drives, scores, optimiser); informative only."""

    def __post_init__(self) -> None:
        bias = [k for k in self.overrides if k in BIAS_SOURCES or k[:-4] in BIAS_SOURCES]
        if bias:
            raise ValueError(
                f"parameter set {self.name!r}: {', '.join(bias)} cannot be part of a parameter set; "
                "the static bias comes from each log (its rest window, or a bias duration)"
            )
        validate(self.preset, self.overrides)

    def pipeline(self, **bias: Any) -> Pipeline:
        """A pipeline with these parameters; ``bias`` gives the static bias (e.g. ``bias_window=...``)."""
        return Pipeline(self.preset, **self.overrides, **bias)

    def method(self) -> Method:
        """This set as a method for :func:`gyrocore.evaluate.compare`."""
        return Method(self.name, self.preset, dict(self.overrides))

    def to_json(self) -> dict[str, Any]:
        """The preset-file content: format, version, name, preset, SI overrides, their units, tuning."""
        units = parameters()
        return {
            "format": FORMAT_NAME,
            "version": FORMAT_VERSION,
            "name": self.name,
            "preset": self.preset,
            "overrides": dict(self.overrides),
            "units": {k: units.get(k, "") for k in self.overrides},
            "tuning": dict(self.tuning),
        }

    def write(self, path: str | Path) -> None:
        """Write the preset file (JSON) atomically."""
        from .cli._common import write_atomically

        text = json.dumps(self.to_json(), indent=2) + "\n"
        write_atomically(Path(path), lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))

    @classmethod
    def read(cls, path: str | Path) -> "ParameterSet":
        """Read a preset file written by :meth:`write` (ValueError naming the file on bad content)."""
        p = Path(path)
        try:
            data = json.loads(p.read_text(encoding="utf-8"))
        except json.JSONDecodeError as e:
            raise ValueError(f"{p}: line {e.lineno} column {e.colno}: {e.msg}") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT_NAME:
            raise ValueError(f"{p}: not a gyrocore parameter file (no \"format\": \"{FORMAT_NAME}\")")
        if data.get("version") != FORMAT_VERSION:
            raise ValueError(
                f"{p}: parameter file version {data.get('version')!r}; this gyrocore reads {FORMAT_VERSION}"
            )
        missing = [k for k in ("name", "preset", "overrides") if k not in data]
        if missing:
            raise ValueError(f"{p}: missing key(s) {', '.join(missing)}")
        if not isinstance(data["overrides"], dict):
            raise ValueError(f"{p}: \"overrides\" must be an object of parameter names to SI values")
        try:
            return cls(str(data["name"]), str(data["preset"]), data["overrides"], data.get("tuning", {}))
        except (ValueError, TypeError) as e:
            raise ValueError(f"{p}: {e}") from None


# ---------------------------------------------------------------------------------------------
# Training and test drives


@dataclass(frozen=True, repr=False)
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
    def from_log(cls, log: Log, *, bias_duration: float | None = None, mode: str = "whole") -> "Case":
        """A real log against its reference. In whole mode (the mode of ``gyrocore evaluate`` and
        :meth:`gyrocore.Log.process`) the bias is the whole log's (:mod:`gyrocore.wholelog`: its
        rest window or ``bias_duration``, else every rest found, with the odometry's speed),
        planned once here, so that every evaluation runs the pipeline alone and gives what
        ``log.process(preset, **overrides)`` gives. In causal mode, as
        :func:`gyrocore.evaluate.log_bias` says."""
        t_ref, heading_ref = log.reference()
        reference = Reference(t_ref, heading_ref)
        if mode == "causal":
            bias, _ = log_bias(log, bias_duration=bias_duration)
            return cls(log.name, log.t, log.rate, reference, bias)
        wholelog.check_mode(mode)
        given = log_bias(log, bias_duration=bias_duration)[0] if log.stationary is not None or bias_duration is not None else {}
        plan = wholelog.plan_arrays("static_bias", given, log.t, log.rate, log.speed_on_gyro_times(), wholelog.Options())
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
        grid = t_ref[0] + step * np.arange(int((t_ref[-1] - t_ref[0]) / step) + 1)
        heading = np.interp(grid, t_ref, np.unwrap(heading_ref))
        t, rate = grid[:-1] + 0.5 * step, np.diff(heading) / step
        return cls(f"{log.name} (reference rate)", t, rate, Reference(t_ref, heading_ref), {"bias": 0.0})

    def heading(self, preset: str, overrides: Mapping[str, Any]) -> HeadingResult:
        """The heading of this drive with ``preset`` and ``overrides``."""
        if not uses_static_bias(preset):
            return Pipeline(preset, **overrides).process(self.t, self.rate)
        if self.plan is None:
            return Pipeline(preset, **overrides, **self.bias).process(self.t, self.rate)
        scaled = self.plan.scaled(preset, dict(overrides))
        return Pipeline(preset, **{**overrides, **scaled}, **self.bias).process(self.t, self._whole_rate)

    @cached_property
    def _whole_rate(self) -> FloatArray:
        """The rate less whole mode's bias (:attr:`plan`), computed once."""
        assert self.plan is not None
        return self.rate - self.plan.bias(self.t)

    def score(self, preset: str, overrides: Mapping[str, Any]) -> HeadingErrors:
        """Heading errors of ``preset`` with ``overrides`` on this drive."""
        r = self.heading(preset, overrides)
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
    unbiased gyro with noise (:func:`unbiased_gyro`) against static bias removal."""
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


def score_cases(cases: Sequence[Case], preset: str, overrides: Mapping[str, Any]) -> tuple[CaseScore, ...]:
    """Score ``preset`` with ``overrides`` on each case."""
    out = []
    for c in cases:
        e = c.score(preset, overrides)
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


#: What :func:`tune` minimises: the paper's mean NE_psi (:func:`mean_ne_psi`) or the mean log
#: ratio to static-bias removal (:func:`mean_log_ratio`).
OBJECTIVES = ("ne_psi", "log_ratio")


def harm_excess(scores: Sequence[CaseScore], limit_deg: float) -> float:
    """Sum over harm drives of how far the harm exceeds ``limit_deg`` [deg]."""
    return float(sum(max(0.0, s.harm_deg - limit_deg) for s in scores))


# ---------------------------------------------------------------------------------------------
# The fit


@dataclass(frozen=True)
class TuningResult:
    """What :func:`tune` found, with the scores before and after."""

    params: ParameterSet
    start: Mapping[str, float]
    """Starting values (SI)."""
    bounds: Mapping[str, tuple[float, float]]
    train_start: tuple[CaseScore, ...]
    train: tuple[CaseScore, ...]
    harm_start: tuple[CaseScore, ...]
    harm: tuple[CaseScore, ...]
    harm_limit_deg: float
    start_objective: float
    objective: float
    """Penalised objective: the mean NE_psi [deg/min] or mean log ratio (``objective``) plus HARM_WEIGHT times the harm excess."""
    evaluations: int
    optimiser: str
    seed: int

    @property
    def train_score(self) -> float:
        """Mean NE_psi over the training drives with the tuned parameters [deg/min]."""
        return mean_ne_psi(self.train)

    @property
    def harm_ok(self) -> bool:
        """Whether every harm drive stays within the limit."""
        return all(s.harm_deg <= self.harm_limit_deg for s in self.harm)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""

        return {
            "preset": self.params.preset,
            "overrides": dict(self.params.overrides),
            "start": dict(self.start),
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "start_objective": self.start_objective,
            "objective": self.objective,
            "train_score_ne_psi_deg_per_min": self.train_score,
            "train_start_score_ne_psi_deg_per_min": mean_ne_psi(self.train_start),
            "train": [c.as_dict() for c in self.train],
            "train_start": [c.as_dict() for c in self.train_start],
            "harm_limit_deg": self.harm_limit_deg,
            "harm": [c.as_dict() for c in self.harm],
            "harm_start": [c.as_dict() for c in self.harm_start],
            "harm_ok": self.harm_ok,
            "evaluations": self.evaluations,
            "optimiser": self.optimiser,
            "seed": self.seed,
        }


OPTIMISERS = ("differential_evolution", "nelder-mead")


def tune(
    cases: Sequence[Case],
    *,
    preset: str = "hdr",
    names: Sequence[str] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    start: Mapping[str, float] | None = None,
    harm: Sequence[Case] = (),
    harm_limit_deg: float = 0.5,
    fixed: Mapping[str, Any] | None = None,
    max_evaluations: int = 2000,
    seed: int = 0,
    optimiser: str = "differential_evolution",
    name: str | None = None,
    objective: str = "ne_psi",
) -> TuningResult:
    """Fit ``names`` of ``preset`` to minimise the mean NE_psi over ``cases`` (HDR section 5.3).

    Args:
        cases: training drives.
        preset: base preset (``hdr``, ``combined``, ``hong_park``, ...).
        names: parameters to fit (default :func:`default_parameters`); each must be positive.
        bounds: search range per parameter, SI (default :data:`BOUNDS`).
        start: starting values, SI (default: the preset's own, clipped into the bounds).
        harm: perfect-gyro drives for the do-no-harm constraint (see the module doc).
        harm_limit_deg: how much worse than its baseline E_psi may get on a harm drive [deg].
        fixed: overrides held at these values (SI) in every evaluation and in the result.
        max_evaluations: bound on objective evaluations (each runs every training and harm drive).
        seed: fixes the optimiser's randomness.
        optimiser: ``differential_evolution`` (global, robust to the objective's steps; the start
            is part of its first population) or ``nelder-mead`` (local, from the start).
        name: name of the parameter set (default ``<preset>_tuned``).
        objective: ``ne_psi`` (the mean NE_psi, HDR section 5.3) or ``log_ratio`` (the mean log
            ratio of E_psi to static-bias removal's: scale-free, for drives as different as real logs).
    """
    optimize = require("scipy.optimize", "tuning")

    if not cases:
        raise ValueError("no training drive given")
    if objective not in OBJECTIVES:
        raise ValueError(f"unknown objective {objective!r}: use one of {', '.join(OBJECTIVES)}")
    if optimiser not in OPTIMISERS:
        raise ValueError(f"unknown optimiser {optimiser!r}: use one of {', '.join(OPTIMISERS)}")
    if max_evaluations < 1:
        raise ValueError(f"max_evaluations must be >= 1, got {max_evaluations}")
    names = tuple(names or default_parameters(preset))
    all_bounds = {**BOUNDS, **(bounds or {})}
    unknown = [n for n in names if n not in all_bounds]
    if unknown:
        raise ValueError(f"no search bounds for {', '.join(unknown)}; give bounds={{name: (low, high)}}")
    box = {n: all_bounds[n] for n in names}
    for n, (low, high) in box.items():
        if not 0 < low < high:
            raise ValueError(f"bounds of {n} must satisfy 0 < low < high, got ({low}, {high})")
        validate(preset, {n: low})
        validate(preset, {n: high})
    fixed = dict(fixed or {})
    overlap = [n for n in names if n in fixed]
    if overlap:
        raise ValueError(f"{', '.join(overlap)} cannot be both fitted and fixed")
    validate(preset, fixed)
    base = preset_params(preset, **fixed)
    # A parameter the preset leaves unset (None) starts in the middle of its bounds.
    given = {n: (start or {}).get(n, base.get(n)) for n in names}
    start_values = {n: float(np.clip(math.sqrt(box[n][0] * box[n][1]) if v is None else v, *box[n]))
                    for n, v in given.items()}

    lo = np.log([box[n][0] for n in names])
    hi = np.log([box[n][1] for n in names])

    def overrides_of(x: np.ndarray) -> dict[str, float]:
        return {**fixed, **{n: float(math.exp(v)) for n, v in zip(names, np.clip(x, lo, hi))}}

    def objective_of(overrides: Mapping[str, float]) -> float:
        scores = score_cases(cases, preset, overrides)
        value = mean_ne_psi(scores) if objective == "ne_psi" else mean_log_ratio(scores)
        if harm:
            value += HARM_WEIGHT * harm_excess(score_cases(harm, preset, overrides), harm_limit_deg)
        return value

    evaluations = 0
    start_values = {**fixed, **start_values}
    best: tuple[float, dict[str, float]] = (math.inf, dict(start_values))

    def evaluate(x: np.ndarray) -> float:
        nonlocal evaluations, best
        evaluations += 1
        overrides = overrides_of(x)
        value = objective_of(overrides)
        if value < best[0]:
            best = (value, overrides)
        return value

    x0 = np.log([start_values[n] for n in names])
    start_objective = evaluate(x0)
    budget = max_evaluations - 1
    if budget > 0 and optimiser == "differential_evolution":
        popsize = 8  # population = popsize * len(names)
        generations = max(1, budget // (popsize * len(names)) - 1)
        optimize.differential_evolution(
            evaluate, list(zip(lo, hi)), x0=x0, seed=seed, popsize=popsize, maxiter=generations,
            polish=False, init="latinhypercube", tol=0.0, updating="immediate",
        )
    elif budget > 0:
        optimize.minimize(
            evaluate, x0, method="Nelder-Mead", bounds=list(zip(lo, hi)),
            options={"maxfev": budget, "xatol": 1e-3, "fatol": 1e-6},
        )
    objective_value, tuned = best
    train = score_cases(cases, preset, tuned)
    tuned_harm = score_cases(harm, preset, tuned)
    params = ParameterSet(
        name or f"{preset}_tuned",
        preset,
        tuned,
        {
            "objective": ("mean NE_psi [deg/min] (HDR eq 16, section 5.3)" if objective == "ne_psi"
                          else "mean log(E_psi / E_psi of static_bias)")
            + (f" + {HARM_WEIGHT} * excess over {harm_limit_deg} deg of E_psi above the baseline on "
               "do-no-harm drives" if harm else ""),
            "training": [c.name for c in cases],
            "harm_drives": [c.name for c in harm],
            "train_score_ne_psi_deg_per_min": mean_ne_psi(train),
            "harm_deg": {s.case: s.harm_deg for s in tuned_harm},
            "optimiser": optimiser,
            "seed": seed,
            "evaluations": evaluations,
            "bounds": {n: list(b) for n, b in box.items()},
        },
    )
    return TuningResult(
        params=params,
        start=start_values,
        bounds=box,
        train_start=score_cases(cases, preset, start_values),
        train=train,
        harm_start=score_cases(harm, preset, start_values),
        harm=tuned_harm,
        harm_limit_deg=harm_limit_deg,
        start_objective=start_objective,
        objective=objective_value,
        evaluations=evaluations,
        optimiser=optimiser,
        seed=seed,
    )


def leave_one_out(
    cases: Sequence[Case], *, progress: Callable[[str], None] | None = None, **options: Any
) -> tuple[CaseScore, ...]:
    """Each case scored with the parameters tuned on all the others (``options`` go to :func:`tune`).

    The mean NE_psi of the result estimates how the tuned parameters do on a drive they were not
    fitted to (the paper's test set, section 5.3).
    """
    if len(cases) < 2:
        raise ValueError("leave-one-out needs at least two training drives")
    preset = options.get("preset", "hdr")
    held_out: list[CaseScore] = []
    for i, case in enumerate(cases):
        if progress is not None:
            progress(f"leave-one-out {i + 1}/{len(cases)}: without {case.name}")
        result = tune([c for j, c in enumerate(cases) if j != i], **options)
        held_out.extend(score_cases([case], preset, result.params.overrides))
    return tuple(held_out)

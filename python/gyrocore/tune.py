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

import math
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from ._checks import check_count, check_number, check_seed, did_you_mean, public_dir, real_number, require_choice
from ._extras import require
from .pipeline import BIAS_SOURCES, parameters, preset_params
from .pipeline_params import _to_si
from .tune_cases import (
    HARM_MIXES,
    OBJECTIVES,
    Case,
    CaseScore,
    harm_cases,
    harm_excess,
    mean_log_ratio,
    mean_ne_psi,
    perfect_gyro,
    score_cases,
    simulated_cases,
    unbiased_gyro,
)
from .tune_params import FORMAT_NAME, FORMAT_VERSION, ParameterSet, validate

__all__ = [
    "BOUNDS", "FORMAT_NAME", "FORMAT_VERSION", "HARM_MIXES", "HARM_WEIGHT", "OBJECTIVES", "OPTIMISERS", "Case", "CaseScore",
    "ParameterSet", "TuningInterrupted", "TuningResult", "default_parameters", "harm_cases", "harm_excess",
    "check_leave_one_out", "leave_one_out",
    "mean_log_ratio", "mean_ne_psi", "perfect_gyro", "score_cases", "search_box", "simulated_cases", "start_point", "tune",
    "unbiased_gyro", "validate",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

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
# The fit


@dataclass(frozen=True, repr=False)
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

    def __repr__(self) -> str:
        """One line (the scores of every drive, four times over, ran to pages): what was fitted, the
        training drives' mean NE_psi before and after, and the harm; :meth:`as_dict` has the rest."""
        tuned = ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v!r}"
                          for k, v in self.params.overrides.items())
        harm = "within" if self.harm_ok else "beyond"
        return (f"TuningResult({self.params.name!r} of {self.params.preset!r}: {tuned}; mean NE_psi "
                f"{mean_ne_psi(self.train_start):.4f} -> {self.train_score:.4f} deg/min on {len(self.train)} drive(s), "
                f"harm {harm} {self.harm_limit_deg:g} deg on {len(self.harm)}; {self.evaluations} evaluations)")

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


def search_box(
    preset: str,
    names: Sequence[str] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    fixed: Mapping[str, Any] | None = None,
) -> dict[str, tuple[float, float]]:
    """The search range of each parameter :func:`tune` fits (``names``, default
    :func:`default_parameters`), checked with the ``fixed`` ones before any drive is scored (the
    command line checks them before it builds its drives): a ValueError for a name that is no
    parameter, a static bias (each drive's own), a parameter without bounds or with bounds that are
    not ``0 < low < high``, one that takes no number, or one both fitted and fixed."""
    if names is not None and (isinstance(names, str) or not isinstance(names, Iterable)):  # its letters were names
        kind = type(names).__name__
        raise TypeError(f"names={names!r}: give a sequence of parameter names, e.g. ('hdr_c1',), not {kind}")
    _require_mapping("bounds", bounds)
    _require_mapping("fixed", fixed)
    by_default = not names  # the preset's own: a fixed one among them was never asked to be fitted
    names = tuple(names or default_parameters(preset))
    fixed = dict(fixed or {})
    known, given = parameters(), (*names, *_to_si(fixed))  # a fixed one may be spelled *_dps or *_deg
    unknown = [n for n in given if n not in known]
    if unknown:
        said = ", ".join(f"{n}{did_you_mean(n, known)}" for n in unknown)
        raise ValueError(f"unknown parameter(s) {said}; the pipeline's are {', '.join(known)}")
    bias = [n for n in given if n in BIAS_SOURCES]
    if bias:
        raise ValueError(f"{', '.join(bias)}: the static bias comes from each drive (its rest window, or a bias "
                         "duration: --bias-duration); it is neither fitted nor fixed")
    for n in names:
        try:
            validate(preset, {n: 1.0})
        except TypeError as e:  # a switch or a choice: tune searches numbers > 0
            raise ValueError(f"{n} cannot be fitted, it takes no number ({e})") from None
        except ValueError:  # a number out of its range here: the bounds are checked below
            pass
    all_bounds = {**BOUNDS, **_given_bounds(bounds, names)}
    unbounded = [n for n in names if n not in all_bounds]
    if unbounded:
        raise ValueError(f"no search bounds for {', '.join(unbounded)}; give them, e.g. "
                         f"bounds={{{unbounded[0]!r}: (low, high)}} (--param {unbounded[0]}=LOW:HIGH), in SI units")
    box = {n: all_bounds[n] for n in names}
    for n, (low, high) in box.items():
        if not 0 < low < high:
            raise ValueError(f"bounds of {n} must satisfy 0 < low < high, got ({low}, {high})")
        validate(preset, {n: low})
        validate(preset, {n: high})
    overlap = [n for n in names if n in _to_si(fixed)]  # hdr_increment_dps fixes hdr_increment
    if overlap:
        why = (f": {preset}'s fit takes {', '.join(names)} unless told; name the parameters to fit without it "
               "(--param NAME, names=)" if by_default else "")
        raise ValueError(f"{', '.join(overlap)} cannot be both fitted and fixed{why}")
    validate(preset, fixed)
    return box


def _require_mapping(what: str, value: object) -> None:
    """A TypeError unless ``value`` is None or a dict (a list failed in ``dict()``'s words,
    "dictionary update sequence element #0 has length 6; 2 is required")."""
    if value is not None and not isinstance(value, Mapping):
        raise TypeError(f"{what} must be a dict of parameter names and values, got {value!r}")


def _given_bounds(bounds: Mapping[str, Any] | None, names: tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """``bounds``, each of a parameter fitted (a typo was ignored, and the fit searched the default
    range) and two numbers (``5`` or ``("a", "b")`` failed in Python's unpacking or comparison)."""
    given = dict(bounds or {})
    stray = [n for n in given if n not in names]
    if stray:
        said = ", ".join(f"{n}{did_you_mean(n, names)}" for n in stray)
        raise ValueError(f"bounds given for {said}, which is not fitted; the parameters fitted are {', '.join(names)} "
                         "(names=)")
    checked = {}
    for n, pair in given.items():
        values = [real_number(v) for v in pair] if isinstance(pair, (tuple, list, np.ndarray)) else []
        if len(values) != 2 or values[0] is None or values[1] is None:
            raise TypeError(f"bounds of {n} must be two numbers (low, high), got {pair!r}")
        checked[n] = (values[0], values[1])
    return checked


def _require_cases(what: str, cases: object) -> None:
    """A TypeError for one :class:`Case` where a list of them is asked for (it failed as "'Case'
    object is not iterable")."""
    if isinstance(cases, Case):
        raise TypeError(f"{what}: give a list of cases, not one Case ([case])")


def start_point(
    preset: str, box: Mapping[str, tuple[float, float]], fixed: Mapping[str, Any] | None = None,
    start: Mapping[str, float] | None = None,
) -> tuple[dict[str, Any], dict[str, float]]:
    """The preset's parameters with ``fixed`` laid over them, and the values the fit of ``box``
    (:func:`search_box`) starts from (see :func:`_start_point`), checked as one pipeline before
    any drive is run: a switch that the fitted parameters need and ``fixed`` turns off (``hdr``
    False with HDR's parameters fitted) failed at the first evaluation."""
    fixed = _to_si(dict(fixed or {}))
    base = preset_params(preset, **fixed)
    values = _start_point(box, start, base)
    preset_params(preset, **fixed, **values)
    return base, values


def _start_point(
    box: Mapping[str, tuple[float, float]], start: Mapping[str, float] | None, base: Mapping[str, Any]
) -> dict[str, float]:
    """The values :func:`tune` starts from: ``start``'s, else the preset's (``base``), else the
    middle of the bounds (a parameter the preset leaves unset). A ``start`` name that is not fitted
    (a typo was ignored, and the fit started from the preset's value) and a value outside its
    bounds (clipped into them without a word) are refused."""
    _require_mapping("start", start)
    start = dict(start or {})
    unknown = [n for n in start if n not in box]
    if unknown:
        said = ", ".join(f"{n}{did_you_mean(n, box)}" for n in unknown)
        raise ValueError(f"unknown start value(s) {said}; the parameters fitted are {', '.join(box)}")
    values = {}
    for n, (low, high) in box.items():
        if n in start:
            values[n] = check_number(f"start[{n!r}]", start[n], low=low, strict=False, high=high,
                                     unit=" (its search bounds)")
        else:
            v = base.get(n)
            values[n] = float(np.clip(math.sqrt(low * high) if v is None else v, low, high))
    return values


class TuningInterrupted(KeyboardInterrupt):
    """Ctrl-C during a fit (:func:`tune`, :func:`leave_one_out`). Its text says how far the fit had
    come and the best parameters it had found (SI), which the interrupt lost without a word after
    minutes of fitting; ``best`` holds them (empty where there are none to keep: a fold of the
    leave-one-out), ``what`` the text before them."""

    def __init__(self, what: str, best: Mapping[str, float]) -> None:
        values = ", ".join(f"{k}={v!r}" for k, v in best.items())
        super().__init__(f"{what}: {values}" if values else what)
        self.what = what
        self.best = dict(best)


class _BudgetSpent(Exception):
    """Raised by an evaluation beyond ``max_evaluations``: it ends the optimiser, whose own limits
    count generations (a population of 8 per parameter, evaluated whole, and at least one generation
    more: ``--max-evals 3`` ran 81 evaluations of HDR's five parameters)."""


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
        max_evaluations: the most objective evaluations (each runs every training and harm drive),
            the start's among them.
        seed: fixes the optimiser's randomness.
        optimiser: ``differential_evolution`` (global, robust to the objective's steps; the start
            is part of its first population) or ``nelder-mead`` (local, from the start).
        name: name of the parameter set (default ``<preset>_tuned``).
        objective: ``ne_psi`` (the mean NE_psi, HDR section 5.3) or ``log_ratio`` (the mean log
            ratio of E_psi to static-bias removal's: scale-free, for drives as different as real logs).
    """
    optimize = require("scipy.optimize", "tuning")

    _require_cases("cases", cases)
    if not cases:
        raise ValueError("no training drive given")
    _require_cases("harm", harm)
    require_choice("objective", objective, OBJECTIVES)
    require_choice("optimiser", optimiser, OPTIMISERS)
    # checked before the fit, in the package's words; scipy's generator takes a 32-bit seed
    max_evaluations = check_count("max_evaluations", max_evaluations)
    seed = check_seed(seed, bits=32)
    harm_limit_deg = check_number("harm_limit_deg", harm_limit_deg, strict=False, unit=" [deg]")
    box = search_box(preset, names, bounds, fixed)
    name = ParameterSet(name or f"{preset}_tuned", preset, {}).name  # a name the file cannot hold fails before the fit
    names, fixed = tuple(box), _to_si(dict(fixed or {}))  # a parameter file holds SI names, with their units
    base, start_values = start_point(preset, box, fixed, start)

    lo = np.log([box[n][0] for n in names])
    hi = np.log([box[n][1] for n in names])

    def overrides_of(x: np.ndarray) -> dict[str, float]:
        return {**fixed, **{n: float(math.exp(v)) for n, v in zip(names, np.clip(x, lo, hi))}}

    def objective_of(overrides: Mapping[str, float]) -> float:
        # The preset's parameters with the fixed ones were built and checked once, above; an
        # evaluation lays its fitted values over them (each pipeline checks its own as it is built).
        params = {**base, **_to_si({n: overrides[n] for n in names})}
        scores = score_cases(cases, preset, overrides, params)
        value = mean_ne_psi(scores) if objective == "ne_psi" else mean_log_ratio(scores)
        if harm:
            value += HARM_WEIGHT * harm_excess(score_cases(harm, preset, overrides, params), harm_limit_deg)
        return value

    evaluations = 0
    start_values = {**fixed, **start_values}
    best: tuple[float, dict[str, float]] = (math.inf, dict(start_values))

    def evaluate(x: np.ndarray) -> float:
        nonlocal evaluations, best
        if evaluations == max_evaluations:
            raise _BudgetSpent
        overrides = overrides_of(x)
        value = objective_of(overrides)
        evaluations += 1  # one that ended: an interrupt in it counts it not
        if value < best[0]:
            best = (value, overrides)
        return value

    x0 = np.log([start_values[n] for n in names])
    start_objective = evaluate(x0)
    budget = max_evaluations - 1
    try:
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
    except _BudgetSpent:  # the best so far is the result
        pass
    except KeyboardInterrupt:
        raise TuningInterrupted(
            f"the fit had run {evaluations} of {max_evaluations} evaluations; the best found (objective "
            f"{best[0]:.6g}, the start's {start_objective:.6g})", {n: best[1][n] for n in names}
        ) from None
    objective_value, tuned = best
    train = score_cases(cases, preset, tuned)
    tuned_harm = score_cases(harm, preset, tuned)
    params = ParameterSet(
        name,
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


def check_leave_one_out(cases: Sequence[Case]) -> None:
    """Refuse fewer than two drives for :func:`leave_one_out`, which fits once without each; the
    command line asks before its main fit, which takes minutes (it failed only after it)."""
    if len(cases) < 2:
        raise ValueError(f"leave-one-out needs at least two training drives, got {len(cases)}: it fits once "
                         "without each drive and scores that drive")


def leave_one_out(
    cases: Sequence[Case], *, progress: Callable[[str], None] | None = None, **options: Any
) -> tuple[CaseScore, ...]:
    """Each case scored with the parameters tuned on all the others (``options`` go to :func:`tune`).

    The mean NE_psi of the result estimates how the tuned parameters do on a drive they were not
    fitted to (the paper's test set, section 5.3).
    """
    check_leave_one_out(cases)
    preset = options.get("preset", "hdr")
    held_out: list[CaseScore] = []
    for i, case in enumerate(cases):
        if progress is not None:
            progress(f"leave-one-out {i + 1}/{len(cases)}: without {case.name}")
        try:
            result = tune([c for j, c in enumerate(cases) if j != i], **options)
        except KeyboardInterrupt:  # how far it came; a fold's best is no held-out score
            raise TuningInterrupted(f"leave-one-out had scored {i} of {len(cases)} drive(s), and was fitting without "
                                    f"{case.name}", {}) from None
        held_out.extend(score_cases([case], preset, result.params.overrides))
    return tuple(held_out)

"""Borenstein's FOG paper: scale factor against temperature on a rotary table (section 3, eq 5-6,
Figures 3 and 6) and return orientation errors of the bi-directional square path (section 4.1)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import calibration, evaluate, motion, sim
from .._arrays import FloatArray
from ..integration import integrate
from ..pipeline import process
from ._report import Row, _Report


def _paper_band(ax: Any, bound: float) -> None:
    """The paper's +-``bound`` [deg] on an error plot."""
    for level in (-bound, bound):
        ax.axhline(level, color="r", ls=":")


def _eq6_corrected(d: sim.Drive, cal: calibration.Calibration) -> FloatArray:
    """The reading scaled by FOG eq 6 (and the direction factors of eq 2-4) at each sample's
    temperature, by the pipeline's correction stage, before any static bias is taken out."""
    overrides: dict[str, Any] = {k: v for k, v in cal.overrides(include_bias=False).items() if k != "bias"}
    corrected: FloatArray = process(d.t, d.rate_measured, "raw", temperature=d.temperature, **overrides).output("rate")
    return corrected


@dataclass(frozen=True, repr=False, eq=False)
class FogRotaryTable(_Report):
    """FOG section 3: turn errors of 360-degree table turns against temperature (eq 1 and 5, Figure
    3) from one warm-up session, and the turn errors of another session after the correction of
    eq 6 (Figure 6).

    Attributes:
        fit: the calibration session's :class:`gyrocore.calibration.RotaryTable` (eq 5 fit).
        corrected: the test session's turns after eq 6 (each with its own 20 s static bias test).
        spec: the simulated FOG.
    """

    fit: calibration.RotaryTable
    corrected: calibration.RotaryTable
    spec: sim.GyroSpec
    title: str = "FOG section 3: rotary-table scale factor against temperature, and turn errors after eq 6"

    def slope_deg_per_c(self) -> float:
        """Fitted ``E_T`` slope [deg/degC] (FOG eq 5: -0.52)."""
        assert self.fit.temperature_fit is not None
        return math.degrees(self.fit.temperature_fit[0])

    def offset_deg(self) -> float:
        """Fitted ``E_T`` at 0 degC [deg] (FOG eq 5: 19.23)."""
        assert self.fit.temperature_fit is not None
        return math.degrees(self.fit.temperature_fit[1])

    def corrected_errors_deg(self) -> FloatArray:
        """Turn errors after eq 6 [deg]."""
        return np.array([t.error_deg for t in self.corrected.turns])

    def rows(self) -> list[Row]:
        before = np.array([t.error_deg for t in self.fit.turns])
        after = self.corrected_errors_deg()
        temps = [t.temperature for t in self.fit.turns if t.temperature is not None]
        return [
            Row("turns (cw + ccw) per session", "-", f"{len(self.fit.turns)}", ""),
            Row("temperature span", "-", f"{min(temps):.1f} .. {max(temps):.1f}", "degC"),
            Row("turn error before correction", "-", f"{before.min():.2f} .. {before.max():.2f}", "deg"),
            Row("eq 5 slope", "-0.52", self.slope_deg_per_c(), "deg/degC"),
            Row("eq 5 offset", "19.23", self.offset_deg(), "deg"),
            Row("eq 5 fit residual rms", "-", math.degrees(self.fit.temperature_fit[2]) if self.fit.temperature_fit else math.nan, "deg"),
            Row("after eq 6: largest |error|", "< 0.25", float(np.abs(after).max()), "deg"),
            Row("after eq 6: share within +-0.2 deg", "typically", f"{100 * np.mean(np.abs(after) < 0.2):.1f} %", ""),
        ]

    def notes(self) -> tuple[str, ...]:
        return (
            "FOG preset at 100 Hz warming from 22 to 42 degC (time constant 40 min); its scale error is "
            "the paper's eq 5 (so the fit should find -0.52 and 19.23); runs of 20 s static bias test, a cw "
            "and a ccw 360 deg turn at 30 deg/s (48 s per run, as in the paper)",
            "calibrated on one warm-up session (gyrocore.calibration.rotary_table), tested on another",
        )

    def _figure(self, plt: Any) -> Any:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
        for direction, marker in (("cw", "o"), ("ccw", "s")):
            turns = [t for t in self.fit.turns if t.direction == direction]
            a1.plot([t.temperature for t in turns], [t.error_deg for t in turns], marker, ms=3, ls="", label=f"E_{direction}")
        temps = np.array([t.temperature for t in self.fit.turns])
        span = np.linspace(temps.min(), temps.max(), 2)
        a1.plot(span, self.slope_deg_per_c() * span + self.offset_deg(), "k", label="fit (eq 5)")
        a1.plot(span, -0.52 * span + 19.23, "r--", label="paper: -0.52 T + 19.23")
        a1.set(xlabel="temperature [degC]", ylabel="turn error [deg]", title="FOG Figure 3 (simulated)")
        a1.legend(fontsize=8)
        for direction, marker in (("cw", "o-"), ("ccw", "s-")):
            errs = [t.error_deg for t in self.corrected.turns if t.direction == direction]
            a2.plot(np.arange(1, len(errs) + 1), errs, marker, ms=3, lw=0.5, label=direction)
        _paper_band(a2, 0.25)
        a2.set(xlabel="run", ylabel="turn error after eq 6 [deg]", title="FOG Figure 6 (simulated)")
        a2.legend(fontsize=8)
        fig.tight_layout()
        return fig


def _rotary_session(runs: int, seed: int) -> sim.Drive:
    return sim.simulate(motion.rotary_table(runs=runs), "fog", seed=seed)


def fog_rotary_table(*, runs: int = 150, seed: int = 0) -> FogRotaryTable:
    """FOG section 3: two warm-up sessions of ``runs`` table runs each (seeds ``seed`` and
    ``seed + 1``); the first calibrates eq 5 (:func:`gyrocore.calibration.rotary_table` with the
    temperature), the second is corrected by eq 6 and its turns measured again."""
    first = _rotary_session(runs, seed)
    fit = calibration.rotary_table(first.t, first.rate_measured, temperature=first.temperature)
    second = _rotary_session(runs, seed + 1)
    corrected = calibration.rotary_table(second.t, _eq6_corrected(second, fit.calibration))
    return FogRotaryTable(fit, corrected, first.sensor)


@dataclass(frozen=True, repr=False, eq=False)
class FogSquarePath(_Report):
    """FOG section 4.1: return orientation errors ``E_g`` of the bi-directional 4x4 m square path,
    each lap after its own 20 s static bias test, with the eq 6 correction of a rotary-table
    calibration and without it.

    Attributes: ``cw``, ``ccw``: E_g per lap with eq 6 [deg]; ``cw_raw``, ``ccw_raw``: with the
    static bias only [deg]; ``calibration``: the eq 6 calibration used.
    """

    cw: FloatArray
    ccw: FloatArray
    cw_raw: FloatArray
    ccw_raw: FloatArray
    calibration: calibration.Calibration
    title: str = "FOG section 4.1: return orientation error on the 4x4 m bi-directional square path"

    def largest(self) -> float:
        """Largest |E_g| with eq 6 [deg] (the paper: within +-1 deg)."""
        return float(max(np.abs(self.cw).max(), np.abs(self.ccw).max()))

    def rows(self) -> list[Row]:
        return [
            Row("runs (cw lap + ccw lap)", "40", f"{len(self.cw)}", ""),
            Row("E_g with eq 6: largest |E_g|", "within +-1", self.largest(), "deg"),
            Row("E_g with eq 6: mean cw / ccw", "-", f"{self.cw.mean():.3f} / {self.ccw.mean():.3f}", "deg"),
            Row("E_g with eq 6: rms", "-", float(np.sqrt(np.mean(np.r_[self.cw, self.ccw] ** 2))), "deg"),
            Row("E_g without eq 6: mean cw / ccw", "-", f"{self.cw_raw.mean():.2f} / {self.ccw_raw.mean():.2f}", "deg"),
        ]

    def notes(self) -> tuple[str, ...]:
        return (
            "FOG preset at 100 Hz warming from 22 to 42 degC; laps of 64 s (0.4 m/s sides, 30 deg/s turns), "
            "each after a 20 s static bias test; eq 6 from a rotary-table session (fog_rotary_table's first)",
            "the gyro alone: the paper's +-1 deg (Figure 5) also holds its reference's +-0.2 deg and a "
            "real robot's vibration; the simulation has neither",
        )

    def _figure(self, plt: Any) -> Any:
        fig, ax = plt.subplots(figsize=(8, 4.5))
        runs = np.arange(1, len(self.cw) + 1)
        ax.plot(runs, self.cw, "o-", ms=3, lw=0.6, label="E_g cw (eq 6)")
        ax.plot(runs, self.ccw, "s-", ms=3, lw=0.6, label="E_g ccw (eq 6)")
        ax.plot(runs, self.cw_raw, "o:", ms=2, lw=0.5, color="0.5", label="cw, static bias only")
        ax.plot(runs, self.ccw_raw, "s:", ms=2, lw=0.5, color="0.3", label="ccw, static bias only")
        _paper_band(ax, 1.0)
        ax.set(xlabel="run", ylabel="return orientation error [deg]", title="FOG Figure 5 (simulated, gyro only)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        return fig


def fog_square_path(*, runs: int = 40, seed: int = 0, calibration_runs: int = 150) -> FogSquarePath:
    """FOG section 4.1: ``runs`` runs of :func:`gyrocore.motion.square_path` with the FOG preset
    (seed ``seed + 2``); eq 6 from a rotary-table session of ``calibration_runs`` runs (seed
    ``seed``). Each lap's rotation is the integral of the reading minus the mean of its 20 s test."""
    table = _rotary_session(calibration_runs, seed)
    cal = calibration.rotary_table(table.t, table.rate_measured, temperature=table.temperature).calibration
    route = motion.square_path(runs=runs)
    d = sim.simulate(route, "fog", seed=seed + 2)
    rests = route.segments_of("rest")
    errors: dict[str, list[float]] = {"cw": [], "ccw": [], "cw_raw": [], "ccw_raw": []}
    for rate, suffix in ((_eq6_corrected(d, cal), ""), (d.rate_measured, "_raw")):
        for direction in ("cw", "ccw"):
            for lap in route.segments_of(f"lap_{direction}"):
                test = [r for r in rests if r.end <= lap.start][-1]
                bias = calibration.static_bias(d.t, rate, (test.start, test.end)).bias
                inside = (d.t >= test.end) & (d.t <= lap.end + 1.0)
                heading = integrate(d.t[inside], rate[inside] - bias)
                e = evaluate.return_orientation_error(d.t[inside], heading, t_start=lap.start, t_end=lap.end,
                                                      rotation=lap.angle)
                errors[direction + suffix].append(math.degrees(e))
    cw, ccw, cw_raw, ccw_raw = (np.array(errors[k]) for k in ("cw", "ccw", "cw_raw", "ccw_raw"))
    return FogSquarePath(cw, ccw, cw_raw, ccw_raw, cal)

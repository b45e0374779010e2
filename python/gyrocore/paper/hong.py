"""Hong & Park: the XV3500's Allan deviation (section 2.1), least squares with a rate and a heading
reference (section 3.1) and Table 1 (pure integration, self-calibration, threshold filter, both).

Sections 2.1 and 3.1 are in :mod:`.hong_sensor`; Table 1 and its sensitivity here; every public
name is here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import calibration, deadband, evaluate, motion, sim
from .._arrays import FloatArray
from ..integration import downsample
from ..pipeline import preset_params, process
from ._report import Row, _Report, format_table
from .hong_sensor import HONG_B, HONG_S, AllanReproduction, HongCalibration, reference_track, hong_allan, hong_calibration

__all__ = [
    "HONG_B", "HONG_S", "AllanReproduction", "HongCalibration", "HongTable1", "HongTable1Sensitivity", "hong_allan",
    "hong_calibration", "hong_table_1", "hong_table_1_sensitivity",
]


@dataclass(frozen=True, repr=False, eq=False)
class HongTable1(_Report):
    """Hong Table 1 on simulated robot runs: mean and standard deviation of the absolute heading
    error of each method [deg], against the 20 Hz reference over the whole run, averaged over
    independent runs (the paper reports one run; one simulated run varies a lot with its seed).

    Attributes:
        spec: the simulated gyro; turn_deg: the size of the robot run's turns [deg].
        errors: method -> the :class:`gyrocore.evaluate.HeadingErrors` of each run.
        calibrations: the self-calibration of each run (Hong eq 8-9 over the calibration motion).
        t_ref, heading_ref: the reference of the first run; headings: method -> (t, heading) of
            the first run, for the figure.
    """

    spec: sim.GyroSpec
    turn_deg: float
    errors: dict[str, tuple[evaluate.HeadingErrors, ...]]
    calibrations: tuple[calibration.Calibration, ...]
    t_ref: FloatArray
    heading_ref: FloatArray
    headings: dict[str, tuple[FloatArray, FloatArray]]
    title: str = "Hong & Park Table 1: mean heading error of each method on simulated robot runs"

    #: The paper's Table 1 [deg]: (mean, standard deviation).
    PAPER = {
        "pure integration": (1.6675, 1.5075),
        "self-calibration": (1.1511, 1.1675),
        "threshold filter": (0.7768, 1.2653),
        "proposed": (0.5985, 1.2998),
    }

    def mean_error(self, method: str) -> float:
        """Mean absolute heading error [deg], averaged over the runs."""
        return float(np.mean([e.mean_error_deg for e in self.errors[method]]))

    def std_error(self, method: str) -> float:
        """Standard deviation of the absolute heading error [deg], averaged over the runs."""
        return float(np.mean([e.std_error_deg for e in self.errors[method]]))

    def ordering(self) -> list[str]:
        """The methods from the largest mean error to the smallest (the paper: the order of PAPER)."""
        return sorted(self.PAPER, key=self.mean_error, reverse=True)

    def rows(self) -> list[Row]:
        rows = []
        for method, (mean, std) in self.PAPER.items():
            rows.append(Row(f"{method}: mean error", f"{mean:.4f}", self.mean_error(method), "deg"))
            rows.append(Row(f"{method}: standard deviation", f"{std:.4f}", self.std_error(method), "deg"))
        s = np.mean([c.scale_error for c in self.calibrations])
        b = np.mean([c.bias for c in self.calibrations])
        rows.append(Row("self-calibration: s, b", "3.73 %, 0.75 deg/s", f"{100 * s:.3g} %, {math.degrees(b):.3g} deg/s", ""))
        short = {"pure integration": "pure", "self-calibration": "cal", "threshold filter": "thr", "proposed": "both"}
        rows.append(Row("mean errors, largest first", " > ".join(short[m] for m in self.PAPER),
                        " > ".join(short[m] for m in self.ordering())))
        return rows

    def notes(self) -> tuple[str, ...]:
        noise, threshold = self.spec.noise_rms_dps, _hong_threshold_dps()
        return (
            f"mean over {len(self.calibrations)} simulated runs: {self.spec.name} at {self.spec.rate_hz:g} Hz "
            f"(true s = {100 * self.spec.scale_error:.3g} %, b = {self.spec.bias_dps:g} deg/s), 20 Hz reference, "
            f"gyrocore.motion.robot_run with {self.turn_deg:g}-degree turns (the paper's trajectory is not given)",
            "pure integration and threshold subtract the static bias of the 5 s at power-up (the paper "
            "does not say how its pure integration handled the bias); self-calibration fits Hong eq 8-9 "
            "over the calibration motion (5-20 s) and applies Hong eq 3",
            f"the noise in one sample is {noise:.2f} deg/s rms (the XV3500's: 0.31, from its ARW and Figure 8a's "
            f"2 deg/s peak-to-peak) against the {threshold:.2f} deg/s threshold, which therefore lets "
            f"{100 * deadband.bias_leak(noise, threshold):.0f} % of a residual bias through "
            "(gyrocore.deadband.bias_leak; hong_table_1_sensitivity varies the noise and the turns)",
        )

    def _figure(self, plt: Any) -> Any:
        fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
        a1.plot(self.t_ref, np.degrees(self.heading_ref), "k", lw=2, label="reference")
        for method, (t, h) in self.headings.items():
            a1.plot(t, np.degrees(h), lw=1, label=method)
            ref = np.interp(t, self.t_ref, self.heading_ref)
            a2.plot(t, np.degrees(h - ref), lw=1, label=method)
        a1.set(ylabel="heading [deg]", title="Hong & Park Figure 10 (simulated)")
        a1.legend(fontsize=8)
        a2.set(ylabel="error [deg]", xlabel="t [s]")
        fig.tight_layout()
        return fig


def _hong_threshold_dps() -> float:
    """Hong eq 12's threshold of the ``hong_park`` preset [deg/s]."""
    return math.degrees(preset_params("hong_park")["threshold"])


def _interval_fit(
    d: sim.Drive, t_ref: FloatArray, heading_ref: FloatArray, window: tuple[float, float]
) -> calibration.Calibration:
    """Hong eq 8-9 with a reference at a lower rate than the gyro: over each reference interval
    in ``window``, the reference's mean rate (its heading change over the interval's length)
    against the gyro's mean reading (block means, HDR's second eq 14), so every gyro sample
    counts."""
    inside = (t_ref >= window[0] - 1e-9) & (t_ref <= window[1] + 1e-9)
    tr, hr = t_ref[inside], heading_ref[inside]
    interval = float(tr[1] - tr[0])
    gyro = (d.t >= tr[0] - 1e-9) & (d.t <= tr[-1] + 1e-9)
    _, mean_reading = downsample(d.t[gyro] - tr[0], d.rate_measured[gyro], interval)
    mean_rate = np.diff(hr) / np.diff(tr)
    n = min(len(mean_reading), len(mean_rate))
    return calibration.rate_reference(mean_reading[:n], mean_rate[:n])


def hong_table_1(
    *, seed: int = 0, runs: int = 10, sensor: str | sim.GyroSpec = "xv3500", turn_deg: float = 90.0
) -> HongTable1:
    """Hong Table 1: the XV3500 (or ``sensor``) on :func:`gyrocore.motion.robot_run` (with turns
    of ``turn_deg``) at 100 Hz, a 20 Hz reference, ``runs`` runs with seeds ``seed``, ``seed + 1``, ...

    - pure integration: static bias of the power-up rest (0-5 s) removed, then integrated;
    - self-calibration: ``s`` and ``b`` from Hong eq 8-9 over the calibration motion (the gyro's
      mean over each 50 ms reference interval against the reference's mean rate), applied as
      Hong eq 3;
    - threshold filter: the static bias removed, then Hong eq 12 (0.3 deg/s);
    - proposed: self-calibration and the threshold filter.
    """
    if runs < 1:
        raise ValueError(f"runs must be >= 1, got {runs}")
    spec = sim.sensor(sensor)
    route = motion.robot_run(turn_deg=turn_deg)
    rest = route.segments_of("rest")[0]
    window = route.segments_of("calibration")[0]
    t_ref, heading_ref, _ = reference_track(route, 20.0, 0.0, route.duration)
    static: dict[str, Any] = {"bias_window": (rest.start, rest.end)}
    errors: dict[str, list[evaluate.HeadingErrors]] = {m: [] for m in HongTable1.PAPER}
    calibrations, headings = [], {}
    for k in range(runs):
        d = sim.simulate(route, spec, seed=seed + k)
        cal = _interval_fit(d, t_ref, heading_ref, (window.start, window.end))
        calibrations.append(cal)
        methods: dict[str, tuple[str, dict[str, Any]]] = {
            "pure integration": ("static_bias", static),
            "self-calibration": ("static_bias", cal.overrides()),
            "threshold filter": ("hong_park", static),
            "proposed": ("hong_park", cal.overrides()),
        }
        for method, (preset, overrides) in methods.items():
            result = process(d.t, d.rate_measured, preset, mode="causal", **overrides)  # the paper's real-time system
            errors[method].append(evaluate.heading_errors(d.t, result.heading, t_ref, heading_ref))
            if k == 0:
                headings[method] = (d.t, result.heading)
    return HongTable1(
        spec, turn_deg, {m: tuple(e) for m, e in errors.items()}, tuple(calibrations), t_ref, heading_ref, headings
    )


@dataclass(frozen=True, repr=False, eq=False)
class HongTable1Sensitivity(_Report):
    """Hong Table 1 over a grid of two things the paper gives only as a plot (the gyro's noise in
    one sample: Figure 8a) or not at all (the size of the robot's turns); the noise is set by the
    noise bandwidth at the sensor's ARW.

    The threshold filter removes a residual bias only where the noise is well below the threshold
    (:func:`gyrocore.deadband.bias_leak`); self-calibration removes the scale error, which costs
    more the larger the turns. The paper's order (self-calibration behind the threshold filter)
    needs both a quiet gyro and small turns.

    Attributes:
        spec: the sensor, before its bandwidth is changed.
        threshold_dps: Hong eq 12's threshold of the ``hong_park`` preset [deg/s].
        tables: (turn [deg], noise bandwidth [Hz]) -> the :class:`HongTable1` of that cell.
    """

    spec: sim.GyroSpec
    threshold_dps: float
    tables: dict[tuple[float, float], HongTable1]
    title: str = "Hong & Park Table 1, sensitivity: mean error / pure integration's, by gyro noise and turn size"

    #: The paper's ratios to pure integration (Table 1): threshold filter, self-calibration.
    PAPER_RATIOS = (0.7768 / 1.6675, 1.1511 / 1.6675)

    @property
    def turns_deg(self) -> list[float]:
        return sorted({turn for turn, _ in self.tables}, reverse=True)

    @property
    def bandwidths_hz(self) -> list[float]:
        return sorted({bandwidth for _, bandwidth in self.tables}, reverse=True)

    def noise_rms_dps(self, bandwidth_hz: float) -> float:
        """The rms of the noise in one sample at this bandwidth [deg/s]."""
        return self.spec.replace(bandwidth_hz=bandwidth_hz).noise_rms_dps

    def leak(self, bandwidth_hz: float) -> float:
        """The fraction of a small residual bias that the threshold lets through at this bandwidth."""
        return deadband.bias_leak(self.noise_rms_dps(bandwidth_hz), self.threshold_dps)

    def ratio(self, method: str, turn_deg: float, bandwidth_hz: float) -> float:
        """``method``'s mean error over pure integration's, in one cell of the grid."""
        table = self.tables[(turn_deg, bandwidth_hz)]
        return table.mean_error(method) / table.mean_error("pure integration")

    def has_paper_order(self, turn_deg: float, bandwidth_hz: float) -> bool:
        """Whether the cell orders the methods as the paper's Table 1 does."""
        return self.tables[(turn_deg, bandwidth_hz)].ordering() == list(HongTable1.PAPER)

    def noisiest_with_paper_order_dps(self, turn_deg: float) -> float | None:
        """The largest noise rms [deg/s] in the grid at which the methods fall in the paper's order
        with these turns (None: at no noise in the grid)."""
        holding = [self.noise_rms_dps(b) for b in self.bandwidths_hz if self.has_paper_order(turn_deg, b)]
        return max(holding, default=None)

    def rows(self) -> list[Row]:
        stated = self.bandwidths_hz[0]
        thr, cal = self.PAPER_RATIOS
        noise = self.noise_rms_dps(stated)
        rows = [
            Row(f"threshold / pure at {noise:.2f} deg/s noise, turns "
                f"{min(self.turns_deg):g}-{max(self.turns_deg):g} deg",
                f"{thr:.2f}", f"{min(self.ratio('threshold filter', t, stated) for t in self.turns_deg):.2f}"
                f"-{max(self.ratio('threshold filter', t, stated) for t in self.turns_deg):.2f}"),
            Row(f"bias leak through the threshold at {noise:.2f} deg/s noise", "", self.leak(stated)),
            Row("self-calibration / pure, over the grid", f"{cal:.2f}",
                f"{min(self.ratio('self-calibration', *c) for c in self.tables):.2f}"
                f"-{max(self.ratio('self-calibration', *c) for c in self.tables):.2f}"),
        ]
        for turn in self.turns_deg:
            noisiest = self.noisiest_with_paper_order_dps(turn)
            rows.append(Row(f"turns of {turn:g} deg: the paper's order up to a noise of", "",
                            f"none down to {self.noise_rms_dps(self.bandwidths_hz[-1]):.3f}" if noisiest is None
                            else noisiest, "deg/s"))
        return rows

    def table(self) -> str:
        cells = [f"{t:g} deg" for t in self.turns_deg]
        head = f"{'noise rms [deg/s]':<24} {'leak':>5}  " + "  ".join(f"{c:>13}" for c in cells)
        lines = [self.title, "cells: threshold filter / pure, self-calibration / pure; * the paper's order", head,
                 "-" * len(head)]
        for b in self.bandwidths_hz:
            row = f"{self.noise_rms_dps(b):.3f} ({b:g} Hz bandwidth)"
            cell = [f"{self.ratio('threshold filter', t, b):.2f} / {self.ratio('self-calibration', t, b):.2f}"
                    f"{'*' if self.has_paper_order(t, b) else ' '}" for t in self.turns_deg]
            lines.append(f"{row:<24} {self.leak(b):>5.2f}  " + "  ".join(f"{c:>13}" for c in cell))
        thr, cal = self.PAPER_RATIOS
        lines.append(f"{'paper (Table 1)':<24} {'':>5}  {thr:.2f} / {cal:.2f}*")
        lines.append("")
        lines.append(format_table("Summary (paper vs ours)", self.rows(), self.notes()))
        return "\n".join(lines)

    def notes(self) -> tuple[str, ...]:
        return (
            f"{self.spec.name} at its ARW ({self.spec.arw_deg_per_sqrt_h:g} deg/sqrt(h)) with the noise bandwidth "
            f"changed; threshold {self.threshold_dps:.2f} deg/s; robot run with turns of each size; "
            f"{len(next(iter(self.tables.values())).calibrations)} runs per cell",
            "pure integration's error is mostly that of the bias measured over the 5 s at power-up "
            "(ARW / sqrt(5 s), 0.019 deg/s rms), which grows with time as in the paper's Figure 10b",
            "the paper's Figure 8a (2 deg/s peak-to-peak at 100 Hz) and its ARW put the noise near the "
            f"top row ({self.noise_rms_dps(self.bandwidths_hz[0]):.2f} deg/s), where the threshold passes "
            f"{100 * self.leak(self.bandwidths_hz[0]):.0f} % of a residual bias",
        )

    def _figure(self, plt: Any) -> Any:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        bandwidths = self.bandwidths_hz
        k = [self.threshold_dps / self.noise_rms_dps(b) for b in bandwidths]
        for turn in self.turns_deg:
            ax.plot(k, [self.ratio("threshold filter", turn, b) for b in bandwidths], "o-",
                    label=f"threshold / pure, turns {turn:g} deg")
        fine = np.linspace(min(k), max(k), 200)
        ax.plot(fine, [deadband.bias_leak(1.0, x) for x in fine], "k--", label="bias leak (deadband.bias_leak)")
        ax.axhline(self.PAPER_RATIOS[0], color="r", lw=1, label="paper: threshold / pure")
        ax.set(xlabel="threshold / noise rms of one sample", ylabel="mean error / pure integration's",
               title="Hong Table 1: what the threshold filter gains, by gyro noise")
        ax.legend(fontsize=8)
        fig.tight_layout()
        return fig


def hong_table_1_sensitivity(
    *,
    bandwidths_hz: tuple[float, ...] = (20.0, 10.0, 5.0, 3.0, 2.0, 1.0),
    turns_deg: tuple[float, ...] = (90.0, 45.0, 20.0, 10.0),
    runs: int = 20,
    seed: int = 0,
    sensor: str | sim.GyroSpec = "xv3500",
) -> HongTable1Sensitivity:
    """:func:`hong_table_1` for every noise bandwidth of ``sensor`` in ``bandwidths_hz`` and turn
    size in ``turns_deg``, each with ``runs`` runs from ``seed`` (the same seeds in every cell)."""
    if not bandwidths_hz or not turns_deg:
        raise ValueError("need at least one bandwidth and one turn size")
    spec = sim.sensor(sensor)
    tables = {
        (float(turn), float(b)): hong_table_1(seed=seed, runs=runs, sensor=spec.replace(bandwidth_hz=b), turn_deg=turn)
        for turn in turns_deg
        for b in bandwidths_hz
    }
    return HongTable1Sensitivity(spec, _hong_threshold_dps(), tables)

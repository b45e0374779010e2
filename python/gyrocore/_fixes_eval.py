"""Scoring a heading fused with fixes against a log's reference (``gyrocore evaluate --fixes`` and
``--sim-fixes``), and the simulated fixes the ``--sim-fixes`` specification asks for.

A heading fused with fixes is absolute, so it is scored without alignment at the start (the
wrapped difference from the reference, :meth:`gyrocore.evaluate.Reference.compared` with
``absolute``); raw integration, which knows no absolute heading, is aligned at the start as
everywhere (HDR eq 15), which is the same as giving it the reference's heading at the first
compared time. A run that applied no fix (all outside the log's time span, or all rejected) has
no absolute heading either: it is scored aligned at the start, as without fixes, and says so.
Inside an outage both are the mean over the reference samples in it, from the same error series
as the whole drive's.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ._checks import did_you_mean, json_ready
from .evaluate import Failed, Method, Reference
from .evaluate_compare import raw_baseline, warn_partial_reference
from .fixes import Fixes
from .io import Log
from .sim_gnss import SIGMA_DEG, edge_rounding, gnss_fixes, inside_outage


@dataclass(frozen=True)
class SimFixes:
    """``--sim-fixes rate=1,sigma_deg=1,outage=START:LENGTH,seed=N``: SIMULATED fixes from the log's
    reference (:func:`gyrocore.sim.gnss_fixes`), at ``rate`` [Hz] with white noise ``sigma_deg``
    [deg], none during ``LENGTH`` seconds from ``START`` seconds after the log's first sample.
    Each log's noise has its own seed, from ``seed`` and the log's name (:meth:`seed_of`)."""

    rate: float = 1.0
    sigma_deg: float = 1.0
    outage: tuple[float, float] | None = None
    seed: int = 0

    @classmethod
    def parse(cls, text: str, option: str = "--sim-fixes") -> SimFixes:
        """The specification ``key=value,...``; a ``ValueError`` naming the bad part."""
        keys = ("rate", "sigma_deg", "outage", "seed")
        values: dict[str, Any] = {}
        for part in filter(None, (p.strip() for p in text.split(","))):
            key, sep, value = (s.strip() for s in part.partition("="))
            if not sep or key not in keys:
                raise ValueError(f"{option} {text}: {part!r} is not key=value with a key of {', '.join(keys)}"
                                 f"{did_you_mean(key, keys) if sep else ''}")
            if key in values:
                raise ValueError(f"{option} {text}: {key} is given twice")
            values[key] = _value(option, key, value)
        return cls(**values)

    def window(self, log: Log) -> tuple[float, float] | None:
        """The outage on the log's clock, as far as the log goes (an outage past its end ends just
        after its last sample), or None; a ``ValueError`` if it starts after the log."""
        window = self._given_window(log)
        if window is None:
            return None
        # an outage of 1e300 s was scored alike, and shown in a report line of 300 digits
        start, end = window
        last = float(log.t[-1])
        if end - edge_rounding(end) <= last:
            return window
        # beyond the rounding inside_outage allows at the end (up to twice the last sample's), so
        # that the last sample is in it
        return start, last + 3.0 * edge_rounding(last)

    def _given_window(self, log: Log) -> tuple[float, float] | None:
        """The outage on the log's clock as given, or None; a ``ValueError`` if it starts after the log."""
        if self.outage is None:
            return None
        start = float(log.t[0]) + self.outage[0]
        if start >= float(log.t[-1]):
            raise ValueError(f"log {log.name}: the outage starts {self.outage[0]:g} s after the first sample, "
                             f"after the log's end ({log.duration:.6g} s); give a smaller START")
        return start, start + self.outage[1]

    def seed_of(self, log: Log) -> int:
        """The seed of ``log``'s fixes: the first 8 bytes (big-endian) of the SHA-256 digest of
        ``"SEED/NAME"`` (the run's seed, the log's name in UTF-8). The run's seed alone gave every
        log the same noise sequence (logs of one rate the very same errors at each fix); from the
        name, a log's fixes are its own, whatever logs run beside it and in whatever order."""
        digest = hashlib.sha256(f"{self.seed}/{log.name}".encode("utf-8", "surrogateescape")).digest()
        return int.from_bytes(digest[:8], "big")

    def fixes(self, log: Log) -> Fixes:
        """The simulated fixes of ``log`` (from its reference heading)."""
        window = self._given_window(log)
        outages = () if window is None else (window,)
        return gnss_fixes(*log.reference(), seed=self.seed_of(log), rate_hz=self.rate, sigma_deg=self.sigma_deg,
                          outages=outages)

    def describe(self, log: Log) -> str:
        """The fixes of ``log`` as the report names them, with the seed they were drawn with."""
        outage = "" if self.outage is None else f", outage of {self.outage[1]:g} s from {self.outage[0]:g} s after the start"
        return (f"SIMULATED fixes from the log's own reference: {self.rate:g} Hz, {self.sigma_deg:g} deg white noise"
                f"{outage}, seed {self.seed_of(log)} (of the run's seed {self.seed} and the log's name {log.name})")


def _value(option: str, key: str, text: str) -> Any:
    """One value of a :class:`SimFixes` specification, checked."""
    where = f"{option}: {key}={text}"
    if key == "outage":
        start, sep, length = text.partition(":")
        try:
            window = (float(start), float(length)) if sep else None
        except ValueError:
            window = None
        if window is None or not all(math.isfinite(v) for v in window) or window[0] < 0 or window[1] <= 0:
            raise ValueError(f"{where}: give START:LENGTH in seconds (START >= 0 after the log's first sample, LENGTH > 0)")
        return window
    if key == "seed":
        # isdigit() is True for "²", which int() refuses; the simulator's seeds end below 2^64
        if not (text.isascii() and text.isdigit() and int(text) < 2**64):
            raise ValueError(f"{where}: the seed is a whole number >= 0 and below 2^64")
        return int(text)
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{where}: must be a number > 0")
    if key == "sigma_deg" and not SIGMA_DEG[0] <= value <= SIGMA_DEG[1]:
        raise ValueError(f"{where}: the fixes' noise must be in [{SIGMA_DEG[0]:.3g}, {SIGMA_DEG[1]:g}] deg (beyond, it "
                         "wraps at +-180 deg and is no longer the sigma)")
    return value


@dataclass(frozen=True)
class FixScore:
    """One method with fixes on one log: E_psi [deg] over the drive and inside the outage, beside
    raw integration's; the fix counts; the residual bias [deg/s] and scale error the fix stage
    estimated at the last sample (of the rate the pipeline corrected). ``absolute``: E_psi is the
    absolute error; False when no fix was applied, and E_psi is aligned at the start."""

    log: str
    method: str
    fixes: str
    counts: dict[str, int]
    e_psi_deg: float
    raw_e_psi_deg: float
    outage: tuple[float, float] | None
    outage_e_psi_deg: float | None
    raw_outage_e_psi_deg: float | None
    bias_deg_s: float
    scale: float
    absolute: bool
    path: str | None = None
    """Where the log was read, as given (:attr:`gyrocore.Log.path`)."""

    @property
    def label(self) -> str:
        """How tables name the log: its path (names repeat), else its name."""
        return self.path if self.path is not None else self.log

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dict, the log's ``path`` and ``name`` first (JSON has no NaN: an outage
        without a reference sample is null)."""
        row = {"path": self.path, "name": self.log}
        row.update((k, getattr(self, k)) for k in self.__dataclass_fields__ if k not in ("path", "log"))
        return json_ready(row)


def _mean_in(tr: np.ndarray, err: np.ndarray, window: tuple[float, float] | None) -> float | None:
    """Mean absolute error [deg] at the compared times inside ``window`` (NaN if none)."""
    if window is None:
        return None
    inside = inside_outage(tr, window)  # as the fixes were left out: at the edges too
    return float(np.degrees(np.abs(err[inside])).mean()) if inside.any() else math.nan


def score_with_fixes(log: Log, methods: Sequence[Method], fixes: Fixes, label: str,
                     window: tuple[float, float] | None, **run: Any) -> list[FixScore]:
    """Every method on ``log`` with ``fixes`` (``run``: :meth:`Method.run`'s keywords)."""
    reference = Reference(*log.reference())
    warn_partial_reference(log)
    raw_result = raw_baseline(log, methods)  # refused a NaN reading that --param nonfinite=hold let through
    tr_raw, err_raw, _ = reference.compared(raw_result.t, raw_result.heading)
    raw = float(np.degrees(np.abs(err_raw)).mean())
    with_fixes = replace(log, fixes=fixes)
    rows = []
    for method in methods:
        result, _ = method.run(with_fixes, **run)
        fusion = result.fusion
        # the log has fixes, and every output is computed by default
        assert fusion is not None and fusion.bias is not None and fusion.scale is not None
        absolute = fusion.counts["applied"] > 0  # else the heading is the gyro's alone: no absolute heading
        tr, err, _ = reference.compared(result.t, result.heading, absolute=absolute)
        rows.append(FixScore(
            log.name, method.name, label, dict(fusion.counts), float(np.degrees(np.abs(err)).mean()), raw,
            window, _mean_in(tr, err, window), _mean_in(tr_raw, err_raw, window),
            math.degrees(float(fusion.bias[-1])), float(fusion.scale[-1]), absolute, log.path,
        ))
    return rows


def format_fix_scores(rows: Sequence[FixScore | Failed]) -> None:
    """The table ``gyrocore evaluate`` prints with fixes, a log that failed as its ``FAILED`` line
    where it comes."""
    scores = [r for r in rows if isinstance(r, FixScore)]
    width = max([28, *(len(r.label) for r in scores)])
    print("E_psi [deg]: with fixes, the absolute heading error (no alignment at the start); raw integration "
          "aligned at the start (HDR eq 15)")
    print(f"{'log':<{width}} {'method':<16} {'E_psi':>7} {'raw':>7} {'outage':>7} {'raw':>7} "
          f"{'bias':>9} {'scale':>8}  fixes")
    # a units row as the table without fixes has: "scale" read as a factor near 1, not an error near 0
    print(f"{'':<{width}} {'':<16} {'[deg]':>7} {'[deg]':>7} {'[deg]':>7} {'[deg]':>7} "
          f"{'[deg/s]':>9} {'[1]':>8}  (bias, scale: the residual bias b and scale error s at the end, "
          "the gyro reading (1 + s) r + b)")
    for r in rows:
        if isinstance(r, Failed):
            print(r)
            continue
        out = "-" if r.outage_e_psi_deg is None else f"{r.outage_e_psi_deg:.2f}"
        raw_out = "-" if r.raw_outage_e_psi_deg is None else f"{r.raw_outage_e_psi_deg:.2f}"
        counts = ", ".join(f"{k} {v}" for k, v in r.counts.items())
        print(f"{r.label:<{width}} {r.method:<16} {r.e_psi_deg:7.2f} {r.raw_e_psi_deg:7.2f} {out:>7} {raw_out:>7} "
              f"{r.bias_deg_s:9.4f} {r.scale:8.4f}  {counts}")
    for label in dict.fromkeys(r.fixes for r in scores):
        print(f"fixes: {label}")
    for r in scores:
        if not r.absolute:
            print(f"no fix applied on {r.label} with {r.method}: its E_psi is aligned at the start, as without fixes")
    outages = {r.label: (r.outage, r.outage_e_psi_deg) for r in scores if r.outage is not None}
    for name, ((start, end), e_psi) in outages.items():
        # "nan" in its column was all an outage between two reference samples said
        empty = "" if e_psi is None or not math.isnan(e_psi) else (
            " holds no reference sample: its E_psi is nan (null in the JSON)")
        print(f"outage of {name}: [{start:.3f}, {end:.3f}) s{empty}")

"""Reading logs in the log-folder layout: gyro.csv (t, gyro_z), reference.csv (t, heading, x, y),
odometry.csv (t, speed) and meta.json (with the ``stationary`` rest window)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ._arrays import FloatArray
from .pipeline import HeadingResult, has_bias_source, process, uses_static_bias


def read_csv_columns(path: Path, columns: tuple[str, ...]) -> dict[str, FloatArray]:
    """Read the named columns of a CSV file with a header line.

    Raises ValueError naming the file (and the line, for a malformed row) on bad content.
    """
    with open(path, encoding="utf-8") as f:
        header = [h.strip() for h in f.readline().strip().split(",")]
    missing = [c for c in columns if c not in header]
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)} (header has {', '.join(header)})")
    idx = [header.index(c) for c in columns]
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=idx, ndmin=2, dtype=np.float64)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return {c: np.ascontiguousarray(data[:, k]) for k, c in enumerate(columns)}


@dataclass(frozen=True)
class Log:
    """One recorded drive: gyro samples, and the reference and odometry where the log has them.

    Units: s, rad/s, rad, m, m/s; headings counter-clockwise positive.
    """

    name: str
    t: FloatArray
    rate: FloatArray
    t_ref: FloatArray | None = None
    heading_ref: FloatArray | None = None
    x_ref: FloatArray | None = None
    y_ref: FloatArray | None = None
    t_odometry: FloatArray | None = None
    speed: FloatArray | None = None
    stationary: tuple[float, float] | None = None
    """Rest window ``(t0, t1)`` at the start, in the log's time base, or None."""
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def duration(self) -> float:
        """Duration of the gyro record [s]."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    def process(self, preset: str = "recommended", **overrides: Any) -> HeadingResult:
        """Run a preset on this log; the static bias comes from the rest window unless given."""
        if self.stationary is not None and uses_static_bias(preset) and not has_bias_source(overrides):
            overrides["bias_window"] = self.stationary
        return process(self.t, self.rate, preset, **overrides)


def read_log(path: str | Path) -> Log:
    """Read a log folder (see the module doc for the layout)."""
    folder = Path(path)
    if not (folder / "gyro.csv").is_file():
        raise FileNotFoundError(f"{folder}: not a log folder (no gyro.csv)")
    meta: dict[str, Any] = {}
    if (folder / "meta.json").is_file():
        try:
            meta = json.loads((folder / "meta.json").read_text(encoding="utf-8"))
        except json.JSONDecodeError as e:
            raise ValueError(f"{folder / 'meta.json'}: line {e.lineno} column {e.colno}: {e.msg}") from None
    gyro = read_csv_columns(folder / "gyro.csv", ("t", "gyro_z"))
    ref: dict[str, FloatArray | None] = dict.fromkeys(("t", "heading", "x", "y"))
    if (folder / "reference.csv").is_file():
        ref.update(read_csv_columns(folder / "reference.csv", ("t", "heading", "x", "y")))
    odo: dict[str, FloatArray | None] = dict.fromkeys(("t", "speed"))
    if (folder / "odometry.csv").is_file():
        odo.update(read_csv_columns(folder / "odometry.csv", ("t", "speed")))
    window = meta.get("stationary")
    return Log(
        name=str(meta.get("name", folder.name)),
        t=gyro["t"],
        rate=gyro["gyro_z"],
        t_ref=ref["t"],
        heading_ref=ref["heading"],
        x_ref=ref["x"],
        y_ref=ref["y"],
        t_odometry=odo["t"],
        speed=odo["speed"],
        stationary=None if window is None else (float(window[0]), float(window[1])),
        meta=meta,
    )

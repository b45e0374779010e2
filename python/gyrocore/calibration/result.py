"""The calibration record: :class:`Calibration` (what a calibration found and how, with units,
saved to and loaded from versioned JSON) and :class:`BiasTable` (FOG section 2)."""

from __future__ import annotations

import json
import math
import numbers
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._arrays import FloatArray, as_float_array, as_window, refuse_masked
from .._checks import MAX_READING, require_choice, require_finite, require_readings, require_version, warn
from ..io._jsonfile import read_json
from ..io.atomic import kept_outputs, write_text_atomically

#: A scale error beyond this [1] is a wrong unit or a fit without turns, not a gyro (the real logs
#: reach 28 %).
MAX_SCALE_ERROR = 0.5

#: Saved calibrations carry this format name and version.
FORMAT = "gyrocore-calibration"
VERSION = 1

_UNITS = {
    "bias": "rad/s (what the gyro reads at rest; corrected = measured - bias)",
    "bias_stderr": "rad/s",
    "scale_error": "1 (s of Hong eq 1: r_m = (1 + s) r + b)",
    "scale_error_stderr": "1",
    "residual_rms": "rad/s, or rad for heading_reference",
    "condition_number": "1",
    "window": "s (log time base)",
    "samples": "count",
    "c_cw": "1 (FOG eq 2a)",
    "c_ccw": "1 (FOG eq 2b)",
    "temp_slope": "1/degC (FOG eq 5's E_T slope / 360 deg)",
    "temp_offset": "1 (FOG eq 5's E_T at 0 degC / 360 deg)",
    "bias_table": "temperatures degC, biases rad/s",
    "time_offset": "s (add to the gyro's times to put them on the reference's clock)",
    "time_offset_stderr": "s",
}
#: Fields saved only where they hold a value: a calibration without them saves as before they were
#: added, and the versions of gyrocore before them read it.
_OPTIONAL = ("time_offset", "time_offset_stderr")
#: The calibrations there are (``Calibration.method``).
METHODS = ("static_bias", "rate_reference", "heading_reference", "rotary_table")
#: What a saved field of each type must be, for the errors of :meth:`Calibration.from_dict`.
_KINDS = {"str": "text", "int": "a whole number"}


@dataclass(frozen=True)
class BiasTable:
    """Bias versus temperature look-up table (FOG section 2), linearly interpolated.

    Beyond the table's temperatures the nearest entry is used: extrapolating a thermal bias
    curve is unreliable.

    Attributes:
        temperatures: mean temperature of each bin [degC], increasing.
        biases: mean rest reading in each bin [rad/s].
        stderr: standard error of each bias [rad/s] (white-noise estimate within the bin).
        counts: readings per bin.
    """

    temperatures: tuple[float, ...]
    biases: tuple[float, ...]
    stderr: tuple[float, ...]
    counts: tuple[int, ...]

    def __post_init__(self) -> None:
        """Refuse a table ``np.interp`` would read wrongly without a word: temperatures out of order
        (a loaded table of 30, 10, 20 degC gave the bias of 30 degC at 20 degC), values that are
        not finite numbers, lists of two lengths (numpy's "fp and xp are not of the same length")
        or no entry ("array of sample points is empty"). Arrays and lists become tuples: a table built
        from numpy arrays failed on ``not self.temperatures`` with numpy's bare "truth value of an
        array ... is ambiguous")."""
        for f in fields(self):
            value = getattr(self, f.name)
            refuse_masked(f"bias table {f.name}", value)
            if isinstance(value, (np.ndarray, list)):
                object.__setattr__(self, f.name, tuple(np.asarray(value).tolist()))
        columns = {f.name: getattr(self, f.name) for f in fields(self)}
        if len({len(v) for v in columns.values()}) != 1 or not self.temperatures:
            sizes = ", ".join(f"{len(v)} {k}" for k, v in columns.items())
            raise ValueError(f"a bias table needs one temperature, bias, stderr and count per entry and at least one "
                             f"entry, got {sizes}")
        for name, values in columns.items():
            for i, v in enumerate(values):
                if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
                    raise ValueError(f"bias table {name}[{i}] is {v!r}: must be a finite number")
        steps = np.diff(self.temperatures)
        if (steps <= 0).any():
            i = int(np.argmax(steps <= 0)) + 1
            raise ValueError(f"bias table temperatures[{i}] = {self.temperatures[i]:g} degC does not come after "
                             f"{self.temperatures[i - 1]:g} degC: a table's temperatures must strictly increase")

    def __call__(self, temperature: ArrayLike) -> FloatArray:
        """Bias [rad/s] at ``temperature`` [degC] (scalar or array; a masked one with masked values is
        refused, as everywhere, and a temperature that is not finite is a ValueError naming it: it
        gave a NaN bias)."""
        refuse_masked("temperature", temperature)
        temp = np.asarray(temperature, dtype=np.float64)
        require_finite("temperature", temp)
        return np.interp(temp, self.temperatures, self.biases)

    def correct(self, rate: ArrayLike, temperature: ArrayLike) -> FloatArray:
        """``rate - bias(temperature)`` [rad/s]; give the result to the pipeline with ``bias=0``.

        Both are readings as the pipeline takes them: a value that is not finite or beyond
        +-2^20 is a :class:`~gyrocore.SampleError` (a ValueError) naming its index (a NaN
        temperature gave a NaN rate); arrays of two lengths are a ValueError."""
        r = as_float_array("rate", rate, unit="rad/s")
        temp = as_float_array("temperature", temperature, unit="degC")
        if len(r) != len(temp):
            raise ValueError(f"rate has {len(r)} samples but temperature has {len(temp)}")
        require_readings("rate", r)
        require_readings("temperature", temp)
        return r - self(temp)


@dataclass(frozen=True, repr=False)
class Calibration:
    """A gyro calibration and how it was obtained (units in :data:`_UNITS` and the JSON).

    Attributes:
        method: ``static_bias``, ``rate_reference``, ``heading_reference`` or ``rotary_table``.
        bias: ``b`` [rad/s], what the gyro reads at rest (for ``rotary_table``: the mean of the
            static tests before the turns, informative only).
        scale_error: ``s`` of Hong eq 1 [1] (0 where not estimated).
        bias_stderr, scale_error_stderr: their standard errors (None where not estimated).
        residual_rms: RMS of the fit's residuals (rad/s; rad for ``heading_reference``); for the
            static bias the standard deviation of the readings.
        condition_number: of the column-scaled least-squares problem (None without one).
        window: the time span used [s]: the rest window of a static bias test, the fitted span
            (None for ``rate_reference``, whose readings come without times).
        samples: readings used.
        c_cw, c_ccw: direction correction factors (FOG eq 2).
        temp_slope, temp_offset: temperature-linear scale factor (FOG eq 5-6, per 360 deg).
        bias_table: bias versus temperature (FOG section 2).
        time_offset, time_offset_stderr: the gyro's time offset against the reference [s] and its
            standard error (:func:`~gyrocore.calibration.time_offset`; None where not estimated):
            add it to the gyro's times to put them on the reference's clock. Informative:
            :meth:`overrides` does not apply it (the pipeline takes the times as given).
    """

    method: str
    bias: float = 0.0
    scale_error: float = 0.0
    bias_stderr: float | None = None
    scale_error_stderr: float | None = None
    residual_rms: float | None = None
    condition_number: float | None = None
    window: tuple[float, float] | None = None
    samples: int = 0
    c_cw: float = 1.0
    c_ccw: float = 1.0
    temp_slope: float | None = None
    temp_offset: float | None = None
    bias_table: BiasTable | None = None
    notes: tuple[str, ...] = field(default=())
    time_offset: float | None = None
    time_offset_stderr: float | None = None

    def __post_init__(self) -> None:
        """Refuse values no calibration gives, so that a hand-edited or damaged file fails where it
        is read: a scale error of -1 (``s_bar = 1/0``) raised ZeroDivisionError, and a NaN bias,
        an unknown method or notes given as one text were taken without a word."""
        require_choice("calibration method", self.method, METHODS)
        for name in ("bias", "scale_error", "c_cw", "c_ccw", "temp_slope", "temp_offset", "time_offset"):
            value = getattr(self, name)
            if value is not None and not math.isfinite(value):
                raise ValueError(f"{name} must be finite, got {value!r}")
        if not self.scale_error > -1.0:  # every fit refuses s_bar <= 0 (a gyro read against the motion)
            raise ValueError(f"scale_error must be > -1 (s_bar = 1/(1 + s) > 0), got {self.scale_error!r}")
        if self.scale_error > MAX_READING:  # 1e300 made every turn 0 (s_bar = 1e-300)
            raise ValueError(f"scale_error must be at most 2^20, got {self.scale_error!r}")
        for name in ("c_cw", "c_ccw"):  # a factor of 0 wipes out every turn of its direction
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")
        for name in ("bias_stderr", "scale_error_stderr", "residual_rms", "condition_number",
                     "samples", "time_offset_stderr"):
            value = getattr(self, name)
            if value is not None and not value >= 0:
                raise ValueError(f"{name} must be >= 0, got {value!r}")
        if (self.temp_slope is None) != (self.temp_offset is None):  # overrides() dropped the one alone
            raise ValueError("temp_slope and temp_offset make one temperature model: give both or neither")
        if self.time_offset is None and self.time_offset_stderr is not None:
            raise ValueError("time_offset_stderr is the standard error of a time_offset: give the offset too")
        if not all(isinstance(n, str) for n in self.notes):
            raise ValueError(f"notes must be a list of text, got {list(self.notes)!r}")

    @property
    def s_bar(self) -> float:
        """``s_bar = 1/(1+s)`` (Hong eq 3) [1]."""
        return 1.0 / (1.0 + self.scale_error)

    @property
    def b_bar(self) -> float:
        """``b_bar = -b/(1+s)`` (Hong eq 3) [rad/s]."""
        return -self.bias / (1.0 + self.scale_error)

    def overrides(self, *, include_bias: bool | None = None) -> dict[str, float]:
        """Parameters for ``gyrocore.Pipeline(preset, **overrides)`` (and ``process``).

        The least-squares fits give Hong eq 3 as ``s_bar * (r_m - b)``, which equals
        ``s_bar r_m + b_bar``: ``scale = s_bar``, ``offset = 0`` and ``bias = b``, so the pipeline
        has an explicit bias and does not measure another one over a rest window. Pass
        ``include_bias=False`` to keep only the scale (and let the pipeline measure a fresh
        static bias). A rotary-table calibration gives the scale factors only (its static biases
        belong to the table runs; FOG section 2 measures the bias again before use).
        """
        if include_bias is None:
            include_bias = self.method != "rotary_table"
        out: dict[str, float] = {}
        if include_bias:
            out["bias"] = self.bias
        if self.method in ("rate_reference", "heading_reference"):
            out["scale"] = self.s_bar
            out["offset"] = 0.0
        if self.method == "rotary_table":
            out["c_cw"] = self.c_cw
            out["c_ccw"] = self.c_ccw
            if self.temp_slope is not None and self.temp_offset is not None:
                out["temp_slope"] = self.temp_slope
                out["temp_offset"] = self.temp_offset
        return out

    def __repr__(self) -> str:
        parts = [self.method]
        err = "" if self.bias_stderr is None else f" +- {self.bias_stderr:.3g}"
        parts.append(f"bias = {self.bias:.6g}{err} rad/s ({math.degrees(self.bias):.4g} deg/s)")
        if self.method in ("rate_reference", "heading_reference"):
            serr = "" if self.scale_error_stderr is None else f" +- {100 * self.scale_error_stderr:.3g}"
            parts.append(f"scale error = {100 * self.scale_error:.4g}{serr} %")
            parts.append(f"s_bar = {self.s_bar:.6g}, b_bar = {self.b_bar:.6g} rad/s")
        if self.method == "rotary_table":
            parts.append(f"c_cw = {self.c_cw:.6g}, c_ccw = {self.c_ccw:.6g}")
            if self.temp_slope is not None and self.temp_offset is not None:
                parts.append(
                    f"E_T = {360 * self.temp_slope:.4g} deg/degC * T + {360 * self.temp_offset:.4g} deg"
                )
        if self.bias_table is not None:
            parts.append(f"bias table of {len(self.bias_table.temperatures)} temperatures")
        if self.residual_rms is not None:
            unit = "rad" if self.method == "heading_reference" else "rad/s"
            parts.append(f"residual rms = {self.residual_rms:.4g} {unit}")
        if self.condition_number is not None:
            parts.append(f"condition number = {self.condition_number:.3g}")
        if self.window is not None:
            parts.append(f"window {self.window[0]:.12g} .. {self.window[1]:.12g} s")
        parts.append(f"{self.samples} samples")
        if self.time_offset is not None:
            err = "" if self.time_offset_stderr is None else f" +- {self.time_offset_stderr:.2g}"
            parts.append(f"time offset = {self.time_offset:+.4g}{err} s (add to the gyro's times)")
        parts += [f"note: {n}" for n in self.notes]
        return f"Calibration({', '.join(parts)})"

    # --- JSON ---

    def to_dict(self) -> dict[str, Any]:
        """The saved form: format, version, units and the values."""
        values = asdict(self)
        values["window"] = None if self.window is None else list(self.window)
        values["notes"] = list(self.notes)
        units = dict(_UNITS)
        for name in _OPTIONAL:
            if values[name] is None:
                del values[name], units[name]
        return {"format": FORMAT, "version": VERSION, "units": units, "calibration": values}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Calibration:
        """Rebuild from :meth:`to_dict`; raises ValueError on another format or version."""
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            found = data.get("format") if isinstance(data, dict) else None
            raise ValueError(f"not a gyrocore calibration (format {found!r})")
        require_version("calibration file", data.get("version"), VERSION)
        if not isinstance(data.get("calibration"), dict):
            raise ValueError("no calibration object")
        values = dict(data["calibration"])
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise ValueError(f"unknown calibration field(s): {', '.join(unknown)}")
        # a file without its bias was one of bias 0 (without a method, Python's "__init__() missing 1
        # required positional argument"); every calibration saved holds both
        missing = [name for name in ("method", "bias") if name not in values]
        if missing:
            raise ValueError(f"missing calibration field(s): {', '.join(missing)}")
        for f in fields(cls):  # JSON types: a number must not be text ("bias": "abc")
            value = values.get(f.name)
            if value is None and f.name in values and "None" not in str(f.type) and f.name != "notes":
                # "bias": null lost the bias without a word, "c_cw": null was Python's "'>' not supported"
                raise ValueError(f"{f.name} must be {_KINDS.get(str(f.type), 'a number')}, got null")
            if value is None or f.name in ("window", "bias_table", "notes"):
                continue
            expected = {"str": str, "int": int}.get(str(f.type), (int, float))
            if isinstance(value, bool) or not isinstance(value, expected):
                raise ValueError(f"{f.name} must be {_KINDS.get(str(f.type), 'a number')}, got {value!r}")
        if values.get("window") is not None:
            values["window"] = as_window("window", values["window"])
        if values.get("bias_table") is not None:
            values["bias_table"] = _table_of(values["bias_table"])
        notes = values.get("notes", [])
        if not isinstance(notes, list):  # tuple("abc") made three notes of a letter each
            raise ValueError(f"notes must be a list of text, got {notes!r}")
        values["notes"] = tuple(notes)
        return cls(**values)

    def save(self, path: str | Path, *, overwrite: bool = True) -> None:
        """Write the calibration as JSON (see :meth:`to_dict`), whole or not at all: a save that
        fails or is interrupted leaves the file that was there. ``overwrite=False`` never replaces
        a file: one at ``path`` is refused (FileExistsError, it exists), and one another run wrote
        meanwhile is kept (FileExistsError, written meanwhile)."""
        with kept_outputs([path], overwrite, "overwrite=True"):
            write_text_atomically(path, json.dumps(self.to_dict(), indent=2) + "\n", replace=overwrite)

    @classmethod
    def load(cls, path: str | Path) -> Calibration:
        """Read a calibration saved by :meth:`save`; one whose scale error is beyond
        :data:`MAX_SCALE_ERROR` warns (no gyro has one: the fit that made it saw no turn, or a
        wrong unit, and applied it scales every turn by its gain)."""
        p = Path(path)
        data = read_json(p)
        try:
            calibration = cls.from_dict(data)
        except (KeyError, TypeError, ValueError) as e:  # missing keys, wrong shapes and types
            raise ValueError(f"{p}: not a valid calibration: {e}") from None
        if abs(calibration.scale_error) > MAX_SCALE_ERROR:
            warn(f"{p}: the scale error {100 * calibration.scale_error:+.4g} % is beyond +-{100 * MAX_SCALE_ERROR:g} % "
                 f"for any gyro: applied, it scales every turn by {calibration.s_bar:.4g}; calibrate again over a "
                 "drive with turns, in the right units")
        return calibration


def _table_of(table: Any) -> BiasTable:
    """The :class:`BiasTable` of a saved ``bias_table``: an object of the table's four lists (a
    number in place of a list was "'int' object is not iterable")."""
    names = [f.name for f in fields(BiasTable)]
    if not isinstance(table, dict) or sorted(table) != sorted(names) or not all(isinstance(v, list) for v in table.values()):
        raise ValueError(f"bias_table must be an object of the lists {', '.join(names)}, got {table!r}")
    return BiasTable(**{k: tuple(v) for k, v in table.items()})

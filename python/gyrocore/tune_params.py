"""Parameter sets: a base preset with overrides, as a versioned JSON preset file
(``gyrocore evaluate --params FILE``); :mod:`gyrocore.tune` re-exports the public names."""

from __future__ import annotations

import json
import re
import reprlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from ._checks import did_you_mean, require_version
from .evaluate import Method
from .io._jsonfile import read_json
from .pipeline import BIAS_SOURCES, Pipeline, parameters

#: Version of the preset-file format written by :meth:`ParameterSet.write`.
FORMAT_VERSION = 1
FORMAT_NAME = "gyrocore-params"
#: The keys of a parameter file (:meth:`ParameterSet.to_json`'s); "tuning" holds anything informative.
_FILE_KEYS = ("format", "version", "name", "preset", "overrides", "units", "tuning")


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
        # checked as the set is made, so that a set written (gyrocore tune --name " ") is one read
        # back; str() would take 5 for the name "5" and ["hdr"] for a preset "['hdr']": refused instead
        for key in ("name", "preset"):
            value = getattr(self, key)
            if not isinstance(value, str):
                raise ValueError(f"\"{key}\" must be a string, got {reprlib.repr(value)}")
            if not value.strip():
                raise ValueError(f"\"{key}\" must not be empty")
            if not value.isprintable():  # a line break split the row of evaluate's table that it names
                raise ValueError(f"\"{key}\" must be one line of text without control characters, got {value!r}")
        bias = [k for k in self.overrides if k in BIAS_SOURCES or k[:-4] in BIAS_SOURCES]
        if bias:
            raise ValueError(
                f"parameter set {self.name!r}: {', '.join(bias)} cannot be part of a parameter set; "
                "the static bias comes from each log (its rest window, or a bias duration)"
            )
        unset = [k for k, v in self.overrides.items() if v is None]
        if unset:  # the pipeline reads None as not given: the preset's value ran under the set's name
            raise ValueError(f"parameter set {self.name!r}: {', '.join(unset)} is null; give a value, or leave it out "
                             "for the preset's")
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

    def write(self, path: str | Path, *, overwrite: bool = True) -> None:
        """Write the preset file (JSON), whole or not at all; ``overwrite=False`` never replaces a
        file (one at ``path`` is refused, one written meanwhile by another run is kept: FileExistsError)."""
        from .io.atomic import kept_outputs, write_text_atomically

        with kept_outputs([path], overwrite, "overwrite=True"):
            write_text_atomically(path, json.dumps(self.to_json(), indent=2) + "\n", replace=overwrite)

    @classmethod
    def read(cls, path: str | Path) -> "ParameterSet":
        """Read a preset file written by :meth:`write` (ValueError naming the file on bad content)."""
        p = Path(path)
        data = read_json(p)
        if isinstance(data, dict) and "format" not in data and {"overrides", "start_objective"} <= set(data):
            # tune --json > FILE is the natural guess for a parameter file; say which output is one
            raise ValueError(f"{p}: the report gyrocore tune --json prints, not a parameter file: the parameter "
                             "file is what gyrocore tune --out FILE writes")
        if not isinstance(data, dict) or data.get("format") != FORMAT_NAME:
            raise ValueError(f"{p}: not a gyrocore parameter file (no \"format\": \"{FORMAT_NAME}\")")
        require_version("parameter file", data.get("version"), FORMAT_VERSION, f"{p}: ")
        missing = [k for k in ("name", "preset", "overrides") if k not in data]
        if missing:
            raise ValueError(f"{p}: missing key(s) {', '.join(missing)}")
        if not isinstance(data["overrides"], dict):
            raise ValueError(f"{p}: \"overrides\" must be an object of parameter names to SI values")
        _check_keys_and_units(p, data)
        if not isinstance(data.get("tuning", {}), dict):
            raise ValueError(f"{p}: \"tuning\" must be an object (how the set was found), got {reprlib.repr(data['tuning'])}")
        try:
            return cls(data["name"], data["preset"], data["overrides"], data.get("tuning", {}))
        except (ValueError, TypeError) as e:
            raise ValueError(f"{p}: {e}") from None


def _check_keys_and_units(path: Path, data: Mapping[str, Any]) -> None:
    """Refuse a key the file format does not have (``"bias_duration": 10`` or ``"mode": "causal"``
    beside the overrides were ignored without a word) and a ``units`` entry that names another
    unit than the SI one the value is read in (``"hdr_turn_threshold": "deg/s"`` beside 0.5 ran a
    turn switch of 0.5 rad/s, 29 deg/s)."""
    unknown = [k for k in data if k not in _FILE_KEYS]
    if unknown:
        said = ", ".join(f"{k!r}{did_you_mean(k, _FILE_KEYS)}" for k in unknown)
        raise ValueError(f"{path}: unknown key(s) {said}; a parameter file holds {', '.join(_FILE_KEYS)} (anything "
                         "informative goes in \"tuning\"); the static bias and the mode are the command's options")
    units = data.get("units", {})
    if not isinstance(units, dict):
        raise ValueError(f"{path}: \"units\" must be an object of parameter names to their SI units, got "
                         f"{reprlib.repr(units)}")
    described = parameters()
    overrides = data["overrides"]
    for name, text in units.items():
        want = _unit_of(described.get(name, ""))
        if name in overrides and want is not None and _unit_of(text, bare=True) != want:
            raise ValueError(f"{path}: units give {name} in {text!r}, but a parameter file holds SI values: {name} is "
                             f"read in [{want}] ({described[name]}); give its value and its unit in [{want}]")


def _unit_of(text: object, bare: bool = False) -> str | None:
    """The unit in brackets of a parameter's description (``Theta_w [rad/s]``: ``rad/s``); None
    without one. ``bare``: a text without brackets (``deg/s``, as a user writes one) is the unit."""
    if not isinstance(text, str):
        return repr(text)
    found = re.search(r"\[([^\]]*)\]", text)
    if found:
        return found.group(1).strip()
    return text.strip() if bare else None

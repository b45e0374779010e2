"""The simulated gyro's fields (:class:`gyrocore.sim.GyroSpec`, in the datasheet's units) and the
core model's parameters they become (SI), so that the core's error about a parameter names the
field the caller gave."""

from __future__ import annotations

import inspect
import re
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from . import _gyrocore
from ._checks import did_you_mean

if TYPE_CHECKING:
    from .sim import GyroSpec

#: The core's parameter -> (the field, its part of a pair or None); a parameter of the field's own
#: name and unit is left as it is.
_FIELDS: dict[str, tuple[str, int | None]] = {
    "jitter": ("jitter_s", None),
    "scale_temperature": ("scale_per_c", None),
    "bias": ("bias_dps", None),
    "bias_temperature": ("bias_dps_per_c", None),
    "arw": ("arw_deg_per_sqrt_h", None),
    "bandwidth": ("bandwidth_hz", None),
    "bias_instability": ("bias_instability_deg_per_h", None),
    "flicker_min": ("flicker_band_s", 0),
    "flicker_max": ("flicker_band_s", 1),
    "rrw": ("rrw_deg_per_h_per_sqrt_h", None),
    "drift_step": ("drift_step_s", None),
    "temperature.start": ("temperature_c", 0),
    "temperature.end": ("temperature_c", 1),
    "temperature.time_constant": ("temperature_time_constant_s", None),
    "reference_temperature": ("reference_temperature_c", None),
    "resolution": ("resolution_dps", None),
    "range": ("range_dps", None),
}
_PARAMETER = re.compile(r"invalid parameter (?P<name>[\w.]+) = (?P<value>\S+?):")


def check_spec(spec: GyroSpec) -> None:
    """The core's checks of the model ``spec`` makes, over one second of it; its error names the
    field given where the core's parameter has another name or unit (``bias_dps=1e9`` was
    ``invalid parameter bias = 17453292.519943297: must be within +-2^20``, rad/s of a field
    given in deg/s, and no word of ``bias_dps``).

    Raises:
        ValueError: a field out of its range.
    """
    try:
        _gyrocore.gyro_check_span(spec.si(), 0.0, 1.0)
    except ValueError as e:
        m = _PARAMETER.search(str(e))
        if m is not None and m["name"] == "gain":  # a sum of five fields, none out of its own range
            fields = ("scale_error", "scale_asymmetry", "scale_per_c", "temperature_c", "reference_temperature_c")
            given = ", ".join(f"{name} = {getattr(spec, name)!r}" for name in fields)
            raise ValueError(
                f"sensor fields {given}: the gain 1 + s they make is {float(m['value']):.6g} at its lowest; it must be > 0 "
                "at every temperature and for both turn directions (1 + scale_error + scale_per_c (T - "
                "reference_temperature_c) +- scale_asymmetry / 2): at 0 or below the gyro reads no turn, or every "
                "turn backwards"
            ) from None
        if m is None or m["name"] not in _FIELDS:
            raise
        name, part = _FIELDS[m["name"]]
        value = getattr(spec, name)
        given = f"{name} = {value!r}" if part is None else f"{name}[{part}] = {value[part]!r}"
        raise ValueError(f"sensor field {given}: {e}; the model takes it in SI units (rad, s, degC)") from None


def refuse_unknown_keywords(function: Callable[..., Any], changes: dict[str, Any], sensor_fields: Sequence[str]) -> None:
    """A TypeError for a keyword of ``changes`` (the ``**changes`` of ``function``, which go to the
    sensor) that is neither one of ``function``'s own nor one of ``sensor_fields``: a misspelt
    ``duration`` was called an unknown sensor field, and ``duration`` was not suggested."""
    own = [p.name for p in inspect.signature(function).parameters.values() if p.kind is not p.VAR_KEYWORD]
    unknown = [k for k in changes if k not in sensor_fields]
    if unknown:
        said = ", ".join(f"{k!r}{did_you_mean(k, (*own, *sensor_fields))}" for k in unknown)
        raise TypeError(f"unknown keyword(s) {said}: neither a keyword of {function.__name__} ({', '.join(own)}) nor a "
                        f"sensor field ({', '.join(sensor_fields)})")

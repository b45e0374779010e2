"""The pipeline's presets and parameters, re-exported by :mod:`gyrocore.pipeline` (units there):
the presets' names, the parameters' SI names and their degree spellings (``threshold_dps``,
``initial_heading_deg``), and the core's checks of them, naming the parameter in error.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from . import _gyrocore
from ._checks import shown
from . import _motion

#: Parameters that are rates [rad/s] and so also accept a ``_dps`` spelling (every one: the docs
#: promise it, and ``hdr_max_correction_dps`` was an unknown parameter).
_RATE_PARAMETERS = (
    "bias", "offset", "threshold", "hdr_increment", "hdr_turn_threshold", "hdr_max_correction", "rest_noise"
)


def preset_names() -> list[str]:
    """Names of the presets, in order of increasing processing (``recommended`` is an alias)."""
    names, _ = _gyrocore.preset_names()
    return list(names)


def recommended_preset() -> str:
    """The preset that ``"recommended"`` stands for."""
    return str(_gyrocore.preset_names()[1])


#: Parameters that each give the static bias (or where to measure it); at most one may be set.
BIAS_SOURCES: tuple[str, ...] = tuple(_gyrocore.BIAS_SOURCES)


def uses_static_bias(preset: str) -> bool:
    """Whether ``preset`` subtracts a static bias (and so wants a bias or a rest window)."""
    _check_preset(preset)
    return bool(_gyrocore.preset_uses_static_bias(preset))


def has_bias_source(overrides: dict[str, Any]) -> bool:
    """Whether ``overrides`` (SI or degree spelling) set the static bias or its rest window."""
    return any(_to_si(overrides).get(k) is not None for k in BIAS_SOURCES)


def unmeasured_bias(preset: str, si: dict[str, Any]) -> str | None:
    """What a causal run of ``preset`` with the SI parameters ``si`` should say when the preset
    removes a static bias that nothing gives (no bias, rest window or leading duration): it is 0,
    until the rest tracker measures one where the run has a tracker. None when there is a source."""
    if not uses_static_bias(preset) or has_bias_source(si):
        return None
    until = " until the rest tracker measures one at a stop" if preset_params(preset, **si)["track_rests"] else ""
    return (f"preset {preset!r} removes a static bias, but no bias, bias_window or bias_duration was given: "
            f"the bias is taken as 0{until}")


def implausible_bias(si: dict[str, Any]) -> str | None:
    """What a pipeline given the SI parameters ``si`` should say of a static ``bias`` beyond any
    gyro's at rest (:data:`gyrocore._motion.REST_LEVEL`): a bias in deg/s given as rad/s, which
    turned the heading 57 times too far each second without a word. None for a plausible one."""
    bias = si.get("bias")
    if not isinstance(bias, (int, float)) or abs(bias) <= _motion.REST_LEVEL:
        return None
    return (f"bias = {bias:.6g} rad/s ({math.degrees(bias):.4g} deg/s) is beyond any gyro's at rest (more than "
            f"{_motion.REST_LEVEL:g} rad/s): a bias in deg/s given as rad/s? Give it in deg/s as bias_dps={bias:.6g} "
            f"(--param bias_dps={bias:.6g}), or in rad/s")


def parameters() -> dict[str, str]:
    """Every pipeline parameter with its description and unit."""
    return dict(_gyrocore.parameter_names())


def _to_si(overrides: dict[str, Any]) -> dict[str, Any]:
    """Convert ``*_dps`` / ``*_deg`` spellings to the SI parameter names, and a list or array (a
    window; a pandas Series too, by position) to the tuple the core takes."""
    si: dict[str, Any] = {}
    for key, value in overrides.items():
        if not isinstance(value, (np.ndarray, list, tuple)) and hasattr(value, "__array__") and np.ndim(value) > 0:
            value = np.asarray(value)  # a pandas Series: its [1] is a look-up by label (a KeyError: 1)
        times = isinstance(value, np.ndarray) and value.dtype.kind in "mM"
        if times or isinstance(value, (np.timedelta64, np.datetime64)):
            # int types to numpy: float() of one was a bare TypeError, and tolist() of nanoseconds ints
            raise TypeError(f"invalid parameter {key} = {value!r}: {_instead_of_times(key)}")
        if np.ma.is_masked(value):  # its item() is 0.0: bias=numpy.ma.mean(rest) of a rest all masked was no bias
            raise TypeError(f"invalid parameter {key} = {str(value)[:60]}: a masked value holds no number (numpy.ma's "
                            "statistic of samples all masked is masked): give numbers, measured on valid samples")
        if isinstance(value, np.ndarray) and value.ndim == 0:  # a number from numpy (tuple() of it failed)
            value = value.item()
        if key.endswith("_dps") and key[:-4] in _RATE_PARAMETERS:
            name = key[:-4]
        elif key == "initial_heading_deg":
            name = "initial_heading"
        else:
            name = key
        if isinstance(value, (list, np.ndarray)):
            _refuse_sequence(key, name, value)
            value = tuple(value.tolist() if isinstance(value, np.ndarray) else value)
        _refuse_bool(key, name, value)
        if name != key:  # given in degrees
            value = _radians(key, value)
        if name in si:
            raise ValueError(f"{name} is given twice (as {name} and in degrees)")
        si[name] = value
    return si


def _instead_of_times(key: str) -> str:
    """What to give as the parameter ``key`` instead of a duration or date: seconds for one of
    seconds, and for any other a float in its unit (a bias given as a duration was told to be
    given in seconds, which a rate never is)."""
    if key.endswith("_dps"):
        unit = "deg/s"
    elif key.endswith("_deg"):
        unit = "deg"
    else:  # the last bracket of its description: "static bias eps0 [rad/s] (...)"
        units = re.findall(r"\[([^\]]*)\]", parameters().get(key, "[s]"))
        unit = units[-1] if units else "its unit"
    if unit == "s":
        return "give seconds (a numpy duration d as d / numpy.timedelta64(1, 's'))"
    return f"a duration or date is no value in {unit}: give {key} as a float in {unit}"


#: The parameters that take a pair, (start, end), which a list or array is turned into.
_PAIRS = ("bias_window",)


def _refuse_sequence(key: str, name: str, value: list[Any] | np.ndarray) -> None:
    """A TypeError for a list or array given as ``key`` to the parameter ``name`` that takes one
    value: turned into the tuple a window is, ``bias=np.array([0.1])`` was refused as the tuple
    ``(0.1,)`` the caller never gave."""
    what = parameters().get(name)
    if what is not None and name not in _PAIRS:
        given = f"an array of shape {value.shape}" if isinstance(value, np.ndarray) else f"a list of {len(value)}"
        listed = value.tolist() if isinstance(value, np.ndarray) else value
        raise TypeError(f"invalid parameter {key} = {shown(listed)}: {key} takes one value, got {given}; {key} is {what}")


def _refuse_bool(key: str, name: str, value: Any) -> None:
    """A TypeError for a bool given as ``key`` to the parameter ``name`` that is no switch: the core
    reads a bool as a number (``bias=True`` was a bias of 1 rad/s, ``bias_window=(False, True)`` the
    window 0 .. 1 s)."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, tuple) and any(isinstance(v, (bool, np.bool_)) for v in value)):
        every = parameters()
        what = every.get(name)
        if what is not None and not what.endswith("[bool]"):
            switches = ", ".join(k for k, v in every.items() if v.endswith("[bool]"))
            raise TypeError(f"invalid parameter {key} = {value!r}: a bool, but {key} is {what} (the switches, which "
                            f"take one, are {switches})")


def _check_preset(preset: object) -> None:
    """A TypeError for a preset that is no name (the core's "'None' is not an instance of 'str'"
    said neither which argument nor what to give)."""
    if not isinstance(preset, str):
        raise TypeError(f"preset must be the name of a preset ({', '.join(preset_names())}, recommended), got {preset!r}")


def _radians(key: str, value: Any) -> float | None:
    """The value of a parameter given in degrees (``key``), in radians; None stays None."""
    if value is None:
        return None
    try:
        return math.radians(value)
    except TypeError:
        raise TypeError(f"invalid parameter {key} = {value!r}: must be a number of degrees") from None
    except OverflowError:  # an int beyond float64
        raise ValueError(f"invalid parameter {key} = {shown(value)}: beyond the range of float64") from None


def preset_params(preset: str = "hdr", **overrides: Any) -> dict[str, Any]:
    """The flat SI parameters of ``preset`` with ``overrides`` applied (validated by the core)."""
    _check_preset(preset)
    si = _to_si(overrides)
    try:
        return dict(_gyrocore.preset_params(preset, si))
    except (TypeError, ValueError, OverflowError) as e:
        raise _named_error(preset, si, e) from None


def core_pipeline(preset: str, si: dict[str, Any]) -> _gyrocore.Pipeline:
    """The core's pipeline of ``preset`` with the SI parameters ``si``: each parameter and the
    rules between them checked (``PipelineConfig::validate``), the one in error named."""
    _check_preset(preset)
    try:
        return _gyrocore.Pipeline(preset, si)
    except (TypeError, ValueError, OverflowError) as e:
        raise _named_error(preset, si, e) from None


def _what_it_takes(error: Exception, value: Any, what: str) -> str:
    """The core's words on a value of the wrong kind, or, for a switch or a name given something
    else, what it takes: the binding's "'int' object is not an instance of 'bool'" (``hdr=0``,
    ``--param hdr=0``, ``tune --set hdr=0``) spoke of Python's types, not of the parameter."""
    said = str(error)
    if said.endswith("is not an instance of 'bool'") and what.endswith("[bool]"):
        return f"a switch takes True or False (on the command line true or false), not {type(value).__name__}"
    if said.endswith("is not an instance of 'str'"):
        return f"takes a name, not {type(value).__name__}"
    return said


def _named_error(preset: str, si: dict[str, Any], error: Exception) -> Exception:
    """The core's error with the parameter it is about and what that parameter takes, where its
    message names no parameter (a conversion: "must be real number, not str", "expected tuple of
    length 2, but got tuple of length 3"; the core converts them all at once). An int beyond
    float64 (``bias_duration=10**400``: "int too large to convert to float") is a ValueError."""
    kind = ValueError if isinstance(error, OverflowError) else type(error)
    if any(key in str(error) for key in si):  # the core's own words name it already
        return error
    for key, value in si.items():
        try:
            _gyrocore.preset_params(preset, {key: value})
        except type(error) as e:
            what = parameters().get(key, "")
            return kind(f"invalid parameter {key} = {shown(value)}: {_what_it_takes(e, value, what)}; {key} is {what}")
    return error

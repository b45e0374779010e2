"""Gyro calibration: static bias (FOG section 2, HDR eq 1-2), least-squares self-calibration
against a heading or rate reference (Hong eq 4-9), rotary-table scale factors with a
temperature-linear model (FOG eq 1-6), a bias-versus-temperature look-up table, and the gyro's
time offset against a reference heading.

The error model is Hong eq 1: ``r_m = (1 + s) r + b + w``, with the scale error ``s`` and the bias
``b`` (what the gyro reads at rest; corrected = measured - bias, HDR eq 2). Hong eq 3 writes the
inverse as ``r = s_bar r_m + b_bar`` with ``s_bar = 1/(1+s)`` and ``b_bar = -b/(1+s)``.

Every result is a :class:`Calibration`: it prints readably, saves to and loads from versioned
JSON with units, and ``overrides()`` gives the pipeline's parameters::

    cal = static_bias(log.t, log.rate)               # rest window found automatically
    gyrocore.process(log.t, log.rate, "hdr", **cal.overrides())

Units: s, rad, rad/s, degC; counter-clockwise positive.

The modules: :mod:`.result` (the record and its JSON), :mod:`.rest` (rests and the static bias),
:mod:`.least_squares` (Hong eq 4-9), :mod:`.rotary` (FOG eq 1-6), :mod:`.temperature` (the bias
table), :mod:`.offset` (the time offset); every public name is here.
"""

from .._checks import public_dir
from .least_squares import MAX_CONDITION, MAX_SCALE_STDERR, heading_reference, rate_reference
from .offset import MAX_OFFSET, MAX_OFFSET_STDERR, MIN_FOLLOWS, MIN_TURN, TimeOffset, time_offset
from .rest import detect_rest, rest_windows, static_bias
from .result import FORMAT, VERSION, BiasTable, Calibration
from .rotary import RotaryTable, Turn, rotary_table
from .temperature import bias_temperature_table

__all__ = [
    "FORMAT", "MAX_CONDITION", "MAX_OFFSET", "MAX_OFFSET_STDERR", "MAX_SCALE_STDERR", "MIN_FOLLOWS", "MIN_TURN",
    "VERSION", "BiasTable", "Calibration", "RotaryTable", "TimeOffset", "Turn", "bias_temperature_table", "detect_rest",
    "heading_reference", "rate_reference", "rest_windows", "rotary_table", "static_bias", "time_offset",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

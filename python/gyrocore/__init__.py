"""gyrocore: a drift-free heading from a yaw-rate gyro.

The per-sample work runs in Rust (``gyrocore._gyrocore``); this package adds the typed API,
log reading, evaluation, simulation and the ``gyrocore`` command. Units are SI (s, rad, rad/s),
counter-clockwise positive; the bias is what the gyro reads at rest.

    >>> import numpy as np, gyrocore
    >>> drive = gyrocore.sim.car_drive(duration=120.0, seed=1)
    >>> result = gyrocore.process(drive.t, drive.rate_measured, "hdr", bias_window=drive.stationary)
    >>> len(result) == len(drive.t)
    True
"""

from . import allan, batch, calibration, deadband, deadreckon, evaluate, io, motion, paper, sim, tune, wholelog
from ._checks import InputWarning
from ._gyrocore import SampleError, __version__
from .evaluate import HeadingErrors, heading_errors
from .io import Log, read_log
from .pipeline import (
    HeadingResult,
    Pipeline,
    downsample,
    integrate,
    parameters,
    preset_names,
    preset_params,
    process,
    recommended_preset,
)

__all__ = [
    "HeadingErrors",
    "HeadingResult",
    "InputWarning",
    "Log",
    "Pipeline",
    "SampleError",
    "__version__",
    "allan",
    "batch",
    "calibration",
    "deadband",
    "deadreckon",
    "downsample",
    "evaluate",
    "heading_errors",
    "integrate",
    "io",
    "motion",
    "paper",
    "parameters",
    "preset_names",
    "preset_params",
    "process",
    "read_log",
    "recommended_preset",
    "sim",
    "tune",
    "wholelog",
]

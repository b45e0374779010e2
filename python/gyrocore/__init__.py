"""gyrocore: a drift-free heading from a yaw-rate gyro.

The per-sample work runs in Rust (``gyrocore._gyrocore``); this package adds the typed API,
log reading, evaluation, simulation and the ``gyrocore`` command. Units are SI (s, rad, rad/s),
counter-clockwise positive; the bias is what the gyro reads at rest.

    >>> import numpy as np, gyrocore
    >>> drive = gyrocore.sim.car_drive(duration=120.0, seed=1)
    >>> result = gyrocore.process(drive.t, drive.rate_measured, "hdr", bias_window=drive.stationary)
    >>> len(result) == len(drive.t)
    True

Where to start (each has its own ``help``; the guide with examples is docs/python.md):

- :func:`process` (arrays in, a :class:`HeadingResult` out: ``heading`` [rad], ``rate`` and
  ``drift`` [rad/s], ``bias_source``, ``rests``; ``columns()`` for a table), :class:`Pipeline`
  (streaming), :func:`integrate`, :func:`parameters` (every parameter with its unit) and
  :func:`preset_names`.
- :func:`read_log` (a file or log folder as a :class:`Log`, with ``Log.process`` and
  ``Log.reference``) and :mod:`gyrocore.datasets` (a sample log, nothing to download).
- :func:`heading_errors` (E_psi against a reference, :class:`HeadingErrors` [deg]) and
  :mod:`gyrocore.evaluate` (presets compared on logs, ``compare``).
- :mod:`gyrocore.calibration` (static bias, scale), :mod:`gyrocore.allan` (Allan deviation,
  noise parameters), :mod:`gyrocore.fixes` (absolute heading fixes, :func:`fuse`),
  :mod:`gyrocore.rests` (the rests found), :mod:`gyrocore.wholelog` (whole-log mode).
- :mod:`gyrocore.io` (readers, writers), :mod:`gyrocore.batch` (many files),
  :mod:`gyrocore.tune` (fitting a preset), :mod:`gyrocore.sim`, :mod:`gyrocore.motion` and
  :mod:`gyrocore.paper` (simulated drives, the papers' experiments), :mod:`gyrocore.deadband`,
  :mod:`gyrocore.deadreckon`; :mod:`gyrocore.pipeline`, :mod:`gyrocore.integration` and
  :mod:`gyrocore.window` (rest windows), where the names above are defined (docs/api.md).

``import gyrocore`` loads only the pipeline (numpy and the extension); the modules below and the
names taken from them load when first used, so that a script that only integrates an array
starts fast and needs numpy only (the optional dependencies: :mod:`gyrocore._extras`).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from ._checks import InputWarning, public_dir
from ._gyrocore import SampleError, __version__
from ._inuse import InUseError
from .integration import downsample, integrate
from .pipeline import (
    HeadingResult,
    Pipeline,
    RestWindowError,
    parameters,
    preset_names,
    preset_params,
    process,
    recommended_preset,
)

if TYPE_CHECKING:
    from . import (
        allan, batch, calibration, datasets, deadband, deadreckon, evaluate, fixes, io, motion, paper, rests, sim,
        tune, wholelog,
    )
    from .evaluate import HeadingErrors, heading_errors
    from .fixes import fuse
    from .io import Log, read_log

_SUBMODULES = ("allan", "batch", "calibration", "datasets", "deadband", "deadreckon", "evaluate", "fixes", "io",
               "motion", "paper", "rests", "sim", "tune", "wholelog")
#: Names of the package taken from a submodule, loaded with it.
_FROM = {"HeadingErrors": "evaluate", "heading_errors": "evaluate", "Log": "io", "read_log": "io", "fuse": "fixes"}


def __getattr__(name: str) -> Any:
    """Load a submodule, or a name taken from one, when it is first used (PEP 562)."""
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    if name in _FROM:
        return getattr(importlib.import_module(f".{_FROM[name]}", __name__), name)
    raise AttributeError(f"module 'gyrocore' has no attribute {name!r}")


#: dir() and tab completion: the public names (submodules not loaded yet among them), not the
#: names imported here (``Any``, ``importlib``) nor the modules loaded as parts of others.
__dir__ = public_dir(__name__)


__all__ = [
    "HeadingErrors",
    "HeadingResult",
    "InUseError",
    "InputWarning",
    "Log",
    "Pipeline",
    "RestWindowError",
    "SampleError",
    "__version__",
    "allan",
    "batch",
    "calibration",
    "datasets",
    "deadband",
    "deadreckon",
    "downsample",
    "evaluate",
    "fixes",
    "fuse",
    "heading_errors",
    "integrate",
    "integration",
    "io",
    "motion",
    "paper",
    "parameters",
    "pipeline",
    "preset_names",
    "preset_params",
    "process",
    "read_log",
    "recommended_preset",
    "rests",
    "sim",
    "tune",
    "wholelog",
    "window",
]

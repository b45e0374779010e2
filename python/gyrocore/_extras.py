"""Optional dependencies: ``pip install gyrocore`` needs numpy only.

The file readers, fitting, plots, bags and Dask each come with an extra of the package; their
modules are imported only where they are used (so that ``import gyrocore`` stays fast), and a
missing one raises :class:`MissingExtra` naming the extra that installs it.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

#: The extra of gyrocore that installs each optional top-level module.
EXTRAS = {
    "pyarrow": "io",
    "tqdm": "io",
    "scipy": "fit",
    "matplotlib": "plot",
    "rosbags": "ros",
    "dask": "dask",
    "distributed": "dask",
    "pynmea2": "nmea",
}


class MissingExtra(ImportError):
    """An optional dependency is not installed; the message names the extra that installs it."""


def require(module: str, purpose: str) -> ModuleType:
    """Import ``module`` (``"scipy.stats"``) for ``purpose`` (``"Allan confidence intervals"``).

    Raises:
        MissingExtra: ``<purpose> needs <package>: pip install 'gyrocore[<extra>]'``.
    """
    top = module.partition(".")[0]
    try:
        return importlib.import_module(module)
    except ImportError as e:
        if e.name is not None and e.name.partition(".")[0] != top:
            raise  # the package is there but one of its own imports failed: not a missing extra
        raise MissingExtra(f"{purpose} needs {top}: pip install 'gyrocore[{EXTRAS[top]}]'") from None


def pyplot(purpose: str) -> Any:
    """matplotlib's pyplot on the Agg backend (files only, no display), or :class:`MissingExtra`."""
    matplotlib = require("matplotlib", purpose)
    matplotlib.use("Agg")
    return require("matplotlib.pyplot", purpose)


def tqdm_class() -> Any:
    """tqdm's progress bar, or None: a bar is a nicety of gyrocore[io], and without tqdm there is none."""
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm

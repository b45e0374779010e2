"""The papers' experiments, reproduced on simulated data with a known truth.

Each function runs one experiment and returns a result whose ``table()`` sets the paper's values
beside ours and whose ``plot(path)`` draws the paper's figure where it has one:

- :func:`hong_allan`: Hong & Park section 2.1, ARW and bias instability of the XV3500 from its
  Allan deviation (their Figure 2), averaged over ten gyros and two runs each, as they did.
- :func:`hong_calibration`: Hong & Park section 3.1, least squares with a rate and a heading
  reference on a gyro with ``s = -10 %``, ``b = 0.1 rad/s`` (their Figures 6 and 7).
- :func:`hong_table_1`: Hong & Park Table 1, pure integration, self-calibration, threshold and both
  on a simulated XV3500 robot run (their Figure 10).
- :func:`hong_table_1_sensitivity`: Table 1 over a grid of gyro noise and turn size, the two
  things the paper leaves open, to show where its order of the methods holds.
- :func:`hdr_figures`: HDR Figures 3 and 5, ``-I`` against the simulated drift around a curving
  episode, without and with the repetition attenuator.
- :func:`hdr_tables`: HDR Tables II and IV, the fourteen drives with one parameter set, with and
  without HDR.
- :func:`fog_rotary_table`: FOG section 3, scale factor against temperature (eq 5, Figure 3) and
  the turn errors after the correction of eq 6 (Figure 6).
- :func:`fog_square_path`: FOG section 4.1, return orientation errors of the 4x4 m
  bi-directional square path (Figure 5).

Every experiment is seeded: the same arguments give the same numbers. Where a paper leaves a
value open (a drift, a trajectory, a noise level), the choice is stated in the function's doc and
in :data:`gyrocore.sim.SENSORS`.
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Callable

from .._checks import public_dir, require_choice
from ..io.atomic import kept_outputs, make_folder
from ._report import Row, _Report, format_table
from .fog import FogRotaryTable, FogSquarePath, fog_rotary_table, fog_square_path
from .hdr import DriveResult, HdrFigures, HdrTables, hdr_figures, hdr_tables
from .hong import (
    AllanReproduction,
    HongCalibration,
    HongTable1,
    HongTable1Sensitivity,
    hong_allan,
    hong_calibration,
    hong_table_1,
    hong_table_1_sensitivity,
)

__all__ = [
    "AllanReproduction",
    "DriveResult",
    "FogRotaryTable",
    "FogSquarePath",
    "HdrFigures",
    "HdrTables",
    "HongCalibration",
    "HongTable1",
    "HongTable1Sensitivity",
    "REPRODUCTIONS",
    "Row",
    "fog_rotary_table",
    "fog_square_path",
    "format_table",
    "hdr_figures",
    "hdr_tables",
    "hong_allan",
    "hong_calibration",
    "hong_table_1",
    "hong_table_1_sensitivity",
    "reproduce",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__


#: Every reproduction: name -> (function, figure file name).
REPRODUCTIONS: dict[str, tuple[Callable[[], _Report], str]] = {
    "hong-allan": (hong_allan, "hong_allan.png"),
    "hong-calibration": (hong_calibration, "hong_calibration.png"),
    "hong-table-1": (hong_table_1, "hong_table_1.png"),
    "hong-table-1-sensitivity": (hong_table_1_sensitivity, "hong_table_1_sensitivity.png"),
    "hdr-figures": (hdr_figures, "hdr_figures_3_5.png"),
    "hdr-tables": (hdr_tables, "hdr_tables_2_4.png"),
    "fog-rotary-table": (fog_rotary_table, "fog_rotary_table.png"),
    "fog-square-path": (fog_square_path, "fog_square_path.png"),
}


def reproduce(name: str, *, out_dir: str | Path | None = ".", overwrite: bool = True) -> _Report:
    """Run the reproduction ``name`` (see :data:`REPRODUCTIONS`) with its defaults, print its
    table and the seed it ran with, and write its figure into ``out_dir`` (created if missing;
    None: no figure; ``overwrite=False`` refuses a figure there before the run, and keeps one
    written meanwhile: FileExistsError)."""
    require_choice("reproduction", name, REPRODUCTIONS)
    run, figure = REPRODUCTIONS[name]
    with kept_outputs([] if out_dir is None else [Path(out_dir) / figure], overwrite, "overwrite=True"):
        return _reproduced(run, figure, out_dir, overwrite)


def _reproduced(run: Callable[[], _Report], figure: str, out_dir: str | Path | None, overwrite: bool) -> _Report:
    """:func:`reproduce`'s run of ``run``: its table printed, its figure written into ``out_dir``."""
    result = run()
    print(result.table())
    seed = inspect.signature(run).parameters["seed"].default
    print(f"simulated data (no real log), seed {seed} (each further run or drive the next one); "
          f"gyrocore.paper.{run.__name__}(seed=N) reruns it from another")
    if out_dir is not None:
        make_folder(Path(out_dir))
        path = result.plot(Path(out_dir) / figure, overwrite=overwrite)
        if path is not None:
            print(f"wrote {path}")
    return result

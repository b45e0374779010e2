"""Plots of a log's headings and their errors against its reference, for :func:`gyrocore.evaluate.compare`
and on their own (:func:`plot_log`); :mod:`gyrocore.evaluate` re-exports the public names.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping, Protocol

import numpy as np

from ._extras import pyplot
from .evaluate_envelope import envelope
from .evaluate_metrics import Reference
from .io import Log
from .io.atomic import kept_outputs, make_folder
from .pipeline import HeadingResult


class Named(Protocol):
    """What names a log's plot: its name, and where it was read (None: built in memory)."""

    @property
    def name(self) -> str: ...

    @property
    def path(self) -> str | None: ...


def plot_path(plot_dir: str | Path, log: Named) -> Path:
    """Where :func:`gyrocore.evaluate.compare` draws the plot of ``log``: ``<plot_dir>/<log name>.png``.

    Raises:
        ValueError: a name that is a path: its plot would land outside ``plot_dir`` (a
            meta.json's name ``/home/me/x`` wrote ``/home/me/x.png``).
    """
    name = log.name
    if os.path.basename(name) != name or "\0" in name:  # NUL: no file name either
        label = log.path if log.path is not None else f"log {log.name}"
        raise ValueError(
            f"{label}: the log's name {name!r} is no file name for its plot ({plot_dir}/<name>.png): "
            "give the log a name without a folder (meta.json's name)"
        )
    return Path(plot_dir) / f"{name}.png"


def evaluation_pyplot() -> Any:
    """matplotlib's pyplot, or an ImportError that names the extra to install."""
    return pyplot("plotting the evaluation")


def plot_log(path: str | Path, log: Log, results: Mapping[str, HeadingResult], *, overwrite: bool = True) -> None:
    """Write a PNG to ``path``: heading of each method and the reference (top), error against time
    (bottom). In a notebook, ``IPython.display.Image(path)`` shows it. ``overwrite=False`` refuses
    a file at ``path`` before the plot is drawn, and keeps one written meanwhile (FileExistsError).

    Headings are aligned with the reference at the first compared time, in degrees.
    """
    path = Path(path)  # a str was "'str' object has no attribute 'parent'", after the plot was drawn
    with kept_outputs([path], overwrite, "overwrite=True"):
        _draw_log(path, log, results, overwrite)


def _draw_log(path: Path, log: Log, results: Mapping[str, HeadingResult], overwrite: bool) -> None:
    """:func:`plot_log`'s figure, drawn and written."""
    plt = evaluation_pyplot()
    from .io.atomic import write_atomically

    reference = Reference(*log.reference())
    t0 = float(log.t[0])
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(10, 6.5))
    for k, (name, r) in enumerate(results.items()):
        tr, err, _ = reference.compared(r.t, r.heading)
        start = np.interp(tr[0], r.t, r.heading)
        if k == 0:
            # The aligned reference is the aligned estimate minus its error.
            ref = np.interp(tr, r.t, r.heading) - start - err
            at = envelope(ref)
            ax1.plot(tr[at] - t0, np.degrees(ref[at]), "k", lw=2.2, label="reference")
        at = envelope(r.heading)  # the points drawn taken first: a long log's lines copied it whole, twice
        ax1.plot(r.t[at] - t0, np.degrees(r.heading[at] - start), lw=1, label=name)
        at = envelope(err)
        ax2.plot(tr[at] - t0, np.degrees(err[at]), lw=1, label=name)
    ax1.set_title(f"{log.name}: heading against the reference")
    ax1.set_ylabel("heading change [deg]")
    ax2.set_ylabel("error [deg]")
    ax2.set_xlabel(f"t - t0 [s] (t0 = {t0:.3f} s)")
    ax2.axhline(0.0, color="k", lw=0.5)
    ax1.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    make_folder(path.parent)
    write_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=100), replace=overwrite)
    plt.close(fig)

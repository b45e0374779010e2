"""What every reproduction's result has: rows of paper value beside ours, notes, a text table, and
a figure written as PNG."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .._extras import MissingExtra, pyplot


@dataclass(frozen=True)
class Row:
    """One line of a comparison: the quantity, the paper's value as printed, ours, the unit."""

    quantity: str
    paper: str
    ours: float | str
    unit: str = ""


def format_table(title: str, rows: tuple[Row, ...] | list[Row], notes: tuple[str, ...] = ()) -> str:
    """A plain-text table: quantity, paper, ours, unit; then the notes."""
    ours = [r.ours if isinstance(r.ours, str) else f"{r.ours:.4g}" for r in rows]
    w0 = max([len("quantity")] + [len(r.quantity) for r in rows])
    w1 = max([len("paper")] + [len(r.paper) for r in rows])
    w2 = max([len("ours")] + [len(o) for o in ours])
    lines = [title, f"{'quantity':<{w0}}  {'paper':>{w1}}  {'ours':>{w2}}  unit"]
    lines.append("-" * len(lines[-1]))
    for r, o in zip(rows, ours):
        lines.append(f"{r.quantity:<{w0}}  {r.paper:>{w1}}  {o:>{w2}}  {r.unit}".rstrip())
    lines.extend(f"note: {n}" for n in notes)
    return "\n".join(lines)


def _pyplot() -> Any:
    """matplotlib's pyplot on the Agg backend, or None (with a hint) when it is not installed."""
    try:
        return pyplot("drawing the figures")
    except MissingExtra as e:
        print(f"(no plot: {e})", file=sys.stderr)
        return None


def _save(fig: Any, path: str | Path, overwrite: bool) -> Path:
    from ..io.atomic import write_atomically

    out = Path(path)
    write_atomically(out, lambda tmp: fig.savefig(tmp, format="png", dpi=100), replace=overwrite)
    fig.clear()
    return out


class _Report:
    """What every result has: a title, rows, notes, ``table()`` and ``plot(path)``."""

    title: str

    def rows(self) -> list[Row]:
        raise NotImplementedError

    def notes(self) -> tuple[str, ...]:
        return ()

    def table(self) -> str:
        """The comparison as text."""
        return format_table(self.title, self.rows(), self.notes())

    def plot(self, path: str | Path, *, overwrite: bool = True) -> Path | None:
        """Write the figure as PNG (None if matplotlib is missing); ``overwrite=False`` refuses a
        file at ``path`` before the figure is drawn, and keeps one written meanwhile (FileExistsError)."""
        from ..io.atomic import kept_outputs

        plt = _pyplot()
        if plt is None:
            return None
        with kept_outputs([path], overwrite, "overwrite=True"):
            fig = self._figure(plt)
            out = _save(fig, path, overwrite)
        plt.close(fig)
        return out

    def _figure(self, plt: Any) -> Any:
        raise NotImplementedError

    def __str__(self) -> str:
        return self.table()

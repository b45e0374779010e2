"""Helpers shared by the subcommands."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..io import atomic_path


def add_command(
    sub: argparse._SubParsersAction[argparse.ArgumentParser],
    name: str,
    help_text: str,
    example: str,
    func: Callable[[argparse.Namespace], int],
) -> argparse.ArgumentParser:
    """Add a subcommand whose ``--help`` ends with an example; ``func(args)`` returns the exit code."""
    # the example also shows in the list of subcommands of ``gyrocore --help``
    parser = sub.add_parser(
        name, help=f"{help_text} (example: {example})", description=help_text, epilog=f"example: {example}"
    )
    parser.set_defaults(func=func)
    return parser


def write_atomically(path: str | Path, write: Callable[[str], object]) -> None:
    """Write through a temporary file in the same folder, then rename: no half-written output."""
    with atomic_path(Path(path)) as tmp:
        write(str(tmp))


def print_json(data: Any) -> None:
    """Machine output on stdout."""
    print(json.dumps(data, indent=2))


def warn(message: str) -> None:
    """One line on stderr: ``gyrocore: warning: ...``."""
    print(f"gyrocore: warning: {message}", file=sys.stderr)


@contextmanager
def progress_bar(description: str) -> Iterator[Callable[[int, int | None, str], None]]:
    """A callback ``(done, total, unit)`` that draws a tqdm bar on stderr, only on a terminal
    (pipes, CI and logs get nothing)."""
    if not sys.stderr.isatty():
        yield lambda done, total, unit: None
        return
    from tqdm import tqdm

    bar: Any = None

    def update(done: int, total: int | None, unit: str) -> None:
        nonlocal bar
        if bar is None:
            bar = tqdm(total=total, unit=unit, unit_scale=True, desc=description, leave=False)
        bar.update(done - bar.n)

    try:
        yield update
    finally:
        if bar is not None:
            bar.close()

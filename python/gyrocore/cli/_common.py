"""Helpers shared by the subcommands."""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path
from typing import Callable


def add_command(
    sub: "argparse._SubParsersAction[argparse.ArgumentParser]",
    name: str,
    help_text: str,
    example: str,
    func: Callable[[argparse.Namespace], int],
) -> argparse.ArgumentParser:
    """Add a subcommand whose ``--help`` ends with an example; ``func(args)`` returns the exit code."""
    parser = sub.add_parser(name, help=help_text, description=help_text, epilog=f"example: {example}")
    parser.set_defaults(func=func)
    return parser


def write_atomically(path: Path, write: Callable[[str], object]) -> None:
    """Write through a temporary file in the same folder, then rename: no half-written output."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)

"""The package's modules: each takes another's public names only (a private name, with a leading
underscore, is its own module's to rename or drop), and each top-level function and class stands
after two blank lines (PEP 8)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

import gyrocore

PACKAGE = Path(gyrocore.__file__).parent


def _private_imports(path: Path) -> list[str]:
    """The private names ``path`` imports from other modules (``from .x import _name``); a
    private module itself (``from . import _gyrocore``) is no name of another's."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [f"{node.module}.{a.name}" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.module
            for a in node.names if a.name.startswith("_") and not a.name.startswith("__")]


@pytest.mark.parametrize("module", ["io/units.py", "fixes_files.py", "fixes_nmea.py"])
def test_the_unit_and_fix_file_readers_import_no_private_name(module: str) -> None:
    """``io.units`` took ``_checks._SUBSET`` (the size of the subset a unit is judged on),
    ``fixes_files`` took ``io.units._normal`` and ``fixes_nmea`` took ``fixes_files._ROW_ERROR``:
    each is now a public name of its module."""
    assert _private_imports(PACKAGE / module) == []


def _blank_lines_before_definitions(path: Path) -> list[str]:
    """Where a top-level ``def`` or ``class`` of ``path`` (or its first decorator, or the comment
    right above it) stands after other than two blank lines: ``line N: K``."""
    lines = path.read_text(encoding="utf-8").split("\n")
    wrong = []
    for i, line in enumerate(lines):
        if not re.match(r"(async def|def|class) ", line):
            continue
        j = i - 1
        while j >= 0 and lines[j].startswith(("@", "#")):  # its decorators and the comment above it
            j -= 1
        blank = 0
        while j >= 0 and lines[j] == "":
            blank, j = blank + 1, j - 1
        if j >= 0 and blank != 2:
            wrong.append(f"line {i + 1}: {blank}")
    return wrong


def test_each_top_level_definition_stands_after_two_blank_lines() -> None:
    """``_checks.keep_readings`` stood after three blank lines and ``_checks.warn`` after one (and a
    few others elsewhere): PEP 8 has two around each top-level function and class."""
    wrong = {str(p.relative_to(PACKAGE)): w for p in sorted(PACKAGE.rglob("*.py"))
             if (w := _blank_lines_before_definitions(p))}
    assert wrong == {}

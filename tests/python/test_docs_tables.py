"""Every table row of the README and the docs pages is in a table: a run of rows that begins with
a header and its separator line, as Markdown renders them. A row appended below a page's last
table, after a paragraph, is shown as text with its bars, not as a row (docs/failure-modes.md's
rows after its fuzzing paragraph were)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SEPARATOR = re.compile(r"^\|(\s*:?-+:?\s*\|)+\s*$")
#: A code span: the docs site's Markdown (Python-Markdown's tables) reads a bar inside one as text.
CODE = re.compile(r"`[^`]*`")


def _cells(row: str) -> int:
    """The cells of a row: its bars less one, a bar escaped (``\\|``) or in a code span being text."""
    return CODE.sub("", row.replace("\\|", "")).strip().count("|") - 1


def strays(text: str) -> list[str]:
    """``line N: ...`` for each row that no table holds, and each whose cells are not its header's."""
    found: list[str] = []
    lines = text.splitlines()
    fenced = False
    header: int | None = None  # the cells of the table the line before belongs to
    for number, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"):
            fenced, header = not fenced, None
            continue
        if fenced or not line.startswith("|"):
            header = None
            continue
        if header is None:
            below = lines[number] if number < len(lines) else ""
            if SEPARATOR.match(below):
                header = _cells(line)
            else:
                found.append(f"line {number}: a row outside any table: {line[:60]}")
        elif SEPARATOR.match(line):
            continue
        elif _cells(line) != header:
            found.append(f"line {number}: {_cells(line)} cells in a table of {header}: {line[:60]}")
    return found


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_row_is_in_a_table(page: Path) -> None:
    assert strays(page.read_text(encoding="utf-8")) == []


def test_a_row_after_a_paragraph_is_found() -> None:
    page = "| a | b |\n|---|---|\n| 1 | 2 |\n\nA paragraph.\n| 3 | 4 |\n"
    assert strays(page) == ["line 6: a row outside any table: | 3 | 4 |"]
    assert strays("| a | b |\n|---|---|\n| 1 | 2 | 3 |\n") == ["line 3: 3 cells in a table of 2: | 1 | 2 | 3 |"]
    assert strays("| a | b |\n|---|---|\n| `|I|` | 2 |\n") == []

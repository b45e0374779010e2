"""A call's signature that a docs page writes out in full is the function's own: every keyword,
in order, with its default."""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import pytest

from gyrocore import batch

ROOT = Path(__file__).resolve().parents[2]


def _shown(page: str, name: str) -> str:
    text = " ".join((ROOT / "docs" / page).read_text(encoding="utf-8").split())
    found = re.search(rf"`({re.escape(name)}\((?!\.\.\.).*?\))`", text)  # not a call such as f(..., x=1)
    assert found, f"docs/{page} writes out no signature of {name}"
    return found[1]


def _actual(function: object) -> str:
    parts, star = [], False
    for p in inspect.signature(function).parameters.values():  # type: ignore[arg-type]
        if p.kind is p.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        if p.kind is p.VAR_KEYWORD:
            parts.append(f"**{p.name}")
        elif p.default is p.empty:
            parts.append(p.name)
        else:
            parts.append(f"{p.name}={p.default!r}".replace("'", '"'))
    return f"{function.__name__}({', '.join(parts)})"  # type: ignore[attr-defined]


@pytest.mark.parametrize(("page", "function"), [("processing.md", batch.process_many)])
def test_a_signature_on_a_page_is_the_function_s(page: str, function: object) -> None:
    # processing.md's process_many left out columns, mode, use_speed, skip_existing, use_fixes and
    # overwrite (whose default, True, is why a link at an output is replaced) and showed chunk_rows=...
    assert _shown(page, function.__name__) == _actual(function)  # type: ignore[attr-defined]

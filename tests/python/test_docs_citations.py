"""A section that the package, its messages, the examples, the tests, the Rust comments or the
docs cite by page and name (docs/fixes_results.md, "Fixes that arrive late") is on that page: a
section moved to another page takes its citations along. CHANGELOG.md is history and keeps the
pages as they were then."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: docs/PAGE.md followed by a quoted name, maybe after "'s" or a comma (in a string, its quotes escaped).
CITED = re.compile(r"docs/([\w-]+\.md)(?:'s)?,?\s+\\?\"([^\"\\]+?)\\?\"")
#: What begins a comment line in the files searched, dropped so that a citation may span lines.
COMMENT = re.compile(r"^\s*(?://[/!]?|#)?\s*")


def _sources() -> list[Path]:
    found = [*(ROOT / "python" / "gyrocore").rglob("*.py"), *(ROOT / "examples").glob("*.py"),
             *(ROOT / "tests" / "python").glob("*.py"), *(ROOT / "rust").rglob("*.rs"),
             *(ROOT / "docs").glob("*.md"), ROOT / "README.md"]
    return [p for p in found if p != Path(__file__).resolve()]


def _flat(text: str) -> str:
    return " ".join(COMMENT.sub("", line) for line in text.splitlines())


def _plain(text: str) -> str:
    """The words of ``text``, in lower case, without Markdown's code and emphasis marks."""
    return " ".join(text.replace("`", "").replace("*", "").lower().split())


def citations() -> list[tuple[str, str, str]]:
    """(the citing file, the page, the section's name), for every citation found."""
    return [(path.relative_to(ROOT).as_posix(), page, " ".join(name.split()))
            for path in _sources()
            for page, name in CITED.findall(_flat(path.read_text(encoding="utf-8")))]


def test_every_cited_section_is_on_the_page_cited() -> None:
    cited = citations()
    # the citations of the heading-fix pages' sections, which moved from docs/fixes.md, are among them
    assert {("python/gyrocore/fixes_stream.py", "fixes_results.md", "Fixes that arrive late"),
            ("python/gyrocore/fixes_check.py", "fixes_model.md", "Fixes checked against the gyro")} <= set(cited)
    wrong = []
    for source, page, name in cited:
        path = ROOT / "docs" / page
        if not path.is_file() or _plain(name) not in _plain(path.read_text(encoding="utf-8")):
            wrong.append(f"{source}: docs/{page} has no {name!r}")
    assert not wrong, "\n".join(wrong)

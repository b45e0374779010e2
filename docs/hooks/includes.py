"""Build-time parts of the docs site (mkdocs.yml's ``hooks``), so that no page copies a text that lives
elsewhere and can drift from it.

A page line ``<!-- include WHAT -->`` is replaced when the site is built by:

- ``README.md:intro``: the README's title and first paragraphs (before its first ``##`` section);
- ``README.md#TITLE`` (one ``#`` or more): the README's section whose heading starts with TITLE,
  with its subsections, its heading at the level given by the number of ``#`` (``#``: the page's
  title, ``##``: as in the README);
- ``CHANGELOG.md``: the whole changelog;
- ``gyrocore --help``: the help of the command and of every subcommand, from their argparse parsers.

The docstrings' Sphinx roles (``:func:``) are dropped from the pages, their names kept as code. A
missing section stops the build naming it. Every page in docs/ is in the navigation: those that
mkdocs.yml's ``nav`` does not list are added after it, in file-name order.
"""

from __future__ import annotations

import argparse
import os
import re
from pathlib import Path
from typing import Any

from mkdocs.exceptions import PluginError

ROOT = Path(__file__).resolve().parents[2]
INCLUDE = re.compile(r"^<!-- include (.+?) -->$", re.M)
HEADING = re.compile(r"^(#+) (.*)$")
SPHINX_ROLE = re.compile(r":(?:func|class|meth|mod|data|attr|exc|obj):(?=<code>)")


def on_files(files: Any, config: Any) -> Any:
    """Add the pages that the configured nav does not list at its end."""
    listed = set(_nav_paths(config["nav"] or []))
    config["nav"] = list(config["nav"] or []) + sorted(
        f.src_uri for f in files.documentation_pages() if f.src_uri not in listed
    )
    return files


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    """Replace every include line of the page with what it names."""
    return INCLUDE.sub(lambda m: _include(m.group(1), page.file.src_uri), markdown)


def on_page_content(html: str, page: Any, config: Any, files: Any) -> str:
    """Drop the Sphinx roles of the docstrings (``:func:`name```), which Markdown shows as text."""
    return SPHINX_ROLE.sub("", html)


def _nav_paths(nav: list[Any]) -> list[str]:
    out: list[str] = []
    for item in nav:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        out.extend(_nav_paths(value) if isinstance(value, list) else [value])
    return out


def _include(what: str, page: str) -> str:
    if what == "CHANGELOG.md":
        return (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    if what == "gyrocore --help":
        return _cli_reference()
    if what == "README.md:intro":
        return "\n".join(_readme_lines()[: _section_starts()[0][0]])
    m = re.fullmatch(r"README\.md(#+)(.+)", what)
    if m is None:
        raise PluginError(f"docs/{page}: cannot include {what!r} (see docs/hooks/includes.py)")
    return _readme_section(m.group(2), len(m.group(1)), page)


def _readme_lines() -> list[str]:
    return (ROOT / "README.md").read_text(encoding="utf-8").splitlines()


def _headings(lines: list[str]) -> list[tuple[int, int, str]]:
    """(line index, level, title) of every heading outside code blocks."""
    out, fenced = [], False
    for i, line in enumerate(lines):
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (m := HEADING.match(line)):
            out.append((i, len(m.group(1)), m.group(2)))
    return out


def _section_starts() -> list[tuple[int, str]]:
    return [(i, title) for i, level, title in _headings(_readme_lines()) if level == 2]


def _readme_section(title: str, level: int, page: str) -> str:
    lines = _readme_lines()
    starts = _section_starts()
    found = [k for k, (_, t) in enumerate(starts) if t.startswith(title)]
    if len(found) != 1:
        raise PluginError(f"docs/{page}: README.md has {len(found)} sections whose heading starts with {title!r} "
                         f"(its ## sections: {', '.join(t for _, t in starts)})")
    begin = starts[found[0]][0]
    end = starts[found[0] + 1][0] if found[0] + 1 < len(starts) else len(lines)
    section = lines[begin:end]
    shift = level - 2
    for i, old, text in _headings(section):
        section[i] = "#" * max(1, old + shift) + " " + text
    # the README links pages of the site as docs/NAME.md
    return re.sub(r"\]\(docs/", "](", "\n".join(section))


def _cli_reference() -> str:
    from gyrocore.cli import build_parser

    columns = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "80"  # argparse wraps at the terminal's width: the page's, on every machine
    try:
        parser = build_parser()
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parts = ["```text", parser.format_help().rstrip(), "```"]
        for name, command in sub.choices.items():
            parts += ["", f"## gyrocore {name}", "", "```text", command.format_help().rstrip(), "```"]
    finally:
        if columns is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = columns
    return "\n".join(parts)

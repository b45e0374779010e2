"""Build-time parts of the docs site (mkdocs.yml's ``hooks``), so that no page copies a text that lives
elsewhere and can drift from it.

A page line ``<!-- include WHAT -->`` is replaced when the site is built by:

- ``CHANGELOG.md``: the whole changelog;
- ``gyrocore --help``: the help of the command and of every subcommand, from their argparse parsers.

The docstrings' Sphinx roles (``:func:``) are dropped from the pages, their names kept as code. Anything
else to include stops the build naming it. Every page in docs/ is in the navigation: those that
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
    raise PluginError(f"docs/{page}: cannot include {what!r} (see docs/hooks/includes.py)")


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

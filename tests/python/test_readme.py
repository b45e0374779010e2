"""Every Python example in the README and in the docs pages runs as written (each in a fresh
interpreter, in a scratch folder beside a link to ../shared, as from a checkout)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import DATA

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
#: (page, its index-th Python block, the block's text), in page order.
EXAMPLES = [
    (page.relative_to(ROOT).as_posix(), index, code)
    for page in PAGES
    for index, code in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S))
]


def test_the_readme_and_the_docs_have_python_examples() -> None:
    readme = [e for e in EXAMPLES if e[0] == "README.md"]
    assert readme, "the README's front page has no Python example"
    # the README had 15 examples before its sections moved into docs/: none was lost on the way
    assert len(EXAMPLES) >= 16


@pytest.mark.parametrize(("page", "index", "code"), EXAMPLES, ids=[f"{p}-{i}" for p, i, _ in EXAMPLES])
def test_example_runs(page: str, index: int, code: str, tmp_path: Path) -> None:
    if not DATA.is_dir():
        pytest.skip(f"shared data not found at {DATA}")
    (tmp_path / "shared").symlink_to(DATA.parent, target_is_directory=True)
    work = tmp_path / "work"
    work.mkdir()
    script = work / f"example_{index}.py"
    script.write_text(code, encoding="utf-8")
    done = subprocess.run([sys.executable, script.name], cwd=work, capture_output=True, text=True, timeout=300)
    first_line = code.splitlines()[0]
    assert done.returncode == 0, f"{page} example {index} ({first_line}) failed:\n{done.stderr[-3000:]}"
    # an example is what a reader copies: it must not show a misuse (processing.md's batch gave the
    # first second of every real log as its rest, and 15 of them warned that the gyro turned in it)
    assert "does not look like a rest" not in done.stderr, f"{page} example {index} gives a rest that is none"

"""Every Python example in the README runs as written (each in a fresh interpreter, in a scratch
folder beside a link to ../shared, as from a checkout)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import DATA

README = Path(__file__).resolve().parents[2] / "README.md"
EXAMPLES = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)


def test_the_readme_has_python_examples() -> None:
    assert len(EXAMPLES) >= 10


@pytest.mark.parametrize("index", range(len(EXAMPLES)))
def test_readme_example_runs(index: int, tmp_path: Path) -> None:
    if not DATA.is_dir():
        pytest.skip(f"shared data not found at {DATA}")
    (tmp_path / "shared").symlink_to(DATA.parent, target_is_directory=True)
    work = tmp_path / "work"
    work.mkdir()
    script = work / f"readme_example_{index}.py"
    script.write_text(EXAMPLES[index], encoding="utf-8")
    done = subprocess.run([sys.executable, script.name], cwd=work, capture_output=True, text=True, timeout=300)
    first_line = EXAMPLES[index].splitlines()[0]
    assert done.returncode == 0, f"README example {index} ({first_line}) failed:\n{done.stderr[-3000:]}"

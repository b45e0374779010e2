"""What pyproject.toml promises of the oldest dependencies and Python versions holds: .ci/floors.txt
pins each dependency at its floor (.ci/run runs the tests on them), and the code is Python 3.10's."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[2]
#: Every Python file of the package, its tests, examples and benchmarks.
SOURCES = sorted(p for folder in ("python", "tests", "examples", "benches") for p in (ROOT / folder).rglob("*.py"))

#: Standard-library names that Python 3.11 or later added: (module, name), name None for a module.
NEWER_THAN_310 = {
    ("tomllib", None), ("wsgiref.types", None),
    ("typing", "Self"), ("typing", "LiteralString"), ("typing", "Never"), ("typing", "assert_never"),
    ("typing", "assert_type"), ("typing", "reveal_type"), ("typing", "Required"), ("typing", "NotRequired"),
    ("typing", "TypeVarTuple"), ("typing", "Unpack"), ("typing", "dataclass_transform"), ("typing", "override"),
    ("datetime", "UTC"), ("enum", "StrEnum"), ("enum", "verify"), ("enum", "member"), ("enum", "nonmember"),
    ("asyncio", "TaskGroup"), ("asyncio", "timeout"), ("asyncio", "Runner"), ("contextlib", "chdir"),
    ("hashlib", "file_digest"), ("operator", "call"), ("math", "cbrt"), ("math", "exp2"),
    ("itertools", "batched"), ("re", "NOFLAG"), ("sys", "exception"),
}
BUILTINS_NEWER_THAN_310 = {"ExceptionGroup", "BaseExceptionGroup"}
#: Where the floor has no wheel for CPython 3.11 (numpy 1.23.0, scipy 1.9.0: Python 3.10 has them),
#: the floors file pins the first release of its series that has one.
FIRST_WITH_A_CP311_WHEEL = {"numpy": Version("1.23.2"), "scipy": Version("1.9.2")}


def _pins() -> dict[str, str]:
    lines = (ROOT / ".ci" / "floors.txt").read_text(encoding="utf-8").splitlines()
    pins = dict(line.split("==") for line in lines if line and not line.startswith("#"))
    return {name.strip().lower(): version.strip() for name, version in pins.items()}


def test_the_floors_file_pins_each_dependency_at_its_floor() -> None:
    tomllib = pytest.importorskip("tomllib")
    from packaging.requirements import Requirement

    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    # the test extra holds every runtime extra's dependencies beside the test runners
    requirements = [Requirement(r) for r in project["dependencies"] + project["optional-dependencies"]["test"]]
    pins = _pins()
    for requirement in requirements:
        (spec,) = requirement.specifier
        assert spec.operator == ">=", f"{requirement}: a floor is a >= bound"
        floor, pin = Version(spec.version), Version(pins[requirement.name.lower()])
        assert pin == FIRST_WITH_A_CP311_WHEEL.get(requirement.name.lower(), floor), requirement
        for extra in requirement.extras:  # dask[distributed]: distributed of dask's version
            assert pins[extra] == pins[requirement.name.lower()]
    named = {r.name.lower() for r in requirements} | {e for r in requirements for e in r.extras}
    assert set(pins) == named


@pytest.mark.parametrize("path", SOURCES, ids=[str(p.relative_to(ROOT)) for p in SOURCES])
def test_the_code_is_python_310s(path: Path) -> None:
    # requires-python says 3.10: the grammar of 3.10 (no except*, no star in an index) and none of
    # the standard library that 3.11 added, which mypy checks in the package alone
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path), feature_version=(3, 10))
    used = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            used |= {(alias.name, None) for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            used |= {(node.module, None)} | {(node.module, alias.name) for alias in node.names}
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            used.add((node.value.id, node.attr))
        elif isinstance(node, ast.Name) and node.id in BUILTINS_NEWER_THAN_310:
            used.add(("builtins", node.id))
    assert not used & (NEWER_THAN_310 | {("builtins", b) for b in BUILTINS_NEWER_THAN_310})

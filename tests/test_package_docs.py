"""The tables of contents stay true: every package's docstring (its ``__init__.py``) names each of
its modules and subpackages, as `name` (issue 38)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import rockbridge_cli

PACKAGE = Path(rockbridge_cli.__file__).resolve().parent
PACKAGES = sorted(p.parent for p in PACKAGE.rglob("__init__.py"))


def contents(package: Path) -> list[str]:
    """The modules and subpackages of a package, by name."""
    modules = [p.stem for p in package.glob("*.py") if p.stem != "__init__"]
    return sorted(modules + [p.parent.name for p in package.glob("*/__init__.py")])


@pytest.mark.parametrize(
    "package", PACKAGES, ids=lambda p: p.relative_to(PACKAGE.parent).as_posix()
)
def test_the_docstring_names_every_module(package):
    docstring = ast.get_docstring(ast.parse((package / "__init__.py").read_text("utf-8"))) or ""
    missing = [name for name in contents(package) if f"`{name}`" not in docstring]
    assert not missing, f"{package.name}/__init__.py's docstring does not name {missing}"


def test_every_package_is_checked():
    assert {p.name for p in PACKAGES} >= {
        "rockbridge_cli", "core", "motions", "records", "results", "config", "assessment",
        "study", "executors", "plots", "report", "cli",
    }  # fmt: skip

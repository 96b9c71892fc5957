"""The numerical core stays free of the I/O and presentation libraries (click, yaml, pydantic,
h5py, pandas, matplotlib): checked on the imports as written and on what importing loads."""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import rockbridge_cli.core

FORBIDDEN = ("click", "yaml", "pydantic", "h5py", "pandas", "matplotlib")
CORE = Path(rockbridge_cli.core.__file__).resolve().parent
MODULES = sorted(p.stem for p in CORE.glob("*.py"))


def test_core_has_modules():
    assert {"geometry", "kinematics", "dynamics", "impacts", "summary"} <= set(MODULES)


def imported_names(path: Path) -> list[tuple[str, int]]:
    """(module, level) of every import statement in a file, at any depth."""
    names = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names += [(alias.name, 0) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            names.append((node.module or "", node.level))
    return names


def test_core_sources_import_nothing_forbidden():
    for name in MODULES:
        for module, level in imported_names(CORE / f"{name}.py"):
            top = module.split(".")[0]
            if level == 0:
                assert top not in FORBIDDEN, (name, module)
                # absolute imports of the package must stay inside the core
                if top == "rockbridge_cli":
                    assert module.startswith("rockbridge_cli.core"), (name, module)
            else:
                # relative imports may not climb out of core/ (to config, cli, plots, …)
                assert level == 1, (name, module, level)


def test_importing_the_core_loads_nothing_forbidden():
    # numba itself imports yaml (for its optional .numba_config.yaml), so the baseline is what the
    # core's own dependencies (numpy, scipy, numba) load; the core may add nothing forbidden.
    code = (
        "import importlib, json, sys\n"
        f"forbidden = {FORBIDDEN!r}\n"
        "loaded = lambda: {m for m in sys.modules if m.split('.')[0] in forbidden}\n"
        "import numpy, scipy.optimize, scipy.fft, numba\n"
        "baseline = loaded()\n"
        f"for name in {MODULES!r}:\n"
        "    importlib.import_module('rockbridge_cli.core.' + name)\n"
        "print(json.dumps({'baseline': sorted(baseline), 'added': sorted(loaded() - baseline)}))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout.strip().splitlines()[-1])
    assert report["added"] == []
    # nothing but numba's yaml in the baseline
    assert {m.split(".")[0] for m in report["baseline"]} <= {"yaml"}

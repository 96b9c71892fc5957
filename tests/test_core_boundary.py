"""The numerical rooms (the core and the ground-motion numerics) stay free of the I/O and
presentation libraries (click, yaml, pydantic, h5py, pandas, matplotlib): checked on the imports as
written and on what importing loads. The package's rooms import in one direction, from the ground
up (docs/architecture.md)."""

from __future__ import annotations

import ast
import json
import os
from pathlib import Path

import pytest
from conftest import fresh_python

import rockbridge_cli.core

FORBIDDEN = ("click", "yaml", "pydantic", "h5py", "pandas", "matplotlib")
CORE = Path(rockbridge_cli.core.__file__).resolve().parent
MOTIONS = CORE.parent / "motions"
MODULES = sorted(p.stem for p in CORE.glob("*.py"))
NUMERIC = sorted(
    f"{folder.name}.{p.stem}" for folder in (CORE, MOTIONS) for p in folder.glob("*.py")
)
"""The modules of the numerical rooms, as ``core.solver``, ``motions.matching``."""


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
    for name in NUMERIC:
        room = name.split(".")[0]
        for module, level in imported_names(CORE.parent / f"{name.replace('.', '/')}.py"):
            top = module.split(".")[0]
            if level == 0:
                assert top not in FORBIDDEN, (name, module)
                # absolute imports of the package must stay inside the core
                if top == "rockbridge_cli":
                    assert module.startswith("rockbridge_cli.core"), (name, module)
            elif room == "core":
                # relative imports may not climb out of core/ (to config, cli, plots, …)
                assert level == 1, (name, module, level)
            else:
                # the ground-motion numerics reach the core for its compiler and vocabulary only
                allowed = ("core._jit", "core.quantities")
                assert level == 1 or (level == 2 and module in allowed), (name, module)


def test_importing_the_core_loads_nothing_forbidden():
    # numba itself imports yaml (for its optional .numba_config.yaml), so the baseline is what the
    # core's own dependencies (numpy, scipy, numba) load; the core may add nothing forbidden.
    code = (
        "import importlib, json, sys\n"
        f"forbidden = {FORBIDDEN!r}\n"
        "loaded = lambda: {m for m in sys.modules if m.split('.')[0] in forbidden}\n"
        "import numpy, scipy.optimize, scipy.fft, numba\n"
        "baseline = loaded()\n"
        f"for name in {NUMERIC!r}:\n"
        "    importlib.import_module('rockbridge_cli.' + name)\n"
        "print(json.dumps({'baseline': sorted(baseline), 'added': sorted(loaded() - baseline)}))\n"
    )
    report = json.loads(fresh_python(code).splitlines()[-1])
    assert report["added"] == []
    # nothing but numba's yaml in the baseline
    assert {m.split(".")[0] for m in report["baseline"]} <= {"yaml"}


PACKAGE = CORE.parent


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path: Path, anywhere: bool = True) -> set[str]:
    """The package's modules a file imports: at any depth (inside functions and ``TYPE_CHECKING``
    blocks too), or at its top level only (what loading it loads)."""
    name = module_name(path)
    package = name if path.stem == "__init__" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = set()
    for node in ast.walk(tree) if anywhere else tree.body:
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")
            base = base[: len(base) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            targets = [module] + [f"{module}.{alias.name}" for alias in node.names]
        elif isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        else:
            continue
        found |= {t for t in targets if t.startswith("rockbridge_cli") and t != name}
    return found


def top_level_imports(path: Path) -> set[str]:
    """The package's modules a file imports at its top level."""
    return imports(path, anywhere=False)


SOURCES = {module_name(p): p for p in PACKAGE.rglob("*.py")}


def test_the_package_imports_in_one_direction():
    """No two modules import each other, directly or round a loop, counting the imports inside
    functions (issue 13: config.study read records, which read config.records back; issue 30:
    fragility imported the IDA rule from study, which imported fragility)."""
    graph = {name: imports(path) & SOURCES.keys() for name, path in SOURCES.items()}
    for name in graph:  # a package's __init__ is loaded on the way to any of its modules
        graph[name] -= {name.rpartition(".")[0]}
    state: dict[str, int] = {}

    def visit(name: str, trail: list[str]) -> None:
        state[name] = 1
        for target in sorted(graph[name]):
            assert state.get(target) != 1, " -> ".join([*trail, name, target])
            if target not in state:
                visit(target, [*trail, name])
        state[name] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name, [])


LAYERS = (
    ("core", "errors", "cpus", "interrupts"),
    ("motions", "paths", "kinds"),
    ("records", "warmup"),
    ("results",),
    ("config",),
    ("assessment",),
    ("study", "plots"),
    ("report",),
    ("cli",),
)
"""The package's rooms from the ground up (docs/architecture.md): a room imports its own modules and
the rooms of the layers below it, never those above."""

BACK_UP = {
    ("rockbridge_cli.records.sets", "rockbridge_cli.config.record_sets"),
    ("rockbridge_cli.records.sets", "rockbridge_cli.config.records"),
    ("rockbridge_cli.records.manifest", "rockbridge_cli.config.record_sets"),
    ("rockbridge_cli.records.target", "rockbridge_cli.config.record_sets"),
}
"""The one room's import that runs back up: a record set is generated from its config (its
generator, manifest and target read `config.record_sets.RecordSetConfig`; the generator knows
its seeds' FEMA P695 set, `config.records.FemaSet`)."""


def room(module: str) -> str:
    """The room of a module: its subpackage, or the module itself at the package's top."""
    return module.split(".")[1]


def test_each_room_imports_only_the_rooms_below_it():
    layer = {name: height for height, names in enumerate(LAYERS) for name in names}
    assert {room(m) for m in SOURCES if m != "rockbridge_cli"} == layer.keys()
    upward = set()
    for name, path in SOURCES.items():
        for target in imports(path) & SOURCES.keys():
            if target != "rockbridge_cli" and layer[room(target)] > layer[room(name)]:
                upward.add((name, target))
    assert upward == BACK_UP


def test_nothing_below_the_study_imports_it():
    """The IDA rule lives in `assessment`; `study` plans its rounds with it (issue 30)."""
    below = [
        m
        for m in SOURCES
        if m != "rockbridge_cli" and room(m) not in ("study", "plots", "report", "cli")
    ]
    for name in below:
        assert not {t for t in imports(SOURCES[name]) if t.startswith("rockbridge_cli.study")}


def test_record_files_sit_below_the_configs_that_read_them():
    """config.study reads record files and sets, and record sets are generated from a config:
    the modules that read them import no config, and no config imports the record-set
    generator."""
    for module in ("files.py", "set_files.py"):
        imported = top_level_imports(PACKAGE / "records" / module)
        assert not {m for m in imported if m.startswith("rockbridge_cli.config")}
    for path in (PACKAGE / "config").glob("*.py"):
        assert not {
            m for m in top_level_imports(path) if m.startswith("rockbridge_cli.records.sets")
        }


def test_the_parent_of_a_study_loads_no_compiled_kernel():
    """The process that reads a study and hands its analyses to workers imports neither numba
    nor scipy's solvers (their import is a third of a second it would add to every run, serial
    before any worker starts); the workers load them."""
    code = (
        "import sys\n"
        "from rockbridge_cli.config.study import load_study\n"
        "from rockbridge_cli.study.run import run_study\n"
        "heavy = {'numba', 'scipy.optimize', 'scipy.interpolate', 'scipy.fft', 'scipy.linalg',"
        " 'scipy.special', 'scipy.stats', 'scipy.signal'}\n"
        "print(sorted(heavy & set(sys.modules)))\n"
    )
    assert fresh_python(code) == "[]"


def test_the_results_writer_only_writes():
    """The results file knows no config, no ground-motion numerics and no record files: what it
    stores of a study is computed by `study.describe` (issue 38)."""
    for path in (PACKAGE / "results").glob("*.py"):
        rooms = {room(m) for m in imports(path) & SOURCES.keys() if m != "rockbridge_cli"}
        assert rooms <= {"results", "core", "errors", "paths", "kinds"}, (path.name, rooms)


def test_a_worker_loads_no_scipy_subpackage():
    """What a worker imports for its analyses (the kernels, `warmup`, which `study.kernels`
    calls, the study's description) loads nothing of scipy beyond its top-level package (which
    the results file's writer reads the version of): importing scipy's subpackages took a
    quarter of a second of every worker's start (issue 43); the tables' splines and the failure
    rotations are computed without them (`core.tables.not_a_knot`, `core.impacts`)."""
    code = (
        "import sys\n"
        "import scipy\n"
        "baseline = set(sys.modules)\n"
        "import rockbridge_cli.core.analysis, rockbridge_cli.warmup, rockbridge_cli.study.kernels\n"
        "import rockbridge_cli.study.describe, rockbridge_cli.study.executors.worker\n"
        "print(sorted(m for m in set(sys.modules) - baseline if m.startswith('scipy')))\n"
    )
    assert fresh_python(code) == "[]"


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="no compiled kernel")
def test_rockbridge_s_own_processes_load_the_kernels_without_numba_s_blas_probe():
    """When its compiled code first loads, numba imports ``scipy.linalg`` (0.18 s by ``python
    -X importtime``, scipy 1.17) to learn whether the ``np.convolve`` of compiled code may use
    BLAS. A ``rockbridge`` command and a local pool's worker (`study.kernels.own_process`) skip
    that probe (issue 43: a worker's start); another program's process keeps it, and numba
    there is as it was. The kernels give the same bits either way: an analysis of the studied
    bridge under a pulse at `default`, in both processes."""
    code = (
        "import sys\n"
        "from rockbridge_cli.study import kernels\n"
        "if {own}: kernels.own_process()\n"
        "kernels.prepare()\n"
        "import numba.np.arraymath\n"
        "from rockbridge_cli import warmup\n"
        "from rockbridge_cli.core.bridge import Bridge\n"
        "response = warmup.analyze(Bridge(warmup.studied_bridge()), warmup.pulse(), "
        "warmup.TIME_STEP, 'default')\n"
        "print('scipy.linalg' in sys.modules, numba.np.arraymath._HAVE_BLAS, "
        "[value.hex() for peak in response.peaks.values() for value in peak])\n"
    )
    own = fresh_python(code.format(own=True))
    other = fresh_python(code.format(own=False))
    assert own.startswith("False False [") and other.startswith("True True [")
    assert own.split(" ", 2)[2] == other.split(" ", 2)[2]
    assert "nan" not in own.split(" ", 2)[2]  # the peaks were computed

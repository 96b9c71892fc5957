"""The set-up a new user follows: README's two commands, .ci/run and the Dockerfile agree."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from packaging.version import Version

REPO = Path(__file__).resolve().parents[1]


def readme_commands() -> list[str]:
    """The first two lines of README's first code block (what .ci/run executes)."""
    text = (REPO / "README.md").read_text(encoding="utf-8")
    block = re.search(r"```\w*\n(.*?)```", text, re.S)
    assert block, "README has no code block"
    return block.group(1).strip().splitlines()[:2]


def test_readme_starts_with_the_install_and_test_commands():
    install, tests = readme_commands()
    assert "pip install ." in install and "rockbridge run configs/studies/" in install
    assert "pytest" in tests
    study = re.search(r"rockbridge run (\S+)", install).group(1)
    assert (REPO / study).is_file()


def test_ci_runs_the_readme_commands():
    script = (REPO / ".ci" / "run").read_text(encoding="utf-8")
    assert "README.md" in script and "head -n 2" in script


def dockerfile() -> list[tuple[str, str]]:
    """The Dockerfile's instructions as (keyword, arguments), continuation lines joined."""
    text = (REPO / "Dockerfile").read_text(encoding="utf-8").replace("\\\n", " ")
    lines = [line.strip() for line in text.splitlines()]
    return [tuple(line.split(None, 1)) for line in lines if line and not line.startswith("#")]


def test_dockerfile_installs_from_the_lock_and_runs_as_a_user():
    docker = (REPO / "Dockerfile").read_text(encoding="utf-8")
    commands = [
        " ".join(part.split())
        for keyword, arguments in dockerfile()
        if keyword == "RUN"
        for part in arguments.split("&&")
    ]
    lock = commands.index("pip install --require-hashes -r requirements.lock")
    package = commands.index("pip install --no-deps --no-build-isolation .")
    warm = commands.index("python -m rockbridge_cli.warmup")
    assert lock < package < warm
    assert commands[warm + 1] == 'chmod -R a+rwX "$NUMBA_CACHE_DIR"'
    assert re.search(r"^FROM python:3\.\d+-slim$", docker, re.M)
    assert re.search(r"^USER (?!root)\w+$", docker, re.M)
    assert 'ENTRYPOINT ["rockbridge"]' in docker
    assert (REPO / ".dockerignore").is_file()


def test_the_lock_pins_every_dependency_within_pyproject_and_with_hashes():
    """requirements.lock (uv pip compile --generate-hashes) satisfies pyproject's ranges, so the
    image runs what `pip install .` could install, and pins the build backend for
    --no-build-isolation."""
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    wanted = (
        project["project"]["dependencies"]
        + project["project"]["optional-dependencies"]["dask"]
        + project["dependency-groups"]["build"]
    )
    text = (REPO / "requirements.lock").read_text(encoding="utf-8")
    pins = dict(re.findall(r"^([A-Za-z0-9_.-]+)==(\S+) \\$", text, re.M))
    pins = {canonicalize_name(name): Version(version) for name, version in pins.items()}
    for line in wanted:
        requirement = Requirement(line)
        name = canonicalize_name(requirement.name)
        assert name in pins, f"{name} is not in requirements.lock"
        assert pins[name] in requirement.specifier, f"{name}=={pins[name]} outside {line!r}"
    entries = re.split(r"\n(?=[A-Za-z])", text.split("\n", 2)[2].strip())
    assert len(entries) == len(pins)
    assert all("--hash=sha256:" in entry for entry in entries)


def test_every_path_the_dockerfile_copies_exists():
    docker = (REPO / "Dockerfile").read_text(encoding="utf-8")
    for line in re.findall(r"^COPY (.+) \S+$", docker, re.M):
        for source in line.split():
            assert (REPO / source).exists(), source


SIGNATURES = """
import json, sys
from click.testing import CliRunner
from numba.core.registry import CPUDispatcher
import rockbridge_cli.core
from rockbridge_cli import warmup
from rockbridge_cli.cli import main

if sys.argv[1] == "warm-up":
    warmup.compile_kernels()  # what `python -m rockbridge_cli.warmup` compiles
else:
    study, output = sys.argv[2:]
    for preset in ("fast", "default", "reference", "paper"):
        command = ["run", study, "--workers", "1", "--fidelity", preset, "--overwrite", "-o",
                   output]
        result = CliRunner().invoke(main, command)
        assert result.exit_code == 0, result.output
kernels = {
    (name, kernel)
    for name, module in list(sys.modules.items())
    if name.startswith("rockbridge_cli.")
    for kernel in vars(module).values()
    if isinstance(kernel, CPUDispatcher)
}
print(json.dumps({f"{k.py_func.__module__}.{k.py_func.__qualname__}": sorted(map(str, k.signatures))
                  for _, k in kernels if k.signatures}))
"""
"""Run the warm-up's calls, or `rockbridge run` at every preset, in this process; print the
signatures each compiled kernel was called with (compiled, or loaded from numba's cache)."""


@pytest.mark.slow
@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="nothing is compiled")
@pytest.mark.usefixtures("vertical_kernels", "device_kernels")  # its processes only load them
def test_the_warm_up_reaches_every_kernel_a_run_uses(tmp_path):
    """The Dockerfile's build step (`python -m rockbridge_cli.warmup`) calls every kernel that
    `rockbridge run` at every preset calls, with the same argument types: a run after it loads
    them all from the cache and compiles none. Compared by the signatures each process called
    (numba's dispatchers), so that it holds whatever the cache held before: on the suite's own
    cache, both load what is there (no compile of a cold cache of its own)."""
    script = [sys.executable, "-c", SIGNATURES]
    warmed = subprocess.run([*script, "warm-up"], check=True, timeout=1800, capture_output=True,
                            text=True)  # fmt: skip
    study = str(REPO / "configs" / "studies" / "quick.yaml")
    ran = subprocess.run([*script, "run", study, str(tmp_path / "quick.h5")], check=True,
                         timeout=1800, capture_output=True, text=True)  # fmt: skip
    reached = json.loads(warmed.stdout.splitlines()[-1])
    used = json.loads(ran.stdout.splitlines()[-1])
    assert len(used) > 5 and "rockbridge_cli.core.solver.integrate" in used
    missing = {name: sorted(set(signatures) - set(reached.get(name, ())))
               for name, signatures in used.items()}  # fmt: skip
    assert not any(missing.values()), missing


def test_the_warm_up_also_compiles_the_package_the_command_runs(monkeypatch, tmp_path):
    """Run in a checkout, `python -m rockbridge_cli.warmup` imports the checkout's package (the
    current folder comes first), while the `rockbridge` command imports the installed one: the
    warm-up compiles both, the installed one's from a folder without a checkout; nothing more
    when they are one."""
    from rockbridge_cli import warmup

    compiled, launched = [], []
    monkeypatch.setattr(warmup, "compile_kernels", lambda: compiled.append(1))
    monkeypatch.setattr(warmup, "cache_folder", lambda: "cache")

    def run(command, cwd, check):
        launched.append((command, list(Path(cwd).iterdir())))  # what the folder holds

    monkeypatch.setattr(warmup.subprocess, "run", run)
    monkeypatch.setattr(warmup, "commanded_package", lambda: tmp_path / "site" / "rockbridge_cli")
    warmup.main()
    assert compiled == [1] and len(launched) == 1
    command, held = launched[0]
    assert command[1:] == ["-m", "rockbridge_cli.warmup"] and held == []
    here = Path(warmup.__file__).resolve().parent
    monkeypatch.setattr(warmup, "commanded_package", lambda: here)
    warmup.main()
    assert compiled == [1, 1] and len(launched) == 1


def test_the_package_the_command_runs_is_found_outside_the_current_folder(monkeypatch, tmp_path):
    """A folder named rockbridge_cli in the current folder is not the package the command runs:
    that is the installed one (the checkout itself with an editable install, site-packages with
    `pip install .`, as CI installs it while the tests import the checkout)."""
    from rockbridge_cli import warmup

    (tmp_path / "rockbridge_cli").mkdir()
    (tmp_path / "rockbridge_cli" / "__init__.py").write_text("", encoding="utf-8")  # a shadow
    monkeypatch.chdir(tmp_path)
    found = warmup.commanded_package()
    assert found is not None and found != (tmp_path / "rockbridge_cli").resolve()
    assert (found / "warmup.py").is_file() and (found / "core" / "solver.py").is_file()

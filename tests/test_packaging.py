"""The set-up a new user follows: README's two commands, .ci/run and the Dockerfile agree."""

from __future__ import annotations

import re
from pathlib import Path

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


def test_dockerfile_installs_as_readme_says_and_runs_as_a_user():
    docker = (REPO / "Dockerfile").read_text(encoding="utf-8")
    install = readme_commands()[0]
    command = re.search(r"^RUN (pip install \S+)$", docker, re.M)
    assert command and command.group(1) in install
    assert re.search(r"^FROM python:3\.\d+-slim$", docker, re.M)
    assert re.search(r"^USER (?!root)\w+$", docker, re.M)
    assert 'ENTRYPOINT ["rockbridge"]' in docker
    assert (REPO / ".dockerignore").is_file()


def test_every_path_the_dockerfile_copies_exists():
    docker = (REPO / "Dockerfile").read_text(encoding="utf-8")
    for line in re.findall(r"^COPY (.+) \S+$", docker, re.M):
        for source in line.split():
            assert (REPO / source).exists(), source

"""The worked notebook of README's "From Python" path runs (issue 44, item 3).

`docs/notebooks/from-python.py`, a jupytext "percent" script, runs as plain Python in a fresh
process from a temporary working folder, writes its figure there and nothing into the
repository.
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from studies import REPO

NOTEBOOK = REPO / "docs" / "notebooks" / "from-python.py"


def tree(root) -> set[str]:
    """The repository's files, caches (numba's beside the sources) and hidden folders left out."""
    return {
        p.relative_to(root).as_posix()
        for p in root.rglob("*")
        if not any(
            part.startswith(".") or part == "__pycache__" for part in p.relative_to(root).parts
        )
    }


@pytest.mark.slow  # a study in fresh processes: about 10 s on two idle cores
def test_the_notebook_runs_as_a_script_and_draws_its_figure(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROCKBRIDGE_PATHS"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(REPO), env.get("PYTHONPATH"))))
    env["MPLBACKEND"] = "Agg"
    before = tree(REPO)
    done = subprocess.run(
        [sys.executable, str(NOTEBOOK)], capture_output=True, text=True, cwd=tmp_path, env=env,
        timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    assert (tmp_path / "from-python.png").stat().st_size > 0
    assert (tmp_path / "results" / "stripes.h5").is_file()
    assert tree(REPO) == before, "the notebook wrote into the repository"

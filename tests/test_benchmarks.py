"""The benchmarks run as their docstrings say, from any folder (issue 40: `bench_study.py`
without ``--bundled`` crashed timing the bundled studies from a temporary folder, where the
confinement of a config's paths refused their ``../../records``)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from studies import REPO


@pytest.mark.slow
def test_bench_study_times_a_bundled_study_from_another_folder(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "ROCKBRIDGE_PATHS"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, (str(REPO), env.get("PYTHONPATH"))))
    done = subprocess.run(
        [sys.executable, str(REPO / "benchmarks" / "bench_study.py"), "--sizes", "3",
         "--workers", "1", "--histories", "none", "--bundled", "paper-stripes"],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    rows = [line.split() for line in done.stdout.splitlines()]
    assert ["3", "none", "1"] == next(r for r in rows if r[:1] == ["3"])[:3]
    stripes = next(r for r in rows if r[:1] == ["paper-stripes"])
    assert stripes[3] == "420"  # 3 bridges × 10 records × 14 PGAs (configs/studies)

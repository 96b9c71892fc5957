"""A first run on the image's empty numba cache: it compiles every kernel once and says so.

Apart from the other checks of the image (`test_packaging.py`) because it alone compiles on
purpose, on a cache and a kernel lock of its own (`no_kernels`): on a cold suite cache (CI's) its
worker starts it at once while the other compiles the suite's kernels (tests/conftest.py).
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from test_packaging import REPO, dockerfile

pytestmark = pytest.mark.no_kernels


@pytest.mark.slow
@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="nothing is compiled")
def test_a_cold_run_compiles_once_and_says_so(tmp_path):
    """On the image's empty NUMBA_CACHE_DIR, a first `rockbridge run` on two workers compiles
    every kernel once (numba's cache log: each compiled kernel saved by one process) and says
    so on one line. (The one test that compiles on purpose: 834 s on a loaded host when it also
    ran the whole warm-up; what the warm-up reaches is the next test's, on the suite's cache.)"""
    cache = dict(
        arguments.split("=", 1)
        for keyword, arguments in dockerfile()
        if keyword == "ENV"
        for arguments in arguments.split()
        if "=" in arguments
    )["NUMBA_CACHE_DIR"]
    assert cache.startswith("/opt/rockbridge/")  # inside the image, beside the bundled files
    # a kernel lock of its own too (`study.kernels._kernel_lock`, in the temporary folder): the
    # suite's other processes, loading from the suite's cache, wait for no compile of this one
    environment = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
        "TMPDIR": str(tmp_path),
    }
    study = str(REPO / "configs" / "studies" / "quick.yaml")
    first = [sys.executable, "-c", "from rockbridge_cli.cli import entry; entry()", "run", study,
             "--workers", "2", "-o", str(tmp_path / "first.h5")]  # fmt: skip
    cold = subprocess.run(first, env={**environment, "NUMBA_DEBUG_CACHE": "1"}, check=True,
                          timeout=1800, capture_output=True, text=True)  # fmt: skip
    saved = [line for line in cold.stdout.splitlines() if line.startswith("[cache] data saved")]
    assert saved and len(saved) == len(set(saved))
    assert cold.stderr.count("compiling the analysis kernels") == 1

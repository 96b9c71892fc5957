"""The default worker count: the CPUs a process may use, after its affinity and cgroup quota.

The cgroup cases are fake file trees laid out as the kernel's are (cgroup v2 ``cpu.max``, v1
``cpu.cfs_quota_us``/``cpu.cfs_period_us``, both in µs), so each expected count is the quota
over the period, rounded up, capped by the affinity mask.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from studies import write_study

from rockbridge_cli.cpus import cgroup_cpu_quota, usable_cpus

needs_affinity = pytest.mark.skipif(
    not hasattr(os, "sched_setaffinity"), reason="no CPU affinity on this platform"
)


def cgroups(root: Path, lines: str, files: dict[str, str]) -> Path:
    """A fake ``/proc/self/cgroup`` with ``lines`` and cgroup files under ``root``."""
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    proc = root / "proc-self-cgroup"
    proc.write_text(lines)
    return proc


def test_cgroup_v2_quota(tmp_path):
    proc = cgroups(tmp_path, "0::/job\n", {"job/cpu.max": "150000 100000\n"})
    assert cgroup_cpu_quota(tmp_path, proc) == 1.5


def test_cgroup_v2_without_quota(tmp_path):
    proc = cgroups(tmp_path, "0::/job\n", {"job/cpu.max": "max 100000\n"})
    assert cgroup_cpu_quota(tmp_path, proc) is None


def test_the_tightest_quota_of_the_cgroup_and_its_ancestors(tmp_path):
    files = {"cpu.max": "max 100000", "a/cpu.max": "100000 100000", "a/b/cpu.max": "400000 100000"}
    proc = cgroups(tmp_path, "0::/a/b\n", files)
    assert cgroup_cpu_quota(tmp_path, proc) == 1.0


def test_a_container_s_own_cgroup_is_the_mount_root(tmp_path):
    """In a container, /proc/self/cgroup names a host path the container's mount does not have."""
    proc = cgroups(tmp_path, "0::/kubepods/pod1/abc\n", {"cpu.max": "200000 100000"})
    assert cgroup_cpu_quota(tmp_path, proc) == 2.0


def test_cgroup_v1_quota(tmp_path):
    files = {
        "cpu,cpuacct/docker/x/cpu.cfs_quota_us": "50000\n",
        "cpu,cpuacct/docker/x/cpu.cfs_period_us": "100000\n",
    }
    proc = cgroups(tmp_path, "4:memory:/docker/x\n2:cpu,cpuacct:/docker/x\n", files)
    assert cgroup_cpu_quota(tmp_path, proc) == 0.5


def test_cgroup_v1_unlimited(tmp_path):
    files = {"cpu/cpu.cfs_quota_us": "-1\n", "cpu/cpu.cfs_period_us": "100000\n"}
    proc = cgroups(tmp_path, "1:cpu:/\n", files)
    assert cgroup_cpu_quota(tmp_path, proc) is None


@pytest.mark.parametrize(
    "lines, files",
    [
        ("", {}),  # no cgroups listed
        ("0::/\n", {}),  # v2 without the cpu controller
        ("0::/\n", {"cpu.max": "garbage\n"}),
        ("not a cgroup line\n", {}),
    ],
)
def test_no_readable_quota(tmp_path, lines, files):
    proc = cgroups(tmp_path, lines, files)
    assert cgroup_cpu_quota(tmp_path, proc) is None


def test_no_proc_file(tmp_path):
    assert cgroup_cpu_quota(tmp_path, tmp_path / "absent") is None


@needs_affinity
def test_the_quota_caps_the_affinity_rounded_up(tmp_path):
    affinity = len(os.sched_getaffinity(0))
    half = cgroups(tmp_path, "0::/\n", {"cpu.max": "50000 100000"})
    assert usable_cpus(tmp_path, half) == 1  # never fewer than one
    many = cgroups(tmp_path, "0::/\n", {"cpu.max": f"{100000 * (affinity + 8)} 100000"})
    assert usable_cpus(tmp_path, many) == affinity  # a quota above the mask does not add CPUs
    if affinity >= 2:
        part = cgroups(tmp_path, "0::/\n", {"cpu.max": "150000 100000"})
        assert usable_cpus(tmp_path, part) == 2


@pytest.mark.slow
@needs_affinity
def test_run_pinned_to_one_cpu_uses_one_worker_and_says_so(tmp_path):
    """`taskset -c 0 rockbridge run STUDY`: the affinity mask, not the host's CPU count."""
    cpu = min(os.sched_getaffinity(0))
    study = write_study(tmp_path)
    cli = "from rockbridge_cli.cli import main; main(prog_name='rockbridge')"
    command = [sys.executable, "-c", cli, "run", str(study), "-o", "r.h5"]
    completed = subprocess.run(
        command, cwd=tmp_path, capture_output=True, text=True, timeout=600,
        preexec_fn=lambda: os.sched_setaffinity(0, {cpu}),
    )  # fmt: skip
    assert completed.returncode == 0, completed.stderr
    assert "workers: 1 (the CPUs this process may use" in completed.stderr
    assert "on 1 worker(s)" in completed.stdout

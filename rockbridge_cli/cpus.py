"""How many CPUs this process may use: its CPU affinity and its cgroup's CPU quota.

``os.cpu_count()`` counts the host's CPUs. A process pinned with ``taskset``, placed by SLURM, or
run in a container with a CPU limit (``docker run --cpus``, a Kubernetes ``limits.cpu``) may use
fewer: the affinity mask says which CPUs it may run on, the cgroup's quota how much CPU time it
may take per period (cgroup v2 ``cpu.max``, v1 ``cpu.cfs_quota_us`` / ``cpu.cfs_period_us``).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path

CGROUP_ROOT = Path("/sys/fs/cgroup")
"""Where the cgroup file systems are mounted (v2 there or in ``unified/``, v1 per controller)."""

PROC_CGROUP = Path("/proc/self/cgroup")
"""The cgroups of this process, one ``hierarchy:controllers:path`` line each."""


def usable_cpus(cgroup_root: Path = CGROUP_ROOT, proc_cgroup: Path = PROC_CGROUP) -> int:
    """The number of CPUs this process may use, at least 1.

    The CPUs of its affinity mask, capped by its cgroup's CPU quota rounded up (a quota of 1.5
    CPUs keeps two workers busy part of the time rather than leaving half a CPU unused).

    Parameters
    ----------
    cgroup_root, proc_cgroup
        Where to read the cgroups (replaced in tests).
    """
    if hasattr(os, "sched_getaffinity"):
        count = len(os.sched_getaffinity(0))
    else:  # macOS, Windows: no affinity mask to read
        count = os.cpu_count() or 1
    quota = cgroup_cpu_quota(cgroup_root, proc_cgroup)
    if quota is not None:
        count = min(count, math.ceil(quota))
    return max(count, 1)


def cgroup_cpu_quota(cgroup_root: Path, proc_cgroup: Path) -> float | None:
    """The tightest CPU quota of this process's cgroup and its ancestors [CPUs].

    Returns
    -------
    The quota divided by its period, or None where there is no quota or no cgroup to read.
    """
    try:
        lines = proc_cgroup.read_text().splitlines()
    except OSError:
        return None
    quotas: list[float] = []
    for line in lines:
        parts = line.split(":", 2)
        if len(parts) != 3:
            continue
        _, controllers, path = parts
        if controllers == "":  # cgroup v2: one unified hierarchy
            for mount in (cgroup_root, cgroup_root / "unified"):
                quotas += _quotas_up_to(mount, path, _v2_quota)
        elif "cpu" in controllers.split(","):  # cgroup v1: the cpu controller's hierarchy
            for mount in {cgroup_root / controllers, cgroup_root / "cpu"}:
                quotas += _quotas_up_to(mount, path, _v1_quota)
    return min(quotas, default=None)


def _quotas_up_to(mount: Path, path: str, read: Callable[[Path], float | None]) -> list[float]:
    """The quotas set on the cgroup folder of ``path`` under ``mount`` and on each ancestor.

    Inside a container the cgroup path often does not exist under the mount, whose root is then
    the container's own cgroup: walking up reaches it.
    """
    folder = mount / path.lstrip("/")
    found = []
    while True:
        quota = read(folder)
        if quota is not None:
            found.append(quota)
        if folder == mount or mount not in folder.parents:
            return found
        folder = folder.parent


def _v2_quota(folder: Path) -> float | None:
    """``cpu.max``: ``"<quota> <period>"`` in µs, or ``"max <period>"`` for no quota."""
    try:
        quota, period = (folder / "cpu.max").read_text().split()
        return None if quota == "max" else float(quota) / float(period)
    except (OSError, ValueError):
        return None


def _v1_quota(folder: Path) -> float | None:
    """``cpu.cfs_quota_us`` over ``cpu.cfs_period_us``; a quota of -1 means none."""
    try:
        quota = float((folder / "cpu.cfs_quota_us").read_text())
        period = float((folder / "cpu.cfs_period_us").read_text())
    except (OSError, ValueError):
        return None
    return None if quota <= 0 or period <= 0 else quota / period


WORKERS_PER_CPU = 4
"""The most local worker processes a run starts per CPU it may use (`usable_cpus`): beyond one
per CPU, workers only share the CPUs, while each holds its own interpreter and kernels (about
90 MB: ``--workers 40`` took 3.6 GB); a few per CPU still cover a worker waiting on its disk."""


def excess_workers(workers: int, cpus: int | None = None) -> str | None:
    """Why ``workers`` local worker processes are too many for this process's CPUs (more than
    `WORKERS_PER_CPU` per CPU), or None where they are not."""
    cpus = usable_cpus() if cpus is None else cpus
    most = WORKERS_PER_CPU * cpus
    if workers <= most:
        return None
    return (f"{workers} workers are more than {most} ({WORKERS_PER_CPU} per CPU this process may "
            f"use, {cpus}): more only share the CPUs and take about 90 MB each")  # fmt: skip

"""docs/batch.md's examples, exercised as far as this machine allows: the SLURM scripts' bodies
with the variables SLURM would set, the Kubernetes Job's and the AWS Batch job definition's
command lines with their schedulers' index variables, and the Dask command lines on loopback.
Each ends in the file one run of the whole study writes (`studies.contents`)."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml
from studies import REPO, contents, write_study

from rockbridge_cli.config.study import load_study
from rockbridge_cli.study.run import run_study

BATCH = REPO / "docs" / "batch"
BIN = Path(sys.executable).parent


def environment(**variables: str) -> dict[str, str]:
    """This process's environment, the venv's scripts first on PATH, plus ``variables``."""
    return {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ['PATH']}", **variables}


def rockbridge(args: list[str], cwd: Path, **variables: str) -> None:
    command = [sys.executable, "-c", "from rockbridge_cli.cli import main; main()", *args]
    done = subprocess.run(command, cwd=cwd, env=environment(**variables), capture_output=True,
                          text=True, timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stderr


@pytest.fixture
def study(tmp_path):
    """The four-analysis test study and the contents of its single run."""
    path = write_study(tmp_path)
    single = load_study(path, output=tmp_path / "single.h5")
    run_study(single, workers=1)
    return path, contents(single.output)


def same_as_single(merged: Path, expected: dict) -> bool:
    found = contents(merged)
    for tree in (found, expected):
        tree["/"] = ({k: v for k, v in tree["/"][0].items() if k not in ("merged_from", "host")},
                     None)  # fmt: skip
    return found == expected


@pytest.mark.slow
def test_the_slurm_scripts(study, tmp_path):
    path, expected = study
    array = (BATCH / "slurm-array.sbatch").read_text()
    assert "#SBATCH --array=1-8" in array
    for task in ("1", "2", "3"):  # as `--array=1-3` would run them
        done = subprocess.run(
            ["bash", BATCH / "slurm-array.sbatch"], cwd=tmp_path, capture_output=True, text=True,
            env=environment(STUDY=str(path), SLURM_ARRAY_TASK_ID=task, SLURM_ARRAY_TASK_MIN="1",
                            SLURM_ARRAY_TASK_COUNT="3"), timeout=600,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
    merge = subprocess.run(
        ["bash", BATCH / "slurm-merge.sbatch"], cwd=tmp_path, capture_output=True, text=True,
        env=environment(STUDY=str(path)), timeout=600,
    )  # fmt: skip
    assert merge.returncode == 0, merge.stderr
    assert "4 of 4 analyses, from 3 parts" in merge.stdout
    assert same_as_single(tmp_path / "results" / "study.h5", expected)


@pytest.mark.slow
def test_the_kubernetes_indexed_job(study, tmp_path):
    path, expected = study
    job = yaml.safe_load((BATCH / "kubernetes-indexed-job.yaml").read_text())
    spec = job["spec"]
    assert spec["completionMode"] == "Indexed" and spec["completions"] == spec["parallelism"]
    container = spec["template"]["spec"]["containers"][0]
    args = container["args"]
    assert args[args.index("--shard-count") + 1] == str(spec["completions"])
    assert container["resources"]["limits"]["cpu"] == "2"
    assert {m["mountPath"] for m in container["volumeMounts"]} == {"/work/results"}
    args[1] = str(path)  # the small study instead of the paper's
    for index in range(spec["completions"]):  # 8 pods for 4 analyses: some shards are empty
        rockbridge(args, tmp_path, JOB_COMPLETION_INDEX=str(index))
    parts = sorted((tmp_path / "results").glob("study.part-*-of-8.h5"))
    assert len(parts) == 8
    rockbridge(["merge", "results/study.h5", *map(str, parts)], tmp_path)
    assert same_as_single(tmp_path / "results" / "study.h5", expected)


@pytest.mark.slow
def test_the_aws_batch_job_definition(study, tmp_path):
    path, _ = study
    definition = json.loads((BATCH / "aws-batch-job-definition.json").read_text())
    properties = definition["containerProperties"]
    command = properties["command"]
    assert [m["containerPath"] for m in properties["mountPoints"]] == ["/work/results"]
    command[1] = str(path)
    rockbridge(command, tmp_path, AWS_BATCH_JOB_ARRAY_INDEX="5")
    output = tmp_path / "results" / "study.part-6-of-8.h5"
    assert output.is_file()


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


LOOPBACK = {"0100007F", "00000000000000000000000001000000"}
"""127.0.0.1 and ::1 as Linux's /proc/net/tcp and tcp6 write them."""


def listening(roots: set[int]) -> set[str]:
    """The local addresses (as /proc/net/tcp writes them) on which the processes ``roots`` and
    their descendants listen (Linux)."""
    parents = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            parents[int(stat.parent.name)] = int(stat.read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):  # gone meanwhile
            continue
    family = set(roots)
    while grown := {pid for pid, parent in parents.items() if parent in family} - family:
        family |= grown
    sockets = set()
    for pid in family:
        try:
            links = [os.readlink(fd) for fd in Path(f"/proc/{pid}/fd").iterdir()]
        except OSError:
            continue
        sockets |= {link[8:-1] for link in links if link.startswith("socket:[")}
    found = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[3] == "0A" and fields[9] in sockets:  # 0A: LISTEN
                found.add(fields[1].rsplit(":", 1)[0])
    return found


@pytest.mark.slow
def test_the_dask_command_lines(study, tmp_path):
    pytest.importorskip("distributed", reason='the "dask" extra is not installed')
    path, expected = study
    address = f"tcp://127.0.0.1:{free_port()}"
    host, port = address.removeprefix("tcp://").split(":")
    dask = str(BIN / "dask")
    loopback = ["--dashboard-address", "127.0.0.1:0"]
    processes = [
        subprocess.Popen([dask, "scheduler", "--host", host, "--port", port, *loopback],
                         cwd=tmp_path, env=environment(), stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL),
    ]  # fmt: skip
    try:
        time.sleep(2)
        processes.append(
            subprocess.Popen([dask, "worker", address, "--host", host, *loopback, "--nworkers",
                              "2", "--nthreads", "1"], cwd=tmp_path, env=environment(),
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        )  # fmt: skip
        rockbridge(["run", str(path), "--scheduler", address, "-o", "dask.h5"], tmp_path)
        if Path("/proc/net/tcp").exists():  # every port of the recipe is on loopback (issue 32)
            found = listening({process.pid for process in processes})
            assert found and found <= LOOPBACK, found
    finally:
        for process in reversed(processes):
            process.terminate()
            process.wait(timeout=60)
    assert same_as_single(tmp_path / "dask.h5", expected)

"""Which shard of a study this process runs: from ``--shard K/N``, or from the variables an
array job's scheduler sets for each of its tasks.

Users count shards from 1 (``--shard 1/3`` … ``3/3``); inside, shards are (index, count) with
the index from 0, as Kubernetes and AWS Batch number their tasks.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

from ..config.study_checks import MAX_ANALYSES
from ..errors import InputError

SCHEDULERS = (
    ("JOB_COMPLETION_INDEX", None, None, "a Kubernetes Indexed Job"),
    ("AWS_BATCH_JOB_ARRAY_INDEX", None, None, "an AWS Batch array job"),
    ("SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN", "a SLURM job array"),
)
"""Per scheduler: the variable with the task's index, the one with the number of tasks (None
where the scheduler sets none: give ``--shard-count``), the one with the first index (SLURM
arrays may start anywhere, for example ``--array=1-3``), and its name."""


def shard_label(shard: tuple[int, int]) -> str:
    """A shard as users write it: ``K/N`` with K counted from 1."""
    return f"{shard[0] + 1}/{shard[1]}"


def parse_shard(text: str) -> tuple[int, int]:
    """``K/N`` (1 ≤ K ≤ N) as (index, count).

    Raises
    ------
    ValueError
        Not two integers K/N with 1 ≤ K ≤ N ≤ `config.study_checks.MAX_ANALYSES` (a shard beyond the
        number of analyses is empty).
    """
    try:
        number, count = (int(part) for part in text.split("/"))
    except ValueError:
        raise ValueError(f"{text!r} is not K/N (for example 2/8)") from None
    if not 1 <= number <= count:
        raise ValueError(f"{text!r}: K must be 1 … N")
    if count > MAX_ANALYSES:
        raise ValueError(f"{text!r}: N must be at most {MAX_ANALYSES:,}, the most analyses a study "
                         "may hold")  # fmt: skip
    return number - 1, count


def shard_from_environment(
    count: int | None = None, environment: Mapping[str, str] = os.environ
) -> tuple[int, int]:
    """The shard of this array task, from its scheduler's variables.

    Parameters
    ----------
    count
        The number of shards, where the scheduler does not say it (``--shard-count``).
    environment
        The variables to read (replaced in tests).

    Raises
    ------
    InputError
        No scheduler's variables are set, the number of shards is unknown, or the index is not
        below it.
    """
    for index_name, count_name, first_name, scheduler in SCHEDULERS:
        if index_name not in environment:
            continue
        try:
            index = int(environment[index_name]) - int(environment.get(first_name or "", 0))
            total = count if count is not None else int(environment.get(count_name or "", ""))
        except ValueError:
            where = f"{index_name}" + (f", {count_name}" if count_name else "")
            reason = (f"in {scheduler}, but {where} do not give the task's index and the number "
                      "of tasks; give --shard K/N, or --shard-count N")  # fmt: skip
            raise InputError("--shard auto", [("", reason)]) from None
        if not 0 <= index < total <= MAX_ANALYSES:
            reason = (f"{index_name} gives task {index} (from 0) of {total} shards: the index must "
                      f"be below the count, and the count at most {MAX_ANALYSES:,}")  # fmt: skip
            raise InputError("--shard auto", [("", reason)])
        return index, total
    names = ", ".join(name for name, *_ in SCHEDULERS)
    reason = f"not inside an array job (none of {names} is set); give --shard K/N"
    raise InputError("--shard auto", [("", reason)])

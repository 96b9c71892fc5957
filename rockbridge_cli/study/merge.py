"""Merge the results files of a study's shards into the file one run would have written.

The parts must come from the same study (config hash) and the same rockbridge (version and
format): anything else is refused. Parts made with other numpy/scipy/Python versions are merged
but flagged, since their last digits may differ from a single run's. The merged file describes
the study as its parts do, lists their provenance (``merged_from``), and holds every analysis
once, in the study's order; missing analyses are reported and leave the file incomplete.
"""

from __future__ import annotations

import heapq
import json
import os
import platform
from collections.abc import Iterator
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from ..assessment.fragility import store as store_fragilities
from ..assessment.limit_states import stored_verdicts
from ..config.changes import what_differs
from ..errors import InputError
from ..interrupts import checkpointed, held
from ..paths import checked_output, replace_atomically
from ..results.packing import AnalysisResult
from ..results.reading import is_results_file, open_results, stored_results, stored_shard_of
from ..results.writing import ResultsWriter, copy_description
from .output_lock import exclusive
from .shards import shard_label

PROVENANCE = (
    "host", "created", "finished", "shard_index", "shard_count", "rockbridge_version",
    "python_version", "numpy_version", "scipy_version", "h5py_version", "hdf5_version",
)  # fmt: skip
"""Root attributes of a part recorded in the merged file's ``merged_from``."""

MUST_AGREE = ("config_hash", "format_version", "rockbridge_version")
"""Root attributes on which all parts must agree."""

SHOULD_AGREE = ("python_version", "numpy_version", "scipy_version")
"""Root attributes on which parts should agree (a difference is flagged)."""


@dataclass(frozen=True)
class MergeReport:
    """What `merge_results` did.

    Attributes
    ----------
    output : the merged file
    total : analyses of the study
    merged : analyses in the merged file
    missing : (bridge, record) of the analyses no part holds
    duplicated : (bridge, record) of the analyses more than one part holds (the first part's kept)
    flags : differences between the parts that may change last digits
    """

    output: Path
    total: int
    merged: int
    missing: list[tuple[str, str]]
    duplicated: list[tuple[str, str]]
    flags: list[str]


def merge_results(output: Path, parts: list[Path], overwrite: bool = False) -> MergeReport:
    """Write ``output`` from the results files of a study's shards.

    Raises
    ------
    InputError
        No parts, a part that is not a results file, parts of different studies or rockbridge
        versions, an output that is one of the parts, an existing output without
        ``overwrite``, one that is not a results file or holds a shard (never replaced), or one
        that a run or another merge is writing.
    TypeError
        ``parts`` is one path, not a list of them.
    """
    if isinstance(parts, (str, os.PathLike)):
        raise TypeError("parts is a list of results files, not one path")
    if not parts:
        raise InputError("merge", [("", "give the results files to merge")])
    output = Path(output)
    if any(output.resolve() == Path(part).resolve() for part in parts):
        raise InputError(output, [("", "is one of the parts: choose another output")])
    checked_output(output, ours=is_results_file, what="a rockbridge results file")
    with exclusive(output):  # not while a run or another merge writes it
        if output.exists():
            _not_a_shard(output)
        if output.exists() and not overwrite:
            reason = (
                "holds results; rerun with --overwrite to replace them, or choose another output"
            )
            raise InputError(output, [("", reason)])
        return _written(output, parts)


def _not_a_shard(output: Path) -> None:
    """Refuse an output that holds a shard of a study, even with ``overwrite``: the merged file
    was left out of the command (``merge part-*.h5`` made the first part the output, and
    ``--overwrite`` replaced that shard's analyses with a merge of the others)."""
    with open_results(output) as file:
        shard = stored_shard_of(file)
    if shard is not None:
        reason = (
            f"holds shard {shard_label(shard)} of a study, which a merge never replaces: give "
            "the merged file to write first, then the parts"
        )
        raise InputError(output, [("", reason)])


def _written(output: Path, parts: list[Path]) -> MergeReport:
    """`merge_results`'s file written, through a temporary file beside it."""
    temporary = output.with_name(f".{output.name}.{os.getpid()}.tmp")
    try:
        with ExitStack() as stack:
            files = [stack.enter_context(open_results(part)) for part in parts]
            flags = _check(parts, files)
            holders: dict[tuple[str, str], int] = {}
            duplicated = []
            for number, file in enumerate(files):
                for pair in stored_verdicts(file):
                    if pair in holders:
                        duplicated.append(pair)
                    else:
                        holders[pair] = number
            order, missing = _study_order(files, holders)
            file = stack.enter_context(h5py.File(temporary, "w"))
            copy_description(file, files[0], skip=(*PROVENANCE[:5], "complete", "n_complete"))
            file.attrs.update(
                host=platform.node(),
                created=min(str(part.attrs["created"]) for part in files),
                merged_from=json.dumps(
                    [{"file": str(path), **{k: _plain(f.attrs.get(k)) for k in PROVENANCE}}
                     for path, f in zip(parts, files, strict=True)], indent=1),
            )  # fmt: skip
            writer = ResultsWriter(file, len(order))
            checkpoint = stack.enter_context(held())  # a stop between analyses (`_write`'s)
            ordered = checkpointed(_in_order(files, holders, order), checkpoint)
            writer.add(result.pack() for result in ordered)
            writer.close(max(str(part.attrs["finished"]) for part in files))
            store_fragilities(file)
            checkpoint()
        replace_atomically(temporary, output)
    finally:
        temporary.unlink(missing_ok=True)
    return MergeReport(output, len(order), len(holders), missing, duplicated, flags)


def _check(parts: list[Path], files: list[h5py.File]) -> list[str]:
    """Refuse parts that disagree on what must agree; flag what should, and parts of splits
    into different numbers of shards (a glob of ``part-*-of-*`` that caught an earlier array's:
    its analyses are the same study's, but the missing or duplicated ones then follow no one
    split)."""
    for path, file in zip(parts, files, strict=True):
        _check_counts(path, file)
    first = files[0].attrs
    for path, file in zip(parts[1:], files[1:], strict=True):
        for name in MUST_AGREE:
            if file.attrs.get(name) != first.get(name):
                what = f"{file.attrs.get(name)} ≠ {first.get(name)}"
                if name == "config_hash":  # name the fields that differ, not the hashes
                    what = what_differs(json.loads(first.get("config", "{}")),
                                   json.loads(file.attrs.get("config", "{}")))  # fmt: skip
                reason = (f"{name} differs from {parts[0]}'s ({what}): parts must come from the "
                          "same study and the same rockbridge")  # fmt: skip
                raise InputError(path, [("", reason)])
    flags = []
    for name in SHOULD_AGREE:
        values = sorted({str(file.attrs.get(name)) for file in files})
        if len(values) > 1:
            flags.append(f"{name} differs between the parts ({', '.join(values)}): their last "
                         "digits may differ from a single run's")  # fmt: skip
    splits = sorted({shard[1] for file in files if (shard := stored_shard_of(file)) is not None})
    if len(splits) > 1:
        flags.append(f"the parts come from splits into {' and '.join(map(str, splits))} "
                     "shards: are parts of an earlier array among them?")  # fmt: skip
    return flags


def _check_counts(path: Path, file: h5py.File) -> None:
    """Refuse a part whose counts are not what a run writes (`results.writing.ResultsWriter`):
    ``n_complete`` the rows of its peak table, ``n_analyses`` a whole number at least as large
    (a part of an older rockbridge, without them, passes)."""
    if "n_analyses" not in file.attrs:
        return
    rows = len(file["peaks"]["bridge"])
    for name, least in (("n_complete", rows), ("n_analyses", rows)):
        value = file.attrs.get(name)
        whole = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
        if not whole or value < least or (name == "n_complete" and value != rows):
            wanted = f"{rows}, the rows of its peak table" if name == "n_complete" else (
                f"a whole number ≥ {rows}, the analyses it holds")  # fmt: skip
            shown = _plain(value)
            reason = f"{shown!r} where the part's run writes {wanted}: a damaged part?"
            raise InputError(path, [(name, reason)])


def _study_order(
    files: list[h5py.File], holders: dict[tuple[str, str], int]
) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """(bridge, record) of every analysis of the study in the order of the results, and of those
    no part holds.

    An IDA's analyses are not known beforehand: they are those its parts ran, ordered by bridge,
    record and level; what is missing then is a bridge × record (as read) of which no part holds
    any level.
    """
    config = json.loads(files[0].attrs["config"])
    bridges = [b["id"] for b in config["bridges"]]
    records = [r["id"] for r in config["records"]]
    pairs = [(b, r) for b in bridges for r in records]
    if not (config.get("intensity") or {}).get("ida"):
        return pairs, [pair for pair in pairs if pair not in holders]
    keys = {}
    for file in files:
        peaks = file["peaks"]
        columns = (peaks[name].asstr()[()] for name in ("bridge", "record", "base_record"))
        for bridge, record, base, level in zip(*columns, peaks["intensity"][()], strict=True):
            keys[(bridge, record)] = (bridges.index(bridge), records.index(base), float(level))
    curves = {(bridges[b], records[r]) for b, r, _ in keys.values()}
    return sorted(keys, key=keys.__getitem__), [pair for pair in pairs if pair not in curves]


def _in_order(
    files: list[h5py.File], holders: dict[tuple[str, str], int], order: list[tuple[str, str]]
) -> Iterator[AnalysisResult]:
    """The analyses of the parts, each from its first holder, in the study's order."""
    position = {pair: index for index, pair in enumerate(order)}

    def held(number: int) -> Iterator[tuple[int, AnalysisResult]]:
        for result in stored_results(files[number]):
            if holders[(result.bridge, result.record)] == number:
                yield position[(result.bridge, result.record)], result

    streams = [held(number) for number in range(len(files))]
    for _, result in heapq.merge(*streams, key=lambda item: item[0]):
        yield result


def _plain(value: object) -> object:
    return value.item() if hasattr(value, "item") else value

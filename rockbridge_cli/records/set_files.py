"""A record set on disk, as `sets.generate_record_set` writes it: a folder of record files and
its manifest, which lists them with each file's SHA-256; read here, each file checked against it."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..paths import read_input_text
from .files import Record, read_record

#: Name of the file that describes a generated record set.
MANIFEST = "manifest.json"

MAX_MANIFEST_BYTES = 16 * 2**20
"""Largest manifest read (a set of tens of thousands of records) [bytes]."""


def read_manifest(folder: str | Path) -> dict[str, Any]:
    """The manifest of a record set written by `sets.generate_record_set`.

    Raises
    ------
    InputError
        The manifest is missing, a link out of the folder, not a regular file of at most
        `MAX_MANIFEST_BYTES`, not JSON, or lacks its list of records.
    """
    path = Path(folder) / MANIFEST
    if not path.exists():
        reason = "file not found: is this a folder written by generate-records?"
        raise InputError(path, [("", reason)])
    if path.resolve().parent != Path(folder).resolve():  # as for its record files
        reason = (
            f"is a link out of the set's folder (to {path.resolve()}): a set's manifest is its own"
        )
        raise InputError(path, [("", reason)])
    text = read_input_text(path, MAX_MANIFEST_BYTES, "a record set's manifest")
    try:
        manifest = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(
            path, [(f"line {exc.lineno}, column {exc.colno}", f"invalid JSON: {exc.msg}")]
        ) from None
    if not isinstance(manifest, dict) or not isinstance(manifest.get("records"), list):
        raise InputError(path, [("records", "missing: the manifest must list its records")])
    for index, entry in enumerate(manifest["records"]):
        if not isinstance(entry, dict) or not isinstance(entry.get("file"), str):
            raise InputError(path, [(f"records[{index}].file", "missing or not a file name")])
        if "\0" in entry["file"]:  # no file name holds one (the OS refuses it, raw)
            raise InputError(path, [(f"records[{index}].file", "holds a NUL character")])
    return manifest


def check_set_file(folder: Path, entry: dict[str, Any], index: int, key: str = "file") -> Path:
    """A record file of a set, once it is there and, where the manifest gives its SHA-256 (sets
    written since the manifest has them), has the bytes the set was written with: a file
    changed, or left by a generator killed while it replaced the set, is refused.

    ``key``: the entry's field in messages (``vertical.file`` for a `vertical` companion).

    Raises
    ------
    InputError
        The file is not in the set's folder, is missing or differs from the manifest.
    """
    path, field = folder / entry["file"], f"records[{index}].{key}"
    inside = path.name == entry["file"] and path.name not in (".", "..")
    if not inside or path.resolve().parent != folder.resolve():  # no path or link out of it
        raise InputError(folder / MANIFEST, [(field, "must name a file in the set's folder")])
    if not path.is_file():
        raise InputError(folder / MANIFEST, [(field, f"{entry['file']} not found")])
    expected = entry.get("sha256")
    if expected is not None and hashlib.sha256(path.read_bytes()).hexdigest() != expected:
        why = f"{entry['file']} differs from the file the set was written with (its SHA-256)"
        raise InputError(folder / MANIFEST, [(field, f"{why}: regenerate the set")])
    return path


COMPLIANCE = "compliance.txt"
"""The compliance table `select-records` writes beside a set it selects."""

BESIDE_A_SET = (COMPLIANCE, "spectra.png")
"""Files a set's folder holds beside its records and manifest: the compliance table, and the
figure of ``--plot``."""


def holds_a_set(folder: Path) -> bool:
    """Whether a folder holds a record set (its manifest), which a new set may replace."""
    return (folder / MANIFEST).is_file()


def output_folder(folder: Path, overwrite: bool) -> Path:
    """The folder a new record set is written to, once it is new, empty, or a record set that
    ``overwrite`` lets the new one replace whole and that holds nothing but that set's own
    files (its records, manifest and `BESIDE_A_SET`): a user's file is never deleted with it.

    Raises
    ------
    InputError
        ``folder`` holds files that are not a record set's, or a set without ``overwrite``.
    """
    if not folder.is_dir() or not any(folder.iterdir()):
        return folder
    if not holds_a_set(folder):
        raise InputError(folder, [("", "holds files that are not a record set: give a new or "
                                   "empty folder")])  # fmt: skip
    if not overwrite:
        raise InputError(folder, [("", "holds a record set already: pass --overwrite to replace "
                                   "it, or give a new or empty folder")])  # fmt: skip
    entries = read_manifest(folder)["records"]
    own = {MANIFEST, *BESIDE_A_SET, *(entry["file"] for entry in entries)}
    own |= {entry["vertical"].get("file") for entry in entries
            if isinstance(entry.get("vertical"), dict)}  # fmt: skip
    others = sorted(p.name for p in folder.iterdir() if p.name not in own or p.is_dir())
    if others:
        named = ", ".join(others[:3]) + (f" and {len(others) - 3} more" if len(others) > 3 else "")
        raise InputError(folder, [("", f"holds {named}, which the record set does not list: "
                                   "move them out, or give a new or empty folder (a set is "
                                   "replaced whole)")])  # fmt: skip
    return folder


def read_record_set(folder: str | Path) -> list[Record]:
    """Read every record of a set written by `sets.generate_record_set`, in manifest order.

    Raises
    ------
    InputError
        The manifest is missing or corrupt, or names a file that is missing or malformed.
    """
    folder = Path(folder)
    manifest = read_manifest(folder)
    return [
        read_record(check_set_file(folder, entry, index))
        for index, entry in enumerate(manifest["records"])
    ]

"""What differs between two resolved studies (`config.study.Study.resolved`): the fields a user
changed, named, for a refusal to say why a results file belongs to another study."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

SHOWN = 4
"""Differences named at most; the rest are counted."""


def differences(stored: dict[str, Any], current: dict[str, Any]) -> list[str]:
    """Each difference of ``current`` from ``stored``, as text: ``fidelity.preset: default →
    fast``, ``bridge b: abutments.gap 0.2 → 0.21``, ``records added: AR11``."""
    found = []
    for part in ("bridges", "records"):
        old = {item["id"]: item for item in stored.get(part, [])}
        new = {item["id"]: item for item in current.get(part, [])}
        for label, ids in (("added", new.keys() - old.keys()), ("removed", old.keys() - new)):
            if ids:
                named = sorted(ids)[:SHOWN]
                more = f" and {len(ids) - SHOWN} more" if len(ids) > SHOWN else ""
                found.append(f"{part} {label}: {', '.join(named)}{more}")
        for name in [n for n in new if n in old]:
            if part == "records" and old[name].get("sha256") != new[name].get("sha256"):
                found.append(f"record {name}: other samples")
            elif part == "bridges":
                changed = list(_changes(old[name].get("config"), new[name].get("config"), ""))
                if changed:
                    found.append(f"bridge {name}: {', '.join(changed)}")
    for part in ("fidelity", "histories", "intensity", "uncertainty"):
        found += _changes(stored.get(part), current.get(part), part)
    return found


def what_differs(stored: dict[str, Any], current: dict[str, Any]) -> str:
    """`differences` in one phrase: the first `SHOWN`, and how many more."""
    found = differences(stored, current)
    if not found:
        return "its inputs differ"
    more = f" and {len(found) - SHOWN} more" if len(found) > SHOWN else ""
    return "; ".join(found[:SHOWN]) + more


def _changes(old: Any, new: Any, path: str) -> Iterator[str]:
    """Dotted paths whose values differ, with both values."""
    if isinstance(old, dict) and isinstance(new, dict):
        for key in list(dict.fromkeys([*old, *new])):
            yield from _changes(old.get(key), new.get(key), f"{path}.{key}" if path else key)
    elif old != new and not (old != old and new != new):  # NaN equals NaN here
        yield f"{path}: {_text(old)} → {_text(new)}" if path else f"{_text(old)} → {_text(new)}"


def _text(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, list):
        return "[" + ", ".join(map(_text, value)) + "]"
    return f"{value:g}" if isinstance(value, float) else str(value)

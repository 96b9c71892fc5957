"""A study's checks as a whole, before anything runs: its size against `MAX_ANALYSES`, an
overturning spectrum's map, the limit states asked of bridges without abutments, intensity levels
beyond any ground motion, a fragility on pairs without pairs, and its ids."""

from __future__ import annotations

import collections
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..core.quantities import DEVICE_LIMIT_STATES
from ..errors import InputError
from .intensity import Intensity, absurd_levels
from .loading import ID_PATTERN
from .records import Records
from .spectrum import Spectrum

MAX_ANALYSES = 1_000_000
"""Most analyses in a study (bridges × records × levels): its grid and journal stay within a few
hundred MB; a larger one is several studies, or shards (`study.shards`)."""


_STATED_BY = {
    "tendon_yield": ("tendon", "yield_force"), "tendon_rupture": ("tendon", "rupture_strain"),
    "dissipator_fracture": ("dissipator", "fracture_strain"),
}  # fmt: skip
"""The kind of device and the field of its config that state each device limit state."""


def check_states(bridges: Sequence[Any], states: Sequence[str] | None, where: str,
                  study: Path) -> None:  # fmt: skip
    """Refuse a limit state of the abutments (gap closure, their failure, the backfill's) asked
    of a bridge without abutments (a block, a frame): its IDA or boundary could never end
    there, and ran to the top of its scan without a word. Refuse a device's limit state
    (`DEVICE_LIMIT_STATES`) when no bridge has a device of its kind that states that limit."""
    for state in (s for s in states or () if s in DEVICE_LIMIT_STATES):
        kind, field = _STATED_BY[state]
        if not any(
            d.kind == kind and getattr(d, field, None) is not None
            for b in bridges
            for d in b.config.devices
        ):
            reason = f"{state}: no bridge has a {kind} with a {field}"
            raise InputError(study, [(where, reason)])
    needs = [s for s in states or () if s != "overturning" and s not in DEVICE_LIMIT_STATES]
    without = [
        b.id for b in bridges if b.config.abutments is None or len(b.config.piers.heights) < 2
    ]
    if needs and without:
        reason = f"{', '.join(needs)} need abutments, which {without[0]} has not" + (
            f" (nor {len(without) - 1} other bridges)" if len(without) > 1 else ""
        )
        raise InputError(study, [(where, reason)])


def check_map(bridges: int, spectrum: Spectrum, study: Path) -> None:
    """Refuse a spectrum whose map, its first round (frequencies × amplitudes), is more than
    `MAX_ANALYSES` analyses."""
    frequencies, amplitudes = spectrum.frequencies.count, spectrum.amplitudes.count
    if bridges * frequencies * amplitudes > MAX_ANALYSES:
        reason = (f"{frequencies} frequencies × {amplitudes} amplitudes are more than "
                  f"{MAX_ANALYSES:,} analyses in the map: use fewer")  # fmt: skip
        raise InputError(study, [("spectrum", reason)])


def check_size(
    bridges: int, records: int, one_each: bool, intensity: Intensity | None, study: Path
) -> None:
    """Refuse a study of more than `MAX_ANALYSES` analyses (``one_each``: each bridge meets one
    record)."""
    levels = len(intensity.levels or ()) if intensity is not None else 0
    if (bridges if one_each else bridges * records) * max(levels, 1) > MAX_ANALYSES:
        count = f"{bridges} bridges × {'one record' if one_each else f'{records} records'}"
        count += f" × {levels} levels" * bool(levels)
        reason = f"{count} are more than {MAX_ANALYSES:,} analyses: split the study"
        raise InputError(study, [("", reason)])


def check_levels(intensity: Intensity, study: Path) -> None:
    """Refuse intensity levels beyond any ground motion (`intensity.absurd_levels`): a slip of
    units that would scale every record past what a record file may hold."""
    problems = absurd_levels(intensity)
    if problems:
        raise InputError(study, problems)


def check_orientation(intensity: Intensity, records: Records | None, study: Path) -> None:
    """Refuse a fragility on pairs (``intensity.orientation``) of a study whose records are not
    pairs swept over angles (no ``records.orientation``)."""
    if intensity.orientation is not None and (records is None or records.orientation is None):
        reason = (f"{intensity.orientation} over each pair's angles needs records.orientation "
                  "(pairs of horizontal components along angles): drop it or add one")  # fmt: skip
        raise InputError(study, [("intensity.orientation", reason)])


def check_ids(field: str, ids: list[str]) -> list[tuple[str, str]]:
    """Ids (given or taken from file names) must be unique and fit `ID_PATTERN`."""
    problems = [
        (f"{field}.{index}", f"id {i!r} must be letters, digits and _ . + - (no spaces or slashes)")
        for index, i in enumerate(ids)
        if not re.match(ID_PATTERN, i)
    ]
    twice = sorted(i for i, count in collections.Counter(ids).items() if count > 1)
    return problems + [(field, f"id {i!r} is used twice: ids must be unique") for i in twice]

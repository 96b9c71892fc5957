"""An overturning spectrum from the results of a spectrum study (`config.spectrum`): the map of
what each ω_p/p × a_p/a_ref analysis reached, and per frequency and limit state the lowest
amplitude that reaches it, replayed from the stored verdicts with the IDA rule
(`assessment.ida`), as the run found it. A run stores it in its results file (``/spectrum``,
`store`); `spectrum_of` computes it from the peak table and never changes the file.

The map's regions, in the field's terms (Makris & Roussos 2000; Zhang & Makris 2001): no rocking
(a_p below the onset), rocking that ends safely, the end joints closing (a bridge), the abutment
failing, and overturning after one or more impacts or without any (the two modes of overturning).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from ..core.quantities import ABUTMENT, PIER1_OVERTURNING, PIER2_OVERTURNING
from ..errors import InputError
from ..results.reading import open_results, read_intensity, read_spectrum_section
from ..results.sections import IntensitySection, SpectrumSection
from .ida import Rule
from .limit_states import Verdict

REGIONS = (
    "no_rocking", "rocking", "gap_closure", "abutment_failure", "overturning_after_impact",
    "overturning_without_impact",
)  # fmt: skip
"""What an analysis of the map reached, by code (0 …); −1 where it did not run."""

NOT_RUN = -1
"""The region code of an analysis that did not run (interrupted, or an error)."""


@dataclass(frozen=True)
class OverturningSpectrum:
    """An overturning spectrum of one bridge under one pulse shape.

    Attributes
    ----------
    bridge : the bridge's id
    pulse : shape, phase [rad], cycles (`config.spectrum.SpectrumPulse`)
    frequency_parameter : p [rad/s]
    reference : ``g_tan_alpha`` or ``onset``; ``reference_acceleration`` its value a_ref [m/s²]
    frequency_ratios : ω_p/p, one per record (``records``) [-]
    amplitude_ratios : a_p/a_ref, the map's scan levels [-]
    regions : codes of `REGIONS` (`NOT_RUN` where missing), frequencies × amplitudes
    boundaries : limit state → the lowest a_p/a_ref that reaches it, per frequency, to the
        bisection's tolerance (NaN: not reached up to the last amplitude; the first amplitude
        where it is reached there already) [-]
    below : limit state → the highest a_p/a_ref below it that does not reach it, per frequency
        (NaN where the boundary is at the first amplitude or not found) [-]
    """

    bridge: str
    pulse: dict
    frequency_parameter: float
    reference: str
    reference_acceleration: float
    frequency_ratios: np.ndarray
    amplitude_ratios: np.ndarray
    records: list[str]
    regions: np.ndarray
    boundaries: dict[str, np.ndarray]
    below: dict[str, np.ndarray]


def read_spectrum(path: str | Path) -> OverturningSpectrum:
    """The overturning spectrum of a results file.

    Raises
    ------
    InputError
        The file's study is not a spectrum study.
    """
    with open_results(path) as file:
        return _spectrum_of_file(file, path)


def _spectrum_of_file(file: h5py.File, path: str | Path) -> OverturningSpectrum:
    spectrum, intensity = read_spectrum_section(file), read_intensity(file)
    if spectrum is None or intensity is None or intensity.ida is None:
        raise InputError(path, [("", "the study has no spectrum section: no spectrum")])
    bridge = next(iter(file["bridges"]))  # a spectrum is of one bridge
    return spectrum_of(_map_columns(file), bridge, spectrum, intensity)


MAP_COLUMNS = (
    "record", "base_record", "intensity", "status", "failure_mode", "dcr_backfill", "n_impacts",
    "t_onset",
)  # fmt: skip
"""The columns of the peak table a spectrum is computed from (`spectrum_of`)."""


def _map_columns(file: h5py.File) -> dict[str, np.ndarray]:
    """`MAP_COLUMNS` of an open results file's peak table, as `results.reading.peak_columns`
    gives them (text as ``str`` arrays): only those, of a table that may have 1e6 rows."""
    peaks = file["peaks"]
    return {
        name: peaks[name].asstr()[()].astype(str) if peaks[name].dtype.kind == "O"
        else peaks[name][()]
        for name in MAP_COLUMNS
    }  # fmt: skip


def spectrum_of(
    columns: dict[str, np.ndarray], bridge: str, spectrum: SpectrumSection,
    intensity: IntensitySection,
) -> OverturningSpectrum:  # fmt: skip
    """`read_spectrum` of a peak table's columns (`MAP_COLUMNS` at least), given the study's one
    bridge (its id), its spectrum section and the intensity section it runs as (an IDA of
    ``scale``).

    The map is found on whole columns (`_map_rows`, `_regions`); a row's verdict is built only
    where the rule's replay asks for it."""
    rule = Rule.of(intensity)
    lattice, states = rule.lattice, rule.states
    records, amplitudes = spectrum.records, spectrum.amplitude_ratios
    ids = np.asarray(columns["record"], dtype=str)
    rows = dict(zip(ids.tolist(), range(ids.size), strict=True))  # the replay's, by id

    def verdict(record: str) -> Verdict | None:
        i = rows.get(record)
        if i is None:
            return None
        status, mode = str(columns["status"][i]), str(columns["failure_mode"][i])
        return Verdict(status, mode, float(columns["dcr_backfill"][i]))

    tags = [rule.record("", j * lattice.stride) for j in range(len(amplitudes))]  # once a level
    placed = _map_rows(columns, records, rule, tags)  # −1: not run, the last code appended
    regions = np.append(_regions(columns), np.int8(NOT_RUN))[placed]
    boundaries = {state: np.full(len(records), np.nan) for state in states}
    below = {state: np.full(len(records), np.nan) for state in states}
    for i, base in enumerate(records):
        for state, (low, high) in rule.replay(base, verdict).capacities.items():
            if high is not None:
                boundaries[state][i] = lattice.level(high)
                below[state][i] = lattice.level(low) if low >= 0 else math.nan
    return OverturningSpectrum(
        bridge, spectrum.pulse, spectrum.frequency_parameter, spectrum.reference,
        spectrum.reference_acceleration, np.array(spectrum.frequency_ratios),
        np.array(amplitudes), list(records), regions, boundaries, below,
    )  # fmt: skip


def _map_rows(
    columns: dict[str, np.ndarray], records: Sequence[str], rule: Rule, tags: list[str]
) -> np.ndarray:
    """The row of the peak table of each point of the map (``records`` × the scan levels, what
    each adds to a record's id ``tags``), −1 where none ran: each row placed at once by its base
    record and its level's lattice index, where its id is that point's."""
    lattice, ids = rule.lattice, np.asarray(columns["record"], dtype=str)
    names, ends = np.array(records, dtype=str), np.array(tags, dtype=str)
    rows = np.full((names.size, ends.size), -1)
    order = np.argsort(names, kind="stable")
    i = order[np.minimum(np.searchsorted(names[order], columns["base_record"]), names.size - 1)]
    with np.errstate(invalid="ignore"):  # NaN: a row of no level
        n = np.rint((columns["intensity"] - lattice.start) / lattice.step * lattice.stride)
        j = n / lattice.stride
        scan = (n % lattice.stride == 0) & (j >= 0) & (j < ends.size)
    row = np.flatnonzero(scan)
    i, j = i[row], j[row].astype(np.int64)
    same = np.char.add(names[i], ends[j]) == ids[row]  # what the rule names it (`Rule.record`)
    rows[i[same], j[same]] = row[same]
    return rows


def _regions(columns: dict[str, np.ndarray]) -> np.ndarray:
    """The `REGIONS` code of each analysis of the peak table (`NOT_RUN` where it could not
    run), the first that holds of: overturned (after an impact, or without), the abutment
    failed, the end joints closed (a backfill demand), it rocked (an onset time), none."""
    mode = columns["failure_mode"]
    overturned = np.isin(mode, (PIER1_OVERTURNING, PIER2_OVERTURNING))
    conditions = [
        columns["status"] == "error", overturned & (columns["n_impacts"] > 0), overturned,
        mode == ABUTMENT, columns["dcr_backfill"] > 0.0, np.isfinite(columns["t_onset"]),
    ]  # fmt: skip
    codes = [NOT_RUN, *map(REGIONS.index, (
        "overturning_after_impact", "overturning_without_impact", "abutment_failure",
        "gap_closure", "rocking"))]  # fmt: skip
    return np.select(conditions, codes, default=REGIONS.index("no_rocking")).astype(np.int8)


def store(file: h5py.File) -> None:
    """Write the spectrum of an open results file of a spectrum study into it, as ``/spectrum``:
    the axes, the map of regions (a CF flag variable) and each limit state's boundary."""
    spectrum = _spectrum_of_file(file, file.filename)
    group = file.create_group("spectrum")
    group.attrs.update({
        "description": "overturning spectrum (rockbridge_cli.assessment.spectrum), as the run "
        "found it; rockbridge plot overturning RESULTS.h5 draws it",
        "bridge": spectrum.bridge, "pulse": json.dumps(spectrum.pulse),
        "frequency_parameter": spectrum.frequency_parameter, "reference": spectrum.reference,
        "reference_acceleration": spectrum.reference_acceleration,
        "units": json.dumps({"frequency_parameter": "rad/s", "reference_acceleration": "m/s2"}),
    })  # fmt: skip
    _dataset(group, "frequency_ratio", spectrum.frequency_ratios, "ω_p/p, per row of region")
    _dataset(group, "amplitude_ratio", spectrum.amplitude_ratios, "a_p/a_ref, per column")
    records = group.create_dataset("record", data=spectrum.records, dtype=h5py.string_dtype())
    records.attrs.update(units="-", description="the pulse record of each row")
    region = _dataset(group, "region", spectrum.regions, "what each analysis reached: "
                      "frequency × amplitude; −1 where it did not run")  # fmt: skip
    region.attrs.update(flag_values=np.arange(len(REGIONS), dtype=np.int8),
                        flag_meanings=" ".join(REGIONS))  # fmt: skip
    for state, values in spectrum.boundaries.items():
        upper = f"lowest a_p/a_ref reaching {state} (to the tolerance); NaN: not reached"
        lower = "highest a_p/a_ref found below it; NaN: the boundary is the first amplitude"
        _dataset(group, f"boundary_{state}", values, upper)
        _dataset(group, f"below_{state}", spectrum.below[state], lower)


def _dataset(group: h5py.Group, name: str, values: np.ndarray, description: str) -> h5py.Dataset:
    dataset = group.create_dataset(name, data=values)
    dataset.attrs.update(units="-", description=description)
    return dataset

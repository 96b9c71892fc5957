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
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from ..core.quantities import ABUTMENT, PIER1_OVERTURNING, PIER2_OVERTURNING
from ..errors import InputError
from ..results.reading import open_results, peak_columns, read_intensity, read_spectrum_section
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
    return spectrum_of(peak_columns(file), bridge, spectrum, intensity)


def spectrum_of(
    columns: dict[str, np.ndarray], bridge: str, spectrum: SpectrumSection,
    intensity: IntensitySection,
) -> OverturningSpectrum:  # fmt: skip
    """`read_spectrum` of a peak table's columns, given the study's one bridge (its id), its
    spectrum section and the intensity section it runs as (an IDA of ``scale``)."""
    rule = Rule.of(intensity)
    lattice, states = rule.lattice, rule.states
    records, amplitudes = spectrum.records, spectrum.amplitude_ratios
    rows = {record: i for i, record in enumerate(columns["record"])}
    verdicts = {
        record: Verdict(columns["status"][i], columns["failure_mode"][i],
                        float(columns["dcr_backfill"][i]))
        for record, i in rows.items()
    }  # fmt: skip
    regions = np.full((len(records), len(amplitudes)), NOT_RUN, dtype=np.int8)
    boundaries = {state: np.full(len(records), np.nan) for state in states}
    below = {state: np.full(len(records), np.nan) for state in states}
    tags = [rule.record("", j * lattice.stride) for j in range(len(amplitudes))]  # once a level
    for i, base in enumerate(records):
        for j, tag in enumerate(tags):
            row = rows.get(base + tag)
            regions[i, j] = NOT_RUN if row is None else _region(columns, row)
        found = rule.replay(base, verdicts.get).capacities
        for state, (low, high) in found.items():
            if high is not None:
                boundaries[state][i] = lattice.level(high)
                below[state][i] = lattice.level(low) if low >= 0 else math.nan
    return OverturningSpectrum(
        bridge, spectrum.pulse, spectrum.frequency_parameter, spectrum.reference,
        spectrum.reference_acceleration, np.array(spectrum.frequency_ratios),
        np.array(amplitudes), list(records), regions, boundaries, below,
    )  # fmt: skip


def _region(columns: dict[str, np.ndarray], row: int) -> int:
    """The `REGIONS` code of one analysis of the peak table."""
    if columns["status"][row] == "error":
        return NOT_RUN
    mode = columns["failure_mode"][row]
    if mode in (PIER1_OVERTURNING, PIER2_OVERTURNING):
        return REGIONS.index(
            "overturning_after_impact" if columns["n_impacts"][row] > 0
            else "overturning_without_impact"
        )  # fmt: skip
    if mode == ABUTMENT:
        return REGIONS.index("abutment_failure")
    if columns["dcr_backfill"][row] > 0.0:
        return REGIONS.index("gap_closure")
    return REGIONS.index("rocking" if math.isfinite(columns["t_onset"][row]) else "no_rocking")


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

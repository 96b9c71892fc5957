"""A study's fragilities and demands in the formats of the tools engineers use next: an OpenQuake
fragility model (portfolio damage and risk) and pelicun demand samples (losses).

**OpenQuake** (NRML 0.5 ``fragilityModel``, the engine's manual, "Fragility Models"): one
continuous ``logncdf`` fragility function per bridge with one ``params`` per limit state. Its
``id``, the taxonomy an exposure model names, is the bridge's id in the characters the engine
accepts (letters, digits, ``_ - :``; others become ``_``: ``studied-hbar1.00`` is
``studied-hbar1_00``), at most 75 of them. NRML's ``mean`` and ``stddev`` are the mean and
standard deviation of the intensity itself, not of its logarithm: for a median θ and a
log-standard deviation β, mean = θ·exp(β²/2) and stddev = mean·√(exp(β²) − 1). ``minIML`` and
``maxIML`` are the lowest and the highest level the study ran; the engine holds the probability
constant outside them. Limit states are listed in rockbridge's order (`LIMIT_STATES`), which
the engine takes as successive damage states; a limit state is left out where a bridge has no
fit with a β (the returned list says which and why). The engine requires an ``assetCategory``
and checks no value: ``lifelines``, the manual's example besides buildings.

**pelicun** (its demand sample CSV): one file per bridge and stripe, an intensity level at which
every record of the bridge is accounted for (every level of a multiple-stripe study; in an IDA,
every scan level up to the last one a record ran: a record that failed below a level counts as
collapsed there, with its failure's row, as pelicun's stripes expect, so the stripes reach past
the median capacity; `stripes`). Columns are named ``event-type-location-direction``, the
second row holds units, then one row per record. ``DEC`` is the deck's peak displacement,
``ABP`` the backfill's peak passive displacement (|u_deck| beyond the gap), ``FNR`` the peak
rocking rotation of pier 1 (the tall pier) and 2 at its base, ``PGA``, ``PGV`` or ``SA_<T>`` the
stripe's intensity (`PELICUN_MEASURES`); ``COL`` is 1 where the analysis ended in a failure of
the bridge (abutment or overturning: its demands are those at the failure; pelicun can count it
as collapse through a ``CollapseLimits`` entry or a collapse fragility on ``COL``) and ``ERROR``
1 where the analysis did not run to its end (pelicun drops those rows).
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np

from ..core.quantities import NO_FAILURE
from ..errors import InputError
from ..motions.intensity import MEASURES, scaled_id
from ..paths import checked_output, replace_atomically, writable
from ..results.reading import open_results, peak_columns, read_intensity
from ..results.sections import IntensitySection
from .fragility import Fragility, fragilities
from .hazard import OPENQUAKE_MEASURES, UNITS
from .risk import levels_range

NRML = "http://openquake.org/xmlns/nrml/0.5"
"""The namespace of NRML 0.5, the format of OpenQuake engine ≥ 1.7."""

PELICUN_DEMANDS = (
    ("DEC-1-1", "u_deck_max", "m"), ("ABP-1-1", "backfill", "m"),
    ("FNR-1-1", "theta1_max", "rad"), ("FNR-2-1", "theta2_max", "rad"),
)  # fmt: skip
"""pelicun's demand type-location-direction, the peak-table column and its unit (location: the
deck and the abutments 1, pier 1 or 2; direction 1: along the bridge)."""

PELICUN_MEASURES = {"pga_g": ("PGA", "g"), "pgv": ("PGV", "mps"), "sa_g": ("SA", "g")}
"""pelicun's demand type of an intensity measure and pelicun's name of its unit (its
``default_units.json``: ``g``, ``mps`` for m/s). pelicun's ``PGD`` is a permanent ground
deformation, not a peak ground displacement, and it has no type for AvgSa, Arias intensity, CAV
or a scale factor: their samples hold no intensity column (the file name gives the level)."""


def openquake_fragility_model(results: str | Path, output: str | Path) -> list[str]:
    """Write the fragilities of a results file as an OpenQuake NRML fragility model.

    Returns
    -------
    The limit states left out, each with the reason.

    Raises
    ------
    InputError
        No intensity section, a measure OpenQuake has no type for (``scale``), or no limit
        state with a fit for every bridge.
    """
    target = writable(output)
    with open_results(results) as file:
        intensity = read_intensity(file)
    found = fragilities(results, bootstrap=0)  # refuses a study without an intensity section
    assert intensity is not None
    measure = intensity.measure
    imt, unit = _openquake_type(results, measure, intensity.period)
    factor = UNITS[MEASURES[measure].unit][1] / UNITS[unit][1]
    fitted, left_out = _fitted(found)
    if not fitted:
        raise InputError(results, [("", "no limit state has a fit for every bridge")])
    lowest, highest = levels_range(intensity)
    root = ElementTree.Element("nrml", xmlns=NRML)
    model = ElementTree.SubElement(root, "fragilityModel", id=_model_id(results),
                                   assetCategory="lifelines",
                                   lossCategory="structural")  # fmt: skip
    ElementTree.SubElement(model, "description").text = (
        f"rockbridge: lognormal fragility of {len({item.bridge for item in found})} bridges on "
        f"rocking piers in {imt} [{unit}] from {Path(results).name}"
    )
    ElementTree.SubElement(model, "limitStates").text = " ".join(fitted)
    for bridge, taxonomy in _taxonomies(results, [item.bridge for item in found]).items():
        function = ElementTree.SubElement(model, "fragilityFunction", id=taxonomy,
                                          format="continuous", shape="logncdf")  # fmt: skip
        ElementTree.SubElement(function, "imls", imt=imt, minIML=_tidy(lowest * factor),
                               maxIML=_tidy(highest * factor))  # fmt: skip
        for state, fits in fitted.items():
            median, beta = fits[bridge]
            mean, stddev = lognormal_moments(median * factor, beta)
            ElementTree.SubElement(function, "params", ls=state, mean=repr(mean),
                                   stddev=repr(stddev))  # fmt: skip
    ElementTree.indent(root)
    ElementTree.ElementTree(root).write(target, encoding="UTF-8", xml_declaration=True)
    return left_out


def lognormal_moments(median: float, beta: float) -> tuple[float, float]:
    """Mean and standard deviation of a lognormal variable of median θ and log-standard deviation
    β: θ·exp(β²/2) and mean·√(exp(β²) − 1) [θ's unit]."""
    mean = median * float(np.exp(0.5 * beta * beta))
    return mean, mean * float(np.sqrt(np.expm1(beta * beta)))


def _fitted(found: list[Fragility]) -> tuple[dict[str, dict[str, tuple[float, float]]], list[str]]:
    """Per limit state with a median and a β for every bridge, each bridge's (θ, β); and the
    other limit states, each with the bridges that lack a fit."""
    fitted, left_out = {}, []
    for state in dict.fromkeys(item.limit_state for item in found):
        mine = [item for item in found if item.limit_state == state]
        fits = {i.bridge: (i.median, i.beta) for i in mine if i.median and i.beta is not None}
        if len(fits) == len(mine):
            fitted[state] = fits
        else:
            missing = ", ".join(item.bridge for item in mine if item.bridge not in fits)
            left_out.append(f"{state} (no lognormal fit for {missing})")
    return fitted, left_out


def _openquake_type(results, measure: str, period: float | None) -> tuple[str, str]:
    """OpenQuake's intensity measure type of a rockbridge measure, and the engine's unit."""
    for imt, (name, unit) in OPENQUAKE_MEASURES.items():
        if name == measure:
            return (f"SA({float(period or 0.0)!r})" if imt == "SA" else imt), unit
    reason = f"OpenQuake has no intensity measure type for {measure}"
    raise InputError(results, [("intensity.measure", reason)])


def _taxonomies(results, bridges: list[str]) -> dict[str, str]:
    """Each bridge's taxonomy: its id in the characters OpenQuake accepts, ``[\\w:-]``, ≤ 75."""
    taxonomies = {bridge: re.sub(r"[^\w:-]", "_", bridge) for bridge in bridges}
    problems = [(bridge, "longer than the 75 characters of an OpenQuake taxonomy")
                for bridge, taxonomy in taxonomies.items() if len(taxonomy) > 75]  # fmt: skip
    if len(set(taxonomies.values())) < len(taxonomies):
        problems.append(("", "two bridge ids differ only in characters OpenQuake refuses"))
    if problems:
        raise InputError(results, problems)
    return taxonomies


def _tidy(value: float) -> str:
    """A level at 12 significant digits: 3.9, not 3.9000000000000004."""
    return repr(float(f"{value:.12g}"))


def _model_id(results: str | Path) -> str:
    """The model's id: the results file's stem in the characters NRML allows (≤ 100)."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", Path(results).stem)[:100] or "rockbridge"


def pelicun_demands(results: str | Path, folder: str | Path) -> list[Path]:
    """Write the demand samples of a results file, one pelicun CSV per bridge and stripe, into
    ``folder`` as ``<bridge>+<level>.csv`` (the level as in record ids, ``+0.6g``).

    A file of that name already in ``folder`` is replaced only where it is a demand sample of
    the same columns (its first line is the header written here); anything else there is
    refused before a file is written, and each file is written aside and renamed into place.

    Returns
    -------
    The files written.

    Raises
    ------
    InputError
        The study has no intensity section (no stripes), or a file of a name to be written is
        there and is not such a demand sample (or not a regular file, or the results file).
    """
    with open_results(results) as file:
        intensity = read_intensity(file)
        columns = peak_columns(file)
        capacities = {
            name: float(node.attrs.get("model_u_ab", np.nan))
            for name, node in file["bridges"].items()
        }
    if intensity is None:
        raise InputError(results, [("", "the study has no intensity section: no stripes")])
    folder = writable(folder, folder=True)
    samples: dict[Path, str] = {}
    for bridge in dict.fromkeys(columns["bridge"]):
        mine = {name: values[columns["bridge"] == bridge] for name, values in columns.items()}
        mine["backfill"] = mine["dcr_backfill"] * capacities[bridge]
        for level, rows in stripes(mine):
            path = folder / f"{scaled_id(bridge, level, intensity.measure)}.csv"
            samples[path] = _demands({name: values[rows] for name, values in mine.items()},
                                     intensity, level)  # fmt: skip
    for path, text in samples.items():  # every file checked before any is written

        def ours(existing: Path, header: str = text.partition("\n")[0] + "\n") -> bool:
            with open(existing, "rb") as stream:
                return stream.readline(len(header.encode()) + 1) == header.encode()

        checked_output(path, results, ours=ours, what="a pelicun demand sample of these columns")
    for path, text in samples.items():
        temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        try:
            temporary.write_text(text, encoding="utf-8")
            replace_atomically(temporary, path)
        finally:
            temporary.unlink(missing_ok=True)
    return list(samples)


def stripes(rows: dict[str, np.ndarray]) -> list[tuple[float, np.ndarray]]:
    """The stripes of one bridge's peak rows: each level at which every record is accounted
    for, with the row of each record, in the records' order.

    A record is accounted for at a level it ran (its row there) or at a level above one where
    its analysis ended in a failure of the bridge: an IDA runs a record no further once it
    fails, so the record has collapsed at every higher level, and its row is its failure at the
    highest level below (``COL`` 1). A level some record neither ran nor failed below (an IDA's
    bisection of another record, a record whose scan stopped without a failure) is no stripe.
    """
    failed = (rows["failure_mode"] != NO_FAILURE) & (rows["status"] == "ok")
    records = list(dict.fromkeys(rows["base_record"].tolist()))
    ran: dict[tuple[str, float], int] = {}
    failures: dict[str, list[tuple[float, int]]] = {record: [] for record in records}
    pairs = zip(rows["base_record"], rows["intensity"], strict=True)
    for index, (record, level) in enumerate(pairs):
        ran.setdefault((record, float(level)), index)
        if failed[index]:
            failures[record].append((float(level), index))
    found = []
    for level in sorted(set(rows["intensity"].tolist())):
        chosen = []
        for record in records:
            below = [item for item in failures[record] if item[0] < level]
            found_at = ran.get((record, level), max(below)[1] if below else None)
            if found_at is None:
                break
            chosen.append(found_at)
        else:
            found.append((level, np.array(chosen, dtype=np.int64)))
    return found


def pelicun_intensity(intensity: IntensitySection) -> tuple[str, str] | None:
    """pelicun's demand type and unit of a study's intensity measure (`PELICUN_MEASURES`), or
    None where pelicun has none."""
    found = PELICUN_MEASURES.get(intensity.measure)
    if found is None:
        return None
    name, unit = found
    return (f"{name}_{intensity.period or 0:.2f}" if name == "SA" else name), unit


def _demands(rows: dict[str, np.ndarray], intensity: IntensitySection, level: float) -> str:
    """One pelicun demand sample: a header, a units row and one row per record."""
    header, units, values = [""], ["Units"], []
    for name, column, unit in PELICUN_DEMANDS:
        header.append(f"1-{name}")
        units.append(unit)
        values.append(rows[column])
    measure = pelicun_intensity(intensity)
    if measure is not None:
        header.append(f"1-{measure[0]}-0-1")
        units.append(measure[1])
        values.append(np.full(rows["bridge"].size, float(_tidy(level))))
    header += ["1-COL-0-1", "1-ERROR-0-1"]
    units += ["unitless", "unitless"]
    values.append(((rows["failure_mode"] != NO_FAILURE) & (rows["status"] == "ok")).astype(int))
    values.append((rows["status"] != "ok").astype(int))
    lines = [",".join(header), ",".join(units)]
    for index, row in enumerate(zip(*values, strict=True)):
        cells = [str(index)] + [_cell(value) for value in row]
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def _cell(value) -> str:
    """A CSV cell: integers as they are, floats at full precision, NaN empty."""
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return repr(float(value)) if np.isfinite(value) else ""

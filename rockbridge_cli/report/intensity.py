"""The report's sections of a study with an intensity section (`results.sections.IntensitySection`):
the IDA and fragility curves with their table and intervals, the limit states a failure kept from
being reached, which intensity measure has the smallest β, the risk at a site and an IDA's table
of capacities; and the pieces the report's other sections share with them (`section`,
`measure_name`, `is_ida`)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from ..motions.intensity import MEASURES
from ..results.sections import IntensitySection
from .markup import MAX_ROWS, escaped, number, table_html

if TYPE_CHECKING:
    from ..assessment.hazard import HazardCurve


def section(heading: str, image: str, caption: str) -> str:
    """A section of one figure: its heading, the embedded image and its caption."""
    return (
        f"<h2>{escaped(heading)}</h2>\n<figure>{image}"
        f"<figcaption>{escaped(caption)}</figcaption></figure>"
    )


def measure_name(measure: str) -> str:
    """A measure as a reader names it (PGA, Sa(T)), not by its internal name (pga_g)."""
    return MEASURES[measure].label.split(" [")[0]


def is_ida(intensity: IntensitySection | None) -> bool:
    """Whether the study's intensity section is an IDA (not stripes, not absent)."""
    return intensity is not None and intensity.ida is not None


def intensity_section(
    results: Path, intensity: IntensitySection, figure: Callable[..., str],
    hazard: HazardCurve | None,
    years: float,
) -> str:  # fmt: skip
    from ..assessment.fragility import STUDY, fragilities
    from ..plots.fragility import plot_fragility
    from ..plots.ida import plot_ida

    found = fragilities(results, orientation=STUDY)
    design = intensity.design
    rows = [[item.bridge, item.limit_state, number(item.median), number(item.beta),
             _interval(item.median_90), _interval(item.beta_90)]
            + ([number(None if item.median is None else item.median / design)] if design else [])
            for item in found]  # fmt: skip
    measure = intensity.measure
    unit = MEASURES[measure].unit
    margin = (f"The design level is {design:g} {unit} ({measure}); the last column is each "
              "median's margin over it.") if design else ""  # fmt: skip
    parts = [
        section(f"IDA curves ({MEASURES[measure].label})", figure(plot_ida, results),
                 "Each record's peak against its intensity level; a cross ends a curve where "
                 "the bridge failed.") if is_ida(intensity) else "",
        section(f"Fragility ({MEASURES[measure].label})",
                 figure(plot_fragility, results, found=found),
                 f"Share of the {_records(found)} reaching each limit state, and the fitted "
                 "lognormal; grey, the 90 % band of the curves the bootstrap over the "
                 f"{'pairs' if found and found[0].orientation else 'records'} fits."),
        f"<p>{margin}</p>" if margin else "",
        f'<p class="note">{escaped(INTERVALS)}</p>',
        table_html(["bridge", "limit state", f"median [{unit}]", "β", f"median, 5–95 % [{unit}]",
                    "β, 5–95 %"]
               + (["median / design"] if design else []), rows, text_columns=(0, 1)),
        _unreachable(found),
        _efficiency_section(results) if is_ida(intensity) else "",
        "" if hazard is None else _risk_section(found, intensity, hazard, years),
    ]  # fmt: skip
    return "\n".join(part for part in parts if part)


INTERVALS = (
    "The 5–95 % intervals of the median and of β, the band and the risk's intervals come from "
    "one bootstrap: the records resampled with replacement 100 times and refitted. With few "
    "records they are too narrow (a 90 % interval of β holds the true β in about 65 % of "
    "10-record studies, 83 % of 44-record ones); rockbridge fragility RESULTS --records-needed "
    "shows how they narrow with the number of records."
)
"""What the report says of the fragility's intervals (`assessment.fragility_intervals`)."""


def _records(found: list) -> str:
    """What the fragility's records are: the records, or a swept orientation's pairs and how
    each is taken over its angles."""
    from ..assessment.orientation import COMBINED

    paired = found[0].orientation if found else None
    if paired is None:
        return "records"
    return (f"pairs of horizontal components (each reaching a state where {COMBINED[paired]} "
            "does: the study's intensity.orientation, the median without one)")  # fmt: skip


def _interval(pair: tuple[float, float] | None) -> str:
    return "-" if pair is None else f"{pair[0]:.3g}–{pair[1]:.3g}"


def _unreachable(found: list) -> str:
    """The limit states a failure kept some IDA curves from reaching, one line each."""
    from ..assessment.fragility import unreachable_note

    notes = [f"{item.bridge}: {unreachable_note(item)}" for item in found if item.unreachable]
    if not notes:
        return ""
    items = "".join(f"<li>{escaped(note)}</li>" for note in notes)
    return (
        '<p class="note">A failure ends an analysis, so on a curve that ended in one, the states '
        f"not reached by then cannot be observed:</p><ul>{items}</ul>"
    )


def _efficiency_section(results: Path) -> str:
    """β of the IDA's capacities in each intensity measure (`assessment.efficiency`)."""
    from ..assessment.efficiency import SQUARED, best_measures, comparable_beta, compare

    rows = compare(results)
    measures = list(dict.fromkeys(row.measure for row in rows))
    beta = {(row.bridge, row.limit_state, row.measure): row.beta for row in rows}
    cases = list(dict.fromkeys((row.bridge, row.limit_state) for row in rows))

    def shown(case: tuple[str, str], measure: str) -> str:
        value = beta[case + (measure,)]
        return number(None if value is None else comparable_beta(measure, value))

    table = [[*case, *(shown(case, m) for m in measures)] for case in cases]
    table = [row for row in table if any(cell != "-" for cell in row[2:])]
    text = (
        "β of the capacities converted to each measure (Sa at 1 s, AvgSa over 0.2–3 s): the "
        "smaller β, the fewer records fix the median (its standard error is β/√n). Arias "
        "intensity grows as the square of a record's factor: its column gives half its β. "
        "rockbridge fragility RESULTS --compare-measures adds the trends with magnitude and "
        "distance."
    )
    best = best_measures(rows)
    if best:
        first, *others = best.items()
        text += (f" The smallest β: {measure_name(first[0])}, in {first[1]} of "
                 f"{sum(best.values())} bridge × limit-state cases"
                 + "".join(f"; {measure_name(m)} in {n}" for m, n in others) + ".")  # fmt: skip
    headers = [measure_name(m) + (" (½β)" if m in SQUARED else "") for m in measures]
    return f"<h2>Which intensity measure</h2>\n<p>{escaped(text)}</p>\n" + table_html(
        ["bridge", "limit state", *headers], table, text_columns=(0, 1)
    )


def _risk_section(
    found: list, intensity: IntensitySection, hazard: HazardCurve, years: float
) -> str:
    """Each limit state's annual frequency at the site of the hazard curve, its return period and
    its probability in ``years``."""
    from ..assessment.risk import risk_table, risks_of

    rates = risks_of(found, intensity, hazard, years)
    headers, rows = risk_table(rates, years)
    notes = "".join(f"<li>{escaped(f'{r.bridge}: {r.note}')}</li>" for r in rates if r.note)
    return (
        f"<h2>Risk at the site of {escaped(Path(hazard.source).name)}</h2>\n<p>Hazard curve: "
        f"{escaped(hazard.describe())}; beyond its range it goes on as the power laws of its end "
        "segments. λ is the mean annual frequency of each limit state, ∫ P(LS | im) |dλ<sub>IM"
        "</sub>(im)| (Cornell et al. 2002), the return period 1/λ and P the probability of at "
        f"least one occurrence in {years:g} years, 1 − exp(−λ·{years:g}); the 5–95 % intervals "
        "are those of the bootstrap over the records. &lt; marks an upper bound: no record "
        "reaches the state up to the highest level run, or up to where a failure ended its "
        "curve.</p>\n"
        + table_html(headers, rows, text_columns=(0, 1))
        + (f'<ul class="note">{notes}</ul>' if notes else "")
    )


def capacity_table(results: Path, intensity: IntensitySection, analyses: int) -> str:
    """An IDA's table: each bridge × record's capacity for each limit state, in place of its
    peak table (a row per level run of each record, pages of them)."""
    from ..assessment.fragility import fragilities

    found = fragilities(results)
    states = list(dict.fromkeys(item.limit_state for item in found))
    capacities = {(item.bridge, item.limit_state): item.capacities for item in found}
    unit = MEASURES[intensity.measure].unit
    rows = [
        [bridge, record, *(number(capacities[bridge, state].get(record)) for state in states)]
        for bridge in dict.fromkeys(item.bridge for item in found)
        for record in capacities[bridge, states[0]]
    ]
    more = f'<p class="note">{len(rows) - MAX_ROWS} more rows.</p>' if (
        len(rows) > MAX_ROWS) else ""  # fmt: skip
    return (
        f'<h2>Capacities</h2>\n<p class="note">Each record\'s capacity, the lowest '
        f"{escaped(measure_name(intensity.measure))} at which it reaches each limit state ('-': no "
        f"level run reaches it). The results file holds the peaks of all {analyses} analyses, "
        "a row per level run (rockbridge peaks RESULTS).</p>\n"
        + table_html(["bridge", "record", *(f"{state} [{unit}]" for state in states)],
                     rows[:MAX_ROWS], text_columns=(0, 1))
        + more
    )  # fmt: skip

"""The ``fragility`` command: lognormal fragility functions from a study with an intensity
section; ``plot fragility`` and ``plot ida`` draw them."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

import click

from ..motions.intensity import MEASURES
from . import main, plot
from .output import echo_json, export_csv, figure_option, results_argument, table_text


@main.command()
@results_argument()
@click.option("--json", "as_json", is_flag=True, help="Print the rows (SI, g) as JSON.")
@click.option(
    "--csv", "csv_file", type=click.Path(dir_okay=False, allow_dash=True), default=None,
    help="Write the rows as CSV to FILE, or - for the standard output: one column per record "
    "with its capacity (empty: not reached).",
)  # fmt: skip
@click.option(
    "--measure", type=click.Choice(list(MEASURES)), default=None,
    help="Fit an IDA's capacities converted to this intensity measure (default the study's).",
)  # fmt: skip
@click.option("--period", type=click.FloatRange(min=0.0, min_open=True), default=None,
              help="Period of sa_g [s] (with --compare-measures: 1 s).")  # fmt: skip
@click.option(
    "--period-range", type=(float, float), default=None,
    help="Shortest and longest period of avgsa_g [s] (with --compare-measures: 0.2 3).",
)  # fmt: skip
@click.option(
    "--compare-measures", is_flag=True,
    help="Tabulate, per bridge and limit state, each measure's β (efficiency) and the trend of "
    "the log-capacities with magnitude and distance (sufficiency), from an IDA.",
)  # fmt: skip
@click.option(
    "--records-needed", is_flag=True,
    help="Tabulate, per bridge and limit state, the half-widths of the 90 % intervals of the "
    "median and of β for n of the records (subsets drawn without replacement), and the n from "
    "which the median is settled.",
)  # fmt: skip
@click.option(
    "--subsets", type=click.IntRange(min=1), default=40, show_default=True,
    help="With --records-needed: subsets of n records drawn at each n below the study's count.",
)  # fmt: skip
@click.option(
    "--orientation", type=click.Choice(["median", "worst", "angles"]), default=None,
    help="Of a study whose records section sweeps an orientation: each pair of horizontal "
    "components as one record, reaching a state where the median over its angles does (at "
    "least half of them) or the worst angle does; angles: each angle a record [default: the "
    "study's intensity.orientation, the median without one, as the run stores it].",
)  # fmt: skip
@click.option(
    "--fold-samples", is_flag=True,
    help="Of a sampled study (uncertainty section): per bridge file, the fragility over every "
    "sample × record, beside β_RTR, β_U and the shortcut √(β_RTR² + β_U²).",
)  # fmt: skip
def fragility(
    results: Path,
    as_json: bool,
    csv_file: str | None,
    measure: str | None,
    period: float | None,
    period_range: tuple[float, float] | None,
    compare_measures: bool,
    records_needed: bool,
    subsets: int,
    orientation: str | None,
    fold_samples: bool,
) -> None:
    """Fit a lognormal fragility per bridge and limit state to RESULTS, the file of a study with
    an intensity section: from stripes by maximum likelihood (Baker 2015), from an IDA the
    log-mean and log-standard deviation of the capacities (censored where a record reaches the
    state at the first level or never); 90 % intervals of the median and of β by a bootstrap over
    the records. The run stores the fits in RESULTS (/fragility). An IDA's capacities convert
    exactly to any other intensity measure (--measure): nothing is run again. --records-needed
    shows how the intervals narrow with the number of records; --fold-samples folds a sampled
    study's parameter uncertainty in; a swept orientation's pairs are fitted as the study
    states (--orientation chooses)."""
    from ..assessment.fragility import STUDY, design_level, fragilities, unreachable_note
    from ..assessment.orientation import COMBINED

    if orientation is not None and (fold_samples or compare_measures):
        raise click.UsageError("--orientation fits the fragilities, not with --fold-samples or "
                               "--compare-measures")  # fmt: skip

    if fold_samples:
        _folded(results, as_json, csv_file)
        return
    if compare_measures:
        _compare(results, period or 1.0, period_range or (0.2, 3.0), as_json, csv_file)
        return
    combine = STUDY if orientation is None else None if orientation == "angles" else orientation
    found = fragilities(
        results, measure=measure, period=period, period_range=period_range, orientation=combine
    )
    if records_needed:
        _records_needed(found, results, as_json, csv_file, subsets)
        return
    if csv_file is not None:
        export_csv(csv_file, _columns(found), results)
        return
    if as_json:
        echo_json([item.row() for item in found])
        return
    design = design_level(results)
    if design is not None and found and found[0].measure != design[0]:
        design = None  # a level of the study's measure, not of the one fitted
    paired = found[0].orientation if found else None
    headers = ["bridge", "limit state", "median", "beta", "median 5–95 %", "beta 5–95 %",
               "pairs reaching" if paired else "records reaching"]  # fmt: skip
    headers += ["median / design"] if design else []
    rows = []
    for item in found:
        reaching = sum(value is not None for value in item.capacities.values())
        rows.append([item.bridge, item.limit_state, item.median, item.beta,
                     _interval(item.median_90), _interval(item.beta_90),
                     f"{reaching}/{len(item.capacities)}"])  # fmt: skip
        if design:
            rows[-1].append(None if item.median is None else item.median / design[1])
    unit = f" {MEASURES[found[0].measure].unit}" if found else ""
    click.echo(f"measure: {found[0].measure if found else '-'}"
               + (f"; design level {design[1]:g}{unit}" if design else ""))  # fmt: skip
    if paired:
        click.echo(
            f"records: the pairs of horizontal components, each reaching a state where "
            f"{COMBINED[paired]} does (--orientation angles: each angle)"
        )
    click.echo(table_text(headers, rows))
    for item in found:
        if note := unreachable_note(item):
            click.echo(f"{item.bridge}  {note}")
        if item.median is not None and item.beta is None:
            click.echo(f"{item.bridge}  {item.limit_state}: {_UNFIXED.format(item.median)}")


_UNFIXED = (
    "β cannot be fitted from these data (docs/fragility.md), and the median {:.3g} is only where "
    "they split the records, a bound rather than an estimate: more levels, or an IDA, fix both"
)
"""The note under a fit whose β the data leave open (levels that separate the records, one
level alone, a single capacity)."""


def _interval(pair: tuple[float, float] | None) -> str:
    return "-" if pair is None else f"{pair[0]:.3g}–{pair[1]:.3g}"


def _records_needed(
    found: list, results: Path, as_json: bool, csv_file: str | None, subsets: int
) -> None:
    """Print (or export) the widths of each fragility's intervals against the record count."""
    from ..assessment.fragility_intervals import MIN_RECORDS, SETTLED, all_records_needed

    needed = all_records_needed(found, subsets=subsets)
    if not needed and not as_json and csv_file is None:
        click.echo(f"No fragility with a fitted β from {MIN_RECORDS} records or more: nothing to "
                   "subsample.")  # fmt: skip
        return
    if csv_file is not None:
        export_csv(csv_file, _needed_columns(needed), results)
        return
    if as_json:
        echo_json([item.row() for item in needed])
        return
    total = max((item.records for item in needed), default=0)
    click.echo(textwrap.fill(
        "Half-widths of the 90 % intervals with n of the records: the median's ln(θ95/θ05)/2 "
        f"(about its relative half-width), β's (β95 − β05)/2β; the median over {subsets} "
        "subsets of n records drawn without replacement, each with its own bootstrap; at "
        f"n = {total} the study's own intervals. Settled: the median's half-width at most "
        f"{SETTLED:.3f}, a standard error of ln θ of 0.10 (Shome et al. 1998).", width=100,
    ))  # fmt: skip
    rows = [
        [item.bridge, item.limit_state, w.records, w.median, w.beta, f"{w.fitted}/{w.subsets}",
         "-" if w.kept is None else f"{100 * w.kept:.0f} %", "yes" if w.settled else "no"]
        for item in needed for w in item.widths
    ]  # fmt: skip
    click.echo(table_text(
        ["bridge", "limit state", "records", "median ±", "beta ±", "fitted", "kept", "settled"],
        rows,
    ))  # fmt: skip
    for item in needed:
        click.echo(f"{item.bridge}  {item.limit_state}: {_verdict(item)}")
    if any(w.kept is not None and w.kept < 0.9 for item in needed for w in item.widths):
        click.echo(textwrap.fill(
            "kept: the share of the resamplings whose fit fixes β. Where it is below 90 % "
            "(stripes whose levels separate a few records) the ones left out are the extreme "
            "ones, and the half-widths are too narrow.", width=100,
        ))  # fmt: skip


def _verdict(item) -> str:
    """Whether a fragility is settled, from how many records, or how many it would take."""
    import math

    fewest = item.widths[0].records
    if item.settled_at is None:
        law = "" if item.estimate is None else (
            f"; by the 1/√n law, about {math.ceil(item.estimate)}")  # fmt: skip
        return f"not settled with {item.records} records{law}"
    if item.settled_at == fewest < item.records:
        return f"settled already with {fewest} of {item.records} records, the fewest tried"
    return f"settled from {item.settled_at} of {item.records} records"


def _needed_columns(needed: list) -> dict:
    """The records-needed rows as CSV columns: one row per fragility and record count."""
    import numpy as np

    from ..assessment.fragility_intervals import SETTLED

    rows = [(item, w) for item in needed for w in item.widths]

    def numbers(values) -> np.ndarray:
        return np.array([np.nan if v is None else v for v in values], dtype=float)

    return {
        "bridge": np.array([item.bridge for item, _ in rows]),
        "limit_state": np.array([item.limit_state for item, _ in rows]),
        "measure": np.array([item.measure for item, _ in rows]),
        "records": np.array([w.records for _, w in rows]),
        "subsets": np.array([w.subsets for _, w in rows]),
        "fitted": np.array([w.fitted for _, w in rows]),
        "median_half_width": numbers(w.median for _, w in rows),
        "beta_half_width": numbers(w.beta for _, w in rows),
        "resamplings_kept": numbers(w.kept for _, w in rows),
        "settled": np.array([w.settled for _, w in rows]),
        "settled_at": numbers(item.settled_at for item, _ in rows),
        "estimate": numbers(item.estimate for item, _ in rows),
        "rule_median_half_width": np.full(len(rows), SETTLED),
    }


def _compare(
    results: Path,
    period: float,
    period_range: tuple[float, float],
    as_json: bool,
    csv_file: str | None,
) -> None:
    """Print (or export) the efficiency and sufficiency of each measure."""
    import dataclasses

    import numpy as np

    from ..assessment.efficiency import SQUARED, best_measures, comparable_beta, compare

    rows = compare(results, period=period, period_range=period_range)
    data = [dataclasses.asdict(row) for row in rows]
    if csv_file is not None:
        columns = {key: np.array([np.nan if r[key] is None else r[key] for r in data])
                   for key in data[0]} if data else {}  # fmt: skip
        export_csv(csv_file, columns, results)
        return
    if as_json:
        echo_json(data)
        return
    click.echo(
        f"β of the capacities in each measure (Sa at {period:g} s, AvgSa over "
        f"{period_range[0]:g}–{period_range[1]:g} s): a smaller β fixes the median with fewer "
        "records (its standard error is β/√n); Arias intensity scales as the square of a record's "
        "factor, so its column gives half its β"
    )
    measures = list(dict.fromkeys(r["measure"] for r in data))
    cases = list(dict.fromkeys((r["bridge"], r["limit_state"]) for r in data))
    beta = {(r["bridge"], r["limit_state"], r["measure"]): r["beta"] for r in data}
    table = [[*case, *(None if beta[case + (m,)] is None else comparable_beta(m, beta[case + (m,)])
                       for m in measures)] for case in cases]  # fmt: skip
    click.echo(table_text(
        ["bridge", "limit state", *(f"{m} ½β" if m in SQUARED else m for m in measures)],
        [row for row in table if any(value is not None for value in row[2:])],
    ))  # fmt: skip
    best = best_measures(rows)
    if best:
        first, *others = best.items()
        click.echo(f"smallest β: {first[0]}, in {first[1]} of {sum(best.values())} bridge × "
                   "limit-state cases" + "".join(f"; {m} in {n}" for m, n in others))  # fmt: skip
    trends = [r for r in data if r["magnitude_slope"] is not None]
    if trends:
        biased = [r for r in trends if min(r["magnitude_p"], r["distance_p"] or 1.0) < 0.05]
        click.echo(
            f"Sufficiency: {len(trends) - len(biased)} of {len(trends)} bridge × limit state × "
            "measure fits leave no trend of the log-capacity residuals against magnitude or "
            "ln R_rup at p < 0.05" + (", the others:" if biased else "") + " (--csv for all)"
        )
        keys = ["bridge", "limit_state", "measure", "magnitude_slope", "magnitude_p",
                "distance_slope", "distance_p"]  # fmt: skip
        if biased:
            click.echo(table_text(
                ["bridge", "limit state", "measure", "M slope", "p", "ln R slope", "p"],
                [[r[k] for k in keys] for r in biased],
            ))  # fmt: skip


def _columns(found: list) -> dict:
    """The fragility rows as CSV columns: the fit, then each record's capacity."""
    import numpy as np

    records = list(dict.fromkeys(record for item in found for record in item.capacities))

    def number(value: float | None) -> float:
        return np.nan if value is None else value

    columns = {
        "bridge": np.array([item.bridge for item in found]),
        "limit_state": np.array([item.limit_state for item in found]),
        "measure": np.array([item.measure for item in found]),
        "median": np.array([number(item.median) for item in found], dtype=float),
        "beta": np.array([number(item.beta) for item in found], dtype=float),
        "median_05": np.array([item.median_90[0] if item.median_90 else np.nan for item in found]),
        "median_95": np.array([item.median_90[1] if item.median_90 else np.nan for item in found]),
        "beta_05": np.array([item.beta_90[0] if item.beta_90 else np.nan for item in found]),
        "beta_95": np.array([item.beta_90[1] if item.beta_90 else np.nan for item in found]),
    }
    for record in records:
        columns[f"capacity_{record}"] = np.array(
            [number(item.capacities.get(record)) for item in found], dtype=float
        )
    return columns


@plot.command("fragility")
@results_argument()
@figure_option("<results stem>-fragility.png beside RESULTS")
def plot_fragility(results: Path, output: Path | None) -> None:
    """Fragility curves of RESULTS (a study with an intensity section): the share of records
    reaching each limit state per level and the fitted lognormal, one style per bridge, over the
    90 % band of the bootstrap's curves (grey)."""
    from ..plots.fragility import plot_fragility as draw

    click.echo(
        f"Figure: {draw(results, output or results.with_name(f'{results.stem}-fragility.png'))}"
    )


@plot.command("records-needed")
@results_argument()
@figure_option("<results stem>-records-needed.png beside RESULTS")
def plot_records_needed(results: Path, output: Path | None) -> None:
    """How the 90 % intervals of each fragility of RESULTS narrow with the number of records:
    per limit state, the half-widths of the median's and of β's against n, and the limit under
    which the median is settled (rockbridge fragility RESULTS --records-needed tabulates them)."""
    from ..plots.fragility import plot_records_needed as draw

    target = output or results.with_name(f"{results.stem}-records-needed.png")
    click.echo(f"Figure: {draw(results, target)}")


@plot.command("ida")
@results_argument()
@figure_option("<results stem>-ida.png beside RESULTS")
@click.option(
    "--quantity", default="u_deck_max", show_default=True,
    help="Peak-table column on the horizontal axis (rockbridge peaks --help lists them).",
)  # fmt: skip
def plot_ida(results: Path, output: Path | None, quantity: str) -> None:
    """IDA curves of RESULTS (a study with an intensity section): per bridge, each record's peak
    response against its intensity, failures and each record's capacities marked."""
    from ..plots.ida import plot_ida as draw

    target = output or results.with_name(f"{results.stem}-ida.png")
    click.echo(f"Figure: {draw(results, target, quantity)}")


def _folded(results: Path, as_json: bool, csv_file: str | None) -> None:
    from ..assessment.sampled_fragility import folded_fragilities

    rows = [item.row() for item in folded_fragilities(results)]
    if csv_file is not None:
        columns = {key: [row[key] for row in rows] for key in rows[0] if key != "median_90"}
        export_csv(csv_file, columns, results)  # type: ignore[arg-type]
        return
    if as_json:
        echo_json(rows)
        return
    click.echo(f"measure: {rows[0]['measure'] if rows else '-'}; folded over every sample × record")
    click.echo(table_text(
        ["bridge", "limit state", "median", "beta", "median 5–95 %", "samples fitted",
         "beta_RTR", "beta_U", "shortcut"],
        [[r["bridge"], r["limit_state"], r["median"], r["beta"],
          _span(r["median_90"]),
          f"{r['samples_fitted']}/{r['samples']}", r["beta_rtr"], r["beta_u"],
          r["beta_shortcut"]] for r in rows],
    ))  # fmt: skip
    for r in rows:
        if r["median"] is not None and r["beta"] is None:
            click.echo(f"{r['bridge']}  {r['limit_state']}: {_UNFIXED.format(r['median'])}")


def _span(bounds: Any) -> str:
    return "-" if not bounds else f"{bounds[0]:.3g}–{bounds[1]:.3g}"

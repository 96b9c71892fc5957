"""The ``fragility`` command: lognormal fragility functions from a study with an intensity
section; ``plot fragility`` and ``plot ida`` draw them."""

from __future__ import annotations

from pathlib import Path

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
def fragility(
    results: Path,
    as_json: bool,
    csv_file: str | None,
    measure: str | None,
    period: float | None,
    period_range: tuple[float, float] | None,
    compare_measures: bool,
) -> None:
    """Fit a lognormal fragility per bridge and limit state to RESULTS, the file of a study with
    an intensity section: from stripes by maximum likelihood (Baker 2015), from an IDA the
    log-mean and log-standard deviation of the capacities (censored where a record reaches the
    state at the first level or never); 90 % interval of the median by a bootstrap over the
    records. The run stores the same in RESULTS (/fragility). An IDA's capacities convert exactly
    to any other intensity measure (--measure): nothing is run again."""
    from ..assessment.fragility import design_level, fragilities, unreachable_note

    if compare_measures:
        _compare(results, period or 1.0, period_range or (0.2, 3.0), as_json, csv_file)
        return
    found = fragilities(results, measure=measure, period=period, period_range=period_range)
    if csv_file is not None:
        export_csv(csv_file, _columns(found), results)
        return
    if as_json:
        echo_json([item.row() for item in found])
        return
    design = design_level(results)
    if design is not None and found and found[0].measure != design[0]:
        design = None  # a level of the study's measure, not of the one fitted
    headers = ["bridge", "limit state", "median", "beta", "median 5–95 %", "records reaching"]
    headers += ["median / design"] if design else []
    rows = []
    for item in found:
        reaching = sum(value is not None for value in item.capacities.values())
        interval = "-" if item.median_90 is None else (
            f"{item.median_90[0]:.3g}–{item.median_90[1]:.3g}")  # fmt: skip
        rows.append([item.bridge, item.limit_state, item.median, item.beta, interval,
                     f"{reaching}/{len(item.capacities)}"])  # fmt: skip
        if design:
            rows[-1].append(None if item.median is None else item.median / design[1])
    unit = f" {MEASURES[found[0].measure].unit}" if found else ""
    click.echo(f"measure: {found[0].measure if found else '-'}"
               + (f"; design level {design[1]:g}{unit}" if design else ""))  # fmt: skip
    click.echo(table_text(headers, rows))
    for item in found:
        if note := unreachable_note(item):
            click.echo(f"{item.bridge}  {note}")


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
    reaching each limit state per level and the fitted lognormal, one style per bridge."""
    from ..plots.fragility import plot_fragility as draw

    click.echo(
        f"Figure: {draw(results, output or results.with_name(f'{results.stem}-fragility.png'))}"
    )


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

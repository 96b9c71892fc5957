"""The ``risk`` command: the annual frequency of each limit state at a site, from a study's
fragilities and the site's hazard curve."""

from __future__ import annotations

from pathlib import Path

import click

from . import main
from .output import echo_json, export_csv, results_argument, table_text


@main.command()
@results_argument()
@click.option(
    "--hazard", required=True, type=click.Path(path_type=Path),
    help="Hazard curve: a CSV of '<measure> [<unit>], annual_rate [1/year]', or OpenQuake's "
    "hazard_curve CSV; in the fragilities' intensity measure.",
)  # fmt: skip
@click.option(
    "--years", type=float, default=50.0, show_default=True,
    help="Exposure time T of the probability of occurrence [years].",
)  # fmt: skip
@click.option("--site", type=int, default=None, help="Site row of an OpenQuake curve (from 0).")
@click.option("--json", "as_json", is_flag=True, help="Print the rows as JSON.")
@click.option(
    "--csv", "csv_file", type=click.Path(dir_okay=False, allow_dash=True), default=None,
    help="Write the rows as CSV to FILE, or - for the standard output.",
)  # fmt: skip
def risk(
    results: Path, hazard: Path, years: float, site: int | None, as_json: bool,
    csv_file: str | None,
) -> None:  # fmt: skip
    """Integrate each fragility of RESULTS (a study with an intensity section) with the hazard
    curve of a site: per bridge and limit state, the mean annual frequency λ (Cornell et al.
    2002), the return period 1/λ, the probability in T years 1 − exp(−λT), and their 90 %
    interval from the bootstrap over the records. Beyond its range the curve goes on as the
    power laws of its end segments; 'beyond' is the share of λ that comes from there. '<' marks
    an upper bound (no record reaches the state up to the highest level run, or up to where a
    failure ended its curve)."""
    from ..assessment.hazard import read_hazard_curve
    from ..assessment.risk import extrapolation_warning, risk_table, risks

    curve = read_hazard_curve(hazard, site)
    found = risks(results, curve, years)
    if csv_file is not None:
        export_csv(csv_file, _columns(found), results)
        return
    if as_json:
        echo_json([item.row() for item in found])
        return
    click.echo(f"hazard: {hazard}: {curve.describe()}")
    click.echo(table_text(*risk_table(found, years)))
    for item in found:
        if item.note:
            click.echo(f"{item.bridge}  {item.note}")
    warning = extrapolation_warning(found, curve)
    if warning:
        click.echo(f"warning: {warning}", err=True)


def _columns(found: list) -> dict:
    """The risk rows as CSV columns."""
    import numpy as np

    def numbers(values) -> np.ndarray:
        return np.array([np.nan if v is None else v for v in values], dtype=float)

    return {
        "bridge": np.array([item.bridge for item in found]),
        "limit_state": np.array([item.limit_state for item in found]),
        "measure": np.array([item.measure for item in found]),
        "rate": numbers(item.rate for item in found),
        "bound": np.array([item.bound for item in found]),
        "rate_05": numbers(item.rate_90 and item.rate_90[0] for item in found),
        "rate_95": numbers(item.rate_90 and item.rate_90[1] for item in found),
        "return_period": numbers(item.return_period for item in found),
        "years": numbers(item.years for item in found),
        "probability": numbers(item.probability for item in found),
        "probability_05": numbers(item.probability_90 and item.probability_90[0] for item in found),
        "probability_95": numbers(item.probability_90 and item.probability_90[1] for item in found),
        "beyond": numbers(item.beyond for item in found),
    }

"""The ``fragility`` command: lognormal fragility functions from a multiple-stripe study."""

from __future__ import annotations

from pathlib import Path

import click

from . import main, plot
from .output import echo_json, table_text


@main.command()
@click.argument("results", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the rows (SI, g) as JSON.")
def fragility(results: Path, as_json: bool) -> None:
    """Fit a lognormal fragility per bridge and limit state to RESULTS, the file of a study with
    an intensity section (maximum likelihood, Baker 2015; 90 % interval of the median by a
    bootstrap over the records)."""
    from ..fragility import fragilities

    found = fragilities(results)
    if as_json:
        echo_json([item.row() for item in found])
        return
    headers = ["bridge", "limit state", "median", "beta", "median 5–95 %", "records reaching"]
    rows = []
    for item in found:
        reaching = sum(value is not None for value in item.capacities.values())
        interval = "-" if item.median_90 is None else (
            f"{item.median_90[0]:.3g}–{item.median_90[1]:.3g}")  # fmt: skip
        rows.append([item.bridge, item.limit_state, item.median, item.beta, interval,
                     f"{reaching}/{len(item.capacities)}"])  # fmt: skip
    click.echo(f"measure: {found[0].measure if found else '-'}")
    click.echo(table_text(headers, rows))


@plot.command("fragility")
@click.argument("results", type=click.Path(path_type=Path))
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="Figure file, .png, .pdf or .svg [default: <results stem>-fragility.png beside RESULTS].",
)  # fmt: skip
def plot_fragility(results: Path, output: Path | None) -> None:
    """Fragility curves of RESULTS (a study with an intensity section): the share of records
    reaching each limit state per level and the fitted lognormal, one style per bridge."""
    from ..plots.fragility import plot_fragility as draw

    click.echo(
        f"Figure: {draw(results, output or results.with_name(f'{results.stem}-fragility.png'))}"
    )

"""The ``fragility`` command: lognormal fragility functions from a study with an intensity
section; ``plot fragility`` and ``plot ida`` draw them."""

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
    an intensity section: from stripes by maximum likelihood (Baker 2015), from an IDA the
    log-mean and log-standard deviation of the capacities (censored where a record reaches the
    state at the first level or never); 90 % interval of the median by a bootstrap over the
    records. The run stores the same in RESULTS (/fragility)."""
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


@plot.command("ida")
@click.argument("results", type=click.Path(path_type=Path))
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="Figure file, .png, .pdf or .svg [default: <results stem>-ida.png beside RESULTS].",
)  # fmt: skip
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

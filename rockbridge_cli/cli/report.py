"""The ``report`` command: a study's results as one self-contained HTML page."""

from __future__ import annotations

from pathlib import Path

import click

from . import main
from .output import results_argument


@main.command()
@results_argument()
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="The HTML file [default: <results stem>-report.html beside RESULTS].",
)  # fmt: skip
@click.option(
    "--record", default=None,
    help="Record of the history figure (Fig. 10) [default: the study's first; none for an IDA].",
)  # fmt: skip
@click.option(
    "--hazard", type=click.Path(path_type=Path), default=None,
    help="A site's hazard curve (as rockbridge risk reads it): add the risk table.",
)  # fmt: skip
@click.option(
    "--years", type=float, default=50.0, show_default=True,
    help="Exposure time of the risk table's probabilities [years].",
)  # fmt: skip
def report(
    results: Path, output: Path | None, record: str | None, hazard: Path | None, years: float
) -> None:
    """Write RESULTS as one HTML page to read, print or send: provenance, the demand/capacity
    summary, Figs. 9 and 10, the peak table with units, the failures, the record set's
    compliance and, for a study with an intensity section, the IDA and fragility curves and,
    with --hazard, the annual frequency of each limit state at that site. The figures are
    embedded: the page needs no network and no other file."""
    from ..assessment.hazard import read_hazard_curve
    from ..report import write_report

    curve = None if hazard is None else read_hazard_curve(hazard)
    target = output or results.with_name(f"{results.stem}-report.html")
    click.echo(f"Report: {write_report(results, target, record, curve, years)}")

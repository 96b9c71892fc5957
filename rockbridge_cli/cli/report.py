"""The ``report`` command: a study's results as one self-contained HTML page."""

from __future__ import annotations

from pathlib import Path

import click

from . import main


@main.command()
@click.argument("results", type=click.Path(path_type=Path))
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="The HTML file [default: <results stem>-report.html beside RESULTS].",
)  # fmt: skip
@click.option(
    "--record", default=None,
    help="Record of the history figure (Fig. 10) [default: the study's first; none for an IDA].",
)  # fmt: skip
def report(results: Path, output: Path | None, record: str | None) -> None:
    """Write RESULTS as one HTML page to read, print or send: provenance, the demand/capacity
    summary, Figs. 9 and 10, the peak table with units, the failures, the record set's
    compliance and, for a study with an intensity section, the IDA and fragility curves. The
    figures are embedded: the page needs no network and no other file."""
    from ..report import write_report

    target = output or results.with_name(f"{results.stem}-report.html")
    click.echo(f"Report: {write_report(results, target, record)}")

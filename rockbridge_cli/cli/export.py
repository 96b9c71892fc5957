"""The ``export`` commands: a study's fragilities and demands in the formats of other tools."""

from __future__ import annotations

from pathlib import Path

import click

from . import main
from .output import results_argument


@main.group()
def export() -> None:
    """A study's results for the tools used next: an OpenQuake fragility model, pelicun demand
    samples. (CSV and JSON of the fragilities: rockbridge fragility --csv, --json.)"""


@export.command("openquake")
@results_argument()
@click.option(
    "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="The NRML file [default: <results stem>-fragility.xml beside RESULTS].",
)  # fmt: skip
def export_openquake(results: Path, output: Path | None) -> None:
    """Write the fragilities of RESULTS (a study with an intensity section) as an OpenQuake
    fragility model (NRML 0.5): one continuous lognormal function per bridge, its id the
    bridge's (characters OpenQuake refuses become _), one set of parameters per limit state
    with a fit for every bridge."""
    from ..assessment.exports import openquake_fragility_model
    from ..paths import checked_output

    target = output or results.with_name(f"{results.stem}-fragility.xml")
    checked_output(target, results, what="a fragility model rockbridge wrote")
    for reason in openquake_fragility_model(results, target):
        click.echo(f"left out: {reason}")
    click.echo(f"OpenQuake fragility model: {target}")


@export.command("pelicun")
@results_argument()
@click.option(
    "-o", "--output", type=click.Path(file_okay=False, path_type=Path), default=None,
    help="The folder of the CSV files [default: <results stem>-pelicun/ beside RESULTS].",
)  # fmt: skip
def export_pelicun(results: Path, output: Path | None) -> None:
    """Write the demand samples of RESULTS (a study with an intensity section) for pelicun: one
    CSV per bridge and stripe (a level every record ran or had failed below: in an IDA, up to
    the last level any record ran), named <bridge>+<level>.csv, with the deck's and the
    backfill's peak displacements, the piers' rocking rotations, the intensity (PGA, PGV, Sa), a
    collapse flag (COL) and pelicun's ERROR flag."""
    from ..assessment.exports import pelicun_demands, pelicun_intensity
    from ..results.reading import open_results, read_intensity

    folder = output or results.with_name(f"{results.stem}-pelicun")
    written = pelicun_demands(results, folder)
    with open_results(results) as file:
        intensity = read_intensity(file)
    if intensity is not None and pelicun_intensity(intensity) is None:
        click.echo(f"no intensity column: pelicun has no demand type for {intensity.measure} "
                   "(each file's name gives its level)")  # fmt: skip
    click.echo(f"pelicun demand samples: {len(written)} files in {folder}")

"""Commands for ground motions: ``generate-records`` and ``plot spectra``."""

from __future__ import annotations

from pathlib import Path

import click

from . import main, plot


@main.command("generate-records")
@click.argument("config", type=click.Path(path_type=Path))
@click.option(
    "--out",
    "out",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Output folder [default: records/<config stem>/].",
)
@click.option(
    "--plot", "with_plot", is_flag=True, help="Also draw the spectra to <out>/spectra.png."
)
def generate_records(config: Path, out: Path | None, with_plot: bool) -> None:
    """Generate artificial records matched to an EN 1998-1 spectrum, as CONFIG describes.

    Writes one text file per record and manifest.json, then prints the EN 1998-1 §3.2.3.1.2
    compliance report.
    """
    from ..config.loading import load
    from ..config.records import RecordSetConfig
    from ..records import format_report, generate_record_set

    settings = load(RecordSetConfig, config)
    folder = out if out is not None else Path("records") / config.stem
    report = generate_record_set(settings, folder, config_name=config.stem)
    click.echo(format_report(report))
    if with_plot:
        from ..plots.spectra import plot_record_spectra

        click.echo(f"Figure: {plot_record_spectra([folder], folder / 'spectra.png')}")


@plot.command("spectra")
@click.argument("records", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    default=Path("spectra.png"),
    show_default=True,
    help="Figure file: .png, .pdf or .svg.",
)
@click.option(
    "--units",
    type=click.Choice(["g", "m/s2", "cm/s2"]),
    default=None,
    help="Units of plain record files that do not state them.",
)
@click.option(
    "--time-step", type=float, default=None, help="Time step of one-column record files [s]."
)
def plot_spectra(
    records: tuple[Path, ...], output: Path, units: str | None, time_step: float | None
) -> None:
    """Plot the 5%-damped spectra of RECORDS (files or generated-set folders) and their mean.

    For a generated set the EN 1998-1 target, its ±10% band and the 90% line are drawn too.
    """
    from ..plots.spectra import plot_record_spectra

    click.echo(f"Figure: {plot_record_spectra(list(records), output, units, time_step)}")

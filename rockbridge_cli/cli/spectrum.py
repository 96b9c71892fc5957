"""``rockbridge spectrum overturning BRIDGE``: the overturning spectrum of a bridge file under a
pulse, run as a spectrum study; and ``rockbridge plot overturning RESULTS``, its figure."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click
import yaml

from ..core.fidelity import PRESETS
from ..motions.pulses import SHAPES
from . import main, plot
from .output import figure_option, results_argument, say
from .study import stopped_line


def _grid(text: str) -> dict[str, float]:
    """``START:STOP:COUNT`` as a range of the spectrum section."""
    try:
        start, stop, count = text.split(":")
        return {"start": float(start), "stop": float(stop), "count": int(count)}
    except ValueError:
        raise click.BadParameter(f"expected START:STOP:COUNT, got {text!r}") from None


@main.group()
def spectrum() -> None:
    """Spectra of a bridge computed by running it: overturning under a pulse."""


@spectrum.command()
@click.argument("bridge", type=click.Path(path_type=Path))
@click.option("--pulse", type=click.Choice(SHAPES), default="one-sine-a", show_default=True)
@click.option("--frequencies", default="0.25:10:40", show_default=True, metavar="START:STOP:N",
              help="ω_p/p, evenly spaced [-].")  # fmt: skip
@click.option("--amplitudes", default="1:10:37", show_default=True, metavar="START:STOP:N",
              help="a_p over the reference acceleration, evenly spaced [-].")  # fmt: skip
@click.option("--reference", type=click.Choice(["g_tan_alpha", "onset"]), default="g_tan_alpha",
              show_default=True, help="a_ref: g·tan α1, or the onset (Eq. 8).")  # fmt: skip
@click.option("--phase", type=float, default=None,
              help="φ, where the shape has a free phase [rad].")  # fmt: skip
@click.option("--cycles", type=float, default=None,
              help="N, n or γ of the shape (motions.pulses) [-].")  # fmt: skip
@click.option(
    "--tolerance",
    type=float,
    default=None,
    help="Bisect each boundary to this width, relative [-] (default 0.002).",
)
@click.option("--limit-state", "limit_states", multiple=True, metavar="NAME",
              help="A boundary to find (repeat for more): overturning, and for a bridge "
              "gap_closure, abutment_failure, backfill_<p> [default: overturning, and "
              "gap_closure and abutment_failure with abutments].")  # fmt: skip
@click.option("--fidelity", type=click.Choice(list(PRESETS)), default="default", show_default=True)
@click.option("--workers", type=click.IntRange(min=1), default=None,
              help="Worker processes [default: the CPUs this process may use].")  # fmt: skip
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Results file [default: results/<bridge stem>-<pulse>.h5].")  # fmt: skip
@click.option("--figure", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Figure file [default: <output stem>.png beside the output].")  # fmt: skip
@click.option("--overwrite", is_flag=True, help="Replace an output that holds other results.")
def overturning(
    bridge: Path, pulse: str, frequencies: str, amplitudes: str, reference: str,
    phase: float | None, cycles: float | None, tolerance: float | None,
    limit_states: tuple[str, ...], fidelity: str, workers: int | None, output: Path | None,
    figure: Path | None, overwrite: bool,
) -> None:  # fmt: skip
    """Overturning spectrum of BRIDGE (a YAML file) under a pulse: every ω_p/p × a_p/a_ref of
    the grid, then each limit state's lowest amplitude per frequency by bisection; stored in an
    HDF5 results file and drawn. The options are those of a study's spectrum section (its
    samples per period and rest too, and every option of a study, with rockbridge run).
    """
    from ..config.study import study_from_data
    from ..cpus import excess_workers
    from ..interrupts import exit_status
    from ..plots.common import check_format
    from ..plots.overturning import plot_overturning
    from ..study.run import run_study
    from .progress import ProgressDisplay

    if workers is not None and (excess := excess_workers(workers)) is not None:
        raise click.BadParameter(excess, param_hint="--workers")
    output = output or Path("results") / f"{bridge.stem}-{pulse}.h5"
    shape: dict = {"shape": pulse}
    shape.update((k, v) for k, v in (("phase", phase), ("cycles", cycles)) if v is not None)
    section: dict[str, Any] = {"pulse": shape if len(shape) > 1 else pulse,
                               "frequencies": _grid(frequencies),
                               "amplitudes": _grid(amplitudes), "reference": reference}  # fmt: skip
    if tolerance is not None:
        section["tolerance"] = tolerance
    if limit_states:
        section["limit_states"] = list(limit_states)
    figure = check_format(figure or output.with_suffix(".png"))  # before the spectrum runs
    data = {
        "description": f"rockbridge spectrum overturning {bridge} --pulse {pulse}",
        "bridges": [str(bridge.resolve())],
        "spectrum": section,
        "fidelity": fidelity,
    }
    source = output.with_suffix(".study.yaml")
    study = study_from_data(
        data, source, yaml.safe_dump(data, sort_keys=False), None, output, confined=False
    )
    display = ProgressDisplay(heading=f"spectrum: {len(study.records)} frequencies", growing=True)
    try:
        report = run_study(study, workers, overwrite=overwrite, progress=display,
                           assembly=display.assembling, notice=display.notice)  # fmt: skip
    except KeyboardInterrupt as stop:  # where the map so far is, and that it resumes
        display.close()
        say(stopped_line(stop, output), err=True)
        click.get_current_context().exit(exit_status(stop))
    display.close()
    click.echo(f"results: {report.output} ({report.total} analyses, "
               f"{report.wall_time_s:.1f} s on {report.workers} worker(s))")  # fmt: skip
    drawn = plot_overturning(report.output, figure)
    click.echo(f"Figure: {drawn}")


@plot.command("overturning")
@results_argument()
@figure_option("<results stem>-overturning.png beside RESULTS")
def plot_overturning_spectrum(results: Path, output: Path | None) -> None:
    """The overturning spectrum of RESULTS (a spectrum study): the map of what each analysis
    reached and each limit state's boundary, ω_p/p across, a_p/a_ref up."""
    from ..plots.overturning import plot_overturning

    figure = output or results.with_name(f"{results.stem}-overturning.png")
    click.echo(f"Figure: {plot_overturning(results, figure)}")

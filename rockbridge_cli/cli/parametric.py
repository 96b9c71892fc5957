"""``plot onset | q | restitution | spans BRIDGE``: the paper's parametric figures (Figs. 3, 4, 7
and 8) of a bridge config, each a call of `plots.parametric`."""

from __future__ import annotations

from pathlib import Path

import click

from . import plot
from .output import figure_option

bridge_argument = click.argument("bridge", type=click.Path(path_type=Path))

h_max_option = click.option(
    "--h-max", type=click.FloatRange(min=1.0, min_open=True), default=None,
    help="Largest h̄ = H1/H2 [default: 5, or the bridge's own if larger].",
)  # fmt: skip


def _figure(bridge: Path, output: Path | None, name: str) -> Path:
    """The figure file: ``output``, or ``<bridge stem>-<name>.png`` in the current folder."""
    return output or Path(f"{bridge.stem}-{name}.png")


@plot.command("onset")
@bridge_argument
@figure_option("<bridge stem>-onset.png in the current folder")
@h_max_option
def plot_onset(bridge: Path, output: Path | None, h_max: float | None) -> None:
    """Onset acceleration of rocking in both directions vs h̄ = H1/H2 (Figure 3), varying the
    short pier of BRIDGE (a YAML file)."""
    from ..plots.parametric import plot_onset as draw

    click.echo(f"Figure: {draw(bridge, _figure(bridge, output, 'onset'), h_max)}")


@plot.command("q")
@bridge_argument
@figure_option("<bridge stem>-q.png in the current folder")
@h_max_option
def plot_q(bridge: Path, output: Path | None, h_max: float | None) -> None:
    """Abutment parameter q vs the short pier's mass (Figure 4), varying the short pier of BRIDGE
    (a YAML file)."""
    from ..plots.parametric import plot_q as draw

    click.echo(f"Figure: {draw(bridge, _figure(bridge, output, 'q'), h_max)}")


@plot.command("restitution")
@bridge_argument
@figure_option("<bridge stem>-restitution.png in the current folder")
@h_max_option
def plot_restitution(bridge: Path, output: Path | None, h_max: float | None) -> None:
    """Restitution η of BRIDGE and of the same frame without abutment seats vs h̄, both
    directions (Figure 7)."""
    from ..plots.parametric import plot_restitution as draw

    click.echo(f"Figure: {draw(bridge, _figure(bridge, output, 'restitution'), h_max)}")


@plot.command("spans")
@bridge_argument
@figure_option("<bridge stem>-spans.png in the current folder")
def plot_spans(bridge: Path, output: Path | None) -> None:
    """Restitution η of BRIDGE vs the side span L1 and vs the central span L2, both directions
    (Figure 8); deck mass and inertia are kept."""
    from ..plots.parametric import plot_spans as draw

    click.echo(f"Figure: {draw(bridge, _figure(bridge, output, 'spans'))}")

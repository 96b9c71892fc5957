"""The ``sensitivity`` command: which sampled bridge field drives a quantity (Sobol' indices of a
study with a saltelli design); ``plot sensitivity`` draws them."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from . import main, plot
from .output import echo_json, export_csv, figure_option, results_argument, table_text

if TYPE_CHECKING:
    from ..assessment.sensitivity import FieldIndices, Sensitivity, Tornado

_QUANTITY = click.option(
    "--quantity", default="dcr_backfill", show_default=True,
    help="A numeric peak-table column, a limit state (abutment_failure, backfill_50, …) or "
    "failure (any failure mode): its mean over a sample's records is the share reaching it.",
)  # fmt: skip

NOISE_MARGIN = 0.05
"""How far past its bounds a first-order index may stray before the command says it is noise:
a converged estimate strays by a few hundredths (an additive output's S1 = ST, estimated
apart)."""

_STATISTIC = click.option(
    "--statistic", type=click.Choice(["mean", "median"]), default="mean", show_default=True,
    help="How a sampled bridge's output is taken over its records.",
)  # fmt: skip


@main.command()
@results_argument()
@_QUANTITY
@_STATISTIC
@click.option("--json", "as_json", is_flag=True, help="Print the rows as JSON.")
@click.option(
    "--csv", "csv_file", type=click.Path(dir_okay=False, allow_dash=True), default=None,
    help="Write the rows as CSV to FILE, or - for the standard output.",
)  # fmt: skip
def sensitivity(
    results: Path, quantity: str, statistic: str, as_json: bool, csv_file: str | None
) -> None:
    """Which sampled field drives a quantity of RESULTS. With design: saltelli (n·(d + 2)
    bridges, each with every record): first- and total-order Sobol' indices with 90 % bootstrap
    intervals, and the share of the quantity's variance over all analyses that is
    record-to-record (E[Var(Q|θ)] / Var(Q)). With design: tornado: each field's one-at-a-time
    swing between its low and high percentile, largest first."""
    from ..assessment.sensitivity import design_of, output_unit, sensitivities, tornadoes

    if design_of(results) == "tornado":
        swings = tornadoes(results, quantity, statistic)
        if not _rows_written(swings, results, as_json, csv_file):
            _tornado(swings, output_unit(results, quantity))
        return
    found = sensitivities(results, quantity, statistic)
    if not _rows_written(found, results, as_json, csv_file):
        _indices(found)


def _indices(found: list[Sensitivity]) -> None:
    for item in found:
        click.echo(
            f"{item.bridge}: {item.statistic} of {item.quantity} over {item.records} records, "
            f"{item.samples} base samples: mean {item.mean:.4g}, std {item.std:.4g}; "
            f"record-to-record share of the variance {item.records_share:.2f}"
        )
        ranked = sorted(item.fields, key=lambda f: -f.total if f.total == f.total else 1.0)
        click.echo(table_text(
            ["field", "first order", "5–95 %", "total order", "5–95 %"],
            [[f.field, f.first, _interval(f.first_interval), f.total,
              _interval(f.total_interval)] for f in ranked],
        ))  # fmt: skip
        if ranked and ranked[0].total == ranked[0].total:
            click.echo(f"dominant: {ranked[0].field} (total order {ranked[0].total:.2f})")
        else:
            click.echo(f"{item.quantity} does not vary over the A and B samples: no field drives "
                       "it, and its indices (shares of its variance) are undefined")  # fmt: skip
        if noisy := [f.field for f in ranked if _impossible(f)]:
            click.echo(f"note: {', '.join(noisy)}: a first-order index outside 0–1 or above its "
                       f"total order is the estimators' noise at n = {item.samples} base "
                       "samples (see its interval); more samples narrow it")  # fmt: skip


def _impossible(field: FieldIndices) -> bool:
    """Whether a field's first-order index lies where no true one can: outside 0–1, or above
    its total order by more than `NOISE_MARGIN`."""
    first = field.first
    return first == first and not -NOISE_MARGIN <= first <= min(1.0, field.total) + NOISE_MARGIN


def _rows_written(found: list, results: Path, as_json: bool, csv_file: str | None) -> bool:
    """Write every item's rows as CSV or JSON, if asked; whether they were."""
    rows = [row for item in found for row in item.rows()]
    if csv_file is not None:
        columns = {key: [row[key] for row in rows] for key in rows[0]} if rows else {}
        export_csv(csv_file, columns, results)  # type: ignore[arg-type]
    elif as_json:
        echo_json(rows)
    return csv_file is not None or as_json


def _tornado(found: list[Tornado], unit: str) -> None:
    from ..config.sweep import field_unit

    for item in found:
        click.echo(f"{item.bridge}: {item.statistic} of {item.quantity} [{unit}]; every field "
                   f"at its median: {item.median:.4g} {unit}")  # fmt: skip
        click.echo(table_text(
            ["field", "unit", "low value", "high value", f"output at low [{unit}]",
             f"output at high [{unit}]", f"swing [{unit}]"],
            [[s.field, field_unit(s.field), *s.values, *s.outputs, s.swing] for s in item.swings],
        ))  # fmt: skip


def _interval(bounds: tuple[float, float]) -> str:
    return "-" if bounds[0] != bounds[0] else f"{bounds[0]:.2f}–{bounds[1]:.2f}"


@plot.command("sensitivity")
@results_argument()
@_QUANTITY
@_STATISTIC
@figure_option("<results stem>-sensitivity.png beside RESULTS")
def plot_sensitivity(results: Path, quantity: str, statistic: str, output: Path | None) -> None:
    """Which sampled field matters in RESULTS: per bridge file, each field's first- and
    total-order Sobol' index with its 90 % interval (design: saltelli), or its swing (design:
    tornado)."""
    from ..assessment.sensitivity import design_of
    from ..plots.sensitivity import plot_sensitivity, plot_tornado

    draw = plot_tornado if design_of(results) == "tornado" else plot_sensitivity
    target = output or results.with_name(f"{results.stem}-sensitivity.png")
    click.echo(f"Figure: {draw(results, target, quantity, statistic)}")

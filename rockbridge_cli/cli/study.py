"""Commands for studies: ``run``, ``peaks``, ``merge`` and the figures of a results file ``plot
peaks|sweep|history``."""

from __future__ import annotations

import dataclasses
import json
from contextlib import nullcontext
from pathlib import Path

import click

from ..core.fidelity import PRESETS
from ..core.quantities import SHOWN, display_unit
from ..errors import InputError
from ..motions.intensity import MEASURES
from . import main, plot
from .output import (
    echo_json,
    export_csv,
    figure_option,
    results_argument,
    say,
    shown,
    table_text,
)

_DISPLAY = tuple(
    (f"{name}_max", f"{shown.text} [{shown.unit}]", shown.factor) for name, shown in SHOWN.items()
)
"""Peak columns shown in tables: column, header with the display unit, scale from SI."""


@main.command()
@click.argument("study", type=click.Path(path_type=Path))
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    default=None,
    help="Worker processes [default: the CPUs this process may use, after its affinity "
    "(taskset, SLURM) and cgroup quota (docker --cpus, Kubernetes limits)]; at most 4 per CPU, "
    "and no more start than the study has analyses. The results do not depend on it.",
)
@click.option(
    "--fidelity",
    type=click.Choice(list(PRESETS)),
    default=None,
    help="Fidelity preset, instead of the study's (its knob overrides still apply).",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Results file [default: the study's output.path, else results/<study stem>.h5].",
)
@click.option(
    "--overwrite",
    is_flag=True,
    help="Start afresh: delete the results file (of any study) and its journal, and recompute "
    "everything. Only a results file is ever replaced, never another file at OUTPUT.",
)
@click.option(
    "--no-resume",
    "resume",
    flag_value=False,
    default=True,
    help="Recompute the analyses already in the results file.",
)
@click.option(
    "--tail",
    type=click.FloatRange(min=0.0),
    default=None,
    help="Free vibration after each record, with zero ground motion, so that a bridge still "
    "rocking when the record ends can come to rest or fail [s; default: the study's, else 0].",
)
@click.option(
    "--recheck",
    is_flag=True,
    default=None,
    help="Run again at the reference preset every analysis that ends in a failure of the bridge "
    "or within 5 % of a capacity (a cheaper preset's verdict can be wrong there).",
)
@click.option(
    "--shard",
    default=None,
    metavar="K/N|auto",
    help="Run only shard K of N (K from 1) of the study's analyses, into its own file "
    "[default output: <output stem>.part-K-of-N.h5], for 'rockbridge merge'. 'auto' takes K (and "
    "N where the scheduler sets it) from a Kubernetes Indexed Job, AWS Batch array job or SLURM "
    "job array; with it, --output names the stem of every task's part.",
)
@click.option(
    "--shard-count",
    type=click.IntRange(min=1),
    default=None,
    help="N for --shard auto where the scheduler does not set it (Kubernetes, AWS Batch); alone, "
    "implies --shard auto.",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="Run the analyses on a Dask distributed cluster (tcp://host:8786) instead of local "
    'worker processes; needs pip install "rockbridge[dask]".',
)
@click.pass_context
def run(
    ctx: click.Context,
    study: Path,
    workers: int | None,
    fidelity: str | None,
    output: Path | None,
    overwrite: bool,
    resume: bool,
    tail: float | None,
    recheck: bool | None,
    shard: str | None,
    shard_count: int | None,
    scheduler: str | None,
) -> None:
    """Run every bridge × record analysis of STUDY (a YAML file) into one HDF5 results file.

    Analyses already in the results file are skipped, so an interrupted run resumes where it
    stopped.
    """
    from ..cpus import excess_workers, usable_cpus
    from ..interrupts import exit_status
    from ..study.executors import LocalPool

    chosen = workers is not None
    part = _shard(shard, shard_count)
    count = workers or usable_cpus()
    if scheduler is None and (excess := excess_workers(count)) is not None:
        raise click.BadParameter(excess, param_hint="--workers")
    automatic = part is not None and shard in (None, "auto")  # the same command in every task
    resolved = _loaded(study, fidelity, output, tail, recheck, part, automatic)
    count, asked = min(count, _analyses(resolved, part)), count  # once the study's size is known
    local = scheduler is None and count > 1
    with LocalPool(count) if local else nullcontext() as pool:  # loading their kernels at once
        from ..study.run import run_study  # imported as the workers start: not theirs
        from .progress import ProgressDisplay

        heading = _heading(resolved, count, scheduler, chosen, part, asked)
        display = ProgressDisplay(heading=heading, growing=_in_rounds(resolved))
        try:
            report = run_study(
                resolved, count, resume, overwrite, progress=display,
                assembly=display.assembling, shard=part, scheduler=scheduler,
                notice=display.notice, pool=pool,
            )  # fmt: skip
        except KeyboardInterrupt as stop:
            display.close()
            say(stopped_line(stop, resolved.output, resume), err=True)
            ctx.exit(exit_status(stop))
    display.close()
    counts = report.statuses
    say(f"results: {report.output}")
    say(
        f"analyses: {report.total} ({report.ran} run now, {report.resumed} already done): "
        f"{counts.get('ok', 0)} ok, {counts.get('solver_error', 0)} solver errors, "
        f"{counts.get('error', 0)} could not run; {report.failures} with a failure of the "
        "bridge"
    )
    on = f"the Dask cluster at {scheduler}" if scheduler else f"{report.workers} worker(s)"
    say(
        f"time: {report.wall_time_s:.2f} s wall on {on}, "
        f"{report.solve_time_s:.2f} s solving "
        f"(summed over the {report.ran} analyses run now)"
    )
    say(_bridge_table(report.output))
    problems = sum(counts.values()) - counts.get("ok", 0)
    if problems:
        say(
            f"error: {problems} analyses did not end ok; their status and message are in the "
            f"peak table (rockbridge peaks {report.output})",
            err=True,
        )
        ctx.exit(1)


def stopped_line(stop: KeyboardInterrupt, output: Path, resume: bool = True) -> str:
    """What a run stopped by a signal says last: where the analyses finished are (the journal,
    until the results file holds them), and how to resume; of a recomputation (``resume``
    False, ``--no-resume``), that no run resumes it (the same command used to be advised, which
    starts it over: a cluster task resubmitted so never ends)."""
    from ..interrupts import stopped_by
    from ..study.journal import journal_path

    journal = journal_path(output)  # removed once the results file holds its own
    kept = journal if journal.exists() else output
    if not kept.exists():  # stopped before its first analysis finished (its kernels compiling?)
        return (f"{stopped_by(stop)}: no analysis had finished, nothing to keep; run the same "
                "command again to start")  # fmt: skip
    if not resume:  # a recomputation: the file it replaces stays, no run resumes it
        return (f"{stopped_by(stop)}: the analyses recomputed so far are in {kept}, beside the "
                "earlier results of the others; the same command starts the recomputation "
                "over, one without --no-resume takes them as they are")  # fmt: skip
    return (f"{stopped_by(stop)}: the analyses finished so far are in {kept}; run the same "
            "command again to resume")  # fmt: skip


def _loaded(
    study: Path, fidelity: str | None, output: Path | None, tail: float | None,
    recheck: bool | None, part: tuple[int, int] | None, automatic: bool = False,
):  # fmt: skip
    """The study as ``run``'s options change it (`config.study.load_study`), its warnings said;
    a shard's output named after its part where no ``--output`` is given, or where the shard is
    the scheduler's (``automatic``: every task of an array runs the same command, and an
    ``--output`` named one file for all of them, the second task refused)."""
    from ..config.study import load_study

    resolved = load_study(study, preset=fidelity, output=output)
    changed = {k: v for k, v in (("tail", tail), ("recheck", recheck)) if v is not None}
    if changed:
        try:
            resolved = resolved.with_knobs(**changed)
        except InputError as exc:  # the option's value, not the study's
            raise click.BadParameter(exc.problems[0][1], param_hint="--tail") from None
    for warning in resolved.warnings:
        say(f"warning: {warning}", err=True)
    if part is not None and (output is None or automatic):
        stem = resolved.output.stem
        name = f"{stem}.part-{part[0] + 1}-of-{part[1]}{resolved.output.suffix}"
        resolved = dataclasses.replace(resolved, output=resolved.output.with_name(name))
    return resolved


@main.command()
@results_argument()
@click.option(
    "--csv",
    "csv_file",
    type=click.Path(dir_okay=False, allow_dash=True),
    default=None,
    help="Write the whole table as CSV (SI units) to FILE, or - for the standard output.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the units and the rows (SI) as JSON.")
@click.option(
    "--orientation", is_flag=True, help="Instead: per bridge, swept pair and level, each "
    "quantity's median over the angles, its worst and the critical angle (a study whose records "
    "section sweeps an orientation); with an intensity section, the fragility each angle a "
    "record, on the pairs' median and on their worst.",
)  # fmt: skip
def peaks(results: Path, csv_file: str | None, as_json: bool, orientation: bool) -> None:
    """Print the peak table of RESULTS (an HDF5 file written by 'rockbridge run'); --json also
    says whether the file is complete (complete, n_complete of n_analyses). A study whose records
    section has an orientation gives each row's pair and angle after its record."""
    from ..assessment.orientation import ANGLE_UNITS, angles_in, with_angles
    from ..results.reading import open_results, peak_columns, peak_units

    if orientation:
        if csv_file is not None:
            raise click.UsageError("--orientation prints its table (or --json), not --csv")
        _orientation_table(results, as_json)
        return

    with open_results(results) as file:
        angles = angles_in(file)
        columns = with_angles(_with_missing_counts(peak_columns(file)), angles)
        units = {**peak_units(file), **(ANGLE_UNITS if angles else {})}
        counts = {key: file.attrs.get(key) for key in ("complete", "n_complete", "n_analyses")}
    if csv_file is not None:
        export_csv(csv_file, columns, results)
        return
    if as_json:
        rows = [dict(zip(columns, row, strict=True)) for row in zip(*columns.values(), strict=True)]
        echo_json({"units": units, **counts, "rows": rows})
        return
    along = [("pair", "pair", 1), ("angle_deg", "angle [deg]", 1)] if angles else []
    shown = [("bridge", "bridge", 1), ("record", "record", 1), *along, *_DISPLAY,
             ("t_onset", "onset [s]", 1), ("n_impacts_significant", "significant impacts", 1),
             ("n_poundings", "poundings", 1), ("failure_mode", "failure", 1),
             ("dcr_backfill", "backfill d/c", 1), ("status", "status", 1)]  # fmt: skip
    table = zip(*(_scaled(columns[name], scale) for name, _, scale in shown), strict=True)
    click.echo(table_text([header for _, header, _ in shown], list(table)))


def _orientation_table(results: Path, as_json: bool) -> None:
    """`peaks --orientation`: the summary over angles of each pair and over the pairs
    (`assessment.orientation.summary_of`, `across_pairs`); with an intensity section, the
    fragility each angle a record and on the pairs' median and worst
    (`assessment.orientation_fragility`)."""
    from ..assessment.orientation import across_pairs, summary_of
    from ..assessment.orientation_fragility import fragility_by_orientation
    from ..results.reading import open_results, peak_units

    summary = summary_of(results)
    if summary.empty:
        why = "no record was analysed along an angle: the study has no orientation section"
        raise InputError(results, [("records", why)])
    suite = across_pairs(summary)
    fragility = fragility_by_orientation(results)
    with open_results(results) as file:
        units = {name: peak_units(file)[name] for name in summary["quantity"].unique()}
    if as_json:
        units = {**units, "critical_angle_deg": "deg", "worst_over_first_median": "-",
                 "worst_over_first_max": "-"}  # fmt: skip
        pairs, over = summary.to_dict("records"), suite.to_dict("records")
        echo_json({"units": units, "rows": pairs, "across_pairs": over,
                   **({"fragility": fragility} if fragility else {})})  # fmt: skip
        return
    headers = ["bridge", "pair", "level", "quantity", "0° (first)", "median", "worst",
               "critical [deg]", "angles"]  # fmt: skip
    click.echo(table_text(headers, _shown_in_units(summary, units)))
    click.echo("\nOver the pairs (medians; worst/first: how much the worst angle raises a pair's "
               "first component alone):")  # fmt: skip
    headers = ["bridge", "level", "quantity", "pairs", "0° (first)", "median", "worst",
               "worst/first, median", "worst/first, max"]  # fmt: skip
    click.echo(table_text(headers, _shown_in_units(suite, units)))
    if fragility:
        click.echo(f"\nFragility, median θ and β [{fragility[0]['measure']}]: each angle a record, "
                   "each pair by the median over its angles, by its worst angle (the run stores "
                   f"the {fragility[0]['stored']}; rockbridge fragility RESULTS):")  # fmt: skip
        keys = [
            f"{way}_{part}" for way in ("angles", "median", "worst") for part in ("median", "beta")
        ]
        click.echo(table_text(
            ["bridge", "limit state", "angles: θ", "β", "median: θ", "β", "worst: θ", "β"],
            [[row["bridge"], row["limit_state"], *(row[k] for k in keys)] for row in fragility],
        ))  # fmt: skip


def _shown_in_units(table, units: dict[str, str]) -> list[list]:
    """An orientation table's rows for display: each quantity's values (first, median, worst) in
    its shown unit (`core.quantities.display_unit`), the unit after its name."""
    rows = []
    for row in table.to_dict("records"):
        unit, scale = display_unit(units[row["quantity"]])
        for key in ("first", "median", "worst"):
            row[key] = shown(row[key] * scale)
        row["quantity"] += "" if unit in ("-", "") else f" [{unit}]"
        rows.append(list(row.values()))
    return rows


def _analyses(study, part: tuple[int, int] | None) -> int:
    """The most analyses a run of the study, or of its shard, can have (an IDA's: its curves
    × their scan levels), which no more workers than that can share."""
    from ..study.grid import Grid
    from ..study.plan import plan_of

    grid = Grid.of(study)
    cells = grid.cells if part is None else grid.shard(*part)
    plan = plan_of(study, grid, cells)
    return max(len(cells) * (1 if plan.sized else plan.lattice.count), 1)  # type: ignore[union-attr]


def _heading(
    study, workers: int, scheduler: str | None, chosen: bool, part, asked: int | None = None
) -> str:
    """The run's first line: where it runs (and which shard); for an IDA, that its total grows."""
    from ..study.shards import shard_label

    capped = asked not in (None, workers)
    if scheduler is not None:
        heading = f"workers: the Dask cluster at {scheduler}"
    elif chosen:
        heading = f"workers: {workers} (--workers {asked}: as many as the study's analyses)"
        heading = heading if capped else f"workers: {workers} (--workers)"
    elif capped:
        heading = (f"workers: {workers} (as many as the study's analyses, fewer than the {asked} "
                   "CPUs this process may use)")  # fmt: skip
    else:
        heading = f"workers: {workers} (the CPUs this process may use; --workers to change)"
    if part is not None:
        heading += f"; shard {shard_label(part)}"
    if study.spectrum is not None:
        heading += ("\nspectrum: each frequency's rounds run the amplitudes the verdicts so far "
                    "call for; the total grows")  # fmt: skip
    elif _in_rounds(study):
        heading += "\nIDA: each round runs the levels the verdicts so far call for; the total grows"
    return heading


def _in_rounds(study) -> bool:
    """Whether a study learns its analyses round by round (an IDA, a spectrum's map)."""
    intensity = study.intensity_section
    return study.spectrum is not None or (intensity is not None and intensity.ida is not None)


def _shard(shard: str | None, count: int | None) -> tuple[int, int] | None:
    """(index, count) of the shard to run, None for the whole study."""
    from ..study.shards import parse_shard, shard_from_environment

    if shard is None and count is None:
        return None
    if shard is None or shard == "auto":
        return shard_from_environment(count)
    if count is not None:
        raise click.UsageError("--shard-count goes with --shard auto, not with --shard K/N")
    try:
        return parse_shard(shard)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--shard") from None


@main.command()
@click.argument("output", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("parts", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("--overwrite", is_flag=True, help="Replace OUTPUT if it holds results.")
@click.pass_context
def merge(ctx: click.Context, output: Path, parts: tuple[Path, ...], overwrite: bool) -> None:
    """Merge the results files of a study's shards (PARTS, from 'run --shard') into OUTPUT: the
    file one run of the whole study would have written."""
    from ..study.merge import merge_results

    report = merge_results(output, list(parts), overwrite)
    for flag in report.flags:
        click.echo(f"warning: {flag}", err=True)
    if report.duplicated:
        click.echo(f"warning: {len(report.duplicated)} analyses are in more than one part "
                   f"(the first part's kept): {_pairs(report.duplicated)}", err=True)  # fmt: skip
    click.echo(f"merged: {report.output} ({report.merged} of {report.total} analyses, "
               f"from {len(parts)} parts)")  # fmt: skip
    if report.missing:
        missing = f"{len(report.missing)} analyses are in no part: {_pairs(report.missing)}"
        click.echo(f"error: {missing}; run their shards and merge again", err=True)
        ctx.exit(1)


def _pairs(pairs: list[tuple[str, str]], shown: int = 5) -> str:
    """The first few bridge/record pairs, and how many more."""
    text = ", ".join(f"{bridge}/{record}" for bridge, record in pairs[:shown])
    return text + (f" and {len(pairs) - shown} more" if len(pairs) > shown else "")


def _bridge_table(results: Path) -> str:
    """Per bridge (and intensity level, in a multiple-stripe study): analyses ok / all, the
    largest of each peak and of the backfill's demand/capacity ratio over the records, and how
    many analyses ended in a failure of the bridge; an IDA's pointer to its capacities."""
    import json

    import numpy as np

    from ..assessment.levels import summary_groups
    from ..core.quantities import NO_FAILURE
    from ..results.reading import open_results, peak_columns, read_intensity

    with open_results(results) as file:
        columns = peak_columns(file)
        intensity = read_intensity(file)
        recheck = bool(json.loads(file.attrs.get("knobs", "{}")).get("recheck", False))
        spectrum = "spectrum" in file
    rechecked = _rechecks(columns, recheck)
    if spectrum:  # run as an IDA of its pulse, read as a map
        return ("spectrum: the lowest overturning amplitude at each frequency and the map of "
                "what each analysis ended in: rockbridge plot overturning "
                f"{results}{rechecked}")  # fmt: skip
    try:
        groups = summary_groups(columns, intensity)
    except ValueError as exc:
        return f"peaks: {str(exc).replace('RESULTS', str(results))}{rechecked}"
    level = [] if intensity is None else [f"level [{MEASURES[intensity.measure].unit}]"]
    headers = ["bridge", *level, "ok", *(header for _, header, _ in _DISPLAY), "backfill d/c",
               "failures"]  # fmt: skip
    rows = []
    for group in groups:
        mine = group.rows
        ok = f"{int(np.sum(columns['status'][mine] == 'ok'))}/{int(np.sum(mine))}"
        largest = _scaled([_largest(columns[name][mine]) for name, _, _ in _DISPLAY], 1.0)
        largest = [value * scale for value, (_, _, scale) in zip(largest, _DISPLAY, strict=True)]
        failed = np.isin(columns["failure_mode"][mine], ("", NO_FAILURE), invert=True)
        rows.append([group.bridge, *([] if group.level is None else [group.level]), ok, *largest,
                     _largest(columns["dcr_backfill"][mine]), int(np.sum(failed))])  # fmt: skip
    heading = "peaks, largest over the records" + (" at each level" if level else "")
    if len(rows) > SUMMARY_ROWS:  # a sweep of 1000 bridges: the rows that matter, not 1000
        worst = sorted(range(len(rows)), key=lambda i: (-rows[i][-1], -_finite(rows[i][-2])))
        rows = [rows[i] for i in sorted(worst[:SUMMARY_ROWS])]
        heading += (f", the {SUMMARY_ROWS} of {len(groups)} rows with the most failures, then "
                    "the largest backfill d/c (every analysis: rockbridge peaks "
                    f"{results})")  # fmt: skip
    return f"{heading}:\n{table_text(headers, rows)}{rechecked}"


SUMMARY_ROWS = 20
"""Rows of `run`'s summary table at most."""


def _finite(value: float) -> float:
    """``value``, with NaN (no analysis ran) below every number."""
    return -float("inf") if value != value else value


def _rechecks(columns: dict, recheck: bool) -> str:
    """How many analyses ``--recheck`` ran again at ``reference``, and which changed verdict
    (peak column ``rechecked``: 1, 2 where the failure mode changed), as a line ("" without)."""
    import numpy as np

    counts = columns["rechecked"]
    if not recheck and not (counts > 0).any():
        return ""
    changed = np.flatnonzero(counts == 2)
    verdicts = "no verdict changed" if not changed.size else (
        f"{changed.size} verdict{'s' * (changed.size > 1)} changed: " + _pairs(
            [(columns["bridge"][i], f"{columns['record'][i]} (now {columns['failure_mode'][i]})")
             for i in changed]))  # fmt: skip
    return (f"\nrecheck: {int(np.sum(counts > 0))} of {counts.size} analyses ran again at the "
            f"reference preset (a failure, or within 5 % of a capacity); {verdicts}")  # fmt: skip


def _largest(values) -> float:
    """The largest value that is not NaN; NaN if there is none."""
    import numpy as np

    finite = values[~np.isnan(values)]
    return float(finite.max()) if finite.size else float("nan")


def _with_missing_counts(columns: dict) -> dict:
    """The count columns with None where the analysis could not run (stored as −1)."""
    from ..results.layout import COUNT_COLUMNS

    return {
        name: [None if v < 0 else int(v) for v in values] if name in COUNT_COLUMNS else values
        for name, values in columns.items()
    }


def _scaled(values, scale: float) -> list:
    """A column for display: numbers times ``scale``, round-off as 0 (text and missing values as
    they are)."""
    return [shown(v) * scale if isinstance(v, float) else v for v in values]


@plot.command("peaks")
@results_argument()
@figure_option("<results stem>-peaks.png beside RESULTS")
@click.option(
    "--level", type=float, default=None,
    help="The intensity level drawn, in a study with intensity levels [the measure's unit].",
)  # fmt: skip
def plot_peaks(results: Path, output: Path | None, level: float | None) -> None:
    """Peak responses per record, one marker per bridge (Figure 9 of the paper), from RESULTS."""
    from ..plots.peaks import plot_peaks as draw

    figure = draw(results, output or results.with_name(f"{results.stem}-peaks.png"), level)
    click.echo(f"Figure: {figure}")


@plot.command("sweep")
@results_argument()
@click.option("--field", required=True, help="A swept field's dotted path (abutments.gap).")
@click.option(
    "--quantity", default="u_deck_max", show_default=True,
    help="A peak-table column (median over the records), or a limit state (median capacity; a "
    "study with an intensity section).",
)  # fmt: skip
@click.option(
    "--level", type=float, default=None,
    help="The intensity level of a peak in a study with intensity levels (its median is over "
    "the records at one level) [the measure's unit].",
)  # fmt: skip
@figure_option("<results stem>-sweep-<field>.png beside RESULTS")
def plot_sweep(
    results: Path, field: str, quantity: str, level: float | None, output: Path | None
) -> None:
    """A peak or a capacity of RESULTS (a study with a sweep section) against a swept field."""
    from ..plots.sweep import plot_sweep as draw

    target = output or results.with_name(f"{results.stem}-sweep-{field}.png")
    click.echo(f"Figure: {draw(results, target, field, quantity, level)}")


@plot.command("history")
@results_argument()
@click.option("--record", required=True, help="Record id.")
@click.option("--bridge", "bridges", multiple=True, help="Bridge id (repeat) [default: all].")
@figure_option("<results stem>-history-<record>.png beside RESULTS")
def plot_history(results: Path, record: str, bridges: tuple[str, ...], output: Path | None) -> None:
    """Histories of u_deck, v_deck, θ_deck, θ1 and θ2 under one record (Figure 10)."""
    from ..plots.history import left_out
    from ..plots.history import plot_history as draw
    from ..results.reading import open_results

    default = results.with_name(f"{results.stem}-history-{record}.png")
    click.echo(f"Figure: {draw(results, record, output or default, bridges)}")
    with open_results(results) as file:
        absent = left_out(json.loads(file.attrs.get("histories", "[]")))
    if absent:
        click.echo(f"left out: {', '.join(absent)} (not kept by the study: output.histories)")

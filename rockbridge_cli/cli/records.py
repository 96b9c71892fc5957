"""Commands for ground motions: ``generate-records``, ``select-records`` and the figures
``plot spectra|record``."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from ..records.set_files import MANIFEST
from . import main, plot

if TYPE_CHECKING:
    from ..records.sets import RecordSetReport
    from ..records.summary import RecordSummary


_OVERWRITE = (
    "Replace the record set in the output folder (refused without: a study may read it). Only "
    "a folder that holds nothing but a set's own files is replaced."
)


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
@click.option("--overwrite", is_flag=True, help=_OVERWRITE)
def generate_records(config: Path, out: Path | None, with_plot: bool, overwrite: bool) -> None:
    """Generate artificial records matched to an EN 1998-1 spectrum, as CONFIG describes.

    Writes one text file per record and manifest.json, then prints the EN 1998-1 §3.2.3.1.2
    compliance report; exits with status 1 where the set is NOT compliant (unless its seeds are
    written as read, adjust: none).
    """
    from ..config.loading import load
    from ..config.record_sets import RecordSetConfig
    from ..kinds import expecting
    from ..records.sets import generate_record_set

    with expecting(config, "record set"):
        settings = load(RecordSetConfig, config)
    folder = out if out is not None else Path("records") / config.stem
    report = generate_record_set(settings, folder, config_name=config.stem, overwrite=overwrite)
    click.echo(format_report(report))
    if with_plot:
        from ..plots.spectra import plot_record_spectra

        click.echo(f"Figure: {plot_record_spectra([folder], folder / 'spectra.png')}")
    failed = [what for what, part in (("the records", report), ("their vertical components",
                                                                 report.vertical))
              if part is not None and not part.compliance.compliant]  # fmt: skip
    if failed and settings.adjust != "none":  # written and usable; a batch job must tell
        click.echo(f"error: {folder}: written, but {' and '.join(failed)} are NOT compliant "
                   "with EN 1998-1 §3.2.3.1.2 (the report above says why)", err=True)  # fmt: skip
        click.get_current_context().exit(1)


@main.command("select-records")
@click.argument("config", type=click.Path(path_type=Path))
@click.option(
    "-o",
    "--out",
    "out",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Output folder [default: records/<config stem>/].",
)
@click.option("--plot", "with_plot", is_flag=True,
              help="Also draw the scaled spectra to <out>/spectra.png.")  # fmt: skip
@click.option("--overwrite", is_flag=True, help=_OVERWRITE)
def select_records(config: Path, out: Path | None, with_plot: bool, overwrite: bool) -> None:
    """Select recorded motions from a pool and scale them to an EN 1998-1 spectrum, as CONFIG
    describes; write them as a record set and print the EN 1998-1 §3.2.3.1.2 compliance table
    (also in <out>/compliance.txt). A pool that cannot meet a rule is refused (exit 2)."""
    from ..config.loading import load
    from ..config.selection import SelectionConfig
    from ..kinds import expecting
    from ..records.selection import compliance_text, select_record_set

    with expecting(config, "record selection"):
        settings = load(SelectionConfig, config)
    request = settings.request()
    folder = out if out is not None else Path("records") / config.stem
    report = select_record_set(request, folder, config.stem, config, overwrite)
    click.echo(f"Wrote {len(report.chosen)} records and {MANIFEST} to {report.folder}")
    click.echo(compliance_text(request, report))
    took = f"{report.selection_time:.2f} s ({report.selection_cpu:.2f} s of CPU)"
    click.echo(f"Selection (the pool's spectra once, the choice): {took}; "
               f"wall time {report.wall_time:.1f} s")  # fmt: skip
    if with_plot:
        from ..plots.selection import plot_selection

        click.echo(f"Figure: {plot_selection(folder, folder / 'spectra.png')}")


def _record_figure(default: str):
    """RECORDS, the options that read plain record files (``--units``, ``--time-step``) and the
    figure file ``-o`` (``default``): what every record figure takes."""

    def decorate(command):
        for option in (
            click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path),
                         default=Path(default), show_default=True,
                         help="Figure file: .png, .pdf or .svg."),
            click.option("--time-step", type=float, default=None,
                         help="Time step of one-column record files [s]."),
            click.option("--units", type=click.Choice(["g", "m/s2", "cm/s2"]), default=None,
                         help="Units of plain record files that do not state them."),
            click.argument("records", nargs=-1, required=True, type=click.Path(path_type=Path)),
        ):  # fmt: skip
            command = option(command)
        return command

    return decorate


@plot.command("spectra")
@_record_figure("spectra.png")
def plot_spectra(
    records: tuple[Path, ...], output: Path, units: str | None, time_step: float | None
) -> None:
    """Plot the 5%-damped spectra of RECORDS (files or generated-set folders) and their mean.

    For a generated set the EN 1998-1 target, the set's per-record tolerance and EN 1998-1's 90 %
    line are drawn too.
    """
    from ..plots.spectra import plot_record_spectra

    click.echo(f"Figure: {plot_record_spectra(list(records), output, units, time_step)}")


@plot.command("record")
@_record_figure("record.png")
def plot_record(
    records: tuple[Path, ...], output: Path, units: str | None, time_step: float | None
) -> None:
    """Plot the acceleration, velocity and displacement of RECORDS (files or generated-set
    folders), integrated exactly from rest; for a generated set, EN 1998-1's design ground
    displacement d_g is marked."""
    from ..plots.motion import plot_record_motion

    click.echo(f"Figure: {plot_record_motion(list(records), output, units, time_step)}")


def format_report(report: RecordSetReport) -> str:
    """The EN 1998-1 §3.2.3.1.2 compliance report of a generated set, as text: the records, the
    fit on the dense grid, what matching changed of each seed, then the verdicts."""
    c = report.compliance
    low, high = report.band
    grid = (
        f"on the dense grid ({report.dense_periods} periods over {low:g}-{high:g} s, every "
        "local extreme refined)"
        if report.dense_tolerance
        else f"at {report.check_periods} periods over {low:g}-{high:g} s"
    )
    lines = [
        f"Wrote {len(report.records)} records and {MANIFEST} to {report.folder}",
        f"Spectra {grid}, computed/target:",
        "  record   PGA/(ag*S)   min    max   v_end[cm/s]  d_end[cm]  PGV[cm/s]  PGD[cm]  "
        "PGD/d_g  D5-95[s]  iterations",
        *(_record_line(s, c.surface_pga, report.ground_displacement) for s in report.records),
        f"  {'mean':<8} {'':9} {c.mean_min_ratio:6.3f} {c.mean_max_ratio:6.3f}"
        + ("" if not report.dense_tolerance else f"  (at {report.check_periods} periods)"),
        *([] if report.dense_tolerance else _dense_lines(report)),
        *_ground_lines(report),
        *_seed_lines(report),
        "EN 1998-1 §3.2.3.1.2:",
        f"  (4)a at least 3 records: {c.count} -> {_verdict(c.count_ok)}",
        f"  (4)b mean zero-period value {c.mean_zero_period:.4g} m/s2 >= a_g*S "
        f"{c.surface_pga:.4g} m/s2 -> {_verdict(c.zero_period_ok)}",
        f"  (4)c mean >= 90% of target over {low:g}-{high:g} s (min {c.mean_min_ratio:.3f}) -> "
        f"{_verdict(c.mean_ok)}",
        "  (3) stationary part: not required of recorded motions (§3.2.3.1.3)"
        if c.stationary_duration is None
        else f"  (3) stationary part {c.stationary_duration:g} s >= 10 s -> "
        f"{_verdict(c.stationary_ok)}",
        "Scaled records keep their shapes: no per-record tolerance (min and max above)"
        if c.tolerance is None
        else f"The config's tolerance: every record within {c.tolerance:.0%} of the target "
        f"{grid} -> {_verdict(c.records_ok)}"
        + ("" if report.dense_tolerance else " (between them: the dense grid above)"),
        *(
            f"  {s.name} misses it by {miss:.3f} (min {s.min_ratio:.3f}, max {s.max_ratio:.3f})"
            for s, miss in zip(report.records, c.record_misses, strict=True)
            if miss
        ),
        f"  overall: {'compliant' if c.compliant else 'NOT compliant'}",
        *_vertical_lines(report.vertical),
        f"Wall time: {report.wall_time:.1f} s",
    ]
    return "\n".join(lines)


def _vertical_lines(report: RecordSetReport | None) -> list[str]:
    """The vertical components' fit to the EN 1998-1 §3.2.2.3 vertical spectrum and the rules
    of §3.2.3.1.2 applied to it; nothing for a set without them."""
    if report is None:
        return []
    c = report.compliance
    low, high = report.band
    return [
        f"Vertical components, matched to the EN 1998-1 §3.2.2.3 vertical spectrum (a_vg = "
        f"{c.surface_pga:.4g} m/s2) at {report.check_periods} periods over {low:g}-{high:g} s:",
        "  record     PGA/a_vg   min    max   PGD[cm]  D5-95[s]  iterations",
        *(f"  {s.name:<10} {s.peak_acceleration / c.surface_pga:7.5f} {s.min_ratio:6.3f} "
          f"{s.max_ratio:6.3f} {s.peak_displacement * 100:8.1f} {s.significant_duration:9.1f}  "
          f"{s.iterations:4d} ({s.attempts} attempts)" for s in report.records),
        f"  {'mean':<10} {'':7} {c.mean_min_ratio:6.3f} {c.mean_max_ratio:6.3f}",
        f"  (4)b mean zero-period value >= a_vg -> {_verdict(c.zero_period_ok)}; (4)c mean >= "
        f"90% -> {_verdict(c.mean_ok)}; every record within {c.tolerance:.0%} -> "
        f"{_verdict(c.records_ok)}; overall: {'compliant' if c.compliant else 'NOT compliant'}",
    ]  # fmt: skip


def _record_line(s: RecordSummary, surface_pga: float, dg: float) -> str:
    return (
        f"  {s.name:<8} {s.peak_acceleration / surface_pga:9.5f} {s.min_ratio:6.3f} "
        f"{s.max_ratio:6.3f} {s.final_velocity * 100:+11.1e} "
        f"{s.final_displacement * 100:+10.1e} {s.peak_velocity * 100:10.1f} "
        f"{s.peak_displacement * 100:8.1f} {s.peak_displacement / dg:8.2f} "
        f"{s.significant_duration:9.1f}  "
        + (
            f"{s.iterations:4d} ({s.attempts} attempts)"
            if s.scale_factor is None
            else f"scaled by {s.scale_factor:.4g}"
        )
    )  # fmt: skip


def _dense_lines(report: RecordSetReport) -> list[str]:
    """Where the tolerance is checked at the check periods: the fit between them."""
    lowest = min(report.records, key=lambda s: s.fit.min_ratio)
    highest = max(report.records, key=lambda s: s.fit.max_ratio)
    return [
        f"On the dense grid ({report.dense_periods} periods, every local extreme refined): "
        f"min {lowest.fit.min_ratio:.3f} ({lowest.name} at {lowest.fit.min_period:.3f} s), "
        f"max {highest.fit.max_ratio:.3f} ({highest.name} at {highest.fit.max_period:.3f} s)"
    ]


def _ground_lines(report: RecordSetReport) -> list[str]:
    from ..records.sets import GROUND_DISPLACEMENT_AIM

    dg = report.ground_displacement
    largest = max((s.peak_displacement for s in report.records), default=0.0)
    changes = [s.seed_change for s in report.records if s.seed_change is not None]
    lines = [
        f"EN 1998-1 §3.2.2.4 design ground displacement d_g = 0.025*a_g*S*T_C*T_D = "
        f"{dg * 100:.1f} cm; largest PGD {largest / dg:.2f} d_g (PGD: peak of the doubly "
        "integrated record, from rest)"
    ]
    if changes:
        return lines
    if report.compliance.stationary_duration is None:
        return [*lines, "Scaled seeds keep their own long-period content: their PGD is "
                "reported, not bounded"]  # fmt: skip
    verdict = _verdict(largest <= GROUND_DISPLACEMENT_AIM * dg)
    return [*lines, f"rockbridge's aim: every record's PGD within {GROUND_DISPLACEMENT_AIM:g} "
            f"d_g -> {verdict}"]  # fmt: skip


def _seed_lines(report: RecordSetReport) -> list[str]:
    """What matching changed of each seed, beside the seed linearly scaled to a_g*S."""
    from ..records.sets import GROUND_DISPLACEMENT_AIM, SEED_GROUND_GROWTH
    from ..records.summary import SEED_CHANGE

    matched = [(s.name, s.seed_change) for s in report.records if s.seed_change is not None]
    if not matched:
        return []
    lines = [
        "Beside the seed scaled to a_g*S (matched / seed):",
        "  record      PGV[cm/s]        PGD[cm]        D5-95[s]     D5-75[s]    Arias time[s]"
        f"  changed > {SEED_CHANGE:.0%}",
    ]
    for name, change in matched:
        new, old = change.record, change.seed
        lines.append(
            f"  {name:<8} {new.pgv * 100:6.1f} {old.pgv * 100:6.1f}  {new.pgd * 100:6.1f} "
            f"{old.pgd * 100:6.1f}  {new.d5_95:6.1f} {old.d5_95:5.1f}  {new.d5_75:6.1f} "
            f"{old.d5_75:5.1f}  {new.arias_time:6.1f} {old.arias_time:5.1f}   "
            + (", ".join(change.flags) or "-")
        )  # fmt: skip
    missed = [name for name, change in matched if not change.ground_ok]
    lines.append(
        f"rockbridge's aim: PGD within {SEED_GROUND_GROWTH:g} x the scaled seed's or "
        f"{GROUND_DISPLACEMENT_AIM:g} d_g, PGV within {SEED_GROUND_GROWTH:g} x or "
        f"{GROUND_DISPLACEMENT_AIM:g} v_g (v_g = 2*pi*d_g/T_D), whichever is larger -> "
        + (_verdict(not missed) if not missed else f"NO: {', '.join(missed)}")
    )
    lines += [
        f"  {name} was resampled from {change.resampled[0]:g} s to {change.resampled[1]:g} s "
        f"(band-limited, scipy.signal.resample_poly) to resolve {report.band[0]:g} s"
        for name, change in matched
        if change.resampled is not None
    ]
    return lines


def _verdict(ok: bool | None) -> str:
    return "unknown" if ok is None else ("yes" if ok else "NO")

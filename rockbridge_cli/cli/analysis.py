"""``rockbridge analyze``: one response-history analysis, for a quick look."""

from __future__ import annotations

import math
from pathlib import Path

import click

from ..core.fidelity import PRESETS
from ..errors import InputError
from ..interrupts import held
from . import main
from .output import echo_json, echo_table, shown


@main.command()
@click.argument("bridge", type=click.Path(path_type=Path))
@click.argument("record", type=click.Path(path_type=Path))
@click.option(
    "--units",
    type=click.Choice(["g", "m/s2", "cm/s2"]),
    help="Units of a record file that does not say them.",
)
@click.option("--time-step", type=float, help="Sample interval of a one-column record [s].")
@click.option(
    "--vertical",
    type=click.Path(path_type=Path),
    help="The record's vertical component (positive up): a file with the same time step and "
    "samples. Without it, no vertical ground motion (the paper's model).",
)
@click.option("--fidelity", type=click.Choice(list(PRESETS)), default="default", show_default=True)
@click.option(
    "--tail",
    type=click.FloatRange(min=0.0),
    default=0.0,
    show_default=True,
    help="Free vibration after the record, with zero ground motion [s].",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with SI values.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Also write the histories and events to this HDF5 results file (the layout of `run`).",
)
@click.option("--overwrite", is_flag=True, help="Replace an OUTPUT that holds other results.")
@click.pass_context
def analyze(
    ctx: click.Context,
    bridge: Path,
    record: Path,
    units: str | None,
    time_step: float | None,
    vertical: Path | None,
    fidelity: str,
    tail: float,
    as_json: bool,
    output: Path | None,
    overwrite: bool,
) -> None:
    """Analyze BRIDGE (a YAML file) under the ground motion in RECORD.

    Exits 1 if the integrator stopped before the end of the record (its peaks are then NaN).
    """
    from ..config.study import single_analysis
    from ..study.single import analyze_single, grid_of

    config, motion = _inputs(bridge, record, units, time_step, vertical, fidelity, tail)
    study = single_analysis(bridge, record, units, time_step, fidelity, output, tail, vertical)
    grid = grid_of(study)
    built = grid.bridges[0].bridge  # built once: the set-up, the analysis and the hint share it
    setup = _set_up(built, motion, fidelity)
    single = analyze_single(study, grid, output, overwrite)
    summary = {**single.values, "fidelity": fidelity}
    if summary["status"] == "error":
        raise click.ClickException(f"the analysis could not run: {summary['message']}")
    if single.output is not None:
        summary["output"] = str(single.output)
    times, theta1, mode = single.time, single.theta1, single.mode
    summary.update(setup_time_s=setup, record_pga=motion.peak_acceleration)
    if as_json:
        data = {**summary, "bridge": config.label(bridge.stem), "record": motion.name}
        echo_json({**data, "units": _units(data)})
    else:
        label = f"{motion.name} ({motion.duration:g} s, PGA {motion.peak_acceleration / G:.3g} g)"
        echo_table(_rows(config.label(bridge.stem), label, summary))
    alpha = built.model.alpha1
    if summary["status"] == "ok" and (hint := _tail_hint(alpha, summary, times, theta1, mode,
                                                         tail)):  # fmt: skip
        click.echo(f"note: {hint}", err=True)
    if summary["status"] != "ok":
        reason = summary.get("message") or summary["status"]
        click.echo(f"error: the integrator stopped early ({reason}); no peak is known", err=True)
        ctx.exit(1)


G = 9.80665
"""Standard gravity, the g a record's PGA is printed in [m/s²]."""

TAIL_HINT_ALPHA = 0.25
"""A bridge still rocking at the end of its record, with θ1 in the last second at this fraction
of α1 or more, gets a hint of ``--tail``: its motion after the record is not analyzed."""


def _inputs(bridge: Path, record: Path, units, time_step, vertical, fidelity: str, tail: float):
    """The bridge config and the record (with its ``vertical`` component, a companion file, if
    given), checked, with their plausibility warnings printed; a record and a bridge given the
    other way round are named so."""
    from ..config.bridge import load_bridge  # pydantic: loaded on use
    from ..config.plausibility import bridge_warnings, record_warnings
    from ..kinds import expecting, file_kind
    from ..records.files import read_record
    from ..records.vertical import with_vertical

    if file_kind(bridge) == "record" and file_kind(record) == "bridge":
        swapped = "a record file where the bridge goes: rockbridge analyze BRIDGE RECORD"
        raise InputError(bridge, [("", f"{swapped} (the arguments are swapped)")])
    config = load_bridge(bridge)
    with expecting(record, "record"):
        motion = read_record(record, units=units, time_step=time_step)
    if vertical is not None:
        with expecting(vertical, "record"):
            motion = with_vertical(motion, vertical, units, time_step)
    _check_work(record, motion, fidelity, tail)
    warnings = [f"{bridge}: {w}" for w in bridge_warnings(config)]
    for warning in warnings + [f"{record}: {w}" for w in record_warnings(motion)]:
        click.echo(f"warning: {warning}", err=True)
    return config, motion


def _set_up(bridge, motion, fidelity: str) -> float:
    """What an analysis costs once per process, before its solve: loading the compiled kernels
    (those of a vertical ground motion too, where the record has one, and of a bridge's devices,
    where it has some; where numba's cache does not hold them, compiling them in a child process
    that Ctrl-C ends at once, `study.kernels.prepare_stoppable`, and saying so) and building the
    bridge's tables, timed by analyzing two samples of rest [s]."""
    import time

    import numpy as np

    from ..core.analysis import analyze as run_analysis
    from ..study.kernels import compiling_message, prepare_stoppable
    from ..warmup import announced

    vertical = motion.vertical is not None
    started = time.perf_counter()
    devices = bool(bridge.devices)

    def announce() -> None:
        click.echo(compiling_message(vertical, devices), err=True)

    prepare_stoppable(announce, vertical, devices)  # a stop meanwhile: KeyboardInterrupt
    with held(), announced(announce):  # what the warm-up does not compile, if anything
        run_analysis(bridge, np.zeros(2), motion.time_step, fidelity,
                     vertical=np.zeros(2) if vertical else None)  # fmt: skip
    return time.perf_counter() - started


def _tail_hint(alpha: float, summary: dict, times, theta1, mode, tail: float) -> str:
    """A hint of ``--tail`` where the bridge, of slenderness ``alpha`` (α1 [rad]), still rocks,
    strongly, as the record (and its tail) ends; "" otherwise."""
    import numpy as np

    from ..core.quantities import NO_FAILURE

    if summary["failure_mode"] != NO_FAILURE or not len(mode) or mode[-1] == 0:
        return ""
    last = float(np.nanmax(np.abs(theta1[times >= times[-1] - 1.0])))
    if last < TAIL_HINT_ALPHA * alpha:
        return ""
    after = f"its {tail:g} s tail" if tail else "the record"
    return (
        f"the bridge still rocks as {after} ends (θ1 up to {last / alpha:.2f} α1 in its last "
        f"second): what follows is not analyzed; --tail {max(20.0, 2 * tail):g} runs on with the "
        "ground at rest until it rests or fails"
    )


def _units(data: dict) -> dict[str, str]:
    """The unit of each number of ``analyze --json`` (SI)."""
    from ..results.layout import PEAK_COLUMNS

    extra = {"setup_time_s": "s", "record_pga": "m/s2", **_device_units(data)}
    return {
        key: extra.get(key) or PEAK_COLUMNS[key][0]
        for key, value in data.items()
        if (key in extra or key in PEAK_COLUMNS) and not isinstance(value, str)
    }


def _device_units(summary: dict) -> dict[str, str]:
    """The units of a summary's device peaks (`core.analysis.device_peak_names`): elongations
    [m] and forces [N], by their ``…_max`` keys."""
    units = {"_elongation_max": "m", "_force_max": "N"}
    return {
        key: unit
        for key in summary
        for suffix, unit in units.items()
        if key.endswith(suffix) and key.startswith(("tendon", "damper", "dissipator"))
    }


def _check_work(path: Path, motion, fidelity: str, tail: float) -> None:
    """Refuse a tail out of range, or an analysis of the record that could not end
    (`core.fidelity.check_work`)."""
    from ..core.fidelity import check_work, resolve

    try:
        values = resolve(fidelity, tail=tail).knobs
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--tail") from None
    try:
        check_work(values, motion.acceleration.size, motion.time_step)
    except ValueError as exc:
        raise InputError(path, [("", str(exc))]) from None


def _rows(bridge: str, record: str, s: dict) -> list[tuple[str, str]]:
    from ..core.quantities import NO_FAILURE, PEAK_UNITS

    onset = s["t_onset"]
    failure = s["failure_mode"]
    rows = [
        ("bridge", bridge),
        ("record", record),
        ("model / fidelity", f"{s['model']} / {s['fidelity']}"),
        ("onset of rocking", "never (at rest)" if math.isnan(onset) else f"{onset:.3f} s"),
    ]
    for name, unit in PEAK_UNITS.items():
        peak = shown(s[name + "_max"])
        if math.isnan(peak) and s["status"] == "ok":  # a part the model has not (a block's deck)
            continue
        rows.append((f"max {name}", f"{peak:.5g} {unit} at {s[name + '_time']:.3f} s"))
    for key, unit in _device_units(s).items():  # a bridge's tendons and dampers, if any
        name = key.removesuffix("_max")
        rows.append((f"max {name}", f"{shown(s[key]):.5g} {unit} at {s[name + '_time']:.3f} s"))
    rows += [
        (
            "impacts (significant) / poundings",
            f"{s['n_impacts']} ({s['n_impacts_significant']}) / {s['n_poundings']}",
        ),
        ("failure", failure + ("" if failure == NO_FAILURE else f" at {s['failure_time']:.3f} s")),
        ("backfill demand/capacity", _ratio(s["dcr_backfill"], "(|u_deck| − u_jo)/u_ab")),
        ("overturning demand/capacity", _ratio(s["dcr_overturning"], "|u_pier|/B")),
        ("status", s["status"]),
        ("solve time", f"{s['solve_time_s'] * 1e3:.1f} ms ({s['steps']} steps)"),
        (
            "set-up, once per process",
            f"{s['setup_time_s'] * 1e3:.0f} ms (loading the compiled kernels, or "
            "compiling them the first time; building the bridge's tables)",
        ),
    ]
    if "output" in s:
        rows.append(("results", s["output"]))
    return rows


def _ratio(value: float, definition: str) -> str:
    """A demand/capacity ratio as a percentage with its definition; "-" where it is not known
    (no abutments, or the integrator stopped early)."""
    return "-" if math.isnan(value) else f"{100 * value:.1f} % = {definition}"

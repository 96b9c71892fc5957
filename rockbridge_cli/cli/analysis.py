"""``rockbridge analyze``: one response-history analysis, for a quick look."""

from __future__ import annotations

import math
from pathlib import Path

import click

from ..config.bridge import load_bridge
from ..core.analysis import PEAK_UNITS
from ..core.analysis import analyze as run_analysis
from ..core.fidelity import PRESETS
from ..records import read_record
from . import main
from .output import echo_json, echo_table


@main.command()
@click.argument("bridge", type=click.Path(path_type=Path))
@click.argument("record", type=click.Path(path_type=Path))
@click.option(
    "--units",
    type=click.Choice(["g", "m/s2"]),
    help="Units of a record file that does not say them.",
)
@click.option("--time-step", type=float, help="Sample interval of a one-column record [s].")
@click.option("--fidelity", type=click.Choice(list(PRESETS)), default="default", show_default=True)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with SI values.")
def analyze(
    bridge: Path,
    record: Path,
    units: str | None,
    time_step: float | None,
    fidelity: str,
    as_json: bool,
) -> None:
    """Analyse BRIDGE (a YAML file) under the ground motion in RECORD."""
    config = load_bridge(bridge)
    motion = read_record(record, units=units, time_step=time_step, gravity=config.gravity)
    response = run_analysis(
        config.to_model(), motion.acceleration, motion.time_step, fidelity, mirrored=config.mirrored
    )
    summary = response.summary()
    if as_json:
        echo_json({"bridge": config.label(bridge.stem), "record": motion.name, **summary})
        return
    rows = [
        ("bridge", config.label(bridge.stem)),
        ("record", f"{motion.name} ({motion.duration:g} s)"),
    ]
    rows += [("model / fidelity", f"{response.model} / {fidelity}")]
    onset = (
        "never (the bridge stays at rest)"
        if math.isnan(response.t_onset)
        else f"{response.t_onset:.3f} s"
    )
    rows += [("onset of rocking", onset)]
    for name, unit in PEAK_UNITS.items():
        value, when = response.peaks[name]
        rows.append((f"max {name}", f"{value:.5g} {unit} at {when:.3f} s"))
    rows += [
        ("impacts / poundings", f"{response.n_impacts} / {response.n_poundings}"),
        ("failure", response.failure_mode
         + ("" if response.failure_mode == "none" else f" at {response.failure_time:.3f} s")),
        ("demand/capacity", f"{response.dcr:.3f} ({response.dcr_mode})"),
        ("status", response.status),
        ("solve time", f"{response.solve_time_s * 1e3:.1f} ms ({response.steps} steps)"),
    ]  # fmt: skip
    echo_table(rows)

"""``rockbridge describe``: the derived quantities of one bridge config."""

from __future__ import annotations

import math
from pathlib import Path

import click

from . import main
from .output import echo_json, echo_table


@main.command()
@click.argument("bridge", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with SI values.")
def describe(bridge: Path, as_json: bool) -> None:
    """Print the model used and the quantities a designer checks first for BRIDGE (a YAML file)."""
    from ..config.bridge import load_bridge  # pydantic: loaded on use
    from ..config.plausibility import bridge_warnings
    from ..core.summary import describe as described  # the compiled core: loaded on use

    config = load_bridge(bridge)
    for warning in bridge_warnings(config):
        click.echo(f"warning: {bridge}: {warning}", err=True)
    summary = described(config.to_bridge())
    if as_json:
        devices = [device.model_dump() for device in config.devices]
        echo_json({"name": config.label(bridge.stem), **summary, "devices": devices})
        return
    echo_table(_rows(config.label(bridge.stem), summary) + _device_rows(config))


def _device_rows(config) -> list[tuple[str, str]]:
    """A row per device of a bridge config, as the config states it (pier counted in
    ``piers.heights``, offset in the user's drawing), with a tendon's axial stiffness E·A/L."""
    from ..config.devices import DamperConfig, TendonConfig
    from ..core.devices import names

    stems = names(tuple(config.to_bridge().devices))  # the numbering of results' columns
    rows = []
    for stem, device in zip(stems, config.devices, strict=True):
        where = f"pier {device.pier}, offset {device.offset:g} m"
        if isinstance(device, TendonConfig):
            height = config.piers.heights[device.pier - 1]
            text = (f"P0 {device.prestress:.4g} N, E·A/L {device.stiffness(height):.4g} N/m, "
                    f"yield {_stated(device.yield_force, ' N')}, rupture strain "
                    f"{_stated(device.rupture_strain)}")  # fmt: skip
        elif isinstance(device, DamperConfig):
            text = f"c {device.coefficient:.4g} N·s/m across the {device.interface}"
        else:
            text = (f"k1 {device.stiffness:.4g} N/m, F_y {device.yield_force:.4g} N, k2/k1 "
                    f"{device.post_yield_ratio:g}, fracture at {_stated(device.fracture(), ' m')}"
                    f" across the {device.interface}")  # fmt: skip
        rows.append((stem, f"{where}: {text}"))
    return rows


def _stated(value: float | None, unit: str = "") -> str:
    """A device's optional limit, or ``none`` where the config states none (or it is inf)."""
    return "none" if value is None or math.isinf(value) else f"{value:.4g}{unit}"


def _rows(name: str, s: dict) -> list[tuple[str, str]]:
    """The table of ``describe``: the quantities the model has (a block has no deck, pier 2,
    ratios or abutments; a frame no abutments, so no q, pounding or seat impulses)."""
    block, bridge = s["model"] == "single-block", s["model"].endswith("-bridge")
    mirrored = "  (tall pier on the right: analyzed mirrored)" if s["mirrored"] else ""
    rows = [("bridge" if bridge else "structure", name), ("model", s["model"] + mirrored)]
    if block:
        rows += [
            ("mass", f"{s['m_pier1']:.4g} kg"),
            ("R, alpha", f"{s['R1']:.4g} m, {s['alpha1']:.4f} rad"),
        ]
    else:
        masses = ", ".join(_number(s[k], ".4g") for k in ("m_pier1", "m_pier2", "m_deck"))
        ratios = ", ".join(_number(s[k], ".4g") for k in ("h_bar", "b_bar", "L_bar"))
        rows += [
            ("m_pier1, m_pier2, m_deck", f"{masses} kg"),
            ("h_bar, b_bar, L_bar", ratios),
            ("gamma = m_deck/(m1 + m2)", _number(s["gamma"], ".4f")),
        ]
    if bridge:
        rows.append(("q", _number(s["q"], ".4f", 1e6, " ·10⁻³ m/kN")))
    rows.append(("onset ug_min p / n", f"{s['ug_min_p_g']:.4f} g / {s['ug_min_n_g']:.4f} g"))
    if bridge:
        rows += [
            ("eta bridge p→n / n→p", f"{s['eta_pn']:.4f} / {s['eta_np']:.4f}"),
            ("eta frame  p→n / n→p", f"{s['eta_frame_pn']:.4f} / {s['eta_frame_np']:.4f}"),
            ("pounding ratio", f"{s['pounding_ratio']:.4f}"),
        ]
    else:
        rows.append(("eta p→n / n→p", f"{s['eta_pn']:.4f} / {s['eta_np']:.4f}"))
    return rows + _limits(s)


def _limits(s: dict) -> list[tuple[str, str]]:
    """The rows of the restitution used, the failure rotations and what the ratios divide by."""
    rows = []
    if s["rocking_restitution"] is not None:
        rows.append(("eta used (config)", f"{s['rocking_restitution']:.4f} in both directions"))
    elif min(s["eta_pn"], s["eta_np"]) <= 0.0:
        rows.append(("warning", "eta ≤ 0: set rocking_restitution to analyze this bridge"))
    for limit, rotation in s["failure_rotations"].items():
        text = ", ".join(
            f"{mode} {_number(abs(v) if math.isfinite(v) else None, '.2f', 1e3, ' mrad')}"
            for mode, v in rotation.items()
        )
        rows.append((f"failure rotation {limit} (theta1)", text))
    rows.append(("governing failure", s["governing_failure"]))
    if s["gap"] is not None:
        rows.append(
            (
                "dcr_backfill = (|u_deck| − u_jo)/u_ab",
                f"u_jo = {s['gap'] * 1e3:.0f} mm, u_ab = {s['backfill_capacity'] * 1e3:.0f} mm",
            )
        )
    rows.append(("dcr_overturning = |u_pier|/B", f"B = {s['half_width']:.4g} m"))
    return rows


def _number(value: float | None, spec: str, scale: float = 1.0, unit: str = "") -> str:
    """``value·scale`` formatted with its unit, or "n/a" for a quantity the model does not have."""
    return "n/a" if value is None else f"{value * scale:{spec}}{unit}"

"""``rockbridge describe``: the derived quantities of one bridge config."""

from __future__ import annotations

import math
from pathlib import Path

import click

from ..config.bridge import load_bridge
from ..core.summary import summarize
from . import main
from .output import echo_json, echo_table


@main.command()
@click.argument("bridge", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with SI values.")
def describe(bridge: Path, as_json: bool) -> None:
    """Print the model used and the quantities a designer checks first for BRIDGE (a YAML file)."""
    config = load_bridge(bridge)
    summary = summarize(config.to_model(), mirrored=config.mirrored)
    if as_json:
        echo_json({"name": config.label(bridge.stem), **summary})
        return
    echo_table(_rows(config.label(bridge.stem), summary))


def _rows(name: str, s: dict) -> list[tuple[str, str]]:
    g = s["ug_min_p"] / s["ug_min_p_g"]
    rows = [
        ("bridge", name),
        (
            "model",
            s["model"] + ("  (tall pier on the right: analysed mirrored)" if s["mirrored"] else ""),
        ),
        (
            "m_pier1, m_pier2, m_deck",
            f"{s['m_pier1']:.4g}, {s['m_pier2']:.4g}, {s['m_deck']:.4g} kg",
        ),
        ("h_bar, b_bar, L_bar", f"{s['h_bar']:.4g}, {s['b_bar']:.4g}, {s['L_bar']:.4g}"),
        ("gamma = m_deck/(m1 + m2)", f"{s['gamma']:.4f}"),
        ("q", f"{s['q'] * 1e6:.4f} ·10⁻³ m/kN"),
        (
            "onset ug_min p / n",
            f"{s['ug_min_p_g']:.4f} g / {s['ug_min_n_g']:.4f} g  (g = {g} m/s²)",
        ),
        ("eta bridge p→n / n→p", f"{s['eta_pn']:.4f} / {s['eta_np']:.4f}"),
        ("eta frame  p→n / n→p", f"{s['eta_frame_pn']:.4f} / {s['eta_frame_np']:.4f}"),
        ("pounding ratio", f"{s['pounding_ratio']:.4f}"),
    ]
    for limit, rotation in s["capacities"].items():
        text = ", ".join(
            f"{mode} {'none' if math.isinf(v) else f'{abs(v) * 1e3:.2f} mrad'}"
            for mode, v in rotation.items()
        )
        rows.append((f"capacity {limit} (theta1)", text))
    rows.append(("governing failure", s["governing_failure"]))
    return rows

"""The numbers a designer checks first for one bridge, as a flat dictionary of SI values."""

from __future__ import annotations

from collections.abc import Sequence

from .bridge import Bridge
from .geometry import kind, pounding_ratio, ratios

SUMMARY_UNITS = {
    "m_pier1": "kg", "m_pier2": "kg", "m_deck": "kg", "m_abut": "kg",
    "I_pier1": "kg m2", "I_pier2": "kg m2", "I_deck": "kg m2", "R1": "m", "R2": "m",
    "alpha1": "rad", "alpha2": "rad", "h_bar": "-", "b_bar": "-", "L_bar": "-", "gamma": "-",
    "q": "m/N", "ug_min_p": "m/s2", "ug_min_n": "m/s2", "ug_min_p_g": "g", "ug_min_n_g": "g",
    "eta_pn": "-", "eta_np": "-", "eta_frame_pn": "-", "eta_frame_np": "-",
    "pounding_ratio": "-",
}  # fmt: skip
"""Units of the numeric entries of `summarize` (its ``failure_rotations`` are rotations [rad])."""


def summarize_all(bridges: Sequence[Bridge]) -> list[dict[str, object]]:
    """`summarize` of each bridge, in order (what a worker computes for a results file)."""
    return [summarize(bridge) for bridge in bridges]


def describe(bridge: Bridge) -> dict[str, object]:
    """What ``rockbridge describe`` shows of a bridge: `summarize`, with the restitution the
    config sets (``rocking_restitution``, None where the model's is used) and what the
    demand/capacity ratios divide by (docs/model.md §8): ``gap`` u_jo and ``backfill_capacity``
    u_ab [m] (None without abutments), ``half_width`` B [m]."""
    model = bridge.model
    abutments = model.has_abutments
    return summarize(bridge) | {
        "rocking_restitution": bridge.restitution,
        "gap": model.u_jo if abutments else None,
        "backfill_capacity": model.u_ab if abutments else None,
        "half_width": model.B,
    }


def summarize(bridge: Bridge) -> dict[str, object]:
    """Derived constants, onset, restitution and failure rotations of a bridge.

    Parameters
    ----------
    bridge
        The bridge as analyzed; when mirrored the modes p and n are swapped so that "p" is
        counter-clockwise rocking in the user's drawing, and an overridden restitution is the
        η reported.

    Returns
    -------
    dict with ``model`` (its kind), masses [kg], inertias [kg·m²], ``R1``, ``R2`` [m], ``alpha1``,
    ``alpha2`` [rad], ``h_bar``, ``b_bar``, ``L_bar``, ``gamma`` [-], ``q`` [m/N], onset
    accelerations ``ug_min_p``, ``ug_min_n`` [m/s², magnitudes] and in g (``*_g``), ``eta_pn``,
    ``eta_np`` (the η the analysis uses), ``eta_frame_pn``, ``eta_frame_np`` (same bridge
    without seat impulses), ``pounding_ratio`` [-], ``failure_rotations`` (tall-pier rotation at
    each failure limit [rad]) and
    ``governing_failure``. Ratios that mean nothing for the model (q without abutments; h̄, b̄, L̄,
    γ for a single block) are None.
    """
    from . import impacts  # the compiled kernels, loaded when a summary is first asked for

    model, mirrored = bridge.model, bridge.mirrored
    modes = bridge.user_modes()
    onset = [abs(impacts.onset_threshold(model, s, bridge.device_table())) for s in modes]
    caps = impacts.failure_rotations(model)
    governing = impacts.governing_failure(model, caps)
    if mirrored:
        caps = {name: {"p": -v["n"], "n": -v["p"]} for name, v in caps.items()}
    out: dict[str, object] = {
        "model": kind(model),
        "mirrored": mirrored,
        "m_pier1": model.m1,
        "m_pier2": model.m2,
        "m_deck": model.md,
        "m_abut": model.m_abut,
        "I_pier1": model.I1,
        "I_pier2": model.I2,
        "I_deck": model.Id,
        "R1": model.R1,
        "R2": model.R2,
        "alpha1": model.alpha1,
        "alpha2": model.alpha2,
        **ratios(model),
        "ug_min_p": onset[0],
        "ug_min_n": onset[1],
        "ug_min_p_g": onset[0] / model.g,
        "ug_min_n_g": onset[1] / model.g,
        "eta_pn": bridge.eta(modes[0]),
        "eta_np": bridge.eta(modes[1]),
        "eta_frame_pn": impacts.restitution(model, modes[0], abutment_seats=False),
        "eta_frame_np": impacts.restitution(model, modes[1], abutment_seats=False),
        "pounding_ratio": pounding_ratio(model),
        "failure_rotations": caps,
        "governing_failure": governing,
    }
    if out["model"] == "single-block":  # ratios of a deck and spans the block does not have
        out.update(h_bar=None, b_bar=None, L_bar=None, gamma=None)
    if not model.has_abutments:
        out["q"] = None
    return out

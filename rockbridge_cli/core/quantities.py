"""The quantities an analysis reports, with their units, and the names of the limit states it can
reach: a vocabulary shared by the core, the configs, the results file and the assessment,
importable without the compiled core."""

import re
from collections.abc import Collection
from typing import NamedTuple

HISTORY_UNITS = {
    "theta1": "rad", "theta1_rate": "rad/s", "mode": "-", "theta2": "rad", "theta_deck": "rad",
    "u_deck": "m", "v_deck": "m", "u_pier1": "m", "v_pier1": "m", "u_pier2": "m", "v_pier2": "m",
}  # fmt: skip
"""Every history a `Response` carries, with its unit. Pier 1 is the tall pier (paper's notation)."""

DEVICE_HISTORY_UNITS = {"force": "N", "elongation": "m", "plastic": "m"}
"""A device's histories, ``<device>_<quantity>`` (``tendon1_force``, ``dissipator2_plastic``, …,
the devices named as `core.devices.names` names them), with their units: its force, positive in
tension, its elongation Δ and its plastic elongation Δp (a tendon's or a dissipator's)."""

_DEVICE_HISTORY = re.compile(
    r"^(tendon|dissipator)[1-9][0-9]*_(force|elongation|plastic)$"
    r"|^damper[1-9][0-9]*_(force|elongation)$"  # a damper has no plastic elongation
)


def is_device_history(name: str) -> bool:
    """Whether ``name`` names a device's history (`DEVICE_HISTORY_UNITS`)."""
    return _DEVICE_HISTORY.match(name) is not None


def history_unit(name: str) -> str:
    """The unit of the history ``name``: `HISTORY_UNITS`, or a device's (`DEVICE_HISTORY_UNITS`).

    Raises
    ------
    KeyError
        ``name`` names no history.
    """
    if is_device_history(name):
        return DEVICE_HISTORY_UNITS[name.rsplit("_", 1)[1]]
    return HISTORY_UNITS[name]


def kept_history(name: str, keep: Collection[str]) -> bool:
    """Whether a study that keeps the histories ``keep`` (`config.study_models.Output.kept`) keeps
    the history ``name``: one it names, and every device's where it keeps all of `HISTORY_UNITS`
    (``output.histories: all``, which names no device so that a study's hash stays as it was)."""
    if name in keep:
        return True
    return is_device_history(name) and all(other in keep for other in HISTORY_UNITS)


PEAK_NAMES = ("u_deck", "v_deck", "theta_deck", "theta1", "theta2", "u_pier1", "u_pier2")
"""Peak quantities tracked during the integration, by index (all absolute except v_deck)."""

PEAK_U_DECK, PEAK_U_PIER1, PEAK_U_PIER2 = (
    PEAK_NAMES.index(name) for name in ("u_deck", "u_pier1", "u_pier2")
)
"""The indices in `PEAK_NAMES` of the deck's and the piers' peak displacements, which the demand
ratios read."""

PEAK_UNITS = {name: HISTORY_UNITS[name] for name in PEAK_NAMES}
"""Peak quantities: maxima of the absolute values, except v_deck (largest uplift)."""

DISPLAY_UNITS = {"m": ("mm", 1e3), "rad": ("mrad", 1e3)}
"""How a value in an SI unit is shown in tables and figures: the unit shown, the factor from SI."""


def display_unit(unit: str) -> tuple[str, float]:
    """The unit a value in ``unit`` (SI) is shown in, and the factor to it (`DISPLAY_UNITS`)."""
    return DISPLAY_UNITS.get(unit, (unit, 1.0))


class Shown(NamedTuple):
    """How a response is named where it is shown: ``text`` in tables, ``tex`` (Matplotlib's
    mathtext) on a figure's axis; ``unit`` the shown unit, ``factor`` from SI to it."""

    text: str
    tex: str
    unit: str
    factor: float


SHOWN = {
    name: Shown(text, tex, *display_unit(HISTORY_UNITS[name]))
    for name, text, tex in (
        ("u_deck", "u_deck", r"$u_{deck}^{CG}$"),
        ("v_deck", "v_deck", r"$v_{deck}^{CG}$"),
        ("theta_deck", "θ_deck", r"$\theta_{deck}$"),
        ("theta1", "θ1", r"$\theta_1$ (tall pier)"),
        ("theta2", "θ2", r"$\theta_2$ (short pier)"),
    )
}
"""The responses the tables and figures show (Figs. 9 and 10), in their order: the histories, and
their peaks as ``<name>_max`` columns of the peak table."""

ABUTMENT, PIER1_OVERTURNING, PIER2_OVERTURNING = FAILURE_MODES = (
    "abutment", "overturning_pier1", "overturning_pier2",
)  # fmt: skip
"""How an analysis can end in failure (docs/model.md §7): the abutment–backfill fails
(|u_deck| = u_jo + u_ab) or a pier overturns (|u_pier| = B)."""

NO_FAILURE = "none"
"""The failure mode of an analysis in which nothing failed."""

EVENT_NAMES = (
    "onset", "impact", "pounding", "reopening", "rest",
    "abutment_failure", "overturning_pier1", "overturning_pier2",
)  # fmt: skip
"""What can happen in an analysis, in the order of the solver's event codes; the last three end
it in a failure (`FAILURE_EVENTS`)."""

FAILURE_EVENTS = dict(zip(EVENT_NAMES[-3:], FAILURE_MODES, strict=True))
"""The failure mode of each failure event."""

SIGNIFICANT_RATE = 1e-3
"""|θ̇1| before an impact above which it counts in ``n_impacts_significant`` [rad/s]. Measured on
the paper's Fig. 9 study (2871 impacts): the rates before impacts fall in two groups, chatter near
rest at 1e-6–3e-4 rad/s (1530 impacts) and rocking at 3e-3–0.1 rad/s (987), with the fewest per
decade around 1e-3 rad/s (354 between 3e-4 and 3e-3)."""

STANDARD_GRAVITY = 9.80665
"""The unit g of a record file [m/s²]: standard gravity (CGPM 1901; the g of PEER NGA AT2, ESM
and COSMOS files), whatever gravity the structure is analyzed with (docs/model.md §1, §9)."""

ROUND_OFF = 1e-12
"""A peak below this in SI units (a picometre, a picoradian) is round-off and is shown as 0: the
deck of a symmetric bridge does not rotate, though the arithmetic leaves ~1e-16 rad."""

LIMIT_STATES = ("gap_closure", "backfill_50", "abutment_failure", "overturning")
"""The limit states a study reports when it names none (`assessment.limit_states` decides which
an analysis reaches); ``backfill_<p>`` for any whole p from 1 to 100 is one too."""

DEVICE_LIMIT_STATES = {
    "tendon_yield": "yielded", "tendon_rupture": "ruptured", "dissipator_fracture": "ruptured",
}  # fmt: skip
"""The limit states of a bridge's devices, each with the device table's column that says which
device of the kind the name starts with reached it (a tendon yielded, ruptured; a dissipator
fractured: the solver's state). A study reports them for the bridges whose devices state those
limits (docs/model.md §13)."""

_BACKFILL_STATE = re.compile(r"^backfill_([1-9][0-9]?|100)$")


def check_limit_state(name: str) -> str:
    """``name`` if it names a limit state.

    Raises
    ------
    ValueError
        It does not: the message lists the choices.
    """
    if name in LIMIT_STATES or name in DEVICE_LIMIT_STATES or _BACKFILL_STATE.match(name):
        return name
    raise ValueError(
        f"unknown limit state {name!r}: choose gap_closure, abutment_failure, overturning, "
        "backfill_<p> (p % of the backfill's capacity, 1-100), tendon_yield, tendon_rupture or "
        "dissipator_fracture"
    )

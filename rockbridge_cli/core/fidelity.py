"""Named fidelity presets: the speed/accuracy trade a user picks, each a documented set of knobs.

``reference``  the yardstick: adaptive Dormand–Prince 5(4) at rtol 1e-12, events located to
               1e-13 s, every turning point found, exact kinematics.
``default``    the best trade measured by ``benchmarks/bench_fidelity.py``: the same scheme at
               rtol 1e-8, atol 1e-13, events to 1e-13 s, tabulated kinematics (`tables`:
               piecewise cubics within 1e-13 of the exact linkage); Fig. 9 peaks within 3e-9
               of ``reference`` (rtol 1e-7 left one analysis 2e-8 off for 8 % less time; events
               located to 1e-11 s left 2.4e-8: near-grazing impacts amplify their error; atol
               1e-11, near rest where it rules, left one FEMA P695 analysis 7.5e-9 off once the
               steps were no longer cut at turning points, for 1.8 % fewer steps).
``fast``       for screening large studies: rtol 1e-5, events to 1e-7 s, peaks at the steps'
               ends (no turning points found), tabulated kinematics.
``paper``      the paper's own scheme: fixed-step Runge–Kutta (order 4) at 1e-3 s, events refined
               by bisection to 5e-6 s, peaks sampled at the steps, simplified kinematics.
"""

from __future__ import annotations

import numbers
from typing import Any, NamedTuple

_COMMON = {
    "rest_velocity": 1e-5, "output_step": 0.01, "max_events": 200_000, "tail": 0.0,
    "recheck": False,
}  # fmt: skip
"""Knobs every preset shares. ``tail``: free vibration after the record [s] (`analysis.analyze`);
``recheck``: a study runs again at ``reference`` every analysis that ends in a failure or comes
within `RECHECK_MARGIN` of a capacity (`study.work.analyze_cell`)."""

RECHECK_MARGIN = 0.05
"""A demand/capacity ratio above 1 − this is "within a few percent of a capacity" [-]."""

PRESETS: dict[str, dict[str, Any]] = {
    "reference": {
        "kinematics": "exact", "scheme": "dopri5", "step": 1e-4, "rtol": 1e-12, "atol": 1e-15,
        "max_step": 0.01, "event_tol": 1e-13, "bisection": False, "turning_points": True,
    },
    "default": {
        "kinematics": "tabulated", "scheme": "dopri5", "step": 1e-3, "rtol": 1e-8, "atol": 1e-13,
        "max_step": 0.01, "event_tol": 1e-13, "bisection": False, "turning_points": True,
    },
    "fast": {
        "kinematics": "tabulated", "scheme": "dopri5", "step": 1e-3, "rtol": 1e-5, "atol": 1e-8,
        "max_step": 0.01, "event_tol": 1e-7, "bisection": False, "turning_points": False,
    },
    "paper": {
        "kinematics": "simplified", "scheme": "rk4", "step": 1e-3, "rtol": 0.0, "atol": 0.0,
        "max_step": 1e-3, "event_tol": 5e-6, "bisection": True, "turning_points": False,
    },
}  # fmt: skip

SCHEMES = ("rk4", "dopri5")
"""Names of the integration schemes, in the order of their codes (`schemes.RK4`, `DOPRI5`)."""

KINEMATICS = ("exact", "tabulated", "simplified")
"""How the linkage is computed (`analysis._kinematics`)."""


class Knob(NamedTuple):
    """One fidelity knob: what it is called, its type, its unit, the values it may take and what
    it means. The solver's settings (`Fidelity.settings`), the checks of `resolve` and the
    fields of a study's ``fidelity`` section (`config.study_models.FidelityConfig`) derive from
    `KNOBS`.

    Attributes
    ----------
    name : as a study, `PRESETS` and `Fidelity.knobs` name it
    kind : ``float``, ``int``, ``bool`` or ``str`` (one of ``choices``)
    unit : of a number, as a config's description states it; empty for a switch or a choice
    low, high : the range of a number, ends included, so that an analysis ends and fits in
        memory; None for a switch or a choice
    meaning : what it does, as a config's description states it
    choices : the values of a ``str`` knob
    zero : whether 0 is a value of it; where not, a study and `resolve` refuse 0 (with ``low``
        0: ``rest_velocity: 0`` would let no impact end in rest, so that chattering near rest
        runs on to ``max_events``, a solver error)
    solver : read by the solver (`solver.Settings`), not by the analysis around it
    """

    name: str
    kind: type
    unit: str
    low: float | None
    high: float | None
    meaning: str
    choices: tuple[str, ...] = ()
    zero: bool = True
    solver: bool = True


KNOBS: tuple[Knob, ...] = (
    Knob("scheme", str, "", None, None, "Integration scheme", SCHEMES),
    Knob("kinematics", str, "", None, None, "Kinematics: exact, tabulated (from cubics built "
         "once per bridge) or simplified (the paper's fits)", KINEMATICS, solver=False),
    Knob("step", float, "s", 1e-5, 1.0, "Fixed (rk4) or first (dopri5) step", zero=False),
    Knob("max_step", float, "s", 1e-5, 1.0, "Largest step", zero=False),
    Knob("event_tol", float, "s", 1e-13, 1e-2, "Event times located to within", zero=False),
    Knob("rtol", float, "-", 0.0, 1.0, "Relative tolerance of dopri5"),
    Knob("atol", float, "rad, rad/s", 0.0, 1.0, "Absolute tolerance of dopri5"),
    Knob("bisection", bool, "", None, None, "Locate events by bisection (the paper's)"),
    Knob("turning_points", bool, "", None, None, "Catch each peak at θ̇1 = 0, found on the "
         "step that holds it"),
    Knob("rest_velocity", float, "rad/s", 0.0, 1.0, "Chatter guard: |θ̇1| below which an "
         "impact may end in rest", zero=False),
    Knob("output_step", float, "s", 1e-4, 10.0, "Time step of the stored histories",
         zero=False),
    Knob("max_events", int, "-", 1, 1_000_000, "Stop with a solver error beyond", zero=False),
    Knob("tail", float, "s", 0.0, 3600.0, "Free vibration after the record, with zero ground "
         "motion", solver=False),
    Knob("recheck", bool, "", None, None, "Run again at the reference preset what ends near or "
         "beyond a capacity", solver=False),
)  # fmt: skip
"""Every fidelity knob, in the order `resolve` checks them. Steps below 1e-5 s (a hundredth of
the paper's) would take hours; an event located closer than 1e-13 s cannot be (the spacing of
floating-point times); 1e6 events take 40 MB."""

LIMITS: dict[str, tuple[float, float]] = {
    knob.name: (knob.low, knob.high)
    for knob in KNOBS
    if knob.low is not None and knob.high is not None
}
"""The range of each numeric knob, ends included (`KNOBS`) [SI]."""

TOLERANCE_FLOORS = (1e-13, 1e-16)
"""DOPRI5 needs ``rtol`` or ``atol`` at least this [-, rad]: below both the error control asks
for steps of round-off size and the analysis never ends."""

MAX_GROUND_SAMPLES = 10_000_000
"""Most samples of ground motion an analysis reads, the tail's included (80 MB)."""

MAX_HISTORY_SAMPLES = 2_000_000
"""Most samples of the histories an analysis stores, ``(duration + tail) / output_step`` (about
100 bytes each, all histories)."""

MAX_STEPS = 100_000_000
"""Most steps an analysis may need while rocking all along, ``(duration + tail) / max_step``
(``step`` for RK4): about two minutes."""


class Fidelity(NamedTuple):
    """A preset with every knob settled and checked (`resolve`): what an analysis runs at, and
    what a results file states."""

    preset: str
    knobs: dict[str, Any]

    def changed(self, **overrides: Any) -> Fidelity:
        """The same preset with more knobs changed (checked again)."""
        return resolve(self.preset, **{**self.knobs, **overrides})

    def settings(self):
        """The solver's `Settings`: the knobs of `KNOBS` that are the solver's (``kinematics``,
        ``tail`` and ``recheck`` are not). The solver, and with it the compiler, is imported
        here, not with this module, so that listing the presets stays cheap."""
        from .solver import Settings

        values = {**self.knobs, "scheme": SCHEMES.index(self.knobs["scheme"])}
        return Settings(**{knob.name: values[knob.name] for knob in KNOBS if knob.solver})


def resolve(preset: str, **overrides: Any) -> Fidelity:
    """A preset's knobs, with any of them overridden, checked in range.

    Parameters
    ----------
    preset
        One of `PRESETS`.
    overrides
        Knob values to change, for example ``rtol=1e-9`` or ``output_step=0.005``; None keeps
        the preset's.

    Raises
    ------
    ValueError
        Unknown preset or knob, or a knob out of range (`KNOBS`).
    """
    if preset not in PRESETS:
        raise ValueError(f"unknown fidelity {preset!r}; choose one of {', '.join(PRESETS)}")
    values = {**_COMMON, **PRESETS[preset]}
    unknown = set(overrides) - set(values)
    if unknown:
        raise ValueError(f"unknown fidelity knob(s): {', '.join(sorted(unknown))}")
    values.update({k: v for k, v in overrides.items() if v is not None})
    _check(values)
    return Fidelity(preset, values)


def _check(values: dict[str, Any]) -> None:
    """Raise ValueError for a knob of the wrong type or out of its range (`KNOBS`)."""
    for knob in KNOBS:
        value = values[knob.name]
        if knob.low is None or knob.high is None:
            continue
        kind = numbers.Integral if knob.kind is int else numbers.Real
        if (
            isinstance(value, bool)
            or not isinstance(value, kind)
            or not knob.low <= float(value) <= knob.high
        ):
            raise ValueError(
                f"{knob.name} must be a number from {knob.low:g} to {knob.high:g}, not {value!r}"
            )
        if value == 0 and not knob.zero:  # in range, but no value of it (`Knob.zero`)
            raise ValueError(f"{knob.name} must be a number above 0 and at most {knob.high:g}, "
                             f"not {value!r}: 0 would never apply it "
                             f"({knob.meaning.lower()})")  # fmt: skip
    for knob in KNOBS:
        if knob.choices and values[knob.name] not in knob.choices:
            raise ValueError(f"{knob.name} must be one of {', '.join(knob.choices)}, not "
                             f"{values[knob.name]!r}")  # fmt: skip
    for knob in KNOBS:
        if knob.kind is bool and not isinstance(values[knob.name], bool):
            raise ValueError(f"{knob.name} must be true or false, not {values[knob.name]!r}")
    if values["scheme"] == "dopri5" and not (
        values["rtol"] >= TOLERANCE_FLOORS[0] or values["atol"] >= TOLERANCE_FLOORS[1]
    ):
        raise ValueError(f"dopri5 needs rtol ≥ {TOLERANCE_FLOORS[0]:g} or atol ≥ "
                         f"{TOLERANCE_FLOORS[1]:g}: below both it never ends")  # fmt: skip


def check_work(values: dict[str, Any], samples: int, time_step: float) -> None:
    """Refuse an analysis that could not end or not fit in memory (`MAX_GROUND_SAMPLES`,
    `MAX_HISTORY_SAMPLES`, `MAX_STEPS`).

    Parameters
    ----------
    values
        The knobs (`Fidelity.knobs`).
    samples
        Samples of the record [-].
    time_step
        Its sample interval [s].

    Raises
    ------
    ValueError
        What would be too much, and the knob to change.
    """
    tail = values["tail"]
    ground = samples + tail / time_step
    duration = (samples - 1) * time_step + tail
    step = values["max_step"]
    if values["scheme"] == "rk4":
        step = min(step, values["step"])
    for amount, most, what, knob in (
        (ground, MAX_GROUND_SAMPLES, "samples of ground motion", "a shorter tail"),
        (duration / values["output_step"], MAX_HISTORY_SAMPLES, "history samples",
         "a longer output_step"),
        (duration / step, MAX_STEPS, "steps", "a longer max_step (step for rk4)"),
    ):  # fmt: skip
        if not amount <= most:
            raise ValueError(f"{duration:g} s of analysis would need {amount:.3g} {what}, more "
                             f"than {most:.3g}: give {knob}")  # fmt: skip

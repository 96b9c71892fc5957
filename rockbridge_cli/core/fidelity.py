"""Named fidelity presets: the speed/accuracy trade a user picks, each a documented set of knobs.

``reference``  the yardstick: adaptive Dormand–Prince 5(4) at rtol 1e-12, events located to
               1e-13 s, every turning point located, exact kinematics.
``default``    the best trade measured by ``benchmarks/bench_fidelity.py``: the same scheme at
               rtol 1e-8, events to 1e-13 s, tabulated kinematics (`tables`: piecewise cubics
               within 1e-13 of the exact linkage); Fig. 9 peaks within 3e-9 of ``reference``
               (rtol 1e-7 left one analysis 2e-8 off for 8 % less time; events located to
               1e-11 s left 2.4e-8: near-grazing impacts amplify their error).
``fast``       for screening large studies: rtol 1e-5, events to 1e-7 s, peaks at the steps'
               ends (no turning points located), tabulated kinematics.
``paper``      the paper's own scheme: fixed-step Runge–Kutta (order 4) at 1e-3 s, events refined
               by bisection to 5e-6 s, peaks sampled at the steps, simplified kinematics.
"""

from __future__ import annotations

from typing import Any

_COMMON = {
    "rest_velocity": 1e-5, "output_step": 0.01, "max_events": 200_000, "tail": 0.0,
    "recheck": False,
}  # fmt: skip
"""Knobs every preset shares. ``tail``: free vibration after the record [s] (`analysis.analyze`);
``recheck``: a study runs again at ``reference`` every analysis that ends in a failure or comes
within `RECHECK_MARGIN` of a capacity (`study.work.analyse`)."""

RECHECK_MARGIN = 0.05
"""A demand/capacity ratio above 1 − this is "within a few percent of a capacity" [-]."""

PRESETS: dict[str, dict[str, Any]] = {
    "reference": {
        "kinematics": "exact", "scheme": "dopri5", "step": 1e-4, "rtol": 1e-12, "atol": 1e-15,
        "max_step": 0.01, "event_tol": 1e-13, "bisection": False, "turning_points": True,
    },
    "default": {
        "kinematics": "tabulated", "scheme": "dopri5", "step": 1e-3, "rtol": 1e-8, "atol": 1e-11,
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


def knobs(preset: str, **overrides: Any) -> dict[str, Any]:
    """The knobs of a preset, with any of them overridden.

    Parameters
    ----------
    preset
        One of `PRESETS`.
    overrides
        Knob values to change, for example ``rtol=1e-9`` or ``output_step=0.005``.

    Raises
    ------
    ValueError
        Unknown preset or knob.
    """
    if preset not in PRESETS:
        raise ValueError(f"unknown fidelity {preset!r}; choose one of {', '.join(PRESETS)}")
    values = {**_COMMON, **PRESETS[preset]}
    unknown = set(overrides) - set(values)
    if unknown:
        raise ValueError(f"unknown fidelity knob(s): {', '.join(sorted(unknown))}")
    values.update({k: v for k, v in overrides.items() if v is not None})
    return values


def settings(values: dict[str, Any]):
    """The solver's `Settings` from a knob dictionary (``kinematics`` is not a solver knob).

    The solver (and with it the compiler) is imported here, not with this module, so that listing
    the presets stays cheap.
    """
    from .solver import Settings

    solver_values = {**values, "scheme": SCHEMES.index(values["scheme"])}  # tail: not the solver's
    return Settings(**{name: solver_values[name] for name in Settings._fields})

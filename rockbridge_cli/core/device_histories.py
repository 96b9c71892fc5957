"""The histories of the piers' devices (`devices`), written by the integrator at its output
samples: each device's force, elongation and plastic elongation (docs/model.md §13).

Each function the integrator calls is compiled for the type of its ``devices``: a table
(`devices.table`), or None, for which the histories have no columns and nothing is written, so
that a bridge without devices runs the free-standing model's code.
"""

from __future__ import annotations

import numpy as np
from numba.extending import overload

from ._jit import absent, jit
from .device_mechanics import pull, stretch, turns
from .devices import DAMPER, KIND, PLASTIC
from .geometry import Model

HISTORY_FORCE, HISTORY_ELONGATION, HISTORY_PLASTIC = 0, 1, 2
"""Columns of a device's histories: force, positive in tension [N], elongation Δ [m] and plastic
elongation Δp [m] (0 for a damper)."""

HISTORY_COLUMNS = 3


def histories_of(devices, samples: int) -> np.ndarray:
    """The devices' histories before any sample is written: (samples, devices, `HISTORY_COLUMNS`),
    with no device column without devices."""
    count = 0 if devices is None else devices.shape[0]
    return np.zeros((samples, count, HISTORY_COLUMNS))


@overload(histories_of)
def _compiled_histories_of(devices, samples):
    if absent(devices):
        return lambda devices, samples: np.zeros((samples, 0, HISTORY_COLUMNS))
    return lambda devices, samples: np.zeros((samples, devices.shape[0], HISTORY_COLUMNS))


def sampled(devices, out: np.ndarray, model: Model, s: float, theta1, rate, first, last, kin):
    """Write the devices' histories ``out`` at the samples first … last − 1 [-] from the θ1 and θ̇1
    histories ``theta1``, ``rate`` [rad, rad/s] there, in mode s (0: at rest, Δ = 0), the devices
    in their state, the linkage as ``kin`` computes it; nothing without devices."""
    if devices is not None:
        _sampled(devices, out, model, s, theta1, rate, first, last, kin)


@overload(sampled)
def _compiled_sampled(devices, out, model, s, theta1, rate, first, last, kin):
    if absent(devices):
        return lambda devices, out, model, s, theta1, rate, first, last, kin: None
    return lambda devices, out, model, s, theta1, rate, first, last, kin: _sampled(
        devices, out, model, s, theta1, rate, first, last, kin
    )


@jit
def _sampled(devices: np.ndarray, out: np.ndarray, model: Model, s, theta1, rate, first, last, kin):
    for j in range(first, last):
        if s == 0.0:  # at rest: no elongation
            for i in range(devices.shape[0]):
                _written(devices[i], out[j, i], 0.0, 0.0)
            continue
        turned = turns(model, s, theta1[j], kin)
        for i in range(devices.shape[0]):
            length, lever = stretch(model, devices[i], s, turned)
            _written(devices[i], out[j, i], length, lever * rate[j])


@jit
def _written(row: np.ndarray, out: np.ndarray, length: float, speed: float) -> None:
    """Write one device's force, elongation Δ [m] and plastic elongation at Δ and Δ̇ [m/s]."""
    out[HISTORY_FORCE] = pull(row, length, speed)
    out[HISTORY_ELONGATION] = length
    out[HISTORY_PLASTIC] = 0.0 if row[KIND] == DAMPER else row[PLASTIC]

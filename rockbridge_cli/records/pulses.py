"""Analytic pulses as records: a `motions.pulses.Pulse` sampled and followed by rest, named by its
parameters, with its shape and parameters as provenance (`files.PROVENANCE`)."""

from __future__ import annotations

from ..core.fidelity import MAX_GROUND_SAMPLES
from ..core.quantities import STANDARD_GRAVITY
from ..motions.pulses import DEFAULT_CYCLES, Pulse
from .files import Record

SOURCE = "pulse"
"""How a record of an analytic pulse names its source."""


def pulse_id(pulse: Pulse) -> str:
    """The id of a pulse, from its parameters: ``one-sine-a_0.3g_0.5s``, with the phase and the
    number of cycles where they are not the shape's default (``…_phase1.5708``, ``…_2cycles``);
    the amplitude in g (standard gravity, as for record files)."""
    name = f"{pulse.shape}_{pulse.amplitude / STANDARD_GRAVITY:.10g}g_{pulse.period:.10g}s"
    if pulse.phase:
        name += f"_phase{pulse.phase:.10g}"
    if pulse.cycles != DEFAULT_CYCLES.get(pulse.shape):
        name += f"_{pulse.cycles:.10g}cycles"
    return name


def pulse_record(
    pulse: Pulse, time_step: float, rest: float = 0.0, name: str | None = None
) -> Record:
    """A pulse as a record.

    Parameters
    ----------
    pulse
        The pulse.
    time_step
        Sample interval [s].
    rest
        Time at rest after the pulse [s] (the free vibration that decides many overturnings).
    name
        The record's name; default `pulse_id`.

    Raises
    ------
    ValueError
        It would need more samples than an analysis reads (`Pulse.check_samples`).
    """
    pulse.check_samples(time_step, rest, MAX_GROUND_SAMPLES)  # before a sample is drawn
    metadata = {
        "pulse_shape": pulse.shape, "pulse_amplitude": pulse.amplitude,
        "pulse_period_s": pulse.period, "pulse_phase": pulse.phase, "pulse_rest": rest,
        **({} if pulse.cycles is None else {"pulse_cycles": pulse.cycles}),
    }  # fmt: skip
    return Record(
        name or pulse_id(pulse), time_step, pulse.sampled(time_step, rest), SOURCE, metadata
    )

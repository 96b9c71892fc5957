"""The target spectrum of a record set, resolved in SI units from its config (`resolve_target`)
or read back from a set's manifest (`read_set_target`); a user's spectrum read from a file
(`read_spectrum_file`), a record selection's optional target."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..motions import ec8
from .set_files import MANIFEST, read_manifest

if TYPE_CHECKING:
    from ..config.record_sets import RecordSetConfig


@dataclass(frozen=True)
class TargetDefinition:
    """The resolved target of a record set, in SI units.

    Attributes
    ----------
    spectrum_type, ground_type, damping
        as in the config.
    design_acceleration
        a_g [m/s²].
    surface_pga
        a_g·S, the records' PGA [m/s²]; of a vertical target, a_vg.
    vertical
        whether this is the vertical elastic spectrum (EN 1998-1 §3.2.2.3), the target of the
        vertical components (`vertical_component`).
    """

    spectrum_type: int
    ground_type: str
    damping: float
    design_acceleration: float
    surface_pga: float
    vertical: bool = False

    def vertical_component(self) -> TargetDefinition:
        """The vertical target of the same earthquake: Sve of EN 1998-1 §3.2.2.3, whose a_vg
        (Table 3.4: 0.90·a_g for type 1, 0.45·a_g for type 2) the vertical components peak at."""
        ratio = ec8.VERTICAL_SHAPES[self.spectrum_type][0]
        return dataclasses.replace(
            self, surface_pga=ratio * self.design_acceleration, vertical=True
        )

    @property
    def ground_displacement(self) -> float:
        """EN 1998-1's design ground displacement d_g [m] (`ec8.design_ground_displacement`)."""
        return ec8.design_ground_displacement(
            self.spectrum_type, self.ground_type, self.design_acceleration
        )

    @property
    def ground_velocity(self) -> float:
        """v_g = 2π·d_g/T_D [m/s]: EN 1998-1 gives no design ground velocity; this one stands to
        d_g as the spectrum's pseudo-velocity to its displacement at T_D, where its constant
        velocity and constant displacement branches meet (0.64 m/s for type 1, ground C,
        a_g = 0.6 g)."""
        corner = ec8.get_spectrum_shape(self.spectrum_type, self.ground_type).corner_d
        return 2.0 * np.pi * self.ground_displacement / corner

    def evaluate(self, periods: np.ndarray, extrapolate: bool = False) -> np.ndarray:
        """Se (or Sve, for a vertical target) at the given periods [m/s²]."""
        if self.vertical:
            return ec8.compute_vertical_spectrum(
                periods, self.spectrum_type, self.design_acceleration, self.damping, extrapolate
            )
        return ec8.compute_elastic_spectrum(
            periods,
            self.spectrum_type,
            self.ground_type,
            design_acceleration=self.design_acceleration,
            damping=self.damping,
            extrapolate=extrapolate,
        )


def resolve_target(config: RecordSetConfig) -> TargetDefinition:
    """a_g and a_g·S of a config in m/s², whichever of ``ag_g`` and ``pga_g`` it gives."""
    target = config.target
    soil = ec8.get_spectrum_shape(target.spectrum_type, target.ground_type).soil_factor
    if target.ag_g is not None:
        design = target.ag_g * config.gravity
    else:
        assert target.pga_g is not None  # the config gives exactly one of the two
        design = target.pga_g * config.gravity / soil
    return TargetDefinition(
        target.spectrum_type, target.ground_type, target.damping, design, design * soil
    )


def read_set_target(folder: str | Path) -> TargetDefinition:
    """The target spectrum stored in a record set's manifest (SI units).

    Raises
    ------
    InputError
        The manifest is missing or corrupt, or lacks the target.
    """
    manifest = read_manifest(folder)
    target = manifest.get("target")
    keys = (
        "spectrum_type",
        "ground_type",
        "damping",
        "design_acceleration_m_s2",
        "surface_pga_m_s2",
    )
    if not isinstance(target, dict) or any(key not in target for key in keys):
        raise InputError(Path(folder) / MANIFEST, [("target", "missing or incomplete")])
    return TargetDefinition(*(target[key] for key in keys))


MAX_SPECTRUM_BYTES = 2**20
"""Largest spectrum file read [bytes]."""


@dataclass(frozen=True)
class UserSpectrum:
    """A target spectrum given as points: periods and pseudo-spectral accelerations, read from a
    two-column file (`read_spectrum_file`) and interpolated linearly in log T and log Sa (exact
    on the power-law branches of EN 1998-1's spectra between their corners).

    Attributes
    ----------
    periods
        increasing, positive [s].
    values
        Sa there, positive [m/s²].
    source
        the file's name.
    """

    periods: tuple[float, ...]
    values: tuple[float, ...]
    source: str = ""

    def evaluate(self, periods: np.ndarray) -> np.ndarray:
        """Sa at the given periods, within the file's range [m/s²]."""
        periods = np.asarray(periods, dtype=float)
        low, high = self.periods[0], self.periods[-1]
        if np.any(periods < low * (1 - 1e-12)) or np.any(periods > high * (1 + 1e-12)):
            raise ValueError(f"the user spectrum covers {low:g}-{high:g} s only")
        return np.exp(np.interp(np.log(periods), np.log(self.periods), np.log(self.values)))


def read_spectrum_file(path: str | Path, units: str) -> UserSpectrum:
    """A two-column text file, period [s] and Sa (in ``units``: g, m/s2 or cm/s2), ``#`` lines
    comments, periods increasing and positive, values positive.

    Raises
    ------
    InputError
        The file cannot be read or is not such a table.
    """
    from ..paths import read_input_text
    from .files import UNIT_SCALES

    text = read_input_text(path, MAX_SPECTRUM_BYTES, "a spectrum file")
    rows = [line.replace(",", " ").split() for line in text.splitlines()
            if line.strip() and not line.lstrip().startswith("#")]  # fmt: skip
    try:
        table = np.array(rows, dtype=float)
    except ValueError:
        raise InputError(path, [("", "expected two columns of numbers: period [s], Sa")]) from None
    if table.ndim != 2 or table.shape[1] != 2 or table.shape[0] < 2:
        raise InputError(path, [("", "expected at least two rows of two columns: period, Sa")])
    periods, values = table[:, 0], table[:, 1] * UNIT_SCALES[units]
    if not (np.all(np.isfinite(table)) and periods[0] > 0 and np.all(np.diff(periods) > 0)):
        raise InputError(path, [("", "periods must be positive and increasing")])
    if not np.all(values > 0):
        raise InputError(path, [("", "spectral accelerations must be positive")])
    return UserSpectrum(tuple(periods.tolist()), tuple(values.tolist()), Path(path).name)

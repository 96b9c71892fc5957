"""How each record of a generated set turned out (`RecordSummary`) and, for a matched seed, what
the matching changed of it (`SeedChange`): what the compliance report prints and the manifest
keeps."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..motions import spectral_fit

if TYPE_CHECKING:
    from ..motions import seeds  # scipy.signal: 1-2 s to import, which select-records needs not

SEED_CHANGE = 0.25
"""The report flags a matched seed whose D5–95, D5–75 or PGV changed by more than this share of
the seed's (the PGV of the seed scaled to the target PGA), or whose Arias time moved by more
than this share of its D5–95 [-]."""


@dataclass(frozen=True)
class SeedChange:
    """What matching did to a seed: the matched record's traits beside the seed's, the seed
    linearly scaled to the target PGA.

    Attributes
    ----------
    record, seed
        their PGV, PGD, D5–95, D5–75 and Arias time (`seeds.MotionTraits`).
    pgv_bound, pgd_bound
        the largest PGV [m/s] and PGD [m] the matched record may have (`SEED_GROUND_GROWTH`).
    resampled
        the seed's own time step and the one it was resampled to, to resolve the band [s]; None
        where it was matched at its own.
    """

    record: seeds.MotionTraits
    seed: seeds.MotionTraits
    pgv_bound: float
    pgd_bound: float
    resampled: tuple[float, float] | None

    @property
    def ground_ok(self) -> bool:
        """PGV and PGD within their bounds."""
        return self.record.pgv <= self.pgv_bound and self.record.pgd <= self.pgd_bound

    @property
    def flags(self) -> tuple[str, ...]:
        """The traits that changed by more than `SEED_CHANGE`."""
        new, old = self.record, self.seed
        changes = {
            "PGV": new.pgv / old.pgv - 1.0,
            "D5-95": new.d5_95 / old.d5_95 - 1.0,
            "D5-75": new.d5_75 / old.d5_75 - 1.0,
            "Arias time": (new.arias_time - old.arias_time) / old.d5_95,
        }
        return tuple(name for name, change in changes.items() if abs(change) > SEED_CHANGE)


@dataclass(frozen=True)
class RecordSummary:
    """How one generated record turned out.

    Attributes
    ----------
    name, file
        record name and file name in the set's folder.
    peak_acceleration
        PGA [m/s²].
    min_ratio, max_ratio
        min and max over the check periods of computed / target spectrum [-].
    final_velocity, final_displacement
        ground velocity [m/s] and displacement [m] at the end of the record.
    peak_velocity, peak_displacement
        largest |ground velocity| [m/s] and |displacement| [m] over the record.
    significant_duration
        D5–95 [s].
    attempts, iterations
        phase sets tried and matching iterations of the kept one [-].
    scale_factor
        the factor of a seed scaled rather than matched (`ec8.scale_factors`) [-], else None.
    fit
        the ratio to the target on the dense grid, every local extreme refined
        (`spectral_fit.measure_fit`).
    seed_change
        what the matching changed of a matched seed, else None.
    """

    name: str
    file: str
    peak_acceleration: float
    min_ratio: float
    max_ratio: float
    final_velocity: float
    final_displacement: float
    peak_velocity: float
    peak_displacement: float
    significant_duration: float
    attempts: int
    iterations: int
    fit: spectral_fit.SpectralFit
    scale_factor: float | None = None
    seed_change: SeedChange | None = None

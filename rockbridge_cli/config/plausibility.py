"""Values that are legal but implausible: warnings, not errors.

A config or record that passes validation can still hold a slip of units — a gap of 200 m (mm
typed as m), a backfill of 132 000 N/m (kN typed as N), a record in cm/s² declared as m/s² (a
36 g record) or in g declared as m/s² (a record that never rocks anything). Each check below
returns readable warnings; the command line prints them once per input and the results file
keeps them (root attribute ``warnings``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..core.quantities import STANDARD_GRAVITY

if TYPE_CHECKING:
    from ..records.files import Record
    from .bridge import BridgeConfig

RECORD_PGA_G = (0.001, 5.0)
"""Peak ground accelerations outside this range [g] are not earthquake records (the largest
recorded are about 4 g)."""

GAP_M = 1.0
"""End-joint gaps above this [m] are not bridge expansion joints (they are 0.01–0.3 m)."""

BACKFILL_STIFFNESS_N_M = 1e6
"""Backfill springs below this [N/m] are not abutment backfills (tens to hundreds of MN/m)."""

PIER_ASPECT = (1.5, 40.0)
"""Pier height over width H/B outside this range has not been built as a rocking pier."""


def bridge_warnings(config: BridgeConfig) -> list[str]:
    """Implausible values of a bridge config, as ``field: reason`` texts."""
    found = []
    half_width = config.piers.width / 2
    for index, height in enumerate(config.piers.heights):
        ratio = height / 2 / half_width
        low, high = PIER_ASPECT
        if not low <= ratio <= high:
            found.append(
                f"piers.heights.{index}: a pier {ratio:.3g} times as tall (H) as half its width "
                f"(B); built rocking piers lie between {low:g} and {high:g}"
            )
    abutments = config.abutments
    if abutments is not None:
        if abutments.gap > GAP_M:
            found.append(f"abutments.gap: {abutments.gap:g} m is not an expansion joint "
                         "(0.01–0.3 m): mm typed as m?")  # fmt: skip
        if 0.0 < abutments.stiffness < BACKFILL_STIFFNESS_N_M:
            found.append(f"abutments.stiffness: {abutments.stiffness:g} N/m is far below a "
                         "backfill's (tens of MN/m): kN/m typed as N/m?")  # fmt: skip
    return found


def record_warnings(record: Record) -> list[str]:
    """Implausible features of a ground motion: its peak for its stated unit, a time column that
    does not start at zero."""
    found = list(record.metadata.get("notices", ()))
    pga = record.peak_acceleration / STANDARD_GRAVITY
    low, high = RECORD_PGA_G
    if math.isfinite(pga) and not low <= pga <= high:
        unit = record.metadata.get("file_units", "m/s2")
        found.append(f"peak {pga:.4g} g is not an earthquake's ({low:g}–{high:g} g): is the "
                     f"file really in {unit}?")  # fmt: skip
    return found

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

WEAK_PGA_G = 0.1
"""A record in m/s² that peaks below this [g] rocks few bridges (their onsets are 0.1–0.35 g):
where its numbers would be a record's in g (0.05–5), they may be in g."""

GAP_M = (0.001, 1.0)
"""End-joint gaps outside these [m], but for 0 (no joint), are not bridge expansion joints (they
are 0.01–0.3 m): 0.1 mm is a gap in mm converted to m twice, 200 m one in mm typed as m."""

BACKFILL_STIFFNESS_N_M = 1e6
"""Backfill springs below this [N/m] are not abutment backfills (tens to hundreds of MN/m)."""

PIER_ASPECT = (1.5, 40.0)
"""Pier height over width H/B outside this range has not been built as a rocking pier."""

VERTICAL_PGA_G = 1.0
"""A vertical component that peaks above this [g] lifts the bridge off the ground where it
points down (g + ü_v ≤ 0): the model cannot follow a free flight, and the analysis stops there."""

GRAVITY_M_S2 = (9.76, 9.84)
"""Gravity on Earth's surface, pole to equator and mountain to sea [m/s²]."""

DENSITY_KG_M3 = (1000.0, 8000.0)
"""Densities of structural materials, timber to steel [kg/m³] (25 is kN/m³ typed as kg/m³)."""

DECK_MASS_KG = (1e4, 1e9)
"""Deck masses of bridges, a footbridge's to a long viaduct's [kg]."""

ULTIMATE_DISPLACEMENT_M = 1.0
"""Backfill displacements at failure above this [m] are not a backfill's (about 0.1 m)."""

SPAN_M = 2000.0
"""Spans longer than this [m] have not been built."""

TIME_STEP_S = (1e-4, 0.1)
"""Sample intervals of recorded and synthetic ground motions [s] (10 kHz to 10 Hz): outside, a
time column in ms or in minutes?"""

DECK_DEPTH_SHARE = 0.5
"""Most a deck's depth 2h may be of its shortest pier's height 2H before it is implausible
(the studied bridges: 1.7 m on 20.8 m) [-]."""

RECORD_SAMPLES = 10
"""Fewest samples of a plausible ground motion (a two-sample "record" ran silently) [-]."""

VERTICAL_MEAN_G = 0.1
"""Largest plausible mean of a vertical component: ground motion averages near zero; a constant
near ±1 g is gravity written into the file [g]."""

HORIZONTAL_MEAN_SHARE = 0.01
"""Largest plausible mean of a horizontal ground acceleration, as a share of its peak: recorded
motions average near zero (the FEMA P695 sets' 100 components at most 0.015 %); a larger mean
is an uncorrected baseline or an offset in the file, which shifts the onset of rocking and the
demands (AR07 with 0.5 m/s² added: onset 4.3 s instead of 5.5 s, backfill d/c 33 % instead of
31 %) [-]."""

SCALE_FACTORS = (0.01, 100.0)
"""Factors an intensity level scales a record by, beyond which the level or the measure is
probably wrong [-]."""


TENDON_STRENGTH_PA = 1860e6
"""Ultimate strength of seven-wire prestressing strand (EN 10138-3, Y1860) [Pa]: a tendon's
prestress over its area beyond this is a slip of units."""

TENDON_LEAST_SHARE = 0.01
"""A tendon's prestress below this share of its pier's weight changes nothing a designer would
prestress for [-]."""


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
        if abutments.gap > GAP_M[1]:
            found.append(f"abutments.gap: {abutments.gap:g} m is not an expansion joint "
                         "(0.01–0.3 m): mm typed as m?")  # fmt: skip
        elif 0.0 < abutments.gap < GAP_M[0]:
            found.append(f"abutments.gap: {abutments.gap:g} m is not an expansion joint "
                         "(0.01–0.3 m; 0 for none): a length converted to m twice?")  # fmt: skip
        if 0.0 < abutments.stiffness < BACKFILL_STIFFNESS_N_M:
            found.append(f"abutments.stiffness: {abutments.stiffness:g} N/m is far below a "
                         "backfill's (tens of MN/m): kN/m typed as N/m?")  # fmt: skip
        if abutments.ultimate_displacement > ULTIMATE_DISPLACEMENT_M:
            found.append(f"abutments.ultimate_displacement: {abutments.ultimate_displacement:g} m "
                         "is not a backfill's (about 0.1 m): mm typed as m?")  # fmt: skip
    if config.deck is not None:
        shortest = min(config.piers.heights)
        if config.deck.depth > DECK_DEPTH_SHARE * shortest:
            found.append(f"deck.depth: a {config.deck.depth:g} m deep deck on a {shortest:g} m "
                         "pier is not a bridge's: cm typed as m?")  # fmt: skip
    return found + _outside_ranges(config) + _device_warnings(config)


def _device_warnings(config: BridgeConfig) -> list[str]:
    """Tendons stressed beyond prestressing steel's strength, or prestressed by a force that the
    pier's own weight dwarfs (kN typed as N)."""
    found = []
    weight = config.density * config.gravity * config.piers.width**2 * min(config.piers.heights)
    for index, device in enumerate(config.devices):
        if device.kind != "tendon":
            continue
        stress = device.prestress / device.area
        if stress > TENDON_STRENGTH_PA:
            strength = TENDON_STRENGTH_PA / 1e6
            found.append(f"devices.{index}.prestress: {stress / 1e6:.4g} MPa on its area is more "
                         f"than prestressing steel takes ({strength:g} MPa)")  # fmt: skip
        if 0.0 < device.prestress < TENDON_LEAST_SHARE * weight:
            found.append(f"devices.{index}.prestress: {device.prestress:g} N is less than "
                         f"{TENDON_LEAST_SHARE:.0%} of the shorter pier's weight "
                         f"({weight:.3g} N): kN typed as N?")  # fmt: skip
    return found


def _outside_ranges(config: BridgeConfig) -> list[str]:
    """Gravity, density, deck mass and spans outside what has been built on Earth."""
    values = [("gravity", config.gravity, GRAVITY_M_S2, "m/s²"),
              ("density", config.density, DENSITY_KG_M3, "kg/m³")]  # fmt: skip
    if config.deck is not None and config.deck.mass is not None:
        values.append(("deck.mass", config.deck.mass, DECK_MASS_KG, "kg"))
    if config.spans is not None:
        values += [(f"spans.{name}", getattr(config.spans, name), (0.0, SPAN_M), "m")
                   for name in ("side", "central")]  # fmt: skip
    return [
        f"{field}: {value:g} {unit} is outside {low:g}–{high:g} {unit}, the range of built "
        "bridges: a slip of units?"
        for field, value, (low, high), unit in values
        if not low <= value <= high
    ]


def record_warnings(record: Record) -> list[str]:
    """Implausible features of a ground motion: its peak for its stated unit, a time column that
    does not start at zero or a time step out of range (a record file's, not an analytic
    pulse's), a mean far from zero, a vertical component that can lift the bridge off the
    ground."""
    found = list(record.metadata.get("notices", ()))
    pga = record.peak_acceleration / STANDARD_GRAVITY
    low, high = RECORD_PGA_G
    unit = record.metadata.get("file_units", "m/s2")
    if math.isfinite(pga) and not low <= pga <= high:
        found.append(f"peak {pga:.4g} g is not an earthquake's ({low:g}–{high:g} g): is the "
                     f"file really in {unit}?")  # fmt: skip
    elif unit == "m/s2" and pga < WEAK_PGA_G and 0.05 <= record.peak_acceleration <= high:
        found.append(f"peak {pga:.3g} g, weaker than most records that make a bridge rock: if "
                     f"the file's numbers are in g, it peaks at {record.peak_acceleration:.3g} g "
                     "(say units: g, --units g)")  # fmt: skip
    if record.acceleration.size < RECORD_SAMPLES:
        found.append(f"only {record.acceleration.size} samples: a ground motion has thousands; "
                     "is the file complete?")  # fmt: skip
    low, high = TIME_STEP_S
    analytic = "pulse_shape" in record.metadata  # its step is chosen for it, from its period
    if not analytic and not low <= record.time_step <= high:
        found.append(f"time step {record.time_step:g} s is not a ground motion's ({low:g}–"
                     f"{high:g} s): is the time column in seconds?")  # fmt: skip
    mean = float(record.acceleration.mean()) if record.acceleration.size else 0.0
    if not analytic and abs(mean) > HORIZONTAL_MEAN_SHARE * record.peak_acceleration:
        found.append(f"its mean is {mean / STANDARD_GRAVITY:.3g} g, "
                     f"{abs(mean) / record.peak_acceleration:.1%} of its peak, where a ground "
                     "motion's is near zero: an uncorrected baseline, or an offset in the "
                     "file?")  # fmt: skip
    from ..records.vertical import peak_vertical  # numpy: loaded on use

    vertical = peak_vertical(record) / STANDARD_GRAVITY
    if record.vertical is not None and record.vertical.size:
        mean = float(record.vertical.mean()) / STANDARD_GRAVITY
        if abs(mean) > VERTICAL_MEAN_G:
            found.append(f"vertical component averages {mean:.3g} g: ground motion averages near "
                         "zero; is gravity in the file?")  # fmt: skip
    if vertical > VERTICAL_PGA_G:
        found.append(f"vertical peak {vertical:.3g} g exceeds {VERTICAL_PGA_G:g} g: where "
                     "g + ü_v ≤ 0 the bridge would leave the ground (free flight), which the "
                     "model does not follow: the analysis stops there")  # fmt: skip
    return found


def scale_warning(record: str, scale: float) -> list[str]:
    """A record scaled to an intensity level by an implausible factor (`SCALE_FACTORS`)."""
    low, high = SCALE_FACTORS
    if low <= scale <= high:
        return []
    return [f"{record}: scaled by {scale:.3g} to reach its level (more than {high:g} or less "
            f"than {low:g}): is the level, the measure or its period right?"]  # fmt: skip

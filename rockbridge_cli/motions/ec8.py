"""EN 1998-1 (Eurocode 8) horizontal elastic response spectra and the check of artificial records.

All accelerations are in the same unit as the design ground acceleration passed in (SI inside the
package: m/s²); periods are in seconds, damping ratios are fractions of critical (0.05 for 5%).

References
----------
CEN (2004). EN 1998-1: Eurocode 8, Design of structures for earthquake resistance, Part 1.
§3.2.2.2 (horizontal elastic response spectrum, Eqs. 3.2–3.6, Tables 3.2 and 3.3) and
§3.2.3.1.2 (artificial accelerograms).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Upper end of the period range of Eqs. (3.2)–(3.5); beyond it EN 1998-1 refers to Annex A [s].
MAX_PERIOD = 4.0

#: EN 1998-1 Tables 3.2 (Type 1) and 3.3 (Type 2): ground type -> (S [-], TB, TC, TD [s]).
SPECTRUM_PARAMETERS: dict[int, dict[str, tuple[float, float, float, float]]] = {
    1: {
        "A": (1.0, 0.15, 0.4, 2.0),
        "B": (1.2, 0.15, 0.5, 2.0),
        "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0),
        "E": (1.4, 0.15, 0.5, 2.0),
    },
    2: {
        "A": (1.0, 0.05, 0.25, 1.2),
        "B": (1.35, 0.05, 0.25, 1.2),
        "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2),
        "E": (1.6, 0.05, 0.25, 1.2),
    },
}


@dataclass(frozen=True)
class SpectrumShape:
    """The four parameters of an EN 1998-1 elastic spectrum (Tables 3.2 and 3.3).

    Attributes
    ----------
    soil_factor
        S [-].
    corner_b
        TB, lower limit of the constant-acceleration branch [s].
    corner_c
        TC, upper limit of the constant-acceleration branch [s].
    corner_d
        TD, start of the constant-displacement branch [s].
    """

    soil_factor: float
    corner_b: float
    corner_c: float
    corner_d: float


def get_spectrum_shape(spectrum_type: int, ground_type: str) -> SpectrumShape:
    """Return S, TB, TC and TD of EN 1998-1 Table 3.2 (Type 1) or Table 3.3 (Type 2).

    Parameters
    ----------
    spectrum_type
        1 (high-seismicity, Ms > 5.5) or 2 (Ms <= 5.5) [-].
    ground_type
        "A" to "E" (EN 1998-1 Table 3.1) [-].
    """
    if spectrum_type not in SPECTRUM_PARAMETERS:
        raise ValueError(f"spectrum type must be 1 or 2, got {spectrum_type!r}")
    table = SPECTRUM_PARAMETERS[spectrum_type]
    if ground_type not in table:
        raise ValueError(f"ground type must be one of {', '.join(table)}, got {ground_type!r}")
    return SpectrumShape(*table[ground_type])


def design_ground_displacement(
    spectrum_type: int, ground_type: str, design_acceleration: float
) -> float:
    """EN 1998-1 §3.2.2.4's design ground displacement d_g = 0.025·a_g·S·T_C·T_D [m].

    Parameters
    ----------
    spectrum_type, ground_type
        as in `get_spectrum_shape`.
    design_acceleration
        a_g [m/s²].
    """
    shape = get_spectrum_shape(spectrum_type, ground_type)
    return 0.025 * design_acceleration * shape.soil_factor * shape.corner_c * shape.corner_d


def scale_factors(
    computed: np.ndarray,
    target: np.ndarray,
    peaks: np.ndarray,
    surface_pga: float,
    individual: bool = True,
) -> np.ndarray:
    """Linear factors that bring recorded motions to a target spectrum without changing their
    shape (EN 1998-1 §3.2.3.1.3's scaled records), least misfit first, then the mean rules.

    Each record's factor (or one for the set) minimises the mean squared log ratio of its
    spectrum to the target over the periods given: exp(mean(log(target/computed))). All factors
    are then raised by the one smallest common multiplier, if any is needed, so that the mean
    spectrum nowhere falls below 90 % of the target (§3.2.3.1.2(4)c) and the mean PGA is at
    least a_g·S (4)b.

    Parameters
    ----------
    computed
        spectra of the unscaled records at the periods, shape (records, periods) [m/s²].
    target
        target spectrum at the same periods [m/s²].
    peaks
        the unscaled records' PGA [m/s²].
    surface_pga
        a_g·S [m/s²].
    individual
        one factor per record (True) or one for the set.

    Returns
    -------
    numpy.ndarray
        the factor of each record [-].
    """
    logs = np.log(target[None, :] / computed)
    if individual:
        factors = np.exp(logs.mean(axis=1))
    else:
        factors = np.full(computed.shape[0], np.exp(logs.mean()))
    mean = (factors[:, None] * computed).mean(axis=0)
    needed = max(float(np.max(0.9 * target / mean)), surface_pga / float(np.mean(factors * peaks)))
    return factors * (needed * (1.0 + 1e-9) if needed > 1.0 else 1.0)  # 1e-9: past round-off


def compute_damping_correction(damping: float) -> float:
    """Damping correction factor η = √(10 / (5 + ξ)) ≥ 0.55, ξ in percent (EN 1998-1 Eq. 3.6).

    Parameters
    ----------
    damping
        viscous damping ratio ξ as a fraction of critical (0.05 for 5%) [-].
    """
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"damping ratio must be in [0, 1), got {damping!r}")
    return max(float(np.sqrt(10.0 / (5.0 + 100.0 * damping))), 0.55)


def compute_elastic_spectrum(
    periods: np.ndarray | float,
    spectrum_type: int,
    ground_type: str,
    *,
    design_acceleration: float | None = None,
    surface_pga: float | None = None,
    damping: float = 0.05,
    extrapolate: bool = False,
) -> np.ndarray:
    """Horizontal elastic response spectrum Se(T) of EN 1998-1 §3.2.2.2, Eqs. (3.2)–(3.5).

    Give exactly one of ``design_acceleration`` (a_g) and ``surface_pga`` (a_g·S = Se(0)).

    Parameters
    ----------
    periods
        vibration periods, 0 <= T <= 4 s [s].
    spectrum_type
        1 or 2 [-].
    ground_type
        "A" to "E" [-].
    design_acceleration
        a_g, design ground acceleration on type A ground (a_g = γ_I·a_gR) [m/s²].
    surface_pga
        peak ground acceleration at the surface of the site, a_g·S [m/s²].
    damping
        viscous damping ratio ξ (0.05 for 5%) [-].
    extrapolate
        continue Eq. (3.5) beyond 4 s instead of refusing such periods. EN 1998-1 has no basis
        for it (Annex A takes over); it only gives spectral matching a margin past the band.

    Returns
    -------
    numpy.ndarray
        Se(T), same shape as ``periods`` [m/s²].
    """
    periods = np.asarray(periods, dtype=float)
    beyond = False if extrapolate else np.any(periods > MAX_PERIOD)
    if np.any(~np.isfinite(periods)) or np.any(periods < 0.0) or beyond:
        raise ValueError(
            f"EN 1998-1 Eqs. (3.2)-(3.5) hold for 0 <= T <= {MAX_PERIOD:g} s (beyond, Annex A); "
            f"got periods in [{periods.min():g}, {periods.max():g}] s"
        )
    shape = get_spectrum_shape(spectrum_type, ground_type)
    ag = _resolve_design_acceleration(design_acceleration, surface_pga, shape.soil_factor)
    eta = compute_damping_correction(damping)
    plateau = ag * shape.soil_factor * eta * 2.5
    tb, tc, td = shape.corner_b, shape.corner_c, shape.corner_d
    rising = ag * shape.soil_factor * (1.0 + periods / tb * (eta * 2.5 - 1.0))
    safe = np.maximum(periods, tb)  # avoids 1/0 in the branches that np.select discards
    return np.select(
        [periods <= tb, periods <= tc, periods <= td],
        [rising, np.full_like(periods, plateau), plateau * tc / safe],
        default=plateau * tc * td / safe**2,
    )


VERTICAL_SHAPES = {1: (0.90, 0.05, 0.15, 1.0), 2: (0.45, 0.05, 0.15, 1.0)}
"""EN 1998-1 Table 3.4, the vertical elastic spectrum by spectrum type: a_vg/a_g and the corner
periods T_B, T_C, T_D [s] (the same for every ground type: no soil factor)."""


def compute_vertical_spectrum(
    periods: np.ndarray | float,
    spectrum_type: int,
    design_acceleration: float,
    damping: float = 0.05,
    extrapolate: bool = False,
) -> np.ndarray:
    """Vertical elastic response spectrum Sve(T) of EN 1998-1 §3.2.2.3, Eqs. (3.8)–(3.11).

    Parameters
    ----------
    periods
        vibration periods, 0 <= T <= 4 s [s].
    spectrum_type
        1 or 2 (Table 3.4) [-].
    design_acceleration
        a_g, the horizontal design ground acceleration on type A ground [m/s²]; the vertical
        one is a_vg = 0.90·a_g (type 1) or 0.45·a_g (type 2).
    damping
        viscous damping ratio ξ [-].
    extrapolate
        continue Eq. (3.11) beyond 4 s, as `compute_elastic_spectrum` does (a margin for
        spectral matching, not a rule of EN 1998-1).

    Returns
    -------
    numpy.ndarray
        Sve(T), the shape of ``periods`` [m/s²]; Sve(0) = a_vg, the vertical PGA.
    """
    periods = np.asarray(periods, dtype=float)
    beyond = False if extrapolate else np.any(periods > MAX_PERIOD)
    if np.any(~np.isfinite(periods)) or np.any(periods < 0.0) or beyond:
        raise ValueError(f"EN 1998-1 Eqs. (3.8)-(3.11) hold for 0 <= T <= {MAX_PERIOD:g} s")
    if spectrum_type not in VERTICAL_SHAPES:
        raise ValueError(f"spectrum type must be 1 or 2, got {spectrum_type!r}")
    ratio, tb, tc, td = VERTICAL_SHAPES[spectrum_type]
    avg, eta = ratio * design_acceleration, compute_damping_correction(damping)
    plateau = avg * eta * 3.0
    safe = np.maximum(periods, tb)
    return np.select(
        [periods <= tb, periods <= tc, periods <= td],
        [avg * (1.0 + periods / tb * (eta * 3.0 - 1.0)), np.full_like(periods, plateau),
         plateau * tc / safe],
        default=plateau * tc * td / safe**2,
    )  # fmt: skip


def _resolve_design_acceleration(
    design_acceleration: float | None, surface_pga: float | None, soil_factor: float
) -> float:
    """a_g from either a_g itself or the surface PGA, since Se(0) = a_g·S (Eq. 3.2 at T = 0)."""
    if (design_acceleration is None) == (surface_pga is None):
        raise ValueError("give exactly one of design_acceleration (a_g) and surface_pga (a_g*S)")
    ag = surface_pga / soil_factor if surface_pga is not None else design_acceleration
    assert ag is not None
    if not ag > 0.0:
        raise ValueError(f"the ground acceleration must be positive, got {ag!r}")
    return float(ag)


@dataclass(frozen=True)
class ComplianceReport:
    """Check of a suite of artificial records against EN 1998-1 §3.2.3.1.2(4).

    Attributes
    ----------
    count
        number of records in the suite [-].
    count_ok
        at least three records, §3.2.3.1.2(4)a.
    mean_zero_period
        mean over the records of the zero-period spectral acceleration (the PGA) [m/s²].
    surface_pga
        a_g·S, the target zero-period value [m/s²].
    zero_period_ok
        mean zero-period value >= a_g·S, §3.2.3.1.2(4)b.
    record_min_ratio, record_max_ratio
        per record, min and max over the band of computed / target spectrum [-].
    mean_min_ratio, mean_max_ratio
        min and max over the band of mean spectrum / target [-].
    mean_ok
        no value of the mean spectrum below 90% of the target over the band, §3.2.3.1.2(4)c.
    stationary_duration
        duration of the stationary part of the records [s], or None when unknown.
    stationary_ok
        stationary part at least 10 s, §3.2.3.1.2(3); None when unknown.
    tolerance
        accepted deviation of each record's spectrum from the target over the band, a criterion
        of the record set's config rather than of EN 1998-1 [-]; None when not stated.
    """

    count: int
    count_ok: bool
    mean_zero_period: float
    surface_pga: float
    zero_period_ok: bool
    record_min_ratio: tuple[float, ...]
    record_max_ratio: tuple[float, ...]
    mean_min_ratio: float
    mean_max_ratio: float
    mean_ok: bool
    stationary_duration: float | None
    stationary_ok: bool | None
    tolerance: float | None = None

    @property
    def record_misses(self) -> tuple[float, ...]:
        """Per record, by how much its spectrum leaves the band 1 ± `tolerance` of the target
        (0 inside it, or when no tolerance is stated) [-]."""
        if self.tolerance is None:
            return tuple(0.0 for _ in self.record_min_ratio)
        return tuple(
            max(0.0, 1.0 - self.tolerance - low, high - 1.0 - self.tolerance)
            for low, high in zip(self.record_min_ratio, self.record_max_ratio, strict=True)
        )

    @property
    def records_ok(self) -> bool | None:
        """Every record within its `tolerance` of the target; None when no tolerance is stated."""
        return None if self.tolerance is None else not any(self.record_misses)

    @property
    def compliant(self) -> bool:
        """All the rules of §3.2.3.1.2(3)–(4), and the per-record tolerance, that could be
        checked hold."""
        return (
            self.count_ok
            and self.zero_period_ok
            and self.mean_ok
            and self.stationary_ok is not False
            and self.records_ok is not False
        )


#: Relative slack on the zero-period rule, for PGAs scaled exactly to a_g·S then written to text.
ZERO_PERIOD_SLACK = 1e-6


def check_compliance(
    spectra: np.ndarray,
    target: np.ndarray,
    peak_accelerations: np.ndarray,
    surface_pga: float,
    stationary_duration: float | None = None,
    tolerance: float | None = None,
) -> ComplianceReport:
    """Check a suite of records against EN 1998-1 §3.2.3.1.2(3) and (4)a–c, and each record
    against a stated tolerance.

    Parameters
    ----------
    spectra
        5%-damped spectral accelerations, one row per record, one column per period of the
        checked band (EN 1998-1 checks 0.2·T1 to 2·T1) [m/s²].
    target
        the elastic spectrum Se at the same periods [m/s²].
    peak_accelerations
        zero-period spectral acceleration (PGA) of each record [m/s²].
    surface_pga
        a_g·S of the site [m/s²].
    stationary_duration
        duration of the records' stationary part, if known [s].
    tolerance
        accepted deviation of each record's spectrum from the target, if stated [-].
    """
    spectra = np.atleast_2d(np.asarray(spectra, dtype=float))
    target = np.asarray(target, dtype=float)
    peaks = np.asarray(peak_accelerations, dtype=float)
    if spectra.shape[1] != target.size or spectra.shape[0] != peaks.size:
        raise ValueError(
            f"shapes do not agree: spectra {spectra.shape}, target {target.shape}, "
            f"peaks {peaks.shape}"
        )
    ratios = spectra / target
    mean_ratio = spectra.mean(axis=0) / target
    mean_zero_period = float(peaks.mean())
    return ComplianceReport(
        count=int(peaks.size),
        count_ok=bool(peaks.size >= 3),
        mean_zero_period=mean_zero_period,
        surface_pga=float(surface_pga),
        zero_period_ok=bool(mean_zero_period >= surface_pga * (1.0 - ZERO_PERIOD_SLACK)),
        record_min_ratio=tuple(float(x) for x in ratios.min(axis=1)),
        record_max_ratio=tuple(float(x) for x in ratios.max(axis=1)),
        mean_min_ratio=float(mean_ratio.min()),
        mean_max_ratio=float(mean_ratio.max()),
        mean_ok=bool(mean_ratio.min() >= 0.9),
        stationary_duration=stationary_duration,
        stationary_ok=None if stationary_duration is None else bool(stationary_duration >= 10.0),
        tolerance=tolerance,
    )

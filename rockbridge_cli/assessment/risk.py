"""Risk at a site: the mean annual frequency of each limit state, from a bridge's lognormal
fragility and the site's hazard curve (`assessment.hazard`).

The frequency is the total probability over the intensity (Cornell et al. 2002):

    λ_LS = ∫ P(LS | im) |dλ_IM(im)|,

and, integrated by parts, λ_LS = E[λ_IM(C)]: the hazard at the capacity C, averaged over its
lognormal distribution (median θ, log-standard deviation β). On each piece of the curve, a power
law λ_a·(im/im_a)^(−k) over ln im ∈ [y_lo, y_hi] (the curve's points interpolated in log-log
space, its end segments' power laws beyond them), this mean has a closed form:

    λ_a · exp(k·(ln im_a − ln θ) + k²β²/2) · [Φ(z_hi) − Φ(z_lo)],  z = (y − ln θ)/β + kβ,

summed over the pieces with no further approximation: for a single power law λ = k0·im^(−k) it is
Cornell's λ_LS = k0·θ^(−k)·exp(k²β²/2). The share of λ_LS that the two extensions beyond the
curve's range contribute is reported with it (``beyond``): where it is large, the answer rests on
the extrapolation rather than on the curve.

The return period is 1/λ_LS and the probability of at least one occurrence in T years is
1 − exp(−λ_LS·T) (Poisson occurrences). The 90 % interval is the 5 and 95 % percentiles of λ_LS
over the fragility's bootstrap resamplings of the records (`Fragility.draws`, each a (θ, β)): the
draws whose percentiles are the fragility's intervals of θ and β and whose curves span its band
(`fragility_intervals`), so that risk and fragility rest on the same resamplings.

A limit state that no record reaches within the levels run has no fit; its frequency is then at
most the hazard's rate at the highest level run (reported as a bound, ``<``), unless a failure
ended every record's IDA curve before it (unreachable: no frequency, a note); one that every
record reaches at the lowest level is at least the rate there (``>``). A fit whose β the levels do
not resolve is taken as a certain capacity at its median: λ_LS = λ_IM(θ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.special import log_ndtr

from ..errors import InputError
from ..motions.intensity import MEASURES
from ..results.reading import open_results, read_intensity
from ..results.sections import IntensitySection
from .fragility import Fragility, fragilities, unreachable_note
from .hazard import HazardCurve
from .ida import Lattice

YEARS = 50.0
"""Default exposure time of the probability of occurrence: a design working life [years]."""


@dataclass(frozen=True)
class Risk:
    """The annual frequency of one limit state of one bridge at the site of a hazard curve.

    Attributes
    ----------
    bridge, limit_state, measure : what it is of
    rate : λ_LS [1/year]; a bound where ``bound`` says so; None where the data give neither
    bound : ``""`` (the frequency), ``"<"`` (at most ``rate``) or ``">"`` (at least ``rate``)
    rate_90 : 5 % and 95 % bootstrap percentiles of λ_LS [1/year]; None without draws
    beyond : share of λ_LS from the curve's extensions beyond its range [-]; None without a fit
    years : T of ``probability`` [years]
    note : why the state cannot be observed on some records ("" if it can on all;
        `fragility.unreachable_note`)
    """

    bridge: str
    limit_state: str
    measure: str
    rate: float | None
    bound: str
    rate_90: tuple[float, float] | None
    beyond: float | None
    years: float
    note: str = ""

    @property
    def return_period(self) -> float | None:
        """1/λ_LS [years] (a bound reversed: ``<`` on λ is ``>`` on the return period)."""
        return None if self.rate is None else 1.0 / self.rate if self.rate > 0.0 else math.inf

    @property
    def probability(self) -> float | None:
        """1 − exp(−λ_LS·T): at least one occurrence in ``years`` (Poisson) [-]."""
        return None if self.rate is None else poisson_probability(self.rate, self.years)

    @property
    def probability_90(self) -> tuple[float, float] | None:
        """The interval of ``probability`` (the same resamplings)."""
        if self.rate_90 is None:
            return None
        low, high = self.rate_90
        return poisson_probability(low, self.years), poisson_probability(high, self.years)

    def row(self) -> dict[str, object]:
        """As JSON-ready data."""
        return {
            "bridge": self.bridge, "limit_state": self.limit_state, "measure": self.measure,
            "rate": self.rate, "bound": self.bound,
            "rate_90": list(self.rate_90) if self.rate_90 else None,
            "return_period": self.return_period, "years": self.years,
            "probability": self.probability,
            "probability_90": list(self.probability_90) if self.probability_90 else None,
            "beyond": self.beyond, "note": self.note,
        }  # fmt: skip


def poisson_probability(rate: float, years: float) -> float:
    """1 − exp(−λ·T): the probability of at least one of Poisson occurrences at the annual rate
    λ [1/year] in T years [-]."""
    return -math.expm1(-rate * years)


def limit_state_rate(
    curve: HazardCurve, median: np.ndarray | float, beta: np.ndarray | float
) -> tuple[np.ndarray, np.ndarray]:
    """λ_LS of lognormal fragilities (the module's docstring gives the closed form).

    Parameters
    ----------
    curve
        The hazard curve, in the unit of ``median``.
    median, beta
        θ [the curve's unit] and β [-] (> 0) of each fragility; arrays broadcast.

    Returns
    -------
    The frequencies λ_LS [1/year], and the share of each from beyond the curve's range [-].
    """
    lows, highs, anchors, log_rates, slopes = curve.pieces()
    log_median = np.log(np.asarray(median, dtype=float))[..., None]
    beta = np.asarray(beta, dtype=float)[..., None]
    log_terms = (
        log_rates + slopes * (anchors - log_median) + 0.5 * (slopes * beta) ** 2
        + _log_normal_mass((lows - log_median) / beta + slopes * beta,
                           (highs - log_median) / beta + slopes * beta)
    )  # fmt: skip
    terms = np.exp(log_terms)
    rate = terms.sum(axis=-1)
    return rate, (terms[..., 0] + terms[..., -1]) / rate


def _log_normal_mass(low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """ln(Φ(high) − Φ(low)) for low ≤ high, accurate in both tails."""
    upper = low > 0.0  # in the upper tail, Φ(h) − Φ(l) = Φ(−l) − Φ(−h)
    first = np.where(upper, -low, high)
    second = np.where(upper, -high, low)
    big, small = log_ndtr(first), log_ndtr(second)
    with np.errstate(divide="ignore"):
        return big + np.log1p(-np.exp(small - big))


def risks(results: str | Path, curve: HazardCurve, years: float = YEARS) -> list[Risk]:
    """The annual frequency of every bridge's limit states at the site of a hazard curve
    (`hazard.read_hazard_curve`), from a results file with an intensity section.

    Raises
    ------
    InputError
        The study has no intensity section, or the curve is of another intensity measure than
        the fragilities.
    TypeError
        ``curve`` is not a `hazard.HazardCurve` (a file's path: `read_hazard_curve` it).
    """
    if not isinstance(curve, HazardCurve):
        raise TypeError(f"risks takes a HazardCurve (hazard.read_hazard_curve(path)), not "
                        f"{type(curve).__name__}")  # fmt: skip
    found = fragilities(results)  # refuses a study without an intensity section
    with open_results(results) as file:
        intensity = read_intensity(file)
    assert intensity is not None
    return risks_of(found, intensity, curve, years)


def risks_of(
    found: list[Fragility], intensity: IntensitySection, curve: HazardCurve, years: float = YEARS
) -> list[Risk]:
    """`risks` of fragilities already fitted, with the study's intensity section."""
    if not 0.0 < years < math.inf:  # inf made every probability 1 without a word
        reason = f"must be a positive number of years (finite), not {years}"
        raise InputError("years", [("", reason)])
    matched: dict[str, HazardCurve] = {}
    result = []
    for item in found:
        if item.measure not in matched:
            period = intensity.period if item.measure == intensity.measure else None
            unit = MEASURES[item.measure].unit
            matched[item.measure] = curve.matched(item.measure, unit, period)
        result.append(_risk(item, intensity, matched[item.measure], years))
    return result


def _risk(item: Fragility, intensity: IntensitySection, curve: HazardCurve, years: float) -> Risk:
    def made(rate: float | None, bound: str = "", interval=None, beyond=None) -> Risk:
        return Risk(item.bridge, item.limit_state, item.measure, rate, bound, interval, beyond,
                    years, unreachable_note(item))  # fmt: skip

    if item.median is None:
        return made(*_bound(item, intensity, curve))
    if item.beta is None:
        return made(float(curve.rate(item.median)))
    rate, beyond = limit_state_rate(curve, item.median, item.beta)
    interval = None
    if item.draws:
        medians, betas = np.array(item.draws).T
        low, high = np.percentile(limit_state_rate(curve, medians, betas)[0], [5.0, 95.0])
        interval = (float(low), float(high))
    return made(float(rate), "", interval, float(beyond))


def _bound(
    item: Fragility, intensity: IntensitySection, curve: HazardCurve
) -> tuple[float | None, str]:
    """The bound on λ_LS of a limit state without a fit: ``<`` λ_IM(level) where no record
    reaches it, at the highest level run or, where a failure ended a record's curve first, the
    lowest level such a curve ended at; none where that is every record's; ``>`` λ_IM(lowest
    level) where every record reaches it at the lowest."""
    if item.measure != intensity.measure or not item.capacities:
        return None, ""
    lowest, highest = levels_range(intensity)
    capacities = list(item.capacities.values())
    if all(capacity is None for capacity in capacities):
        if len(item.unreachable) == len(capacities):
            return None, ""  # a failure ends every curve first: nothing bounds it
        ends = [level for _, level in item.unreachable.values()]
        return float(curve.rate(min([highest, *ends]))), "<"
    if all(capacity is not None and capacity <= lowest for capacity in capacities):
        return float(curve.rate(lowest)), ">"
    return None, ""


def levels_range(intensity: IntensitySection) -> tuple[float, float]:
    """The lowest and the highest intensity level a study's intensity section can run: the
    stripes' levels, or an IDA's first and last scan level [the measure's unit]."""
    if intensity.ida is not None:
        lattice = Lattice.of(intensity.ida)
        return lattice.start, lattice.level(lattice.count - 1)
    assert intensity.levels is not None  # a section has one of levels and ida
    return min(intensity.levels), max(intensity.levels)


MOSTLY_BEYOND = 0.5
"""Share of λ from beyond the hazard curve's range above which `extrapolation_warning` warns."""


def extrapolation_warning(found: list[Risk], curve: HazardCurve) -> str:
    """A warning where more than `MOSTLY_BEYOND` of a frequency comes from the curve's
    extensions beyond its points ("" where none does): that λ rests on an extrapolated power law,
    and where all of every λ does, the curve is likely in another unit than its header says."""
    shares = [item.beyond for item in found if item.beyond is not None]
    heavy = [share for share in shares if share > MOSTLY_BEYOND]
    if not heavy:
        return ""
    text = (
        f"{len(heavy)} of {len(shares)} frequencies take more than half of λ (up to "
        f"{100 * max(heavy):.0f} %) from beyond the hazard curve's points "
        f"({curve.intensities[0]:.3g}–{curve.intensities[-1]:.3g} {curve.unit}), where its end "
        "segments' power laws are extrapolated: extend the curve over the fragilities' medians"
    )
    if len(heavy) == len(shares) and min(heavy) > 0.99:  # no median within reach of the curve
        text += f"; all of every λ: is the curve really in {curve.unit}?"
    return text


def risk_table(found: list[Risk], years: float) -> tuple[list[str], list[list[str]]]:
    """Headers and rows of the risk table, as text: λ, its interval, the return period, the
    probability in ``years`` [%] and its interval, the share from beyond the curve [%]."""
    headers = ["bridge", "limit state", "λ [1/yr]", "λ 5–95 %", "return period [yr]",
               f"P in {years:g} yr [%]", "P 5–95 %", "beyond curve [%]"]  # fmt: skip
    rows = []
    for item in found:
        percent = None if item.probability is None else 100.0 * item.probability
        interval = item.probability_90 and tuple(100.0 * p for p in item.probability_90)
        rows.append([
            item.bridge, item.limit_state, _bounded(item.bound, item.rate),
            _interval(item.rate_90), _bounded(_REVERSED[item.bound], item.return_period),
            _bounded(item.bound, percent, _percent), _interval(interval, _percent),
            "-" if item.beyond is None else f"{100 * item.beyond:.1f}",
        ])  # fmt: skip
    return headers, rows


_REVERSED = {"": "", "<": ">", ">": "<"}
"""A bound on λ as a bound on the return period."""


def _number(value: float) -> str:
    """Three significant digits; a large number without an exponent (11800, not 1.18e+04)."""
    if math.isinf(value):
        return "inf"
    return f"{value:.3g}" if abs(value) < 1e3 else f"{float(f'{value:.3g}'):.0f}"


def _percent(value: float) -> str:
    """A probability in percent as `_number` gives it, but never rounded up to a certainty:
    99.95 % and above (short of 100) is "> 99.9"."""
    return "> 99.9" if 99.95 <= value < 100.0 else _number(value)


def _bounded(bound: str, value: float | None, shown=_number) -> str:
    if value is None:
        return "-"
    return f"{bound} {shown(value)}" if bound else shown(value)


def _interval(pair: tuple[float, ...] | None, shown=_number) -> str:
    return "-" if not pair else f"{shown(pair[0])}–{shown(pair[1])}"

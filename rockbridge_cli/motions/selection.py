"""Record selection on arrays: the scale factor of each candidate, the greedy choice of a set under
per-group caps, and the raise that EN 1998-1 §3.2.3.1.2(4)b–c asks of the chosen set.

A candidate's spectrum S_i(T) is scaled by the factor f_i that minimises its own misfit
Σ_T (ln f_i + ln S_i(T) − ln Se(T))² over the periods: in closed form,
ln f_i = mean_T (ln Se − ln S_i), clipped to the bounds of the rules. A set K of scaled log
spectra X_i = ln f_i S_i is scored by the objective of Baker & Lee (2018, Eq. 4) with a target
dispersion of zero,

    J(K) = mean_T [ (m_K(T) − ln Se(T))² + w · s_K²(T) ],

m_K and s_K² the mean and (population) variance over the set of X_i(T), w the weight of the
dispersion; with w = 1, J is the mean over the set of each record's own squared log misfit
(mean of squares = square of the mean + variance). The set is chosen as Baker & Lee (2018) do:
greedily, one record at a time, each the candidate that lowers J most among those the caps admit
(at most so many per earthquake, per recording), then improved by swaps, one position at a time,
until no swap lowers J. Ties go to the earlier candidate: the choice is deterministic.

EN 1998-1 checks the arithmetic mean of the scaled spectra, not its logarithm: once the set is
chosen, all its factors are raised by the one smallest common multiplier (`code_multiplier`)
that brings the mean spectrum to 90 % of Se over the period range (4)c and the mean PGA to a_g·S
(4)b, as `ec8.scale_factors` does for scaled seeds.

References
----------
Baker, J. W. and Lee, C. (2018). An improved algorithm for selecting ground motions to match a
conditional spectrum. Journal of Earthquake Engineering 22(4), 708–723.
CEN (2004). EN 1998-1, §3.2.3.1.2 (4)a–c and §3.2.3.1.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MEAN_RATIO = 0.9
"""EN 1998-1 §3.2.3.1.2(4)c: the mean spectrum stays at or above this share of Se [-]."""

MAX_SWAP_PASSES = 20
"""Most rounds of swaps over every position of the set [-]."""

RAISE_MARGIN = 1e-9
"""A raise is made this much larger than needed, past round-off [-]."""


@dataclass(frozen=True)
class Selection:
    """A chosen set.

    Attributes
    ----------
    indices
        the chosen candidates, in the pool's order [-].
    factors
        their scale factors, each its closed-form least log misfit within the bounds [-].
    objective
        J of the set (module docstring) [-].
    misfit
        mean_T (m_K − ln Se)², the mean log spectrum's squared misfit [-].
    dispersion
        mean_T s_K², the scaled log spectra's variance about their mean [-].
    swaps
        swaps made after the greedy build [-].
    """

    indices: tuple[int, ...]
    factors: tuple[float, ...]
    objective: float
    misfit: float
    dispersion: float
    swaps: int


class PoolTooSmall(ValueError):
    """The caps admit fewer candidates than the set needs; ``rule`` names the cap at fault and
    ``available`` the most records the caps admit."""

    def __init__(self, rule: str, needed: int, available: int):
        self.rule, self.needed, self.available = rule, needed, available
        super().__init__(f"{rule}: the caps admit {available} records, {needed} needed")


def compute_scale_factors(
    log_spectra: np.ndarray, log_target: np.ndarray, bounds: tuple[float, float]
) -> np.ndarray:
    """Each candidate's factor of least log misfit, clipped to the bounds.

    Parameters
    ----------
    log_spectra
        ln S_i(T) of each candidate, shape (candidates, periods) [ln(m/s²)].
    log_target
        ln Se(T) at the same periods [ln(m/s²)].
    bounds
        lowest and highest factor admitted [-].

    Returns
    -------
    numpy.ndarray
        f_i = clip(exp(mean_T(ln Se − ln S_i)), bounds) [-].
    """
    low, high = bounds
    if not 0.0 < low <= high:
        raise ValueError(f"the bounds must satisfy 0 < low <= high, got {bounds!r}")
    logs = np.mean(log_target[None, :] - log_spectra, axis=1)
    return np.exp(np.clip(logs, np.log(low), np.log(high)))


def evaluate_objective(
    scaled: np.ndarray, log_target: np.ndarray, dispersion_weight: float = 0.0
) -> tuple[float, float, float]:
    """J of a set of scaled log spectra, with its two parts.

    Parameters
    ----------
    scaled
        X_i(T) = ln f_i S_i(T), shape (records, periods) [ln(m/s²)].
    log_target
        ln Se(T) [ln(m/s²)].
    dispersion_weight
        w [-].

    Returns
    -------
    tuple of float
        J, mean_T (m − ln Se)², mean_T s² [-].
    """
    mean = scaled.mean(axis=0)
    misfit = float(np.mean((mean - log_target) ** 2))
    dispersion = float(np.mean(scaled.var(axis=0)))
    return misfit + dispersion_weight * dispersion, misfit, dispersion


def select_records(
    log_spectra: np.ndarray,
    log_target: np.ndarray,
    count: int,
    bounds: tuple[float, float],
    groups: list[tuple[np.ndarray, int]],
    dispersion_weight: float = 0.0,
) -> Selection:
    """Choose ``count`` candidates and their factors (module docstring).

    Parameters
    ----------
    log_spectra
        ln S_i(T) of each candidate, unscaled, shape (candidates, periods) [ln(m/s²)].
    log_target
        ln Se(T) [ln(m/s²)].
    count
        records in the set [-].
    bounds
        lowest and highest scale factor [-].
    groups
        (label of each candidate, the most records of one label): an earthquake's, a
        recording's [-].
    dispersion_weight
        w, the weight of the set's dispersion in J [-].

    Returns
    -------
    Selection

    Raises
    ------
    PoolTooSmall
        The caps admit fewer than ``count`` candidates (`most_admitted`).
    """
    log_spectra = np.asarray(log_spectra, dtype=float)
    candidates = log_spectra.shape[0]
    if count < 1:
        raise ValueError(f"count must be at least 1, got {count!r}")
    labels = [np.asarray(label) for label, _ in groups]
    caps = [cap for _, cap in groups]
    for index in range(len(caps)):
        admitted = most_admitted([(labels[i], caps[i]) for i in range(index + 1)], candidates)
        if admitted < count:
            raise PoolTooSmall(f"group {index}", count, admitted)
    factors = compute_scale_factors(log_spectra, log_target, bounds)
    scaled = log_spectra + np.log(factors)[:, None]
    chosen: list[int] = []
    for _ in range(count):
        scores = _scores(scaled, log_target, chosen, labels, caps, dispersion_weight)
        chosen.append(int(np.argmin(scores)))
    swaps = _swap(scaled, log_target, chosen, labels, caps, dispersion_weight)
    chosen.sort()
    objective, misfit, dispersion = evaluate_objective(
        scaled[chosen], log_target, dispersion_weight
    )
    return Selection(tuple(chosen), tuple(float(factors[i]) for i in chosen), objective,
                     misfit, dispersion, swaps)  # fmt: skip


def most_admitted(groups: list[tuple[np.ndarray, int]], candidates: int) -> int:
    """The most candidates a set can hold under caps on nested labels (each label's members
    share the labels of the groups before it: recordings within an earthquake) [-]."""
    if not groups:
        return candidates
    *outer, (label, cap) = groups
    # within each label of the last group, what the outer groups admit, capped
    admitted = {value: min(cap, int(np.count_nonzero(label == value))) for value in set(label)}
    if not outer:
        return sum(admitted.values())
    outer_label, outer_cap = outer[-1]
    per_outer: dict = {}
    for value in sorted(set(label), key=str):
        key = outer_label[np.flatnonzero(label == value)[0]]
        per_outer[key] = per_outer.get(key, 0) + admitted[value]
    return sum(min(outer_cap, n) for n in per_outer.values())


def _scores(scaled, log_target, chosen, labels, caps, weight) -> np.ndarray:
    """J of the set with each candidate added; infinite where the caps or the set exclude it."""
    size = len(chosen) + 1
    total = scaled[chosen].sum(axis=0)
    squares = (scaled[chosen] ** 2).sum(axis=0)
    mean = (total[None, :] + scaled) / size
    variance = np.maximum((squares[None, :] + scaled**2) / size - mean**2, 0.0)
    scores = np.mean((mean - log_target[None, :]) ** 2 + weight * variance, axis=1)
    scores[_excluded(chosen, labels, caps, scaled.shape[0])] = np.inf
    return scores


def _excluded(chosen, labels, caps, candidates) -> np.ndarray:
    """The candidates a set ``chosen`` cannot take: its own, and those whose label is full."""
    out = np.zeros(candidates, dtype=bool)
    out[chosen] = True
    for label, cap in zip(labels, caps, strict=True):
        taken = label[chosen]
        full = [value for value in set(taken.tolist()) if np.count_nonzero(taken == value) >= cap]
        out |= np.isin(label, full)
    return out


def _swap(scaled, log_target, chosen, labels, caps, weight) -> int:
    """Replace one member at a time by the candidate that lowers J most, until none does;
    ``chosen`` is changed in place. Returns the number of swaps [-]."""
    swaps = 0
    best = evaluate_objective(scaled[chosen], log_target, weight)[0]
    for _ in range(MAX_SWAP_PASSES):
        changed = False
        for position in range(len(chosen)):
            rest = chosen[:position] + chosen[position + 1 :]
            scores = _scores(scaled, log_target, rest, labels, caps, weight)
            scores[chosen[position]] = np.inf
            candidate = int(np.argmin(scores))
            if scores[candidate] < best * (1.0 - 1e-12):
                chosen[position], best, changed = candidate, float(scores[candidate]), True
                swaps += 1
        if not changed:
            break
    return swaps


def code_multiplier(
    spectra: np.ndarray,
    target: np.ndarray,
    peaks: np.ndarray,
    surface_pga: float,
    factors: np.ndarray,
    mean_ratio: float = MEAN_RATIO,
) -> float:
    """The smallest common multiplier k >= 1 of a set's factors that meets EN 1998-1
    §3.2.3.1.2(4)b (mean PGA >= a_g·S) and (4)c (mean spectrum >= 0.9·Se over the periods, or
    ``mean_ratio``·Se for a margin above it).

    Parameters
    ----------
    spectra
        the chosen records' unscaled spectra, shape (records, periods) [m/s²].
    target
        Se at the periods [m/s²].
    peaks
        the records' unscaled PGA [m/s²].
    surface_pga
        a_g·S [m/s²].
    factors
        their scale factors before the raise [-].
    mean_ratio
        the share of Se the mean must reach, at least EN 1998-1's `MEAN_RATIO` [-].

    Returns
    -------
    float
        k, a little above the least that meets both (`RAISE_MARGIN`), or 1 [-].
    """
    mean = (factors[:, None] * spectra).mean(axis=0)
    needed = max(float(np.max(mean_ratio * target / mean)),
                 surface_pga / float(np.mean(factors * peaks)))  # fmt: skip
    return needed * (1.0 + RAISE_MARGIN) if needed > 1.0 else 1.0

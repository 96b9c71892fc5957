"""Fragilities of sampled bridges (`config.uncertainty`): the fragility that folds parameter
uncertainty in, beside the record-to-record one and the common shortcut.

For each bridge file of a sampled study with an intensity section, every analysis of every sample
is one draw of (bridge, record): the *folded* fragility is the fit (`assessment.fragility`, by the
same code as one bridge's) over all samples × records, its bootstrap over those pairs. Where each
sample met every record (``pairing: all``), each sample has a fragility of its own: β_RTR is the
root mean square of their β (the record-to-record dispersion), β_U the standard deviation of the
logarithms of their medians (the dispersion the parameters add), and the shortcut of FEMA P-58 and
P695, β_total = √(β_RTR² + β_U²), stands beside the folded β to show how far it holds.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..results.reading import (
    UNFINISHED,
    bridge_samples,
    open_results,
    partial,
    peak_columns,
    read_intensity,
)
from ..results.sections import IntensitySection
from .fragility import Fragility, fragilities_of


@dataclass(frozen=True)
class FoldedFragility:
    """One bridge file's fragility for one limit state over its samples.

    Attributes
    ----------
    folded : the fit over every sample × record (its ``bridge`` is the bridge file's id)
    samples : samples with a fit of their own, of all samples
    beta_rtr, beta_u, beta_shortcut : [-], NaN where the samples did not meet every record or
        fewer than two have a fit
    """

    folded: Fragility
    samples: tuple[int, int]
    beta_rtr: float
    beta_u: float
    beta_shortcut: float

    def row(self) -> dict[str, object]:
        """As JSON-ready data."""
        item = self.folded
        return {
            "bridge": item.bridge, "limit_state": item.limit_state, "measure": item.measure,
            "median": item.median, "beta": item.beta,
            "median_90": list(item.median_90) if item.median_90 else None,
            "samples_fitted": self.samples[0], "samples": self.samples[1],
            "beta_rtr": self.beta_rtr, "beta_u": self.beta_u,
            "beta_shortcut": self.beta_shortcut,
        }  # fmt: skip


def folded_fragilities(path: str | Path, seed: int = 0) -> list[FoldedFragility]:
    """The folded fragility of each bridge file and limit state of a sampled study.

    Raises
    ------
    InputError
        The study sampled no bridges, has no intensity section, or the file holds part of it
        (a shard, a stopped run).
    """
    with open_results(path) as file:
        intensity = read_intensity(file)
        config = json.loads(file.attrs["config"])
        samples = bridge_samples(file)
        columns = peak_columns(file)
        part = partial(file)
    if (config.get("uncertainty") or {}).get("design") == "tornado":
        why = ("a tornado's bridges are chosen percentiles, not draws from the distributions: "
               "fold a study with an lhs, sobol, random or saltelli design")  # fmt: skip
        raise InputError(path, [("", why)])
    if intensity is None or not samples:
        raise InputError(path, [("", "not a sampled study with an intensity section (uncertainty "
                                 "and intensity): no fragility to fold")])  # fmt: skip
    if part or set(samples) - set(columns["bridge"].astype(str)):
        why = "holds part of a sampled study, and a folded fragility needs all its analyses"
        raise InputError(path, [("", f"{why}: {UNFINISHED}")])
    paired_all = config["uncertainty"].get("pairing", "all") == "all"
    return fold(columns, intensity, list(samples), paired_all, seed)


def fold(
    columns: dict[str, np.ndarray],
    intensity: IntensitySection,
    samples: list[str],
    paired_all: bool,
    seed: int = 0,
) -> list[FoldedFragility]:
    """`folded_fragilities` of a peak table's columns.

    Parameters
    ----------
    intensity
        The study's intensity section.
    samples
        The sampled bridges' ids, ``<bridge file>+<label>``.
    paired_all
        Whether each sample met every record (then each has a fragility of its own).
    """
    own = {(f.bridge, f.limit_state): f for f in fragilities_of(columns, intensity, 0, seed)}
    sampled = np.isin(columns["bridge"], samples)
    columns = {name: values[sampled] for name, values in columns.items()}
    bridges = columns["bridge"].astype(str)
    pooled = {
        **columns,
        "bridge": np.array([name.rsplit("+", 1)[0] for name in bridges], dtype=object),
        "record": np.char.add(np.char.add(bridges, "|"), columns["record"].astype(str)),
        "base_record": np.char.add(np.char.add(bridges, "|"), columns["base_record"].astype(str)),
    }
    found = []
    for item in fragilities_of(pooled, intensity, seed=seed):
        mine = [own[(name, item.limit_state)] for name in samples
                if name.rsplit("+", 1)[0] == item.bridge]  # fmt: skip
        fitted = [(f.median, f.beta) for f in mine if f.median is not None and f.beta is not None]
        beta_rtr = beta_u = math.nan
        if paired_all and len(fitted) > 1:
            beta_rtr = math.sqrt(np.mean([beta**2 for _, beta in fitted]))
            beta_u = float(np.std([math.log(median) for median, _ in fitted], ddof=1))
        found.append(FoldedFragility(item, (len(fitted), len(mine)), beta_rtr, beta_u,
                                     math.hypot(beta_rtr, beta_u)))  # fmt: skip
    return found

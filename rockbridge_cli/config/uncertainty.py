"""Sampled bridges: a study's uncertain bridge fields, their distributions, and the design that
draws them (`config.study`'s ``uncertainty`` section).

A field is named by its dotted path in the bridge config, as a sweep names it (`config.sweep`):
``abutments.gap``, ``abutments.pounding.restitution``, ``rocking_restitution``. Each gets a
distribution; optional rank correlations between fields are imposed through a Gaussian copula
(Iman & Conover's aim, by the normal-scores route: a Spearman ρ_s becomes the Pearson correlation
2 sin(π ρ_s / 6) of the normal scores). A design draws points in the unit hypercube:

- ``lhs``: a Latin hypercube (McKay, Beckman & Conover 1979);
- ``sobol``: a scrambled Sobol' sequence (Owen scrambling; ``size`` a power of two);
- ``random``: independent uniform draws;
- ``saltelli``: the matrices A, B and A_B^(i) of Saltelli et al. (2010), n·(d + 2) samples from a
  scrambled Sobol' sequence in 2d dimensions, for first- and total-order Sobol' indices
  (`assessment.sensitivity`);
- ``tornado``: a one-at-a-time screening, 2d + 1 bridges: every field at its median, then each
  field at a low and a high percentile with the others at their medians.

Each point's coordinates go through the inverse distribution function of their field. The same
seed gives the same samples bit for bit wherever the study runs: they are drawn once, when the
study is loaded, never in a worker.
"""

from __future__ import annotations

import inspect
import math
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Discriminator, Field, NonNegativeInt, PositiveInt, Tag, model_validator

from .bridge import BridgeConfig
from .loading import StrictModel
from .sweep import varied

MAX_SAMPLES = 100_000
"""Most sampled bridges a study makes of each bridge file (each is a bridge config in memory)."""

UNIT_MARGIN = 2.0**-53
"""Unit coordinates are kept in [margin, 1 − margin]: a scrambled Sobol' point may be exactly 0,
where an unbounded distribution's inverse is infinite (the margin is 8.2 standard deviations)."""


class Uniform(StrictModel):
    """Uniform between ``low`` and ``high``."""

    distribution: Literal["uniform"]
    low: float = Field(description="Lower bound [the field's unit]")
    high: float = Field(description="Upper bound [the field's unit]")

    @model_validator(mode="after")
    def _ordered(self) -> Uniform:
        if not self.low < self.high:
            raise ValueError(f"low ({self.low:g}) must be below high ({self.high:g})")
        return self

    def quantile(self, unit: np.ndarray) -> np.ndarray:
        """The values at probabilities ``unit`` [the field's unit]."""
        return self.low + (self.high - self.low) * unit


class Normal(StrictModel):
    """Normal with ``mean`` and standard deviation ``std``."""

    distribution: Literal["normal"]
    mean: float = Field(description="Mean [the field's unit]")
    std: float = Field(gt=0.0, description="Standard deviation [the field's unit]")

    def quantile(self, unit: np.ndarray) -> np.ndarray:
        """The values at probabilities ``unit`` [the field's unit]."""
        from scipy import stats  # here: the parent of a study without samples never loads it

        return self.mean + self.std * stats.norm.ppf(unit)


class Lognormal(StrictModel):
    """Lognormal, by its ``median`` and logarithmic standard deviation ``beta``, or by its
    ``mean`` and coefficient of variation ``cov`` (β² = ln(1 + cov²), median = mean/√(1 + cov²))."""

    distribution: Literal["lognormal"]
    median: float | None = Field(None, gt=0.0, description="Median [the field's unit]")
    beta: float | None = Field(None, gt=0.0, description="Standard deviation of ln [-]")
    mean: float | None = Field(None, gt=0.0, description="Mean [the field's unit]")
    cov: float | None = Field(None, gt=0.0, description="Coefficient of variation [-]")

    @model_validator(mode="after")
    def _one_pair(self) -> Lognormal:
        pairs = (self.median is not None and self.beta is not None) + (
            self.mean is not None and self.cov is not None
        )
        given = sum(v is not None for v in (self.median, self.beta, self.mean, self.cov))
        if pairs != 1 or given != 2:
            raise ValueError("give median and beta, or mean and cov")
        return self

    def parameters(self) -> tuple[float, float]:
        """(median [the field's unit], β [-])."""
        if self.median is not None and self.beta is not None:
            return self.median, self.beta
        assert self.mean is not None and self.cov is not None
        spread = 1.0 + self.cov**2
        return self.mean / math.sqrt(spread), math.sqrt(math.log(spread))

    def quantile(self, unit: np.ndarray) -> np.ndarray:
        """The values at probabilities ``unit`` [the field's unit]."""
        from scipy import stats

        median, beta = self.parameters()
        return median * np.exp(beta * stats.norm.ppf(unit))


class TruncatedNormal(StrictModel):
    """A normal of ``mean`` and ``std`` cut to [``low``, ``high``] (either may be absent)."""

    distribution: Literal["truncated-normal"]
    mean: float = Field(description="Mean of the untruncated normal [the field's unit]")
    std: float = Field(gt=0.0, description="Its standard deviation [the field's unit]")
    low: float | None = Field(None, description="Lower bound [the field's unit]")
    high: float | None = Field(None, description="Upper bound [the field's unit]")

    @model_validator(mode="after")
    def _bounded(self) -> TruncatedNormal:
        if self.low is None and self.high is None:
            raise ValueError("give low, high or both (without either, use normal)")
        low, high = self._standard_bounds()
        if not low < high:
            raise ValueError("low must be below high")
        if _normal_cdf(high) - _normal_cdf(low) < 1e-9:
            raise ValueError("the bounds hold less than 1e-9 of the normal: move them or the mean")
        return self

    def _standard_bounds(self) -> tuple[float, float]:
        low = -np.inf if self.low is None else (self.low - self.mean) / self.std
        high = np.inf if self.high is None else (self.high - self.mean) / self.std
        return low, high

    def quantile(self, unit: np.ndarray) -> np.ndarray:
        """The values at probabilities ``unit`` [the field's unit], within the bounds."""
        from scipy import stats

        low, high = self._standard_bounds()
        values = self.mean + self.std * stats.truncnorm.ppf(unit, low, high)
        return np.clip(values, self.low, self.high)  # round-off at the bounds


class Choice(StrictModel):
    """One of ``values``, with ``weights`` (default: equally likely)."""

    distribution: Literal["choice"]
    values: list[float] = Field(min_length=2, description="The values [the field's unit]")
    weights: list[float] | None = Field(None, description="Their relative weights [-]")

    @model_validator(mode="after")
    def _weights(self) -> Choice:
        if len(set(self.values)) != len(self.values):
            raise ValueError("a value is listed twice")
        if self.weights is not None:
            if len(self.weights) != len(self.values):
                raise ValueError(
                    f"{len(self.weights)} weights for {len(self.values)} values: give one each"
                )
            if min(self.weights) < 0.0 or sum(self.weights) <= 0.0:
                raise ValueError("weights must be non-negative and not all zero")
        return self

    def quantile(self, unit: np.ndarray) -> np.ndarray:
        """The values at probabilities ``unit``: value k where the cumulative weight first
        exceeds the probability."""
        weights = np.ones(len(self.values)) if self.weights is None else np.array(self.weights)
        cumulative = np.cumsum(weights) / weights.sum()
        index = np.minimum(np.searchsorted(cumulative, unit, side="right"), len(self.values) - 1)
        return np.asarray(self.values, dtype=float)[index]


def _named(value: Any) -> str | None:
    """The ``distribution`` of a field's mapping (or of its model, when written), or None."""
    return (
        value.get("distribution")
        if isinstance(value, dict)
        else getattr(value, "distribution", None)
    )


Distribution = Annotated[
    Annotated[Uniform, Tag("uniform")] | Annotated[Normal, Tag("normal")]
    | Annotated[Lognormal, Tag("lognormal")]
    | Annotated[TruncatedNormal, Tag("truncated-normal")] | Annotated[Choice, Tag("choice")],
    Discriminator(
        _named, custom_error_type="distribution",
        custom_error_message="expected a mapping whose distribution is uniform, normal, "
        "lognormal, truncated-normal or choice",
    ),
]  # fmt: skip
"""A sampled field's distribution, by its ``distribution`` key."""

DESIGNS = ("lhs", "sobol", "random", "saltelli", "tornado")


class Uncertainty(StrictModel):
    """Bridge fields drawn from distributions (`config.study`'s ``uncertainty`` section)."""

    fields: dict[str, Distribution] = Field(
        min_length=1, description="Dotted path of a bridge field → its distribution"
    )
    design: Literal["lhs", "sobol", "random", "saltelli", "tornado"] = Field(
        "lhs", description="How the samples are drawn: lhs, sobol, random, saltelli or tornado"
    )
    size: PositiveInt | None = Field(
        None,
        description="Samples of each bridge (saltelli: the base sample n, giving n·(d + 2); "
        "tornado: none, it makes 2d + 1) [-]",
    )
    percentiles: tuple[float, float] = Field(
        (10.0, 90.0), description="A tornado's low and high percentile of each field [%]"
    )
    seed: NonNegativeInt = Field(0, description="Seed of the design [-]")
    pairing: Literal["all", "one"] = Field(
        "all",
        description="all: every sample with every record; one: each sample with one record "
        "(accelerogram-wise, records assigned in a balanced random order)",
    )
    correlations: list[tuple[str, str, float]] = Field(
        default_factory=list,
        description="Spearman rank correlations, each a list of two dotted field paths and ρ_s [-]",
    )

    @model_validator(mode="after")
    def _consistent(self) -> Uncertainty:
        if self.design == "tornado":
            return self._tornado()
        if self.size is None:
            raise ValueError(f"size: give the number of samples of a {self.design} design")
        if self.design in ("sobol", "saltelli") and self.size & (self.size - 1):
            below = 2 ** int(math.log2(self.size))
            raise ValueError(
                f"size: a {self.design} design needs a power of two (Sobol' points balance only "
                f"then): {below} or {2 * below}, not {self.size}"
            )
        if self.design == "saltelli" and (self.correlations or self.pairing == "one"):
            raise ValueError(
                "a saltelli design samples independent fields with every record: Sobol' indices "
                "assume independent inputs (no correlations) and pair every sample with every "
                "record (pairing: all)"
            )
        if self.count > MAX_SAMPLES:
            raise ValueError(f"{self.count:,} samples of each bridge, more than {MAX_SAMPLES:,}")
        _correlation_matrix(list(self.fields), self.correlations)  # raises if invalid
        return self

    def _tornado(self) -> Uncertainty:
        if self.size is not None or self.correlations or self.pairing == "one":
            raise ValueError(
                "a tornado swings one field at a time from the median bridge (2d + 1 bridges, "
                "each with every record): leave out size, correlations and pairing"
            )
        low, high = self.percentiles
        if not 0.0 < low < high < 100.0:
            raise ValueError(f"percentiles: need 0 < low < high < 100, got {low:g}, {high:g}")
        return self

    @property
    def count(self) -> int:
        """Samples of each bridge: ``size``, n·(d + 2) for a saltelli design, 2d + 1 for a
        tornado."""
        d = len(self.fields)
        if self.design == "tornado":
            return 2 * d + 1
        assert self.size is not None
        return self.size * (d + 2) if self.design == "saltelli" else self.size

    def samples(self) -> list[Sample]:
        """Every sample of the design, in the order of the results."""
        fields = list(self.fields)
        d = len(fields)
        if self.design == "tornado":
            return self._swings(fields)
        assert self.size is not None
        if self.design == "saltelli":
            points = _unit_points("sobol", 2 * d, self.size, self.seed)
            a, b = points[:, :d], points[:, d:]
            blocks = [("A", "A", a, ""), ("B", "B", b, "")]
            for i, name in enumerate(fields):
                mixed = a.copy()
                mixed[:, i] = b[:, i]
                blocks.append((f"AB{i + 1}.", "AB", mixed, name))
        else:
            points = _unit_points(self.design, d, self.size, self.seed)
            correlation = _correlation_matrix(fields, self.correlations)
            if correlation is not None:
                points = _copula(points, correlation)
            blocks = [("s", "", points, "")]
        width = len(str(self.size - 1))
        found = []
        for label, matrix, unit, column in blocks:
            values = self._values(np.clip(unit, UNIT_MARGIN, 1.0 - UNIT_MARGIN))
            for k in range(self.size):
                drawn = {f: float(values[j][k]) for j, f in enumerate(fields)}
                found.append(Sample(f"{label}{k:0{width}d}", drawn, matrix, k, column))
        return found

    def _swings(self, fields: list[str]) -> list[Sample]:
        """A tornado's bridges: every field at its median (``mid``), then each field i at its
        low and high percentile with the others at their medians (``low<i>``, ``high<i>``)."""
        middle = np.full((1, len(fields)), 0.5)
        found = [Sample("mid", self._drawn(fields, middle), "mid", 0, "")]
        for i, name in enumerate(fields):
            for matrix, percentile in zip(("low", "high"), self.percentiles, strict=True):
                point = middle.copy()
                point[0, i] = percentile / 100.0
                found.append(
                    Sample(f"{matrix}{i + 1}", self._drawn(fields, point), matrix, 0, name)
                )
        return found

    def _drawn(self, fields: list[str], unit: np.ndarray) -> dict[str, float]:
        values = self._values(unit)
        return {f: float(values[j][0]) for j, f in enumerate(fields)}

    def record_order(self, records: int) -> np.ndarray:
        """For ``pairing: one``, the record of each sample (indices into ``records``): every
        record ⌊n/R⌋ or ⌈n/R⌉ times, in a random order drawn from the seed."""
        assert self.size is not None
        order = np.resize(np.arange(records), self.size)
        return np.random.default_rng([self.seed, 1]).permutation(order)

    def _values(self, unit: np.ndarray) -> list[np.ndarray]:
        return [dist.quantile(unit[:, j]) for j, dist in enumerate(self.fields.values())]

    def described(self) -> dict[str, Any]:
        """The section as stored with the results: every field's distribution in full (a
        tornado's percentiles only in a tornado)."""
        unused = {"percentiles"} if self.design != "tornado" else set()
        return self.model_dump(mode="json", exclude_none=True, exclude=unused)


@dataclass(frozen=True)
class Sample:
    """One sampled bridge's draw.

    Attributes
    ----------
    label : its suffix in the bridge id (``s07``; ``A07``, ``B07``, ``AB2.07`` in a saltelli design)
    values : the sampled value of every field (path → value [the field's unit])
    matrix : ``A``, ``B`` or ``AB`` in a saltelli design, else empty
    index : its row in the design (0-based)
    field : in A_B^(i), the field i whose column comes from B; else empty
    """

    label: str
    values: dict[str, float]
    matrix: str
    index: int
    field: str

    def described(self) -> dict[str, Any]:
        """What the results keep of the draw (besides its values)."""
        found: dict[str, Any] = {"index": self.index}
        if self.matrix:
            found["matrix"] = self.matrix
        if self.field:
            found["field"] = self.field
        return found


def sampled_configs(
    config: BridgeConfig, uncertainty: Uncertainty
) -> list[tuple[Sample, BridgeConfig]]:
    """The bridge ``config`` in every sample of the design, each validated like a bridge file.

    Raises
    ------
    ValueError
        A sample makes an invalid bridge: the message names the sample, every sampled field with
        its value and distribution, and the bridge's objection.
    """
    found = []
    for sample in uncertainty.samples():
        try:
            found.append((sample, varied(config, sample.values)))
        except ValueError as exc:
            drawn = ", ".join(
                f"{path} = {value:.6g} from {_phrase(uncertainty.fields[path])}"
                for path, value in sample.values.items()
            )  # fmt: skip
            raise ValueError(
                f"sample {sample.label}: {drawn} {exc}; bound the distribution (truncated-normal, "
                "uniform, choice) so that every draw is a bridge"
            ) from None
    return found


def record_pairs(
    bridges: int, bases: list[str], uncertainty: Uncertainty
) -> tuple[tuple[int, int], ...]:
    """For ``pairing: one``, the (bridge, record) index pairs of the study, in its order.

    Parameters
    ----------
    bridges
        The study's sampled bridges, every bridge file's `Uncertainty.size` in a row.
    bases
        Each of the study's records, the id of the record as read it is a copy of (itself when
        unscaled).

    Each sample meets one record as read (`Uncertainty.record_order`), at every intensity level
    it is scaled to; every bridge file's samples meet the same records.
    """
    distinct = list(dict.fromkeys(bases))
    copies: dict[str, list[int]] = {base: [] for base in distinct}
    for index, base in enumerate(bases):
        copies[base].append(index)
    order = uncertainty.record_order(len(distinct))
    return tuple((b, r) for b in range(bridges) for r in copies[distinct[order[b % len(order)]]])


def _phrase(distribution: StrictModel) -> str:
    """A distribution in one phrase: ``lognormal median=0.12 beta=0.3``."""
    spec = distribution.model_dump(exclude_none=True)
    name = spec.pop("distribution")
    return " ".join([name, *(f"{key}={value:g}" if isinstance(value, float) else
                             f"{key}={value}" for key, value in spec.items())])  # fmt: skip


def _unit_points(design: str, d: int, n: int, seed: int) -> np.ndarray:
    """n points of ``design`` in [0, 1)^d."""
    rng = np.random.default_rng(seed)
    if design == "random":
        return rng.random((n, d))
    from scipy.stats import qmc

    engine = qmc.LatinHypercube if design == "lhs" else qmc.Sobol
    # scipy ≥ 1.15 names the generator rng, older ones seed (both take a Generator)
    keyword = "rng" if "rng" in inspect.signature(engine.__init__).parameters else "seed"
    sampler = engine(d, scramble=True, **{keyword: rng})
    if design == "sobol":
        return sampler.random_base2(int(math.log2(n)))
    return sampler.random(n)


def _correlation_matrix(
    fields: list[str], correlations: list[tuple[str, str, float]]
) -> np.ndarray | None:
    """The Pearson correlation of the normal scores for the rank correlations given, or None
    without any.

    Raises
    ------
    ValueError
        A field is not sampled, a pair is given twice or on itself, |ρ_s| ≥ 1, or the matrix is
        not positive definite.
    """
    if not correlations:
        return None
    matrix = np.eye(len(fields))
    for first, second, rho in correlations:
        for name in (first, second):
            if name not in fields:
                raise ValueError(f"correlations: {name} is not one of the sampled fields")
        i, j = fields.index(first), fields.index(second)
        if i == j or matrix[i, j] != 0.0:
            raise ValueError(f"correlations: {first}, {second} given twice or with itself")
        if not -1.0 < rho < 1.0:
            raise ValueError(f"correlations: ρ_s = {rho:g} must lie strictly between -1 and 1")
        matrix[i, j] = matrix[j, i] = 2.0 * math.sin(math.pi * rho / 6.0)
    if np.linalg.eigvalsh(matrix)[0] <= 1e-10:
        raise ValueError("correlations: these rank correlations cannot hold together (the "
                         "matrix is not positive definite)")  # fmt: skip
    return matrix


def _normal_cdf(x: float) -> float:
    """Φ(x), the standard normal distribution function."""
    return 0.5 * (1.0 + math.erf(x / math.sqrt(2.0)))


def _copula(unit: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Points with the normal-score correlation ``matrix``, each coordinate still uniform."""
    from scipy import stats

    scores = stats.norm.ppf(np.clip(unit, UNIT_MARGIN, 1.0 - UNIT_MARGIN))
    return stats.norm.cdf(scores @ np.linalg.cholesky(matrix).T)

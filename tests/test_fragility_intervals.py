"""How sure a fragility is (`assessment.fragility_intervals`): the bootstrap intervals of θ and β,
their band, and how their widths fall with the number of records.

Expected values, each from outside the code:

* the resamplings are the fit's own: `bootstrap` replays `fragility`'s draws from the same seed
  to round-off (the intervals, the band and `risk` share them);
* coverage, from capacities drawn from a known lognormal (θ = 1.2 g, β = 0.4): the percentile
  interval of ln θ is ȳ ± 1.645·σ̂/√n with σ̂ the 1/n deviation, so it holds the true median
  when |t| ≤ 1.645·√((n − 1)/n) for Student's t with n − 1 degrees of freedom; β's interval
  holds the true β in 90 % of many-record studies (the bootstrap's asymptotic normality). Each
  share is a binomial proportion of M experiments, checked to 3 standard errors
  √(p(1 − p)/M) (0.3 % of such checks fail by chance), plus an allowance for the percentile
  interval of 100 resamplings where stated;
* widths: the asymptotic standard errors of the lognormal maximum-likelihood estimates,
  se(ln θ) = β/√n and se(β) = β/√(2n) (the normal sample's mean and standard deviation), so
  a 90 % half-width of 1.645 of them, and a width that halves when the records quadruple;
* the band of draws that share one β: Φ is monotone in θ, so its pointwise percentiles are the
  curves at the 5 % and 95 % percentiles of θ.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import replace

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.stats import norm, t
from studies import REPO, STRIPE_LEVELS, stripes_table

from rockbridge_cli.assessment.fragility import (
    Fragility,
    _bootstrap,
    _fit_capacities,
    fit_capacities,
    fragilities,
    fragilities_of,
)
from rockbridge_cli.assessment.fragility_intervals import (
    SETTLED,
    RecordsNeeded,
    Resampling,
    Width,
    _censored_fits,
    _stripe_fits,
    band,
    beta_interval,
    bootstrap,
    half_widths,
    record_counts,
    records_needed,
)
from rockbridge_cli.assessment.hazard import read_hazard_curve
from rockbridge_cli.assessment.risk import risks
from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.results.sections import IntensitySection
from rockbridge_cli.study.run import run_study

MEDIAN, BETA = 1.2, 0.4
"""The lognormal the capacities are drawn from: θ [g], β [-]."""


def ida_rows(capacities: np.ndarray, start: float = 0.05, top: float = 20.0) -> np.ndarray:
    """An IDA's rows (capacity, first level, last level), none censored (the levels far out)."""
    return np.column_stack([capacities, np.full_like(capacities, start),
                            np.full_like(capacities, top)])  # fmt: skip


def drawn(rng: np.random.Generator, n: int) -> Resampling:
    """n capacities drawn from the lognormal, as an IDA's rows."""
    return Resampling.of_capacities(ida_rows(MEDIAN * np.exp(BETA * rng.standard_normal(n))),
                                    _fit_capacities)  # fmt: skip


def quantiles(n: int) -> np.ndarray:
    """n capacities at the lognormal's quantiles (i + ½)/n: a sample whose fit is θ and β."""
    return MEDIAN * np.exp(BETA * norm.ppf((np.arange(n) + 0.5) / n))


def fragility(resampling: Resampling, draws: np.ndarray) -> Fragility:
    median, beta = fit_capacities(resampling.rows[:, 0], 0.05, 20.0) or (None, None)
    return Fragility("b", "abutment_failure", "pga_g", median, beta, None, [], [], {},
                     tuple(map(tuple, draws)), resampling=resampling)  # fmt: skip


def coverage(
    n: int, experiments: int, seed: int = 1, resamplings: int = 100
) -> tuple[float, float]:
    """Shares of ``experiments`` studies of n records whose 90 % intervals (of ``resamplings``,
    the fit's 100 by default) hold the true θ and β."""
    rng = np.random.default_rng(seed)
    median = beta = 0
    for _ in range(experiments):
        draws = bootstrap(drawn(rng, n), rng, resamplings)
        low, high = np.percentile(draws, [5.0, 95.0], axis=0)
        median += bool(low[0] <= MEDIAN <= high[0])
        beta += bool(low[1] <= BETA <= high[1])
    return median / experiments, beta / experiments


def binomial_error(share: float, experiments: int) -> float:
    return math.sqrt(share * (1.0 - share) / experiments)


# The resamplings are the fit's own


def records(capacities: np.ndarray) -> dict[str, float]:
    """Records R0, R1, … with the given capacities [g]."""
    return {f"R{i}": float(c) for i, c in enumerate(capacities)}


STRIPES = IntensitySection.of({"measure": "pga_g", "levels": list(STRIPE_LEVELS)})
"""The intensity section of the synthetic stripe studies (`studies.stripes_table`)."""


def test_bootstrap_replays_the_fits_draws():
    """Stripes through `fragilities_of` (Newton's fits) and censored IDA rows through
    `fragility._bootstrap`: the same seed gives the same resamplings, so the same draws, to the
    round-off of two ways to the same maximum."""
    capacities = MEDIAN * np.exp(BETA * np.random.default_rng(3).standard_normal(12))
    found = fragilities_of(stripes_table(records(capacities)), STRIPES, seed=5)
    first = found[0]  # gap closure: the first fit the study's generator draws for
    assert first.limit_state == "gap_closure" and first.resampling is not None
    np.testing.assert_allclose(  # the same maximum, found for all at once: to round-off
        bootstrap(first.resampling, np.random.default_rng(5), 100),
        np.array(first.draws),
        rtol=1e-12,
    )
    assert first.beta_90 == tuple(np.percentile([b for _, b in first.draws], [5.0, 95.0]))
    coded = capacities.copy()
    coded[coded > 2.0] = np.inf  # censored above the last level
    rows = ida_rows(coded, 0.1, 2.0)
    fit = _fit_capacities(rows)
    expected = _bootstrap(fit, rows, np.random.default_rng(7), 100, _fit_capacities)
    resampling = Resampling.of_capacities(rows, _fit_capacities)
    assert np.isnan(resampling.log_capacities).sum() == np.isinf(coded).sum() > 0
    found = bootstrap(resampling, np.random.default_rng(7), 100)
    np.testing.assert_allclose(found, np.array(expected), rtol=1e-6)  # the same maximum


def test_many_censored_fits_at_once_are_the_plain_fits():
    """`_censored_fits` (Newton's method on every resampling at once) against `fit_capacities`
    one by one, on capacities drawn from the lognormal and censored below 0.7 g and above 1.8 g:
    the same maximum of a concave likelihood, so the same θ and β to 1e-6 (where a resampling
    holds few distinct records β is tiny and the likelihood flat to its round-off, which lets
    the two stop 1e-7 apart), and the plain fit left only the few without a maximum inside the
    fit's region."""
    rng = np.random.default_rng(12)
    capacities = MEDIAN * np.exp(BETA * rng.standard_normal(30))
    coded = np.where(capacities > 1.8, np.inf, np.where(capacities <= 0.7, 0.0, capacities))
    assert np.isinf(coded).sum() >= 2 and (coded == 0.0).sum() >= 2
    rows = ida_rows(coded, 0.7, 1.8)
    solved_count = 0
    for n in (5, 10, 30):
        part = rows[rng.choice(30, n, replace=False)]
        picks = rng.integers(0, n, (200, n))
        fits, solved = _censored_fits(part, picks)
        solved_count += solved.sum()
        for fit, chosen in zip(fits[solved], picks[solved], strict=True):
            plain = fit_capacities(*part[chosen].T)
            np.testing.assert_allclose(fit, plain, rtol=1e-6)
    assert solved_count >= 0.95 * 600


def test_many_stripe_fits_at_once_are_the_plain_fits():
    """`_stripe_fits` against `fit_lognormal` one by one, on resamplings of subsets of a stripe
    study drawn from the lognormal: the same θ and β to 1e-9 wherever the batch finds them,
    and every resampling it leaves to the plain fit one whose levels fix no β (None, or β
    open: `fit_lognormal` decides those without Newton's method)."""
    rng = np.random.default_rng(13)
    capacities = MEDIAN * np.exp(BETA * rng.standard_normal(20))
    found = fragilities_of(stripes_table(records(capacities)), STRIPES)
    resampling = found[0].resampling
    solved_count = 0
    for n in (5, 10, 20):
        part = resampling.subset(np.sort(rng.choice(20, n, replace=False)))
        picks = rng.integers(0, n, (200, n))
        fits, solved = _stripe_fits(part.rows, part.levels, picks)
        solved_count += solved.sum()
        for fit, chosen, done in zip(fits, picks, solved, strict=True):
            plain = part.refit(part.rows[chosen])
            if done:
                np.testing.assert_allclose(fit, plain, rtol=1e-9)
            else:
                assert plain is None or plain[1] is None
    assert solved_count > 300


def test_beta_interval_is_the_percentiles_of_the_draws():
    draws = ((1.0, 0.2), (1.1, 0.5), (0.9, 0.3), (1.2, 0.4))
    assert beta_interval(draws) == tuple(np.percentile([0.2, 0.5, 0.3, 0.4], [5.0, 95.0]))
    assert beta_interval(()) is None


# Coverage


@pytest.mark.parametrize("n", [10, 44])
def test_the_median_interval_covers_as_students_t_says(n):
    """Expected: P(|t_{n−1}| ≤ 1.645·√((n − 1)/n)), 0.847 at n = 10 and 0.889 at 44 (not 0.90:
    the bootstrap knows σ only through σ̂); tolerance 3 binomial standard errors of 600
    experiments plus 0.015 for the percentiles of 100 resamplings."""
    experiments = 600
    expected = 1.0 - 2.0 * t.sf(1.645 * math.sqrt((n - 1) / n), n - 1)
    found, _ = coverage(n, experiments)
    assert found == pytest.approx(expected, abs=3 * binomial_error(expected, experiments) + 0.015)


@pytest.mark.slow
def test_the_beta_interval_covers_ninety_percent_with_many_records_and_resamplings():
    """200 records, 1000 resamplings (Efron & Tibshirani 1993, §19.3: about 1000 for a
    percentile interval), 200 experiments: 0.90 to 3 binomial standard errors (0.064)."""
    experiments = 200
    _, found = coverage(200, experiments, seed=2, resamplings=1000)
    assert found == pytest.approx(0.90, abs=3 * binomial_error(0.9, experiments))


@pytest.mark.xfail(strict=True, reason="known: with few records the 90 % interval of β "
                   "under-covers, 0.65 measured at n = 10: β̂, the 1/n estimate, is biased low "
                   "and its bootstrap spread too narrow")  # fmt: skip
def test_the_beta_interval_covers_ninety_percent_with_ten_records():
    experiments = 400
    _, found = coverage(10, experiments, seed=3)
    assert found == pytest.approx(0.90, abs=3 * binomial_error(0.9, experiments))


# Widths


def test_the_widths_are_the_asymptotic_standard_errors():
    """400 records at the lognormal's quantiles (their fit is θ and β to 0.3 %), 4000
    resamplings: half-widths 1.645·β/√n = 0.0329 of ln θ and 1.645/√(2n) = 0.0582 of β,
    each to 6 %: the 5 % and 95 % percentiles of 4000 draws scatter by about 2 % each, and the
    sample's kurtosis is the normal's only to O(1/n)."""
    n = 400
    resampling = Resampling.of_capacities(ida_rows(quantiles(n)), _fit_capacities)
    fit = fit_capacities(resampling.rows[:, 0], 0.05, 20.0)
    assert fit[0] == pytest.approx(MEDIAN, rel=1e-3) and fit[1] == pytest.approx(BETA, rel=3e-3)
    median, beta = half_widths(fit, bootstrap(resampling, np.random.default_rng(11), 4000))
    assert median == pytest.approx(1.645 * BETA / math.sqrt(n), rel=0.06)
    assert beta == pytest.approx(1.645 / math.sqrt(2 * n), rel=0.06)


def test_the_widths_halve_when_the_records_quadruple():
    """Subsets of 25 and of 100 of 400 records: both half-widths fall by 2 (1/√n), less the
    bias of σ̂ at 25 records, E[σ̂_25]/E[σ̂_100] = 0.977 (√((n − 1)/n)·c4(n), c4 the normal
    sample's bias factor 1 − 1/(4n) + …): expected 1.954; tolerance 10 %, 3 standard errors of
    a ratio of two medians over 40 subsets whose widths scatter by about 15 % and 7 %."""
    resampling = Resampling.of_capacities(ida_rows(quantiles(400)), _fit_capacities)
    draws = bootstrap(resampling, np.random.default_rng(0), 100)
    needed = records_needed(fragility(resampling, draws), counts=(25, 100))
    assert needed is not None
    low, high = needed.widths
    assert (low.records, high.records, low.fitted, high.fitted) == (25, 100, 40, 40)
    assert low.median / high.median == pytest.approx(1.954, rel=0.10)
    assert low.beta / high.beta == pytest.approx(1.954, rel=0.10)
    assert low.median == pytest.approx(1.645 * BETA / 5.0 * 0.97, rel=0.15)  # se(ln θ) at 25


def test_the_band_of_draws_of_one_beta_is_the_curves_of_the_median_percentiles():
    medians = np.exp(np.random.default_rng(4).normal(0.2, 0.1, 200))
    x = np.geomspace(0.3, 5.0, 40)
    low, high = band(np.column_stack([medians, np.full(200, 0.3)]), x)
    at_high, at_low = np.percentile(medians, [95.0, 5.0])  # a larger θ, a lower curve
    np.testing.assert_allclose(low, norm.cdf(np.log(x / at_high) / 0.3), atol=2e-3)
    np.testing.assert_allclose(high, norm.cdf(np.log(x / at_low) / 0.3), atol=2e-3)
    assert band((), x) is None


# Records needed


def test_the_counts_are_the_ladder_below_the_study():
    assert record_counts(44) == [5, 7, 10, 15, 22, 33, 44]
    assert record_counts(10) == [5, 7, 10] and record_counts(5) == [5]


def test_settled_is_from_the_fewest_records_that_stay_settled():
    def needed(*medians):
        widths = tuple(Width(n, 40, 40, m, 0.3) for n, m in zip((5, 10, 20), medians, strict=True))
        return RecordsNeeded("b", "s", "pga_g", 20, widths)

    assert needed(0.3, 0.1, 0.1).settled_at == 10
    assert needed(0.1, 0.2, 0.1).settled_at == 20  # not settled at 10: not from 5 on
    assert needed(0.3, 0.2, 0.2).settled_at is None
    own = needed(0.3, 0.3, 0.2)
    assert own.estimate == pytest.approx(20 * (0.2 / SETTLED) ** 2)  # the 1/√n law


def test_records_needed_of_stripes_narrow_with_the_records():
    """A stripe study of 20 records (Newton's fits): 5 and 10 records give wider intervals than
    20; at 20 they are the study's own intervals."""
    capacities = MEDIAN * np.exp(BETA * np.random.default_rng(8).standard_normal(20))
    found = fragilities_of(stripes_table(records(capacities)), STRIPES)
    item = next(f for f in found if f.limit_state == "gap_closure")
    needed = records_needed(item, subsets=10, resamplings=40)
    assert needed is not None and [w.records for w in needed.widths] == [5, 7, 10, 15, 20]
    medians = [w.median for w in needed.widths]
    assert min(medians[0], medians[2]) > medians[-1]
    assert medians[-1] == pytest.approx(0.5 * math.log(item.median_90[1] / item.median_90[0]))
    with pytest.raises(ValueError, match="within 5–20"):
        records_needed(item, counts=(30,))
    few = Resampling(item.resampling.rows[:4], item.resampling.refit)
    assert records_needed(replace(item, resampling=few)) is None  # too few to resample


# A study


EXAMPLE = REPO / "configs" / "hazard" / "example-site-pga.csv"
K0, K = 1.0 / 475.0 * 0.69**3.0, 3.0
"""The example site's power law, λ = K0·pga^−K (its file's comment)."""


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """The h̄ = 1.25 bridge under the ten bundled records (configs/studies/paper-ida.yaml's), an
    IDA of gap closure and abutment failure at `fast`: 148 analyses, about 2 s."""
    folder = tmp_path_factory.mktemp("intervals")
    path = folder / "study.yaml"
    path.write_text(
        f"bridges: [{(REPO / 'configs' / 'bridges' / 'studied-hbar1.25.yaml').as_posix()}]\n"
        f"records: {{set: {(REPO / 'records' / 'ec8-type1-C-ag0.6g').as_posix()}}}\n"
        "intensity: {measure: pga_g, ida: {start: 0.1, step: 0.4, max: 3.0, tolerance: 0.05, "
        "limit_states: [gap_closure, abutment_failure]}}\n"
        "fidelity: fast\noutput: {path: ida.h5, histories: none}\n",
        encoding="utf-8",
    )
    loaded = load_study(path)
    run_study(loaded, workers=1)
    return loaded.output


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_the_command_gives_betas_interval_beside_the_medians(study):
    """Table, --json and --csv: β's interval is the 5 % and 95 % percentiles of the draws that
    give the median's."""
    result = invoke("fragility", study)
    assert result.exit_code == 0, result.output
    assert "median 5–95 %  beta 5–95 %" in result.output.splitlines()[1]
    rows = json.loads(invoke("fragility", study, "--json").output)
    table = list(csv.DictReader(io.StringIO(invoke("fragility", study, "--csv", "-").output)))
    for row, line, item in zip(rows, table, fragilities(study), strict=True):
        medians, betas = np.array(item.draws).T
        assert len(medians) > 50  # most resamplings of ten records fix β
        assert row["median_90"] == pytest.approx(np.percentile(medians, [5.0, 95.0]), rel=1e-12)
        assert row["beta_90"] == pytest.approx(np.percentile(betas, [5.0, 95.0]), rel=1e-12)
        assert [float(line["beta_05"]), float(line["beta_95"])] == row["beta_90"]
        assert f"{row['beta_90'][0]:.3g}–{row['beta_90'][1]:.3g}" in result.output


def test_risk_integrates_the_draws_of_the_intervals(study):
    """The example site is a power law, so each draw's λ is Cornell's K0·θ^−K·exp(K²β²/2)
    (Cornell et al. 2002, Eq. 11): risk's interval is their 5 % and 95 % percentiles, from the
    draws of the fragility's intervals (to the hazard file's 6 digits)."""
    found = {item.limit_state: item for item in fragilities(study)}
    for risk in risks(study, read_hazard_curve(EXAMPLE)):
        medians, betas = np.array(found[risk.limit_state].draws).T
        cornell = K0 * medians**-K * np.exp(0.5 * (K * betas) ** 2)
        assert risk.rate_90 == pytest.approx(np.percentile(cornell, [5.0, 95.0]), rel=1e-5)


def test_the_records_needed_are_printed_exported_and_drawn(study, tmp_path, monkeypatch):
    """Counts 5, 7 and 10 of the ten records; at 10, the study's own intervals: half the
    ln-width of the median's interval of ``fragility --json``."""
    result = invoke("fragility", study, "--records-needed", "--subsets", 10)
    assert result.exit_code == 0, result.output
    assert "the median over 10 subsets" in result.output
    assert "records  median ±  beta ±  fitted  kept   settled" in result.output
    rows = {row["limit_state"]: row for row in
            json.loads(invoke("fragility", study, "--json").output)}  # fmt: skip
    needed = json.loads(invoke("fragility", study, "--records-needed", "--subsets", 10,
                               "--json").output)  # fmt: skip
    assert [row["limit_state"] for row in needed] == ["gap_closure", "abutment_failure"]
    for row in needed:
        assert [w["records"] for w in row["widths"]] == [5, 7, 10]
        low, high = rows[row["limit_state"]]["median_90"]
        own = row["widths"][-1]
        assert own["median_half_width"] == pytest.approx(0.5 * math.log(high / low), rel=1e-12)
        assert own["subsets"] == 1 and row["widths"][0]["subsets"] == 10
        assert row["rule"] == {"median_half_width_at_most": pytest.approx(0.1645)}
        line = f"studied-hbar1.25  {row['limit_state']}: "
        assert any(text.startswith(line) for text in result.output.splitlines())
    exported = invoke("fragility", study, "--records-needed", "--subsets", 10, "--csv", "-")
    header = exported.output.splitlines()[0]
    assert header.startswith("bridge,limit_state,measure,records,subsets,fitted,median_half")
    assert len(exported.output.splitlines()) == 1 + 2 * 3
    for kind in ("records-needed", "fragility"):
        figure = tmp_path / f"{kind}.png"
        drawn = invoke("plot", kind, study, "-o", figure)
        assert drawn.exit_code == 0, drawn.output
        assert figure.stat().st_size > 10_000
    from rockbridge_cli.plots import fragility as fragility_plot

    figures = []
    monkeypatch.setattr(fragility_plot, "save", lambda figure, output: figures.append(figure))
    fragility_plot.plot_records_needed(study, tmp_path / "n.png")
    shown = [axes for axes in figures[0].axes if axes.get_visible()]
    assert shown and all(axes.get_xlabel() == "records n [-]" for axes in shown)  # every panel

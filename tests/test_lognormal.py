"""The lognormal fits by Newton's method (`assessment.lognormal`) behind both fragility fits.

Expected values: scipy's general optimiser (L-BFGS-B, the fits' former method) on the
likelihoods written anew here with scipy.stats (Baker 2015's binomial likelihood of stripes; the
censored normal likelihood of IDA capacities), at tolerances far tighter than the fits used;
closed forms: without censoring the maximum-likelihood μ and β are the sample mean and the 1/n
standard deviation of the log-capacities; two levels are fitted exactly (a saturated model:
Φ((ln x_j − ln θ)/β) equals each level's share).
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import minimize
from scipy.stats import norm

from rockbridge_cli.assessment import lognormal
from rockbridge_cli.assessment.fragility import fit_capacities, fit_lognormal

BOUNDS_BETA = (math.log(lognormal.BETA_RANGE[0]), math.log(lognormal.BETA_RANGE[1]))


def stripes_minus_log_likelihood(parameters, logs, reached, tried) -> float:
    """−ln L of Baker's binomial likelihood at (ln θ, ln β)."""
    u = (logs - parameters[0]) / math.exp(parameters[1])
    return -float(np.sum(reached * norm.logcdf(u) + (tried - reached) * norm.logsf(u)))


def censored_minus_log_likelihood(parameters, known, lows, highs) -> float:
    """−ln L of log-capacities known, at most ``lows`` or above ``highs``, at (μ, ln β)."""
    mean, beta = parameters[0], math.exp(parameters[1])
    value = np.sum(norm.logpdf(known, mean, beta)) + np.sum(norm.logcdf((lows - mean) / beta))
    return -float(value + np.sum(norm.logsf((highs - mean) / beta)))


def scipy_optimum(function, start, span, args):
    """L-BFGS-B with tight tolerances in (μ, ln β), held to the fits' region."""
    bounds = [(span[0] - lognormal.MARGIN, span[1] + lognormal.MARGIN), BOUNDS_BETA]
    options = {"ftol": 1e-15, "gtol": 1e-11, "maxiter": 10_000}
    return minimize(function, start, args=args, method="L-BFGS-B", bounds=bounds, options=options)


def random_stripes(rng):
    """Levels, records reaching the state and records analyzed, drawn from a random lognormal;
    None where the levels separate the records (β not fixed: `fit_lognormal` says so)."""
    count = int(rng.integers(2, 15))
    levels = np.sort(rng.uniform(0.05, 4.0, count))
    tried = (
        np.full(count, rng.integers(3, 40)) if rng.random() < 0.7 else rng.integers(1, 30, count)
    )
    median, beta = math.exp(rng.uniform(math.log(0.1), math.log(3.0))), rng.uniform(0.05, 1.5)
    reached = rng.binomial(tried, norm.cdf(np.log(levels / median) / beta))
    fit = fit_lognormal(levels, reached, tried)
    return None if fit is None or fit[1] is None else (levels, reached, tried, fit)


def test_the_stripe_fit_is_the_optimum_scipy_finds():
    """Never a worse likelihood than scipy's, a stationary point (central differences of −ln L
    in (ln θ, ln β) below 1e-6), and the same parameters wherever scipy's L-BFGS-B converged as
    far (scipy 1.11's stops early on a few of these cases, at a worse likelihood)."""
    rng = np.random.default_rng(7)
    cases = [case for case in (random_stripes(rng) for _ in range(120)) if case is not None]
    assert len(cases) > 60
    agreed = 0
    for levels, reached, tried, (median, beta) in cases:
        logs = np.log(levels)
        args = (logs, reached, tried)
        reference = scipy_optimum(stripes_minus_log_likelihood, [np.median(logs), math.log(0.3)],
                                  (logs.min(), logs.max()), args)  # fmt: skip
        found = np.array([math.log(median), math.log(beta)])
        ours = stripes_minus_log_likelihood(found, *args)
        assert ours <= reference.fun + 1e-9  # never a worse likelihood
        low, high = logs.min() - lognormal.MARGIN, logs.max() + lognormal.MARGIN
        inside = BOUNDS_BETA[0] + 1e-3 < found[1] < BOUNDS_BETA[1] - 1e-3
        if inside and low + 1e-3 < found[0] < high - 1e-3:  # not held at the fits' region
            for axis in (0, 1):
                h = np.eye(2)[axis] * 1e-5
                slope = (stripes_minus_log_likelihood(found + h, *args)
                         - stripes_minus_log_likelihood(found - h, *args)) / 2e-5  # fmt: skip
                assert abs(slope) < 1e-6 * (1.0 + abs(ours))
        if reference.fun <= ours + 1e-9:  # scipy got as far: the same point
            assert found[0] == pytest.approx(reference.x[0], abs=2e-5)
            assert found[1] == pytest.approx(reference.x[1], abs=2e-5)
            agreed += 1
    assert agreed >= 0.9 * len(cases)


def test_the_censored_fit_is_the_optimum_scipy_finds():
    rng = np.random.default_rng(8)
    fitted = 0
    for _ in range(100):
        median, beta = math.exp(rng.uniform(math.log(0.1), math.log(3.0))), rng.uniform(0.05, 1.5)
        capacities = median * np.exp(beta * rng.standard_normal(int(rng.integers(2, 40))))
        start, top = rng.uniform(0.05, 0.5), rng.uniform(1.0, 4.0)
        coded = np.where(capacities > top, np.inf, np.where(capacities <= start, 0.0, capacities))
        known = np.log(coded[np.isfinite(coded) & (coded > 0.0)])
        lows = np.full(np.count_nonzero(coded == 0.0), math.log(start))
        highs = np.full(np.count_nonzero(np.isinf(coded)), math.log(top))
        if known.size < 2 or lows.size + highs.size == 0:
            continue
        fitted += 1
        found_median, found_beta = fit_capacities(coded, start, top)
        args = (known, lows, highs)
        reference = scipy_optimum(censored_minus_log_likelihood, [known.mean(), math.log(0.3)],
                                  (math.log(start), math.log(top)), args)  # fmt: skip
        ours = censored_minus_log_likelihood([math.log(found_median), math.log(found_beta)], *args)
        assert ours <= reference.fun + 1e-9
        assert math.log(found_median) == pytest.approx(reference.x[0], abs=2e-6)
        assert math.log(found_beta) == pytest.approx(reference.x[1], abs=2e-6)
    assert fitted > 50


def test_without_censoring_newton_gives_the_sample_mean_and_deviation():
    """From a start far off, Newton's iterations end at the closed form (1/n deviation)."""
    logs = np.log(np.array([0.31, 0.52, 0.55, 0.9, 1.7, 2.4]))
    sample = lognormal.Sample(logs, np.empty(0), np.empty(0), np.empty(0, dtype=bool))
    mean, beta = lognormal.fit(sample, (logs.min(), logs.max()), (3.0, 4.0))
    assert mean == pytest.approx(logs.mean(), abs=1e-12)
    assert beta == pytest.approx(logs.std(), rel=1e-12)


def test_two_levels_are_fitted_exactly():
    """Two levels with shares 0.2 and 0.7: Φ((ln x_j − ln θ)/β) = p_j at both."""
    levels, shares = np.array([0.4, 1.1]), np.array([0.2, 0.7])
    median, beta = fit_lognormal(levels, 100 * shares, np.array([100, 100]))
    z = norm.ppf(shares)
    expected_beta = math.log(levels[1] / levels[0]) / (z[1] - z[0])
    assert beta == pytest.approx(expected_beta, rel=1e-10)
    assert median == pytest.approx(levels[0] * math.exp(-expected_beta * z[0]), rel=1e-10)


def test_a_share_falling_with_the_level_is_held_at_the_largest_beta():
    """The likelihood grows with β without end (a > 0 is kept): the fit stops at β's bound, where
    the optimiser with the same bounds does too."""
    levels, reached, tried = np.array([0.2, 0.5, 1.0]), np.array([6, 5, 4]), np.full(3, 10)
    median, beta = fit_lognormal(levels, reached, tried)
    logs = np.log(levels)
    reference = scipy_optimum(stripes_minus_log_likelihood, [math.log(0.5), 0.0],
                              (logs.min(), logs.max()), (logs, reached, tried))  # fmt: skip
    assert beta == lognormal.BETA_RANGE[1]
    assert math.log(median) == pytest.approx(reference.x[0], abs=1e-6)


@pytest.mark.parametrize(
    ("reached", "median"),
    [([0, 3, 10, 10], 0.3), ([7, 10, 10, 10], 0.1), ([0, 0, 0, 4], 0.9), ([0, 0, 10, 10], None)],
)
def test_levels_that_separate_the_records_leave_beta_open(reached, median):
    """At most one level with some records reaching the state and some not, the others all or
    none in order: the likelihood grows as β → 0 (its supremum is the saturated one, with θ at
    that level), so β is not fixed; without such a level θ is the geometric mean of the two
    levels where the records change."""
    levels = np.array([0.1, 0.3, 0.5, 0.9])
    fit = fit_lognormal(levels, np.array(reached), np.full(4, 10))
    assert fit == (pytest.approx(median or math.sqrt(0.3 * 0.5)), None)


def test_the_fits_import_no_general_optimiser():
    code = (
        "import sys\nfrom rockbridge_cli.assessment import fragility\n"
        "print('scipy.optimize' in sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=120, check=True)  # fmt: skip
    assert result.stdout.strip() == "False"

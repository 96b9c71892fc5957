"""Sampled bridges and their sensitivity indices (`config.uncertainty`, `assessment.sensitivity`).

The estimator is checked against the Ishigami function's analytic indices (Ishigami & Homma
1990; the variances in Saltelli et al. 2008, "Global Sensitivity Analysis: The Primer", §4.10)
and against SALib's estimators on the same outputs; the distributions against their defining
properties; a sampled study against itself across worker counts, shards, a resume.
"""

from __future__ import annotations

import json
import math

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from scipy import stats
from studies import contents, write_study

from rockbridge_cli.assessment.sensitivity import design_outputs, sensitivities, sobol
from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.config.uncertainty import Uncertainty
from rockbridge_cli.results import read_peaks
from rockbridge_cli.results.sections import IntensitySection
from rockbridge_cli.study.run import run_study


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


# ---------------------------------------------------------------------------------------------
# The estimator


def ishigami(x: np.ndarray, a: float = 7.0, b: float = 0.1) -> np.ndarray:
    """f = sin x1 + a sin² x2 + b x3⁴ sin x1, x uniform on [−π, π]³."""
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices(a: float = 7.0, b: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    """The analytic first- and total-order indices: V1 = ½(1 + bπ⁴/5)², V2 = a²/8, V3 = 0,
    V13 = b²π⁸(1/18 − 1/50), V = V1 + V2 + V13."""
    v1 = 0.5 * (1.0 + b * math.pi**4 / 5.0) ** 2
    v2 = a**2 / 8.0
    v13 = b**2 * math.pi**8 * (1.0 / 18.0 - 1.0 / 50.0)
    v = v1 + v2 + v13
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v


FIELDS = ("x1", "x2", "x3")


def test_ishigami_indices_through_the_design_and_the_estimator():
    """A saltelli design of three uniform fields on [−π, π] at n = 2¹³ (the design a study
    draws), its outputs assembled as the command assembles a study's (`design_outputs`), the
    indices within 0.02 of the analytic ones (S1 = 0.3139, 0.4424, 0; ST = 0.5576, 0.4424,
    0.2437)."""
    n = 2**13
    design = Uncertainty.model_validate({
        "fields": {f: {"distribution": "uniform", "low": -math.pi, "high": math.pi}
                   for f in FIELDS},
        "design": "saltelli", "size": n, "seed": 3,
    })  # fmt: skip
    samples = design.samples()
    assert len(samples) == n * (len(FIELDS) + 2)
    x = np.array([[s.values[f] for f in FIELDS] for s in samples])
    outputs = dict(zip((s.label for s in samples), ishigami(x), strict=True))
    f_a, f_b, f_ab = design_outputs(
        {s.label: s.described() for s in samples}, outputs, list(FIELDS), n
    )
    first, total, first_ci, total_ci = sobol(f_a, f_b, f_ab, resamples=200)
    expected_first, expected_total = ishigami_indices()
    assert expected_first == pytest.approx([0.3139, 0.4424, 0.0], abs=1e-4)  # the Primer's
    assert expected_total == pytest.approx([0.5576, 0.4424, 0.2437], abs=1e-4)
    assert first == pytest.approx(expected_first, abs=0.02)
    assert total == pytest.approx(expected_total, abs=0.02)
    assert np.all(first_ci[0] <= first) and np.all(first <= first_ci[1])
    assert np.all(total_ci[0] <= total) and np.all(total <= total_ci[1])
    assert np.all(first_ci[1] - first_ci[0] < 0.1)  # n = 8192 pins them


def _weyl_design(n: int, d: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ishigami outputs on A, B and A_B^(i) from a Kronecker sequence (frac(k·√p) for the first
    2d primes p): deterministic on any library version."""
    primes = np.array([2, 3, 5, 7, 11, 13], dtype=float)[: 2 * d]
    points = np.modf(np.arange(1, n + 1)[:, None] * np.sqrt(primes))[0]
    x = -math.pi + 2.0 * math.pi * points
    a, b = x[:, :d], x[:, d:]
    mixed = [np.where(np.arange(d) == i, b, a) for i in range(d)]
    return ishigami(a), ishigami(b), np.vstack([ishigami(m) for m in mixed])


SALIB_PRINTED = ([0.29629559, 0.44954843, 0.00265731], [0.51985178, 0.44197163, 0.24415188])
"""`SALib.analyze.sobol.first_order` and `total_order` (SALib 1.6.0: Saltelli et al. 2010 and
Jansen 1999) on `_weyl_design(1024, 3)` centred by the mean of A and B, printed to 8 digits.
scipy, and so rockbridge, centre the outputs before the first-order estimator (a term
mean(f_B)·mean(f_AB − f_A)/V, which vanishes as n grows, is removed); SALib does not, so it is
given the centred outputs. The total order does not depend on the centring."""


def _centred(f_a, f_b, f_ab):
    mean = np.mean(np.concatenate([f_a, f_b]))
    return f_a - mean, f_b - mean, f_ab - mean


def test_the_estimator_agrees_with_salib():
    f_a, f_b, f_ab = _weyl_design(1024, 3)
    first, total, _, _ = sobol(f_a, f_b, f_ab, resamples=10)
    assert first == pytest.approx(SALIB_PRINTED[0], abs=1e-8)
    assert total == pytest.approx(SALIB_PRINTED[1], abs=1e-8)
    salib = pytest.importorskip("SALib.analyze.sobol")
    f_a, f_b, f_ab = _centred(f_a, f_b, f_ab)
    for i in range(3):  # and live, where SALib is installed
        assert first[i] == pytest.approx(salib.first_order(f_a, f_ab[i], f_b), rel=1e-12)
        assert total[i] == pytest.approx(salib.total_order(f_a, f_ab[i], f_b), rel=1e-12)


def test_the_intervals_are_reproducible_and_narrow_with_n():
    """The same seed, the same bounds; four times the samples, about half the width (the
    bootstrap's width goes as 1/√n)."""
    small = sobol(*_weyl_design(256, 3), resamples=400)
    again = sobol(*_weyl_design(256, 3), resamples=400)
    assert np.array_equal(small[2], again[2]) and np.array_equal(small[3], again[3])
    large = sobol(*_weyl_design(1024, 3), resamples=400)
    ratio = (small[2][1] - small[2][0])[:2] / (large[2][1] - large[2][0])[:2]
    assert ratio == pytest.approx([2.0, 2.0], rel=0.35)


# ---------------------------------------------------------------------------------------------
# The distributions and designs


def _draw(spec: dict, size: int = 4096, design: str = "lhs", **more) -> np.ndarray:
    config = Uncertainty.model_validate(
        {"fields": {"x": spec}, "size": size, "design": design, **more}
    )
    return np.array([s.values["x"] for s in config.samples()])


def test_a_latin_hypercube_puts_one_sample_in_each_stratum():
    values = _draw({"distribution": "uniform", "low": 0.0, "high": 1.0}, size=10)
    assert sorted(np.floor(values * 10).astype(int)) == list(range(10))


@pytest.mark.parametrize(
    "spec, mean, std",
    [
        ({"distribution": "normal", "mean": 0.12, "std": 0.02}, 0.12, 0.02),
        # mean·√(1 + cov²)… the mean and c.o.v. given are the moments
        ({"distribution": "lognormal", "mean": 132e6, "cov": 0.3}, 132e6, 0.3 * 132e6),
        # median e^{β²/2} and median·e^{β²/2}·√(e^{β²} − 1)
        ({"distribution": "lognormal", "median": 0.1, "beta": 0.25},
         0.1 * math.exp(0.25**2 / 2), 0.1 * math.exp(0.03125) * math.sqrt(math.exp(0.0625) - 1)),
        # a uniform's (a + b)/2 and (b − a)/√12
        ({"distribution": "uniform", "low": 0.5, "high": 0.9}, 0.7, 0.4 / math.sqrt(12)),
    ],
)  # fmt: skip
def test_moments_of_the_samples(spec, mean, std):
    """A 4096-sample Latin hypercube: the sample moments within 1 % (mean) and 3 % (std) of the
    distribution's closed forms."""
    values = _draw(spec)
    assert values.mean() == pytest.approx(mean, rel=0.01)
    assert values.std() == pytest.approx(std, rel=0.03)


def test_a_truncated_normal_stays_in_its_bounds():
    """Bounds at the mean and +1σ: every value inside; the mean that of a normal cut there,
    μ + σ·(φ(0) − φ(1))/(Φ(1) − Φ(0)) (Johnson, Kotz & Balakrishnan 1994, §10.1)."""
    values = _draw({"distribution": "truncated-normal", "mean": 0.9, "std": 0.05,
                    "low": 0.9, "high": 0.95})  # fmt: skip
    assert values.min() >= 0.9 and values.max() <= 0.95
    pdf, cdf = stats.norm.pdf, stats.norm.cdf
    assert values.mean() == pytest.approx(
        0.9 + 0.05 * (pdf(0) - pdf(1)) / (cdf(1) - cdf(0)), rel=1e-3
    )


def test_a_choice_follows_its_weights():
    values = _draw({"distribution": "choice", "values": [0.6, 0.8, 1.0], "weights": [1, 2, 1]})
    shares = [np.mean(values == v) for v in (0.6, 0.8, 1.0)]
    assert shares == pytest.approx([0.25, 0.5, 0.25], abs=0.01)


def test_rank_correlations_are_imposed():
    """ρ_s = 0.6 asked; scipy's Spearman coefficient of 4096 samples within 0.03; each marginal
    still its own (a uniform stays uniform: its mean within 1 %)."""
    config = Uncertainty.model_validate({
        "fields": {"a": {"distribution": "uniform", "low": 0.0, "high": 1.0},
                   "b": {"distribution": "lognormal", "median": 2.0, "beta": 0.4}},
        "size": 4096, "correlations": [["a", "b", 0.6]],
    })  # fmt: skip
    samples = config.samples()
    a = np.array([s.values["a"] for s in samples])
    b = np.array([s.values["b"] for s in samples])
    assert stats.spearmanr(a, b).statistic == pytest.approx(0.6, abs=0.03)
    assert a.mean() == pytest.approx(0.5, rel=0.01)


def test_the_same_seed_gives_the_same_samples_and_another_seed_others():
    spec = {"distribution": "normal", "mean": 1.0, "std": 0.1}
    for design in ("lhs", "sobol", "random"):
        first = _draw(spec, 64, design, seed=5)
        assert np.array_equal(first, _draw(spec, 64, design, seed=5))
        assert not np.array_equal(first, _draw(spec, 64, design, seed=6))


@pytest.mark.parametrize(
    "section, reason",
    [
        ({"design": "saltelli", "size": 100}, "a saltelli design needs a power of two"),
        ({"design": "sobol", "size": 3}, "2 or 4, not 3"),
        ({"design": "saltelli", "size": 4, "pairing": "one"}, "pair every sample with every"),
        ({"size": 4, "correlations": [["x", "y", 0.5]]}, "y is not one of the sampled fields"),
        ({"size": 4, "correlations": [["x", "x", 0.5]]}, "given twice or with itself"),
        ({"size": 4, "fields": {"x": {"distribution": "weibull"}}}, "expected a mapping whose"),
        ({"size": 4, "fields": {"x": {"distribution": "lognormal", "median": 1.0}}},
         "give median and beta, or mean and cov"),
        ({"size": 4, "fields": {"x": {"distribution": "uniform", "low": 2.0, "high": 1.0}}},
         "must be below high"),
    ],
)  # fmt: skip
def test_impossible_sections_are_refused(tmp_path, section, reason):
    fields = {"x": {"distribution": "uniform", "low": 0.0, "high": 1.0},
              "y": {"distribution": "uniform", "low": 0.0, "high": 1.0}}  # fmt: skip
    data = {"fields": {"x": fields["x"]}, **section}
    study = write_study(tmp_path, bridges=("studied-hbar1.25",),
                        extra="uncertainty: " + json.dumps(data) + "\n")  # fmt: skip
    result = invoke("run", study)
    assert result.exit_code == 2 and reason in result.output, result.output
    assert "Traceback" not in result.output and "uncertainty" in result.output


# ---------------------------------------------------------------------------------------------
# Sampled studies

SAMPLED = """uncertainty:
  design: lhs
  size: 3
  seed: 11
  fields:
    abutments.gap: {distribution: lognormal, median: 0.12, beta: 0.3}
    rocking_restitution: {distribution: truncated-normal, mean: 0.9, std: 0.05, high: 1.0}
    abutments.pounding.restitution: {distribution: choice, values: [0.4, 0.6, 0.8]}
fidelity: fast
output: {histories: none}
"""


def test_sampled_bridges_are_the_bridge_with_the_drawn_values(tmp_path):
    study = load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SAMPLED))
    assert [b.id for b in study.bridges] == [f"studied-hbar1.25+s{k}" for k in range(3)]
    for bridge in study.bridges:
        config = bridge.config
        assert config.abutments.gap == bridge.swept["abutments.gap"]
        assert config.rocking_restitution == bridge.swept["rocking_restitution"] <= 1.0
        assert config.abutments.pounding.restitution in (0.4, 0.6, 0.8)
        assert config.abutments.stiffness == 132e6  # the bridge file's, unsampled
    assert study.resolved()["uncertainty"]["fields"]["abutments.gap"]["median"] == 0.12


@pytest.mark.slow
def test_a_sampled_study_is_the_same_on_any_worker_count_shard_split_and_resume(tmp_path):
    """Its sampled values and results in the file and the peak table; identical on 1 and 2
    workers, in two shards merged, and after an interrupted run resumed."""
    path = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SAMPLED)
    one = invoke("run", path, "--workers", "1", "-o", "one.h5")
    assert one.exit_code == 0, one.output
    expected = contents(tmp_path / "one.h5")
    two = invoke("run", path, "--workers", "2", "-o", "two.h5")
    assert two.exit_code == 0, two.output
    assert contents(tmp_path / "two.h5") == expected
    for k in (1, 2):
        part = invoke("run", path, "--shard", f"{k}/2", "-o", f"part{k}.h5")
        assert part.exit_code == 0, part.output
    merged = invoke("merge", "merged.h5", "part1.h5", "part2.h5")
    assert merged.exit_code == 0, merged.output
    ignored = ("merged_from", "host")
    strip = lambda found: {k: ({a: v for a, v in attrs.items() if a not in ignored}, data)  # noqa: E731
                           for k, (attrs, data) in found.items()}  # fmt: skip
    assert strip(contents(tmp_path / "merged.h5")) == strip(expected)
    study = load_study(path, output=tmp_path / "resumed.h5")

    def stop_after_two(item, done, total):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(study, workers=1, progress=stop_after_two)
    report = run_study(study, workers=1)
    assert report.resumed == 2 and contents(tmp_path / "resumed.h5") == expected
    peaks = read_peaks(tmp_path / "one.h5")
    gaps = peaks.groupby("bridge")["abutments.gap"].first()
    assert list(gaps) == [b.swept["abutments.gap"] for b in study.bridges]
    with h5py.File(tmp_path / "one.h5", "r") as file:
        assert json.loads(file["bridges/studied-hbar1.25+s2"].attrs["sample"]) == {"index": 2}
        stored = json.loads(file.attrs["config"])["uncertainty"]
    assert stored["fields"]["rocking_restitution"]["distribution"] == "truncated-normal"


def test_an_invalid_sample_is_refused_naming_the_field_and_distribution(tmp_path):
    """A normal gap of mean 0.05 m and σ 0.05 m: some of 64 draws are negative gaps."""
    extra = ("uncertainty: {size: 64, fields: {abutments.gap: "
             "{distribution: normal, mean: 0.05, std: 0.05}}}\n")  # fmt: skip
    study = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=extra)
    result = invoke("run", study)
    assert result.exit_code == 2 and "Traceback" not in result.output
    for part in ("uncertainty.fields", "abutments.gap = -", "from normal mean=0.05 std=0.05",
                 "truncated-normal"):  # fmt: skip
        assert part in result.output, result.output


def test_one_record_per_sample(tmp_path):
    """pairing: one — 5 samples over 2 records: each sample meets one record (3 samples one, 2
    the other: balanced), at every level of an intensity section."""
    extra = SAMPLED.replace("size: 3", "size: 5").replace(
        "  seed: 11\n", "  seed: 11\n  pairing: one\n"
    )
    extra = extra.replace("fidelity: fast", "intensity: {measure: pga_g, levels: [0.2, 0.4]}\n"
                          "fidelity: fast")  # fmt: skip
    study = load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), extra=extra))
    assert study.pairs is not None and len(study.pairs) == 5 * 2
    met = [{study.records[r].base for b, r in study.pairs if b == k} for k in range(5)]
    assert all(len(records) == 1 for records in met)
    assert sorted(sum(records == {name} for records in met) for name in ("R1", "R2")) == [2, 3]
    report = run_study(study, workers=1)
    assert len(report.peaks) == 10
    assert set(zip(report.peaks["bridge"], report.peaks["record"], strict=True)) == {
        (study.bridges[b].id, study.records[r].id) for b, r in study.pairs
    }


SALTELLI = """uncertainty:
  design: saltelli
  size: 4
  seed: 2
  fields:
    abutments.gap: {distribution: uniform, low: 0.06, high: 0.18}
    abutments.ultimate_displacement: {distribution: uniform, low: 0.05, high: 0.15}
fidelity: fast
output: {histories: none}
"""


def test_sensitivity_of_a_saltelli_study_from_the_command_line(tmp_path):
    """n = 4, d = 2: 16 bridges × 2 records. The command prints each field's indices, the JSON
    holds them; the failure indicator is accepted; the figure is drawn. dcr_backfill is
    (u − u_jo)/u_ab: ``ultimate_displacement`` divides it, so its total index is not zero."""
    path = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SALTELLI)
    assert invoke("run", path, "-o", "s.h5").exit_code == 0
    result = invoke("sensitivity", "s.h5")
    assert result.exit_code == 0, result.output
    assert "abutments.ultimate_displacement" in result.output and "dominant:" in result.output
    rows = json.loads(invoke("sensitivity", "s.h5", "--json").output)
    assert [r["field"] for r in rows] == ["abutments.gap", "abutments.ultimate_displacement"]
    assert all(r["samples"] == 4 and r["records"] == 2 for r in rows)
    assert rows[1]["total_order"] > 0.0
    assert invoke("sensitivity", "s.h5", "--quantity", "failure").exit_code == 0
    assert invoke("report", "s.h5", "-o", "s.html").exit_code == 0
    page = (tmp_path / "s.html").read_text(encoding="utf-8")
    ids = [r["bridge"] for r in json.loads(invoke("peaks", "s.h5", "--json").output)["rows"]]
    assert all(f"({bridge})</td>" in page for bridge in ids)  # samples told apart by their ids
    drawn = invoke("plot", "sensitivity", "s.h5", "-o", "s.png")
    assert drawn.exit_code == 0 and (tmp_path / "s.png").stat().st_size > 10_000
    bad = invoke("sensitivity", "s.h5", "--quantity", "u_dek_max")
    assert bad.exit_code == 2 and "unknown quantity 'u_dek_max'" in bad.output
    found = sensitivities(tmp_path / "s.h5", "dcr_backfill")
    assert 0.0 <= found[0].records_share <= 1.0


def test_an_output_constant_over_a_and_b_has_no_indices_and_no_dominant_field(capsys):
    """Every Sobol' index is a share of Var(Q) over the A and B samples (Saltelli et al. 2010,
    the denominator of both estimators): with Q = 0 on all of them the shares are 0/0, even
    where an A_B sample reaches the limit state. The command says so, and names no field
    dominant (it named the first field, with indices of 0)."""
    from rockbridge_cli.assessment.sensitivity import _indices
    from rockbridge_cli.cli.sensitivity import _indices as printed

    f_ab = np.zeros((2, 8))
    f_ab[0, 3] = 1.0  # one A_B sample fails
    rows = [np.zeros(3)] * 16
    found = _indices("b", "abutment_failure", "mean", ["gap", "damping"], np.zeros(8),
                     np.zeros(8), f_ab, rows, 0.9, 99)  # fmt: skip
    assert all(math.isnan(f.first) and math.isnan(f.total) for f in found.fields)
    printed([found])
    output = capsys.readouterr().out
    assert "abutment_failure does not vary over the A and B samples" in output
    assert "dominant" not in output


@pytest.mark.parametrize(
    ("first", "total", "noted"),
    [(1.29, 0.77, True), (0.95, 0.70, True), (-0.20, 0.10, True), (0.30, 0.29, False),
     (-0.01, 0.02, False), (0.50, 0.80, False)],
)  # fmt: skip
def test_first_order_indices_no_output_can_have_are_called_noise(capsys, first, total, noted):
    """A first-order index is a share of a variance, at most its total order (Saltelli et al.
    2010): one past 0–1 or above the total by more than a few hundredths (a converged
    additive output's S1 = ST, estimated apart) is the estimators' noise, and the command says
    so (a new user quoted S1 = 1.29 at n = 8)."""
    from rockbridge_cli.assessment.sensitivity import FieldIndices, Sensitivity
    from rockbridge_cli.cli.sensitivity import _indices as printed

    field = FieldIndices("abutments.damping", first, (first - 0.1, first + 0.1), total,
                         (total - 0.1, total + 0.1))  # fmt: skip
    printed([Sensitivity("b", "dcr_backfill", "mean", 8, 10, 0.5, 0.1, 0.2, (field,))])
    output = capsys.readouterr().out
    assert ("note: abutments.damping: a first-order index" in output) is noted
    assert "at n = 8 base samples" in output or not noted


def test_sensitivity_refuses_a_study_without_a_saltelli_design(tmp_path):
    path = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SAMPLED)
    assert invoke("run", path, "-o", "l.h5").exit_code == 0
    result = invoke("sensitivity", "l.h5")
    assert result.exit_code == 2 and "not a study with a saltelli design" in result.output


# ---------------------------------------------------------------------------------------------
# Screening and fragilities of sampled bridges

TORNADO = """uncertainty:
  design: tornado
  percentiles: [10, 90]
  fields:
    abutments.gap: {distribution: uniform, low: 0.06, high: 0.18}
    abutments.ultimate_displacement: {distribution: lognormal, median: 0.10, beta: 0.3}
fidelity: fast
output: {histories: none}
"""


def test_a_tornado_swings_each_field_between_its_percentiles(tmp_path):
    """2d + 1 = 5 bridges: the medians (0.12 m; 0.10 m), then each field at its 10th and 90th
    percentile: 0.06 + 0.1·0.12 = 0.072 and 0.168 m; 0.10·exp(∓1.2816·0.3) = 0.0681 and 0.1469 m
    (z₀.₉ = 1.2816). dcr_backfill = (u − u_jo)/u_ab falls as u_ab grows: its output at the high
    percentile is the smaller."""
    path = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=TORNADO)
    study = load_study(path)
    assert [b.id.split("+")[1] for b in study.bridges] == ["mid", "low1", "high1", "low2", "high2"]
    drawn = {b.id.split("+")[1]: b.swept for b in study.bridges}
    middle = {"abutments.gap": 0.12, "abutments.ultimate_displacement": 0.10}
    assert drawn["mid"] == pytest.approx(middle, rel=1e-12)
    assert drawn["low1"]["abutments.gap"] == pytest.approx(0.072, rel=1e-12)
    assert drawn["high1"]["abutments.gap"] == pytest.approx(0.168, rel=1e-12)
    assert drawn["low1"]["abutments.ultimate_displacement"] == pytest.approx(0.10, rel=1e-12)
    z = 1.2815515655446004  # Φ⁻¹(0.9)
    assert drawn["low2"]["abutments.ultimate_displacement"] == pytest.approx(
        0.10 * math.exp(-0.3 * z), rel=1e-12
    )
    assert invoke("run", path, "-o", "t.h5").exit_code == 0
    rows = json.loads(invoke("sensitivity", "t.h5", "--json").output)
    capacity = next(r for r in rows if r["field"] == "abutments.ultimate_displacement")
    assert capacity["output_high"] < capacity["output_median"] < capacity["output_low"]
    assert rows[0]["swing"] >= rows[1]["swing"]
    table = invoke("sensitivity", "t.h5").output  # units: the fields' (the config's), the output's
    assert "output at low [-]" in table and "swing [-]" in table
    assert all(line.split()[1] == "m" for line in table.splitlines() if line.startswith("abutm"))
    assert invoke("plot", "sensitivity", "t.h5", "-o", "t.png").exit_code == 0
    folded = invoke("fragility", "t.h5", "--fold-samples")
    assert folded.exit_code == 2 and "not draws from the distributions" in folded.output


def _stripes(medians: list[float], beta: float, records: int, seed: int) -> dict:
    """A peak table of stripes whose records' capacities are lognormal (median θ_k of sample k,
    β): at each level, a record reaches gap_closure (dcr_backfill > 0) where the level exceeds
    its capacity."""
    rng = np.random.default_rng(seed)
    levels = np.geomspace(0.05, 5.0, 40)
    rows: dict[str, list] = {k: [] for k in ("bridge", "record", "base_record", "intensity",
                                             "status", "failure_mode", "dcr_backfill")}  # fmt: skip
    for k, median in enumerate(medians):
        capacities = median * np.exp(beta * rng.standard_normal(records))
        for r, capacity in enumerate(capacities):
            for level in levels:
                rows["bridge"].append(f"b+s{k}")
                rows["record"].append(f"R{r}+{level:.10g}g")
                rows["base_record"].append(f"R{r}")
                rows["intensity"].append(level)
                rows["status"].append("ok")
                rows["failure_mode"].append("none")
                rows["dcr_backfill"].append(level / capacity - 1.0)
    return {name: np.array(values) for name, values in rows.items()}


def test_the_folded_fragility_is_the_mixture_of_the_samples():
    """Eight samples with medians spread over ln θ ~ ±0.4 and β = 0.3, 300 records each: the
    folded fit over all 2400 pairs has the mixture's moments (law of total variance): ln θ the
    mean of ln θ_k and β² = β_RTR² + Var(ln θ_k), within 4 %; its β_RTR and β_U those of the
    samples' own fits, and the shortcut their root sum of squares."""
    from rockbridge_cli.assessment.sampled_fragility import fold

    medians = list(np.exp(np.linspace(-0.4, 0.4, 8)) * 0.6)
    columns = _stripes(medians, 0.3, 300, seed=4)
    intensity = IntensitySection.of(
        {"measure": "pga_g", "levels": sorted(set(columns["intensity"].tolist()))}
    )
    samples = [f"b+s{k}" for k in range(8)]
    found = {f.folded.limit_state: f for f in fold(columns, intensity, samples, True)}
    item = found["gap_closure"]
    logs = np.log(medians)
    assert item.folded.median == pytest.approx(math.exp(logs.mean()), rel=0.04)
    assert item.folded.beta == pytest.approx(math.sqrt(0.3**2 + logs.var()), rel=0.04)
    assert item.beta_rtr == pytest.approx(0.3, rel=0.08)
    assert item.beta_u == pytest.approx(np.std(logs, ddof=1), rel=0.08)
    assert item.beta_shortcut == pytest.approx(math.hypot(item.beta_rtr, item.beta_u), rel=1e-12)
    assert item.samples == (8, 8)


SALTELLI_IDA = """uncertainty:
  design: saltelli
  size: 2
  fields:
    abutments.ultimate_displacement: {distribution: uniform, low: 0.05, high: 0.15}
intensity:
  measure: pga_g
  ida: {start: 0.2, step: 0.4, max: 2.6, tolerance: 0.1, limit_states: [abutment_failure]}
fidelity: fast
output: {histories: none}
"""


def test_sensitivity_of_an_ida_capacity_and_the_folded_fragility(tmp_path):
    """n = 2, d = 1: 6 bridges × 2 records, each an IDA. Its capacity's indices are computed
    (a larger u_ab fails the abutment later); a peak of an IDA is refused; `fragility
    --fold-samples` prints the folded fit."""
    path = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SALTELLI_IDA)
    assert invoke("run", path, "-o", "i.h5").exit_code == 0
    result = invoke("sensitivity", "i.h5", "--quantity", "capacity:abutment_failure", "--json")
    assert result.exit_code == 0, result.output
    (row,) = json.loads(result.output)
    assert row["statistic"] == "median capacity" and row["samples"] == 2
    peak = invoke("sensitivity", "i.h5", "--quantity", "dcr_backfill")
    assert peak.exit_code == 2 and "ask for a capacity" in peak.output
    folded = invoke("fragility", "i.h5", "--fold-samples", "--json")
    assert folded.exit_code == 0, folded.output
    (fit,) = json.loads(folded.output)
    assert fit["bridge"] == "studied-hbar1.25" and fit["samples"] == 6
    assert "beta_RTR" in invoke("fragility", "i.h5", "--fold-samples").output
    assert invoke("run", path, "--shard", "1/2", "-o", "half.h5").exit_code == 0
    for command in (
        ("fragility", "half.h5", "--fold-samples"),
        ("sensitivity", "half.h5", "--quantity", "capacity:abutment_failure"),
    ):
        part = invoke(*command)  # a shard: refused in one line (it was a KeyError, exit 1)
        assert part.exit_code == 2 and "merge its shards (rockbridge merge)" in part.output, (
            command,
            part.output,
        )
        assert "Traceback" not in part.output and "KeyError" not in part.output
    report = invoke("report", "i.h5", "-o", "i.html")
    assert report.exit_code == 0, report.output
    page = (tmp_path / "i.html").read_text(encoding="utf-8")
    assert "Sampled bridges: abutments.ultimate_displacement" in page and "β_RTR" in page

"""Intensity as a study dimension (multiple stripes) and the fragility fits on top of it.

Expected values: a scaled record's PGA or Sa(T) is its level exactly (both are linear in the
scale factor); the maximum-likelihood fit of Baker (2015) recovers the parameters of the
lognormal that generated the counts.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.stats import norm
from studies import write_study

from rockbridge_cli.assessment.fragility import fit_lognormal
from rockbridge_cli.cli import main
from rockbridge_cli.config.intensity import sa_amplification
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.quantities import STANDARD_GRAVITY
from rockbridge_cli.errors import InputError
from rockbridge_cli.motions.spectra import compute_psa
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study.run import run_study


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # default outputs (results/<stem>.h5) land in tmp_path


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_pga_stripes_scale_every_record_to_every_level(tmp_path):
    path = write_study(tmp_path, extra="intensity: {measure: pga_g, levels: [0.2, 0.5]}\n")
    study = load_study(path)
    assert [r.id for r in study.records] == ["R1+0.2g", "R1+0.5g", "R2+0.2g", "R2+0.5g"]
    for item in study.records:
        pga = np.abs(item.record.acceleration).max() / STANDARD_GRAVITY
        assert pga == pytest.approx(item.level, rel=1e-12) and item.base in ("R1", "R2")
    plain = load_study(write_study(tmp_path, name="plain.yaml"))
    assert study.config_hash != plain.config_hash
    run_study(study, workers=1)
    peaks = read_peaks(study.output)
    assert list(peaks["base_record"]) == ["R1", "R1", "R2", "R2"] * 2
    assert list(peaks["intensity"]) == [0.2, 0.5] * 4
    # R1 peaks at 5.0 m/s², so its 0.5 g copy is scaled by 0.5·9.80665/5.0
    assert peaks["scale"][1] == pytest.approx(0.5 * STANDARD_GRAVITY / 5.0, rel=1e-12)


def test_sa_stripes_hit_the_spectral_level(tmp_path):
    extra = "intensity: {measure: sa_g, levels: [0.3], period: 1.0}\n"
    study = load_study(write_study(tmp_path, extra=extra))
    for item in study.records:
        sa = compute_psa(item.record.acceleration, item.record.time_step, np.array([1.0]))[0]
        assert sa / STANDARD_GRAVITY == pytest.approx(0.3, rel=1e-9)


@pytest.mark.parametrize(
    ("section", "message"),
    [
        ("{measure: sa_g, levels: [0.3]}", "give period with measure sa_g"),
        ("{measure: pga_g, levels: [0.3], period: 1.0}", "give period with measure sa_g"),
        ("{measure: pga_g, levels: [0.3, 0.3]}", "a level is listed twice"),
        ("{measure: pga_g, levels: []}", "intensity.levels"),
        ("{measure: pgv_g, levels: [0.3]}", "intensity.measure"),
    ],
)
def test_bad_intensity_sections(tmp_path, section, message):
    with pytest.raises(InputError, match=message):
        load_study(write_study(tmp_path, extra=f"intensity: {section}\n"))


@pytest.mark.parametrize(
    ("section", "fields", "bound"),
    [
        ("{measure: pga_g, levels: [0.5, 499]}", ("intensity.levels.1",), "100 g at most"),
        ("{measure: pga_g, levels: [0.5], design: 101}", ("intensity.design",), "100 g at most"),
        ("{measure: pgv, ida: {start: 0.1, step: 0.1, max: 80}}", ("intensity.ida.max",),
         "75 m/s at most"),
        ("{measure: pgd, ida: {start: 300, step: 1, max: 400}}",
         ("intensity.ida.start", "intensity.ida.max"), "250 m at most"),
        ("{measure: sa_g, period: 1.0, levels: [1300]}", ("intensity.levels.0",), "1274 g at most"),
        ("{measure: avgsa_g, period_range: [0.2, 2.0], damping: 0.2, levels: [400]}",
         ("intensity.levels.0",), "322.5 g at most"),
    ],
)  # fmt: skip
def test_a_level_beyond_any_ground_motion_is_refused(tmp_path, section, fields, bound):
    """Issue 40: ``levels: [499]`` in g ran with a scale-factor warning. The bounds: 100 g of PGA,
    as for a record file (`records.files.ABSURD_PGA_G`: 25 × the largest recorded, ~4 g); 75 m/s
    of PGV and 250 m of PGD, 25 × the largest recorded (~3 m/s, ~10 m); Sa and AvgSa, 100 g times
    coth(πζ / (2√(1 − ζ²))), the most an oscillator amplifies any motion's peak: 12.74 at ζ = 0.05
    (1274 g), 3.225 at ζ = 0.2 (322.5 g) — numbers from the closed form, checked by quadrature in
    `test_the_spectral_bound_is_the_oscillators_greatest_amplification`."""
    with pytest.raises(InputError) as raised:
        load_study(write_study(tmp_path, extra=f"intensity: {section}\n"))
    message = str(raised.value)
    assert all(f"{field}: " in message for field in fields) and bound in message
    assert message.count("beyond any ground motion") == len(fields)


@pytest.mark.parametrize(
    "section",
    [
        "{measure: pga_g, levels: [100], design: 100}",
        "{measure: pgv, ida: {start: 0.1, step: 0.1, max: 75}}",
        "{measure: arias, levels: [1.0e6]}",
        "{measure: cav, levels: [1.0e6]}",
        "{measure: scale, levels: [1.0e6]}",
    ],
)
def test_a_level_at_the_bound_or_of_a_measure_without_one_is_only_warned_of(tmp_path, section):
    """At the bound (refused only above it), and for the measures without a natural bound
    (Arias and CAV grow with a record's length; a scale factor's bound is the record's own),
    the study loads; a stripe far from the records is warned of (the factor, `SCALE_FACTORS`)."""
    study = load_study(write_study(tmp_path, extra=f"intensity: {section}\n"))
    if "levels" in section:
        assert any("scaled by" in w for w in study.warnings)


def test_the_spectral_bound_is_the_oscillators_greatest_amplification():
    """coth(πζ / (2√(1 − ζ²))) against ω²∫|h(t)| dt computed by quadrature, with ω = 1 and
    h = e^(−ζt)·sin(ω_d t)/ω_d the oscillator's impulse response: a motion of peak A gives a
    relative displacement of at most A∫|h| dt, so Sa ≤ A·ω²∫|h| dt."""
    for damping in (0.02, 0.05, 0.2):
        omega_d = np.sqrt(1.0 - damping**2)
        t = np.linspace(0.0, 60.0 / damping, 2_000_001)
        h = np.exp(-damping * t) * np.abs(np.sin(omega_d * t)) / omega_d
        integral = float(np.sum((h[1:] + h[:-1]) / 2 * np.diff(t)))
        assert sa_amplification(damping) == pytest.approx(integral, rel=1e-6)


def test_the_fit_recovers_a_known_lognormal():
    """Counts drawn exactly from θ = 0.8 g, β = 0.35 at eight levels, 10⁵ records each."""
    levels = np.array([0.2, 0.4, 0.6, 0.8, 1.0, 1.3, 1.6, 2.0])
    tried = np.full(levels.size, 100_000)
    reached = np.round(tried * norm.cdf(np.log(levels / 0.8) / 0.35))
    median, beta = fit_lognormal(levels, reached, tried)
    assert median == pytest.approx(0.8, rel=1e-4) and beta == pytest.approx(0.35, rel=1e-3)


def test_the_fit_says_what_the_data_cannot_fix():
    levels = np.array([0.1, 0.3, 0.5])
    tried = np.array([10, 10, 10])
    assert fit_lognormal(levels, np.array([0, 0, 0]), tried) is None  # never reached
    assert fit_lognormal(levels, tried, tried) is None  # reached at the lowest level already
    median, beta = fit_lognormal(levels, np.array([0, 10, 10]), tried)  # all change at once
    assert median == pytest.approx(np.sqrt(0.1 * 0.3)) and beta is None


def test_fragility_from_a_stripe_study(tmp_path):
    extra = "intensity: {measure: pga_g, levels: [0.05, 0.2, 0.4, 0.8, 1.6]}\n"
    study = load_study(write_study(tmp_path, extra=extra))
    run_study(study, workers=1)
    result = invoke("fragility", study.output, "--json")
    assert result.exit_code == 0, result.output
    rows = json.loads(result.output)
    assert {r["limit_state"] for r in rows} >= {"gap_closure", "abutment_failure", "overturning"}
    peaks = read_peaks(study.output)
    for row in rows:
        assert set(row) >= {"bridge", "limit_state", "measure", "median", "beta", "capacities"}
        assert row["measure"] == "pga_g" and set(row["capacities"]) == {"R1", "R2"}
        if row["limit_state"] != "gap_closure":
            continue
        for record, capacity in row["capacities"].items():  # the first level that closes the gap
            mine = peaks[(peaks["bridge"] == row["bridge"]) & (peaks["base_record"] == record)]
            closed = mine[mine["dcr_backfill"] > 0]["intensity"]
            assert capacity == (closed.min() if len(closed) else None)
    table = invoke("fragility", study.output)
    assert table.exit_code == 0 and "gap_closure" in table.output
    for row in rows:  # a median whose β the data leave open is called a bound (the fit's rule)
        note = f"{row['bridge']}  {row['limit_state']}: β cannot be fitted from these data"
        assert (note in table.output) is (row["median"] is not None and row["beta"] is None)
    figure = invoke("plot", "fragility", study.output, "-o", tmp_path / "fragility.png")
    assert figure.exit_code == 0, figure.output
    assert (tmp_path / "fragility.png").stat().st_size > 10_000


def test_fragility_needs_stripes(tmp_path):
    study = load_study(write_study(tmp_path))
    run_study(study, workers=1)
    result = invoke("fragility", study.output)
    assert result.exit_code == 2 and "no intensity section" in result.output

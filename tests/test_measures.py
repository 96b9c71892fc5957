"""Intensity measures (issue 28): their values against closed forms, their scaling with a record's
factor, and the conversion of an IDA's capacities to another measure against an IDA run in that
measure."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from studies import REPO as ROOT

from rockbridge_cli.assessment.efficiency import (
    COMPARED,
    MeasureRow,
    best_measures,
    comparable_beta,
    compare,
)
from rockbridge_cli.assessment.fragility import fit_capacities, fragilities
from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.quantities import STANDARD_GRAVITY
from rockbridge_cli.motions import intensity
from rockbridge_cli.study.run import run_study


def test_a_triangle_by_hand():
    """a = 0, A, 0 at step h (a triangle): ∫a² dt = 2·A²·h/3, ∫|a| dt = A·h, the velocity peaks
    at the end, A·h, and the displacement there is A·h²/6 + A·h·h/2 + … integrated by hand:
    d(2h) = A·h² (the triangle's area A·h times its centroid's distance to the end, h)."""
    a, h = np.array([0.0, 3.0, 0.0]), 0.02
    assert intensity.arias_intensity(a, h) == pytest.approx(
        math.pi / (2 * STANDARD_GRAVITY) * 2 * 9.0 * h / 3, rel=1e-14
    )
    assert intensity.cumulative_absolute_velocity(a, h) == pytest.approx(3.0 * h, rel=1e-14)
    pga, pgv, pgd = intensity.peak_motion(a, h)
    assert (pga, pgv, pgd) == pytest.approx((3.0, 3.0 * h, 3.0 * h * h), rel=1e-14)


def test_a_step_across_zero_by_hand():
    """a = A, −A over one step: |a| is two triangles of height A and base h/2 (CAV = A·h/2); the
    velocity peaks between the samples, at the zero crossing, at A·h/4 (a sample-only peak would
    give 0)."""
    a, h = np.array([2.0, -2.0]), 0.1
    assert intensity.cumulative_absolute_velocity(a, h) == pytest.approx(2.0 * h / 2, rel=1e-14)
    assert intensity.peak_motion(a, h)[1] == pytest.approx(2.0 * h / 4, rel=1e-14)


def test_one_sine_cycle_against_its_integrals():
    """a = a0·sin(ωt) over one period, from rest: v = (a0/ω)(1 − cos ωt) peaks at 2a0/ω;
    ∫|a| dt = 4a0/ω; ∫a² dt = a0²·π/ω. Sampled at 2000 points a period: the piecewise-linear
    interpolant's integrals differ by O((hω)²): ∫a² by (hω)²/6 = 1.6e-6 relative, the others
    less."""
    a0, period = 3.0, 0.5
    omega, time = 2 * math.pi / period, np.linspace(0.0, period, 2001)
    a, h = a0 * np.sin(omega * time), time[1]
    assert intensity.peak_motion(a, h)[1] == pytest.approx(2 * a0 / omega, rel=1e-6)
    assert intensity.cumulative_absolute_velocity(a, h) == pytest.approx(4 * a0 / omega, rel=1e-6)
    arias = math.pi / (2 * STANDARD_GRAVITY) * a0**2 * math.pi / omega
    assert intensity.arias_intensity(a, h) == pytest.approx(arias, rel=2e-6)


@settings(max_examples=30, deadline=None)
@given(
    samples=st.lists(st.floats(-20.0, 20.0), min_size=2, max_size=40),
    factor=st.floats(0.01, 100.0),
)
def test_a_scaled_record_scales_each_measure_by_its_power(samples, factor):
    """λ·a has each measure scaled by λ^power (Arias λ², the others λ): what makes the
    conversion of capacities exact."""
    a, h = np.array(samples), 0.01
    for name in ("pga_g", "pgv", "pgd", "arias", "cav"):
        power = intensity.MEASURES[name].power
        base, scaled = (intensity.measure_value(name, x, h) for x in (a, factor * a))
        assert scaled == pytest.approx(factor**power * base, rel=1e-9, abs=1e-300), name


def test_convert_inverts_the_scaling():
    """A record with PGA 0.2 g, PGV 0.3 m/s and Arias 0.5 m/s scaled to PGA 0.8 g (λ = 4) has
    PGV 1.2 m/s and Arias 8 m/s; scaled to Arias 2 m/s (λ = 2), PGA 0.4 g."""
    assert intensity.convert(0.8, 0.2, "pga_g", 0.3, "pgv") == pytest.approx(1.2)
    assert intensity.convert(0.8, 0.2, "pga_g", 0.5, "arias") == pytest.approx(8.0)
    assert intensity.convert(2.0, 0.5, "arias", 0.2, "pga_g") == pytest.approx(0.4)


def test_censoring_per_record_equals_one_bound_for_all():
    """`fit_capacities` with per-record bounds that are all equal is the fit with one bound."""
    capacities = np.array([0.0, 0.3, 0.45, 0.5, np.inf, 0.7])
    one = fit_capacities(capacities, 0.1, 2.0)
    each = fit_capacities(capacities, np.full(6, 0.1), np.full(6, 2.0))
    assert one == each


def ida_study(tmp_path, measure: str, lattice: tuple[float, float, float], record: str) -> Path:
    """An IDA of the studied bridge h̄ = 2 under one bundled record, scanning ``lattice`` (start,
    step, max) of ``measure`` to 1 %, for gap closure and half the backfill's capacity."""
    start, step, top = lattice
    path = tmp_path / f"ida-{measure}-{record}.yaml"
    path.write_text(
        f"bridges: [{ROOT}/configs/bridges/studied-hbar2.00.yaml]\n"
        f"records: {{files: [{{path: {ROOT}/records/ec8-type1-C-ag0.6g/{record}.txt}}]}}\n"
        f"intensity:\n  measure: {measure}\n  ida: {{start: {start!r}, step: {step!r}, "
        f"max: {top!r}, tolerance: 0.01, limit_states: [gap_closure, backfill_50]}}\n"
        "fidelity: default\noutput: {histories: none}\n",
        encoding="utf-8",
    )
    return path


@pytest.mark.parametrize("record", ["AR03", "AR07"])
def test_capacities_converted_to_pgv_equal_an_ida_run_on_pgv(tmp_path, record):
    """An IDA in PGA, its capacities converted to PGV, against an IDA run in PGV on the lattice
    the record's PGV/PGA maps the first one to: both analyze the same scaled records, so the
    capacities agree to round-off (1e-9 here, far inside the IDA's 1 % tolerance). On other
    lattices they need not agree record by record: rocking IDA curves are not monotonic, and a
    scan on other levels may meet another first crossing (assessment.ida)."""
    path = ida_study(tmp_path, "pga_g", (0.1, 0.2, 2.1), record)
    study = load_study(path, output=tmp_path / "a.h5")
    acceleration, step = study.records[0].record.acceleration, study.records[0].record.time_step
    ratio = intensity.measure_value("pgv", acceleration, step) / intensity.measure_value(
        "pga_g", acceleration, step
    )
    run_study(study, workers=1)
    path = ida_study(tmp_path, "pgv", (0.1 * ratio, 0.2 * ratio, 2.1 * ratio), record)
    run_study(load_study(path, output=tmp_path / "v.h5"), workers=1)
    converted = fragilities(tmp_path / "a.h5", 0, measure="pgv")
    ran = fragilities(tmp_path / "v.h5", 0)
    for mine, theirs in zip(converted, ran, strict=True):
        assert (mine.limit_state, mine.measure) == (theirs.limit_state, "pgv")
        assert mine.capacities[record] == pytest.approx(theirs.capacities[record], rel=1e-9)
        assert mine.capacities[record] is not None


def test_the_measures_table(tmp_path):
    """At least six measures; PGA/(g·tan α) is PGA times a constant of the bridge, so its β is
    PGA's, whatever the records (to the censored fit's optimiser, 1e-6)."""
    path = tmp_path / "ida.yaml"
    path.write_text(
        f"bridges: [{ROOT}/configs/bridges/studied-hbar2.00.yaml]\n"
        f"records: {{set: {ROOT}/records/ec8-type1-C-ag0.6g}}\n"
        "intensity:\n  measure: pga_g\n  ida: {start: 0.1, step: 0.4, max: 1.3, tolerance: 0.05,"
        " limit_states: [gap_closure, backfill_50]}\nfidelity: fast\noutput: {histories: none}\n",
        encoding="utf-8",
    )
    run_study(load_study(path, output=tmp_path / "a.h5"), workers=2)
    rows = compare(tmp_path / "a.h5", COMPARED + ("pga_tan_alpha",))
    measures = {r.measure for r in rows}
    assert len(measures) >= 6
    beta = {(r.limit_state, r.measure): r.beta for r in rows}
    for state in ("gap_closure", "backfill_50"):
        assert beta[state, "pga_tan_alpha"] == pytest.approx(beta[state, "pga_g"], rel=1e-6)
    # issue 40: the command leaves the duplicate out, halves Arias' β and names the best measure
    result = CliRunner().invoke(main, ["fragility", str(tmp_path / "a.h5"), "--compare-measures"])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert "pga_tan_alpha" not in result.output and "arias ½β" in lines[1]
    header = lines[1].split()
    for state in ("gap_closure", "backfill_50"):
        row = next(line.split() for line in lines if line.split()[1:2] == [state])
        arias = row[header.index("arias") - 1]  # "½β" is a word of its header, not a column
        assert float(arias) == pytest.approx(beta[state, "arias"] / 2, rel=2e-3)
    best = min(("pga_g", "pgv", "pgd", "sa_g", "avgsa_g", "arias", "cav"),
               key=lambda m: beta["gap_closure", m] / (2 if m == "arias" else 1))  # fmt: skip
    assert any(line.startswith("smallest β: ") and best in line for line in lines)


def test_the_best_measure_compares_half_the_beta_of_an_energy_measure():
    """Arias intensity scales as a record's factor squared: a β of 0.4 in it predicts as well as
    0.2 in PGA (ln I_A = 2 ln a + const)."""
    rows = [MeasureRow("b", state, measure, beta, 10, None, None, None, None)
            for state, measure, beta in (("s", "pga_g", 0.3), ("s", "arias", 0.5),
                                         ("t", "pga_g", 0.2), ("t", "arias", 0.5),
                                         ("u", "pga_g", None))]  # fmt: skip
    assert best_measures(rows) == {"arias": 1, "pga_g": 1}
    assert comparable_beta("arias", 0.5) == 0.25 and comparable_beta("pgv", 0.5) == 0.5

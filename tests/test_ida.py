"""Incremental dynamic analysis: the rule (scan, then bisect), its lattice, the runner's rounds,
and the fragility of the capacities.

Expected values: for the rule on synthetic curves, a capacity must bracket the synthetic
threshold to the tolerance (the definition in `assessment.ida`); on real analyses, the capacity must
agree with plain stripe runs of the same record scaled to the capacity and to the level just
below it (a plain `rockbridge run` computes the same scaled samples, so the verdicts must be the
same, bit for bit); the censored fit must recover the lognormal the capacities were drawn from.
"""

from __future__ import annotations

import csv
import io
import json

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from scipy.stats import norm
from studies import contents, write_study

from rockbridge_cli.assessment import limit_states
from rockbridge_cli.assessment.fragility import fit_capacities, fragilities
from rockbridge_cli.assessment.ida import Lattice, Outcome, walk
from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.quantities import check_limit_state
from rockbridge_cli.core.summary import summarize
from rockbridge_cli.errors import InputError
from rockbridge_cli.report import write_report
from rockbridge_cli.results import read_peaks
from rockbridge_cli.results.sections import IdaSection
from rockbridge_cli.study.run import run_study

IDA = (
    "intensity: {measure: pga_g, ida: {start: 0.1, step: 0.4, max: 2.5, tolerance: 0.05, "
    "limit_states: [gap_closure, backfill_50, abutment_failure, overturning]}}\n"
    "fidelity: fast\noutput: {histories: none}\n"
)
"""Two bridges × the two synthetic bursts of `studies`; their abutments fail at 1.1–2.1 g."""


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


# The rule


def _ida(data: dict) -> IdaSection:
    """An intensity section's IDA, of no limit state unless ``data`` names them."""
    return IdaSection.of({"limit_states": [], **data})


def test_the_lattice_holds_every_scan_and_bisection_level():
    lattice = Lattice.of(_ida({"start": 0.1, "step": 0.2, "max": 4.0, "tolerance": 0.02}))
    assert lattice.depth == 7  # 0.2 / 2^7 = 0.0016 ≤ 0.02 · 0.1 < 0.2 / 2^6
    assert lattice.level(0) == 0.1 and lattice.level(lattice.count - 1) == pytest.approx(3.9)
    assert lattice.level(3 * lattice.stride) == pytest.approx(0.7, rel=1e-15)
    assert lattice.level(lattice.stride // 2) == pytest.approx(0.2, rel=1e-15)


def synthetic(lattice, thresholds):
    """A monotonic curve: state s is reached from level thresholds[s] on; runs are counted."""
    ran = []

    def reaches(n):
        ran.append(n)
        return Outcome(frozenset(s for s, c in thresholds.items() if lattice.level(n) >= c))

    return reaches, ran


@pytest.mark.parametrize("tolerance", [0.2, 0.05, 0.01])
def test_a_capacity_brackets_the_threshold_to_the_tolerance(tolerance):
    lattice = Lattice.of(_ida({"start": 0.1, "step": 0.3, "max": 3.0, "tolerance": tolerance}))
    thresholds = {"a": 0.1234, "b": 1.777, "c": 2.65}  # scan levels 0.1, 0.4, …, 2.8
    reaches, ran = synthetic(lattice, thresholds)
    steps = walk(lattice, tolerance, tuple(thresholds), reaches)
    assert not steps.wanted
    for state, threshold in thresholds.items():
        below, level = (lattice.level(n) for n in steps.capacities[state])
        assert below < threshold <= level
        assert level - below <= tolerance * level
    assert max(ran) == 9 * lattice.stride  # the scan stops at 2.8, where every state is reached


def test_reached_at_start_and_never_reached():
    lattice = Lattice.of(_ida({"start": 0.5, "step": 0.5, "max": 2.0, "tolerance": 0.05}))
    reaches, ran = synthetic(lattice, {"early": 0.1, "never": 9.0})
    steps = walk(lattice, 0.05, ("early", "never"), reaches)
    assert steps.capacities["early"] == (-1, 0)  # at most start: nothing below to bisect
    assert steps.capacities["never"] == (-1, None)
    assert sorted(set(ran)) == [0, 1 * lattice.stride, 2 * lattice.stride, 3 * lattice.stride]


def test_a_non_monotonic_curve_follows_the_rule():
    """Reached at the third scan level only: the capacity is between the second and the third,
    whatever the levels above say."""
    lattice = Lattice.of(_ida({"start": 1.0, "step": 1.0, "max": 5.0, "tolerance": 0.1}))
    resurrects = {2 * lattice.stride}

    def reaches(n):
        hit = n in resurrects or lattice.level(n) >= 2.6 and n <= 2 * lattice.stride
        return Outcome(frozenset({"s"}) if hit else frozenset())

    steps = walk(lattice, 0.1, ("s",), reaches)
    below, level = (lattice.level(n) for n in steps.capacities["s"])
    assert 2.0 <= below < 2.6 <= level <= 3.0 and level - below <= 0.1 * level


def test_the_walk_asks_for_what_it_needs_next():
    """Without verdicts the rule asks for the start; with the scan done, for the bisections."""
    lattice = Lattice.of(_ida({"start": 1.0, "step": 1.0, "max": 3.0, "tolerance": 0.3}))
    assert walk(lattice, 0.3, ("s",), lambda n: None).wanted == {0}
    scan = {0: Outcome(frozenset()), lattice.stride: Outcome(frozenset({"s"}))}
    steps = walk(lattice, 0.3, ("s",), scan.get)
    assert steps.wanted == {lattice.stride // 2}  # between 1.0 and 2.0


def ending(lattice, thresholds, failures):
    """A monotonic curve whose analyses from level failures[s] on end in the failure s (the
    lowest such level wins): a failure reaches its own state and every state below it."""
    ran = []

    def outcome(n):
        ran.append(n)
        level = lattice.level(n)
        ended = min((c, s) for s, c in failures.items() if level >= c)[1] if any(
            level >= c for c in failures.values()) else ""  # fmt: skip
        hit = {s for s, c in thresholds.items() if level >= c} | ({ended} if ended else set())
        return Outcome(frozenset(hit), ended)

    return outcome, ran


def test_a_curve_ends_at_its_first_failure():
    """The abutment fails from 2.0 on: overturning cannot be observed, the scan stops at 2.2, the
    first scan level at or above 2.0, nothing above it runs, and the curve ends at the lowest
    level that failed, the abutment's capacity."""
    lattice = Lattice.of(_ida({"start": 0.2, "step": 0.4, "max": 4.0, "tolerance": 0.05}))
    states = ("gap_closure", "abutment_failure", "overturning")
    outcome, ran = ending(lattice, {"gap_closure": 0.3}, {"abutment_failure": 2.0})
    steps = walk(lattice, 0.05, states, outcome)
    assert not steps.wanted and max(ran) == 5 * lattice.stride  # 0.2 + 5 · 0.4 = 2.2
    assert steps.ended_by == "abutment_failure"
    assert steps.end == steps.capacities["abutment_failure"][1]
    assert steps.unreachable("overturning") and steps.capacities["overturning"] == (-1, None)
    below, level = (lattice.level(n) for n in steps.capacities["abutment_failure"])
    assert below < 2.0 <= level and level - below <= 0.05 * level
    assert not steps.unreachable("gap_closure") and not steps.unreachable("abutment_failure")


def test_a_failure_found_by_bisection_shortens_the_curve():
    """The scan meets the abutment's failure at 2.2, but its bisection finds a pier overturning at
    2.05 (from 2.04 on, a bridge whose failures come in the other order in one direction): the
    curve ends there, the abutment's failure is unreachable, overturning's capacity is bracketed
    below 2.05, and the rule replayed on its own verdicts asks for nothing more."""
    lattice = Lattice.of(_ida({"start": 0.2, "step": 0.4, "max": 4.0, "tolerance": 0.02}))
    states = ("abutment_failure", "overturning")
    outcome, ran = ending(lattice, {}, {"abutment_failure": 2.1, "overturning": 2.04})
    scan_only = {n: outcome(n) for n in range(0, 6 * lattice.stride, lattice.stride)}
    scan_only[5 * lattice.stride] = Outcome(frozenset({"abutment_failure"}), "abutment_failure")
    first = walk(lattice, 0.02, states, scan_only.get)
    assert first.end == 5 * lattice.stride and first.wanted  # bisecting the abutment's failure

    def mixed(n):  # the scan level 2.2 fails the abutment, levels 2.04–2.2 below it overturn
        return scan_only.get(n) or outcome(n)

    steps = walk(lattice, 0.02, states, mixed)
    assert not steps.wanted and steps.ended_by == "overturning"
    assert 2.04 <= lattice.level(steps.end) < 2.2
    assert steps.unreachable("abutment_failure")
    below, level = (lattice.level(n) for n in steps.capacities["overturning"])
    assert below < 2.04 <= level and level - below <= 0.02 * level
    replayed = walk(lattice, 0.02, states, {n: mixed(n) for n in steps.visited}.get)
    assert not replayed.wanted and replayed.capacities == steps.capacities


def test_limit_states_of_a_peak_table():
    columns = {"dcr_backfill": np.array([0.0, 0.3, 0.5, 1.0, np.nan]),
               "failure_mode": np.array(["none", "none", "none", "abutment", ""])}  # fmt: skip
    assert limit_states.reached("gap_closure", columns).tolist() == [0, 1, 1, 1, 0]
    assert limit_states.reached("backfill_50", columns).tolist() == [0, 0, 1, 1, 0]
    assert limit_states.reached("backfill_25", columns).tolist() == [0, 1, 1, 1, 0]
    assert limit_states.reached("abutment_failure", columns).tolist() == [0, 0, 0, 1, 0]
    with pytest.raises(ValueError, match="unknown limit state 'backfill_0'"):
        check_limit_state("backfill_0")


# The config


@pytest.mark.parametrize(
    ("section", "message"),
    [
        ("{measure: pga_g, levels: [0.3], ida: {start: 0.1, step: 0.1, max: 1}}", "exactly one"),
        ("{measure: pga_g}", "exactly one of levels"),
        ("{measure: pga_g, ida: {start: 1, step: 0.1, max: 0.5}}", "max must not be below"),
        ("{measure: pga_g, ida: {start: 0.1, step: 0.1, max: 1, limit_states: [collapse]}}",
         "unknown limit state 'collapse'"),
        ("{measure: pga_g, ida: {start: 1e-9, step: 1, max: 2, tolerance: 0.001}}",
         r"at most 2\^20"),
        ("{measure: pga_g, ida: {start: 0.1, max: 1}}", "intensity.ida.step"),
    ],
)  # fmt: skip
def test_bad_ida_sections(tmp_path, section, message):
    with pytest.raises(InputError, match=message):
        load_study(write_study(tmp_path, extra=f"intensity: {section}\n"))


# The runner


@pytest.fixture(scope="module")
def ida_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ida")
    study = load_study(write_study(folder, extra=IDA), output=folder / "ida.h5")
    report = run_study(study, workers=2)
    return study, report


def test_an_ida_runs_in_rounds_and_keeps_every_level(ida_run):
    study, report = ida_run
    peaks = read_peaks(study.output)
    assert report.ran == report.total == len(peaks) > 40
    for (_, record), rows in peaks.groupby(["bridge", "base_record"], sort=False):
        assert list(rows["intensity"]) == sorted(rows["intensity"])  # the order of the results
        assert rows["intensity"].iloc[0] == 0.1
        ids = [f"{record}+{x:.10g}g" for x in rows["intensity"]]
        assert list(rows["record"]) == ids
    with h5py.File(study.output) as file:
        assert json.loads(file.attrs["intensity"])["ida"]["tolerance"] == 0.05
        assert file.attrs["complete"] and list(file["records"]) == ["R1", "R2"]
    assert run_study(study, workers=1).ran == 0  # complete: nothing to do


def test_no_level_runs_above_a_failure_and_overturning_is_unreachable(ida_run):
    """The model has one degree of freedom: u_deck and the piers' rotations are functions of θ1,
    so a bridge whose tall pier reaches the abutment's failure rotation before either overturning
    rotation, in both directions (`summarize`'s failure rotations), fails its abutment before
    any pier can overturn. The studied bridges are such bridges: every curve ends at its
    abutment's failure, no analysis runs above a failure, and overturning is unreachable on
    every curve."""
    study, _ = ida_run
    peaks = read_peaks(study.output)
    for bridge in study.bridges:
        caps = summarize(bridge.config.to_bridge())["failure_rotations"]
        for direction in ("p", "n"):
            abutment = abs(caps["abutment"][direction])
            assert abutment < min(abs(caps[m][direction]) for m in caps if m != "abutment")
    assert set(peaks["failure_mode"]) == {"none", "abutment"}
    scans = np.round(0.1 + 0.4 * np.arange(7), 12)  # the scan levels of IDA, 0.1 to 2.5 g
    for _, rows in peaks.groupby(["bridge", "base_record"]):
        levels = np.round(rows["intensity"].to_numpy(), 12)
        failed = levels[(rows["failure_mode"] != "none").to_numpy()]
        assert levels.max() == min(set(failed) & set(scans))  # no scan above the first failure
    result = invoke("fragility", study.output)
    assert result.exit_code == 0, result.output
    for bridge in ("studied-hbar1.00", "studied-hbar2.00"):
        line = f"{bridge}  overturning: unreachable — the abutment fails first on 2/2 records"
        assert line in result.output
    rows = json.loads(invoke("fragility", study.output, "--json").output)
    overturning = [row for row in rows if row["limit_state"] == "overturning"]
    assert all(row["median"] is None and len(row["unreachable"]) == 2 for row in overturning)


def test_the_report_of_an_ida_counts_records_and_points_to_the_capacities(ida_run, tmp_path):
    """An IDA's levels differ by record: the page counts its 2 records (not its analyses' scaled
    ids), gives no demand/capacity table over all levels at once, and says which states a
    failure kept from being observed."""
    study, _ = ida_run
    text = write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8")
    analyses = len(read_peaks(study.output))
    assert f"{analyses} analyses of 2 bridges under 2 records in an IDA of PGA" in text
    demand = text.split("<h2>Demand and capacity</h2>")[1].split("<h2>")[0]
    assert "IDA&#x27;s levels differ by record" in demand and "<table>" not in demand
    assert "studied-hbar1.00: overturning: unreachable — the abutment fails first on 2/2" in text
    # issue 40: the efficiency table gives Arias intensity's β halved, as its sentence compares
    # it, and names the measure with the smallest β
    which = text.split("<h2>Which intensity measure</h2>")[1].split("<h2>")[0]
    assert "its column gives half its β" in which and "Arias intensity (½β)" in which
    assert "The smallest β: " in which and "pga_tan_alpha" not in which
    # an IDA's page gives each record's capacities, not a peak row per level run (pages of them)
    assert "<h2>Peak table</h2>" not in text and "<h2>Capacities</h2>" in text
    table = text.split("<h2>Capacities</h2>")[1].split("</table>")[0]
    reached = [(f.limit_state, c) for f in fragilities(study.output)
               for c in f.capacities.values() if c is not None]  # fmt: skip
    assert table.count("<tr>") == 1 + 2 * 2  # the header, two bridges × two records
    state, capacity = reached[0]
    assert f"{capacity:.3g}" in table and f"{state} [g]" in table


def test_a_capacity_agrees_with_plain_runs_just_below_and_above(ida_run, tmp_path):
    """For every bridge × record and limit state, a stripe study at the capacity and at the
    level just below it (the IDA's last level not reaching the state) reaches the state at the
    first and not at the second."""
    study, _ = ida_run
    rows = json.loads(invoke("fragility", study.output, "--json").output)
    peaks = read_peaks(study.output)
    levels, expected = set(), []
    for row in rows:
        for record, capacity in row["capacities"].items():
            if capacity is None:
                continue
            mine = peaks[(peaks["bridge"] == row["bridge"]) & (peaks["base_record"] == record)]
            run_below = mine["intensity"][mine["intensity"] < capacity]
            below = float(run_below.max())
            assert (capacity - below) <= 0.05 * capacity or below == 0.1
            levels |= {below, capacity}
            expected += [(row["bridge"], record, row["limit_state"], below, False),
                         (row["bridge"], record, row["limit_state"], capacity, True)]  # fmt: skip
    assert len(expected) >= 2 * 10
    stripes = (f"intensity: {{measure: pga_g, levels: {sorted(levels)!r}}}\n"
               "fidelity: fast\noutput: {histories: none}\n")  # fmt: skip
    path = write_study(tmp_path, extra=stripes, name="plain.yaml")
    result = invoke("run", path, "-o", tmp_path / "plain.h5")
    assert result.exit_code == 0, result.output
    plain = read_peaks(tmp_path / "plain.h5").set_index(["bridge", "base_record", "intensity"])
    for bridge, record, state, level, reached in expected:
        row = plain.loc[(bridge, record, level)]
        assert bool(limit_states.reached(state, row)) is reached, (bridge, record, state, level)


def test_an_interrupted_ida_resumes_to_the_same_file(ida_run, tmp_path):
    study, _ = ida_run
    expected = contents(study.output)
    again = load_study(study.path, output=tmp_path / "again.h5")

    def stop_after_20(finished, done, total):
        if done == 20:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(again, workers=1, progress=stop_after_20)
    kept = read_peaks(again.output).shape[0]  # the 20 reported, and the rest of their batch
    assert 20 <= kept < len(read_peaks(study.output))
    report = run_study(again, workers=2)
    assert report.resumed == kept and report.ran == report.total - kept
    assert contents(again.output) == expected


def test_ida_shards_merged_equal_a_single_run(ida_run, tmp_path):
    study, _ = ida_run
    parts = [tmp_path / f"part{k}.h5" for k in (1, 2)]
    for k, part in zip((1, 2), parts, strict=True):
        result = invoke("run", study.path, "--shard", f"{k}/2", "-o", part)
        assert result.exit_code == 0, result.output
    merged = invoke("merge", tmp_path / "all.h5", *parts)
    assert merged.exit_code == 0, merged.output
    assert "from 2 parts" in merged.output and "missing" not in merged.output
    merged, single = contents(tmp_path / "all.h5"), contents(study.output)
    for found in (merged, single):  # provenance: where and how the parts ran
        found["/"] = ({k: v for k, v in found["/"][0].items()
                       if k not in ("host", "merged_from", "study_file")}, None)  # fmt: skip
    assert merged == single


def test_fragility_of_an_ida_is_stored_printed_and_drawn(ida_run, tmp_path):
    study, _ = ida_run
    rows = json.loads(invoke("fragility", study.output, "--json").output)
    assert {r["limit_state"] for r in rows} == {
        "gap_closure",
        "backfill_50",
        "abutment_failure",
        "overturning",
    }
    assert {"bridge", "limit_state", "measure", "median", "beta", "capacities"} <= set(rows[0])
    with h5py.File(study.output) as file:
        stored = file["fragility"]
        assert json.loads(stored.attrs["records"]) == ["R1", "R2"]
        np.testing.assert_array_equal(
            stored["median"][()], [np.nan if r["median"] is None else r["median"] for r in rows]
        )
        capacities = stored["capacities"][()]
    for row, stored_row in zip(rows, capacities, strict=True):
        assert [row["capacities"][r] for r in ("R1", "R2")] == stored_row.tolist() or (
            row["limit_state"] == "overturning" and np.isnan(stored_row).all()
        )
        if row["limit_state"] == "overturning":
            continue  # unreachable (the test above)
        known = np.log([c for c in row["capacities"].values()])
        assert row["median"] == pytest.approx(np.exp(known.mean()), rel=1e-12)
    table = list(
        csv.DictReader(io.StringIO(invoke("fragility", study.output, "--csv", "-").output))
    )
    assert [(r["bridge"], r["limit_state"]) for r in table] == [
        (r["bridge"], r["limit_state"]) for r in rows
    ]
    for line, row in zip(table, rows, strict=True):
        if row["median"] is None:
            assert line["median"] == "" and row["limit_state"] == "overturning"
            continue
        assert float(line["median"]) == row["median"]
        assert float(line["capacity_R2"]) == row["capacities"]["R2"]
    for kind in ("ida", "fragility"):
        figure = tmp_path / f"{kind}.png"
        result = invoke("plot", kind, study.output, "-o", figure)
        assert result.exit_code == 0, result.output
        assert figure.stat().st_size > 10_000
    bad = invoke("plot", "ida", study.output, "--quantity", "status")
    assert bad.exit_code == 2 and "not a peak column: 'status'" in bad.output


# The fit


def test_the_capacity_fit_is_the_log_mean_and_log_deviation():
    capacities = np.array([0.8, 1.1, 1.5, 2.2])
    median, beta = fit_capacities(capacities, 0.1, 4.0)
    assert median == pytest.approx(np.exp(np.log(capacities).mean()), rel=1e-14)
    assert beta == pytest.approx(np.log(capacities).std(), rel=1e-14)


def test_the_censored_fit_recovers_a_known_lognormal():
    """20 000 capacities at the quantiles of θ = 1.2 g, β = 0.45; those above 2 g never reached
    within the scan (censored), those below 0.5 g reached at the start already."""
    capacities = 1.2 * np.exp(0.45 * norm.ppf((np.arange(20_000) + 0.5) / 20_000))
    coded = np.where(capacities > 2.0, np.inf, np.where(capacities <= 0.5, 0.0, capacities))
    assert np.isinf(coded).sum() > 2000 and (coded == 0).sum() > 100
    median, beta = fit_capacities(coded, 0.5, 2.0)
    assert median == pytest.approx(1.2, rel=2e-3) and beta == pytest.approx(0.45, rel=5e-3)
    dropped = fit_capacities(coded[np.isfinite(coded) & (coded > 0)], 0.5, 2.0)
    assert abs(dropped[1] - 0.45) > 0.1  # leaving the censored records out would be biased


def test_the_ida_figure_of_one_bridge_keeps_its_legend_inside(tmp_path, monkeypatch):
    """One bridge, one panel: the legend of three limit states fits the figure's width."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from rockbridge_cli.plots import ida as figures

    path = write_study(tmp_path, bridges=("studied-hbar1.25",), records=("R1",), extra=IDA)
    study = load_study(path, output=tmp_path / "one.h5")
    run_study(study, workers=1)
    drawn = []
    monkeypatch.setattr(figures, "save", lambda figure, output: drawn.append(figure) or output)
    figures.plot_ida(study.output, tmp_path / "one.png")
    canvas = FigureCanvasAgg(drawn[0])
    canvas.draw()
    box = drawn[0].legends[0].get_window_extent(canvas.get_renderer())
    assert 0.0 <= box.x0 and box.x1 <= drawn[0].bbox.width


def test_the_ida_figure_names_its_bridges_and_its_axis_as_fig_9_does(ida_run, tmp_path):
    """Issue 40: panel titles were ids and the x label a column name (`u_deck_max [mm]`)."""
    import re

    import matplotlib

    from rockbridge_cli.plots.ida import plot_ida
    from rockbridge_cli.results.reading import bridge_attributes, open_results

    study, _ = ida_run
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        svg = plot_ida(study.output, tmp_path / "ida.svg").read_text(encoding="utf-8")
    texts = re.findall(r"<text[^>]*>([^<]*)</text>", svg)
    with open_results(study.output) as file:
        names = [attributes["name"] for attributes in bridge_attributes(file).values()]
    assert all(name in texts for name in names), texts
    assert "u_deck_max" not in svg and "peak" in svg  # mathtext: "peak" and u, deck, CG apart

"""A swept orientation's fragility where a user reads it (issue 42, item 2: "stripes, IDA and
fragility can be run on the orientation median or the maximum"): the run stores it per pair of
horizontal components at the study's ``intensity.orientation`` (the median without one), as
``rockbridge fragility --orientation`` computes it, and ``plot fragility`` draws the pairs."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from studies import write_study

from rockbridge_cli.assessment import limit_states
from rockbridge_cli.assessment.fragility import fragilities
from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.errors import InputError
from rockbridge_cli.plots import fragility as fragility_plot
from rockbridge_cli.results.reading import peak_columns

LEVELS = (0.15, 0.3, 0.6, 1.2)
"""The stripes [g]: from about the onset of rocking of the h̄ = 2 bridge (0.10–0.15 g) to
well past it."""

ANGLES = (0.0, 30.0, 90.0)
"""The angles of each pair [deg]: P and Q, each the other mirrored, differ at 30°."""


def paired_study(folder, orientation: str = ""):
    """The h̄ = 2 bridge under two pairs, P = (R1, R2) and Q = (R2, R1), at `ANGLES`, scaled to
    `LEVELS` of PGA; ``orientation`` the intensity section's (none: the default)."""
    path = write_study(folder, bridges=("studied-hbar2.00",))
    text = path.read_text(encoding="utf-8").replace("    - path: R1.txt\n    - path: R2.txt\n", "")
    text = text.replace(
        "  files:\n",
        "  files:\n    - {path: R1.txt, id: P, second: R2.txt}\n"
        "    - {path: R2.txt, id: Q, second: R1.txt}\n",
    )
    stated = f", orientation: {orientation}" if orientation else ""
    text += (
        f"  orientation: {{angles: {list(ANGLES)}}}\n"
        f"intensity: {{measure: pga_g, levels: {list(LEVELS)}{stated}}}\n"
    )
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The study run twice: as stated by default (``median.h5``) and with ``orientation: worst``
    (``worst.h5``); 24 short analyses each, about 4 s together."""
    folder = tmp_path_factory.mktemp("paired")
    runner = CliRunner()
    for name, stated in (("median", ""), ("worst", "worst")):
        study = paired_study(folder / name, stated)
        result = runner.invoke(main, ["run", str(study), "-o", str(folder / f"{name}.h5")])
        assert result.exit_code == 0, result.output
    return folder


def stored(path) -> dict[tuple[str, str], tuple]:
    """The run's /fragility: (bridge, limit state) → (median, beta, median_05, median_95,
    capacities by record), NaN where none."""
    with h5py.File(path) as file:
        group = file["fragility"]
        records = json.loads(group.attrs["records"])
        keys = zip(group["bridge"].asstr()[()], group["limit_state"].asstr()[()], strict=True)
        return {
            key: (*(float(group[n][i]) for n in ("median", "beta", "median_05", "median_95")),
                  dict(zip(records, group["capacities"][i].tolist(), strict=True)))
            for i, key in enumerate(keys)
        }  # fmt: skip


def computed(path, orientation: str) -> dict[tuple[str, str], tuple]:
    """`stored`'s rows as ``rockbridge fragility --orientation`` computes them."""

    def number(value):
        return float("nan") if value is None else float(value)

    return {
        (item.bridge, item.limit_state): (
            number(item.median), number(item.beta),
            *((number(None), number(None)) if item.median_90 is None else item.median_90),
            {record: number(c) for record, c in item.capacities.items()},
        )
        for item in fragilities(path, orientation=orientation)
    }  # fmt: skip


@pytest.mark.parametrize("name", ["median", "worst"])
def test_a_run_stores_the_fragility_of_the_pairs_at_the_study_s_orientation(runs, name):
    """The stored /fragility of an orientation study is `fragility --orientation <its choice>`
    on the file, row by row, with the pairs P and Q as its records and the choice as an
    attribute; the command without --orientation prints the same."""
    path = runs / f"{name}.h5"
    got, want = stored(path), computed(path, name)
    assert list(got) == list(want)
    for key, row in got.items():
        assert np.allclose(row[:4], want[key][:4], rtol=0, atol=0, equal_nan=True), key
        assert list(row[4]) == ["P", "Q"]
        assert np.allclose(list(row[4].values()), list(want[key][4].values()), rtol=0, atol=0,
                           equal_nan=True), key  # fmt: skip
    with h5py.File(path) as file:
        assert file["fragility"].attrs["orientation"] == name
    runner = CliRunner()
    default = json.loads(runner.invoke(main, ["fragility", str(path), "--json"]).output)
    chosen = runner.invoke(main, ["fragility", str(path), "--json", "--orientation", name])
    assert default == json.loads(chosen.output)
    assert {row["orientation"] for row in default} == {name}
    text = runner.invoke(main, ["fragility", str(path)]).output
    assert "pairs reaching" in text and "records: the pairs of horizontal components" in text


def test_each_angle_remains_a_record_on_request(runs):
    """``--orientation angles`` fits each of the six projections as a record, as before."""
    path = runs / "median.h5"
    rows = json.loads(
        CliRunner().invoke(main, ["fragility", str(path), "--json", "--orientation", "angles"])
        .output
    )  # fmt: skip
    assert all(len(row["capacities"]) == 2 * len(ANGLES) for row in rows)
    assert all("orientation" not in row for row in rows)


def test_plot_fragility_draws_the_share_of_pairs(runs, monkeypatch, tmp_path):
    """One marker series and (where fitted) one curve per bridge in each limit state's panel,
    the markers at the share of the two pairs whose median over the three angles reaches the
    state (at least two angles of three), counted here from the peak table's states; the axis
    and the legend say so."""
    path = runs / "median.h5"
    drawn = []
    monkeypatch.setattr(fragility_plot, "save", lambda figure, output: drawn.append(figure))
    fragility_plot.plot_fragility(path, tmp_path / "f.png")
    (figure,) = drawn
    with h5py.File(path) as file:
        columns = peak_columns(file)
    pairs = np.array([record.split("+")[0] for record in columns["record"]])
    panels = [axes for axes in figure.axes if axes.get_visible() and axes.get_title()]
    assert panels
    for axes in panels:
        state = axes.get_title().replace(" ", "_")
        reached = limit_states.reached(state, columns)
        at = {level: columns["intensity"] == level for level in LEVELS}
        pairs_reaching = {
            level: sum(reached[(pairs == pair) & at[level]].sum() >= 2 for pair in ("P", "Q"))
            for level in LEVELS
        }
        by_hand = {level: count / 2 for level, count in pairs_reaching.items()}
        markers = [line for line in axes.lines if line.get_linestyle() == "None"]
        curves = [line for line in axes.lines if line.get_linestyle() != "None"]
        assert len(markers) == 1 and len(curves) <= 1
        assert dict(zip(*markers[0].get_data(), strict=True)) == by_hand
    assert panels[0].get_ylabel() == "share of pairs reaching it [-]"
    assert "median over its angles" in figure.legends[0].get_title().get_text()


def test_an_orientation_for_the_fragility_needs_pairs(tmp_path):
    """``intensity.orientation`` of a study whose records are not swept over angles: refused,
    naming the field."""
    path = write_study(tmp_path, bridges=("studied-hbar2.00",))
    path.write_text(
        path.read_text(encoding="utf-8")
        + "intensity: {measure: pga_g, levels: [0.3], orientation: worst}\n",
        encoding="utf-8",
    )
    with pytest.raises(InputError, match="intensity.orientation.*needs records.orientation"):
        load_study(path)


def test_peaks_orientation_gives_the_fragility_three_ways(runs):
    """``peaks --orientation --json`` of an orientation study with stripes carries, per limit
    state, the fragility each angle a record and on the pairs' median and worst, the one the run
    stored (worst here) equal to /fragility's; the text prints it as a third table."""
    path = runs / "worst.h5"
    runner = CliRunner()
    data = json.loads(runner.invoke(main, ["peaks", str(path), "--orientation", "--json"]).output)
    kept = stored(path)
    assert [(r["bridge"], r["limit_state"]) for r in data["fragility"]] == list(kept)
    for row in data["fragility"]:
        median, beta = kept[row["bridge"], row["limit_state"]][:2]
        assert row["stored"] == "worst"
        assert np.allclose([row["worst_median"] or np.nan, row["worst_beta"] or np.nan],
                           [median, beta], rtol=0, atol=0, equal_nan=True)  # fmt: skip
    text = runner.invoke(main, ["peaks", str(path), "--orientation"]).output
    assert "Fragility, median θ and β [pga_g]" in text and "the run stores the worst" in text


@pytest.mark.slow
def test_the_report_shows_the_fragility_of_the_pairs(runs):
    """The report of an orientation study: its Fragility section's caption names the pairs and
    how each is taken, and its Orientation section tabulates the three fits. (A report with its
    figures: about 10 s under a load of 8.)"""
    from rockbridge_cli.report import write_report

    path = runs / "worst.h5"
    page = write_report(path, path.with_suffix(".html")).read_text(encoding="utf-8")
    assert "Share of the pairs of horizontal components (each reaching a state where its " in page
    assert "<th>pairs&#x27; worst: θ</th>" in page and "median θ of pga_g [g]" in page

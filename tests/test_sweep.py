"""Parameter sweeps: bridge fields varied over lists or ranges, one at a time or as a grid.

Expected values: a swept variant must be exactly the bridge a user would get by editing the
bridge file to that value (same config, same peaks bit for bit); the counts and ids follow from
the definition (one at a time: the sum of the lists' lengths; grid: their product).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import yaml
from click.testing import CliRunner
from studies import BRIDGES, write_study

from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.config.sweep import Range, Sweep, field_unit
from rockbridge_cli.errors import InputError
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study.run import run_study

SWEEP = """sweep:
  fields:
    abutments.gap: [0.06, 0.24]
    piers.heights.1: {start: 13.0, stop: 26.0, count: 3}
fidelity: fast
output: {histories: none}
"""


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_one_at_a_time_and_grid():
    fields = {"abutments.gap": [0.06, 0.24], "spans.side": [30.0, 40.0, 50.0]}
    one = Sweep(fields=fields).variations()
    assert len(one) == 5 and one[0] == {"abutments.gap": 0.06} and one[-1] == {"spans.side": 50.0}
    grid = Sweep(fields=fields, grid=True).variations()
    assert len(grid) == 6 and grid[1] == {"abutments.gap": 0.06, "spans.side": 40.0}
    assert Range(start=1.0, stop=100.0, count=3, spacing="log").values() == pytest.approx(
        [1.0, 10.0, 100.0], rel=1e-15
    )


def test_variants_are_the_bridge_with_the_field_changed(tmp_path):
    study = load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SWEEP))
    ids = [b.id for b in study.bridges]
    assert ids == [
        "studied-hbar1.25+abutments.gap_0.06", "studied-hbar1.25+abutments.gap_0.24",
        "studied-hbar1.25+piers.heights.1_13", "studied-hbar1.25+piers.heights.1_19.5",
        "studied-hbar1.25+piers.heights.1_26",
    ]  # fmt: skip
    base = load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), name="b.yaml"))
    original = base.bridges[0].config
    gap = study.bridges[1].config
    assert gap.abutments.gap == 0.24 and gap.to_bridge().model.u_jo == 0.24
    assert gap.model_dump(exclude={"abutments"}) == original.model_dump(exclude={"abutments"})
    assert study.bridges[2].config.piers.heights == [26.0, 13.0]
    assert study.bridges[4].config.to_bridge().model.H2 == 13.0  # half the 26 m pier: h̄ = 1
    assert study.bridges[1].swept == {"abutments.gap": 0.24, "piers.heights.1": 20.8}
    assert study.bridges[1].varied == ("abutments.gap",)


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ("{abutments.gap_size: [0.1]}", "abutments.gap_size is not a field of this bridge"),
        ("{piers.heights.2: [10.0]}", "piers.heights.2 is not a field of this bridge"),
        ("{name: [1.0]}", "name is not a number of this bridge"),
        ("{abutments.gap: [-0.1]}", "gives an invalid bridge: abutments.gap"),
        (
            "{spans.central: [1.0]}",
            r"invalid bridge: spans: the central span \(1.0 m\) must exceed",
        ),
        ("{abutments.gap: [0.1, 0.1]}", "a value is listed twice"),
        ("{abutments.gap: {start: 0, stop: 1, count: 3, spacing: log}}", "log spacing"),
        ("{abutments.gap: {start: 0.1, stop: 1, count: 1}}", "count"),
    ],
)
def test_bad_sweeps(tmp_path, fields, message):
    extra = f"sweep: {{fields: {fields}}}\n"
    with pytest.raises(InputError, match=message) as error:
        load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), extra=extra))
    assert "sweep.fields" in str(error.value)


@pytest.mark.slow
def test_a_swept_run_equals_the_edited_bridge_file(tmp_path):
    """The variant with gap 0.24 m gives the peaks of a bridge file edited to gap 0.24 m."""
    study = load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), extra=SWEEP))
    run_study(study, workers=2)
    peaks = read_peaks(study.output)
    assert list(peaks.columns[-2:]) == ["abutments.gap", "piers.heights.1"]
    assert peaks.attrs["units"]["abutments.gap"] == "m" == peaks.attrs["units"]["piers.heights.1"]
    variant = peaks[peaks["bridge"] == "studied-hbar1.25+abutments.gap_0.24"]
    assert set(variant["abutments.gap"]) == {0.24} and set(variant["piers.heights.1"]) == {20.8}

    edited = yaml.safe_load((BRIDGES / "studied-hbar1.25.yaml").read_text())
    edited["abutments"]["gap"] = 0.24
    (tmp_path / "edited.yaml").write_text(yaml.safe_dump(edited))
    path = write_study(tmp_path, bridges=(), name="edited-study.yaml",
                       extra="fidelity: fast\noutput: {histories: none}\n",
                       bridge_files=(tmp_path / "edited.yaml",))  # fmt: skip
    plain = read_peaks(run_study(load_study(path), workers=1).output)
    for column in ("u_deck_max", "theta1_max", "n_impacts", "dcr_backfill"):
        np.testing.assert_array_equal(variant[column].to_numpy(), plain[column].to_numpy())

    figure = invoke("plot", "sweep", study.output, "--field", "abutments.gap", "-o", "g.png")
    assert figure.exit_code == 0, figure.output
    bad = invoke("plot", "sweep", study.output, "--field", "spans.side")
    assert bad.exit_code == 2 and "'spans.side' is not swept here" in bad.output


def test_units_of_swept_fields():
    assert field_unit("abutments.stiffness") == "N/m"
    assert field_unit("abutments.pounding.restitution") == "-"
    assert field_unit("piers.heights.1") == "m"


@pytest.mark.slow
def test_a_peak_per_swept_value_is_taken_at_one_intensity_level(tmp_path):
    """A median over the records at 0.2 g and 0.8 g at once mixes two stripes: the figure asks
    for one (--level), and an IDA, whose levels differ by record, points to its capacities."""
    stripes = (
        "sweep: {fields: {abutments.gap: [0.06, 0.24]}}\nfidelity: fast\n"
        "output: {histories: none}\nintensity: {measure: pga_g, levels: [0.2, 0.8]}\n"
    )
    study = load_study(write_study(tmp_path, bridges=("studied-hbar1.25",), extra=stripes))
    ran = invoke("run", study.path, "--workers", 1)
    assert ran.exit_code == 0, ran.output
    assert "peaks, largest over the records at each level:" in ran.output
    assert re.search(r"studied-hbar1.25\+abutments.gap_0.06 +0.8 +2/2", ran.output)  # per level
    args = ("plot", "sweep", study.output, "--field", "abutments.gap", "-o", "s.png")
    refused = invoke(*args)
    assert refused.exit_code == 2
    assert "taken at one intensity level: choose one with --level (0.2, 0.8 g)" in refused.output
    assert "0.5 is not one" in invoke(*args, "--level", 0.5).output
    drawn = invoke(*args, "--level", 0.8)
    assert drawn.exit_code == 0, drawn.output
    fig9 = invoke("plot", "peaks", study.output, "-o", "p.png")  # its means: one level's too
    assert fig9.exit_code == 2 and "Fig. 9: a summary over the records" in fig9.output
    assert invoke("plot", "peaks", study.output, "-o", "p.png", "--level", 0.2).exit_code == 0
    ida = ("sweep: {fields: {abutments.gap: [0.06, 0.24]}}\nfidelity: fast\n"
           "output: {path: ida.h5, histories: none}\n"
           "intensity: {measure: pga_g, ida: {start: 0.3, step: 0.6, max: 0.9, tolerance: 0.5,"
           " limit_states: [gap_closure]}}\n")  # fmt: skip
    path = write_study(tmp_path, bridges=("studied-hbar1.25",), extra=ida, name="ida.yaml")
    ran = invoke("run", path, "--workers", 1)
    assert "peaks: an IDA's levels differ by record" in ran.output
    output = tmp_path / "ida.h5"
    refused = invoke("plot", "sweep", output, "--field", "abutments.gap")
    assert refused.exit_code == 2 and "an IDA's levels differ by record" in refused.output
    capacity = invoke("plot", "sweep", output, "--field", "abutments.gap", "--quantity",
                      "gap_closure", "-o", "c.png")  # fmt: skip
    assert capacity.exit_code == 0, capacity.output


def test_a_tuple_of_values_is_a_list():
    """From Python, a sweep's values may be a tuple, as a list (the list-or-mapping field is
    told apart by the value's kind, `config.loading.kind_of`)."""
    from rockbridge_cli.config.loading import validate
    from rockbridge_cli.config.sweep import Sweep

    sweep = validate(Sweep, {"fields": {"abutments.gap": (0.1, 0.2)}}, "api")
    assert sweep.variations() == [{"abutments.gap": 0.1}, {"abutments.gap": 0.2}]

"""Exports: the OpenQuake fragility model and pelicun's demand samples, read back by the standard
library and, where installed, by OpenQuake and pelicun themselves.

Expected values: NRML's ``mean`` and ``stddev`` are the moments of the intensity, not of its
logarithm (OpenQuake's manual, "Fragility Models"); the engine recovers the lognormal as
σ = √ln(1 + stddev²/mean²), median = mean²/√(stddev² + mean²) (its
``FragilityFunctionContinuous``), written out here; the moments themselves are scipy's lognormal.
pelicun's demands are the peak table's rows; the backfill's displacement is max(0, |u_deck| −
u_jo) with the gap u_jo of the bridge's config.
"""

from __future__ import annotations

import csv
import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from scipy.stats import lognorm
from studies import BRIDGES, REPO, write_study

from rockbridge_cli.assessment.exports import lognormal_moments, openquake_fragility_model
from rockbridge_cli.assessment.fragility import fragilities
from rockbridge_cli.assessment.hazard import read_hazard_curve
from rockbridge_cli.assessment.risk import risks
from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.study import load_study
from rockbridge_cli.results import read_peaks
from rockbridge_cli.study.run import run_study

IDA = (
    "intensity: {measure: pga_g, ida: {start: 0.1, step: 0.4, max: 2.5, tolerance: 0.05, "
    "limit_states: [gap_closure, abutment_failure, overturning]}}\n"
    "fidelity: fast\noutput: {path: ida.h5, histories: none}\n"
)
"""Two bridges × the two synthetic bursts of `studies`: the gaps close and the abutments fail
within 0.1–2.5 g; no pier overturns, so every record runs every scan level (0.1, 0.5, … 2.5 g)."""

PGV_STRIPES = (
    "intensity: {measure: pgv, levels: [0.1, 0.2]}\n"
    "fidelity: fast\noutput: {path: pgv.h5, histories: none}\n"
)
"""Two PGV stripes, 0.1 and 0.2 m/s."""

NRML = "{http://openquake.org/xmlns/nrml/0.5}"
EXAMPLE = REPO / "configs" / "hazard" / "example-site-pga.csv"


@pytest.fixture(scope="module")
def ida(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ida")
    study = load_study(write_study(folder, extra=IDA))
    run_study(study, workers=1)
    return study.output


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_the_moments_are_those_of_the_lognormal():
    for median, beta in ((0.15, 0.1), (2.0, 0.5), (1.0, 1.2)):
        distribution = lognorm(s=beta, scale=median)
        mean, stddev = lognormal_moments(median, beta)
        assert mean == pytest.approx(distribution.mean(), rel=1e-13)
        assert stddev == pytest.approx(distribution.std(), rel=1e-12)


def test_the_openquake_model_holds_every_fitted_limit_state(ida, tmp_path):
    result = invoke("export", "openquake", ida, "-o", tmp_path / "model.xml")
    assert result.exit_code == 0, result.output
    assert "left out: overturning (no lognormal fit for studied-hbar1.00, studied-hbar2.00)" in (
        result.output)  # fmt: skip
    root = ElementTree.parse(tmp_path / "model.xml").getroot()
    assert root.tag == f"{NRML}nrml"
    (model,) = root
    assert model.tag == f"{NRML}fragilityModel" and model.get("lossCategory") == "structural"
    assert model.find(f"{NRML}description").text
    states = model.find(f"{NRML}limitStates").text.split()
    assert states == ["gap_closure", "abutment_failure"]
    fits = {(f.bridge.replace(".", "_"), f.limit_state): f for f in fragilities(ida, bootstrap=0)}
    functions = model.findall(f"{NRML}fragilityFunction")
    assert [f.get("id") for f in functions] == ["studied-hbar1_00", "studied-hbar2_00"]
    for function in functions:
        assert (function.get("format"), function.get("shape")) == ("continuous", "logncdf")
        imls = function.find(f"{NRML}imls")
        assert (imls.get("imt"), float(imls.get("minIML")), float(imls.get("maxIML"))) == (
            "PGA", 0.1, 2.5)  # fmt: skip
        params = function.findall(f"{NRML}params")
        assert [p.get("ls") for p in params] == states
        for p in params:
            mean, stddev = float(p.get("mean")), float(p.get("stddev"))
            sigma = math.sqrt(math.log(1.0 + stddev**2 / mean**2))
            median = mean**2 / math.sqrt(stddev**2 + mean**2)
            fit = fits[function.get("id"), p.get("ls")]
            assert median == pytest.approx(fit.median, rel=1e-12)
            assert sigma == pytest.approx(fit.beta, rel=1e-12)


def test_openquake_reads_the_model(ida, tmp_path):
    """Where the engine is installed (it is not an extra: see README): it parses the file with
    its validators and its fragility functions give one half at each median."""
    pytest.importorskip("openquake.risklib.read_nrml")
    from openquake.hazardlib import nrml
    from openquake.risklib import read_nrml  # noqa: F401 (registers the fragility reader)

    openquake_fragility_model(ida, tmp_path / "model.xml")
    model = nrml.to_python(str(tmp_path / "model.xml"))
    fits = {(f.bridge.replace(".", "_"), f.limit_state): f for f in fragilities(ida, bootstrap=0)}
    for (imt, taxonomy), functions in model.items():
        assert imt == "PGA"
        for function in functions.build(model.limitStates):
            fit = fits[taxonomy, function.limit_state]
            assert function(np.array([fit.median]))[0] == pytest.approx(0.5, abs=1e-9)


def rows_of(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.reader(stream))


def expected_stripes(peaks, bridge):
    """The stripes of one bridge as pelicun reads an IDA, from the peak table: at each level, each
    record's own row, or, where it did not run that level, the row of its failure at the highest
    level below it (an IDA runs a record no further once the bridge fails: it has collapsed
    above); a level some record neither ran nor failed below is no stripe."""
    mine = peaks[peaks["bridge"] == bridge]
    failed = mine[(mine["failure_mode"] != "none") & (mine["status"] == "ok")]
    found = {}
    for level in sorted(mine["intensity"].unique()):
        rows = []
        for record in dict.fromkeys(mine["base_record"]):
            own = mine[(mine["base_record"] == record) & (mine["intensity"] == level)]
            below = failed[(failed["base_record"] == record) & (failed["intensity"] < level)]
            rows.append(own.iloc[:1] if len(own) else below.sort_values("intensity").iloc[-1:])
        if all(len(row) for row in rows):
            found[level] = pd.concat(rows)
    return found


def test_pelicun_demands_are_the_peak_tables_rows(ida, tmp_path):
    result = invoke("export", "pelicun", ida, "-o", tmp_path / "demands")
    assert result.exit_code == 0, result.output
    assert "no intensity column" not in result.output
    peaks = read_peaks(ida)
    stripes = {bridge: expected_stripes(peaks, bridge) for bridge in peaks["bridge"].unique()}
    names = sorted(p.name for p in (tmp_path / "demands").iterdir())
    assert names == sorted(f"{bridge}+{level:.10g}g.csv" for bridge, levels in stripes.items()
                           for level in levels)  # fmt: skip
    medians = {(f.bridge, f.limit_state): f.median for f in fragilities(ida, bootstrap=0)}
    for bridge, levels in stripes.items():
        # every scan level (0.1 + 0.4 n g) up to the last a record ran is a stripe, the top one
        # above the median abutment capacity and all collapse: the export stopped below
        top = peaks.loc[peaks["bridge"] == bridge, "intensity"].max()
        scans = 0.1 + 0.4 * np.arange(round((top - 0.1) / 0.4) + 1)
        assert set(np.round(scans, 9)) <= {round(level, 9) for level in levels}
        assert max(levels) == top > medians[bridge, "abutment_failure"]
        assert (levels[top]["failure_mode"] != "none").all()
        gap = load_bridge(BRIDGES / f"{bridge}.yaml").abutments.gap
        for level, stripe in levels.items():
            table = rows_of(tmp_path / "demands" / f"{bridge}+{level:.10g}g.csv")
            assert table[0] == ["", "1-DEC-1-1", "1-ABP-1-1", "1-FNR-1-1", "1-FNR-2-1",
                                "1-PGA-0-1", "1-COL-0-1", "1-ERROR-0-1"]  # fmt: skip
            assert table[1] == ["Units", "m", "m", "rad", "rad", "g", "unitless", "unitless"]
            values = np.array([row[1:] for row in table[2:]], dtype=float)
            np.testing.assert_array_equal(values[:, 0], stripe["u_deck_max"])
            np.testing.assert_allclose(values[:, 1], np.maximum(0.0, stripe["u_deck_max"] - gap),
                                       rtol=1e-12, atol=1e-15)  # fmt: skip
            np.testing.assert_array_equal(values[:, 2], stripe["theta1_max"])
            np.testing.assert_array_equal(values[:, 3], stripe["theta2_max"])
            np.testing.assert_allclose(values[:, 4], level, rtol=1e-12)
            np.testing.assert_array_equal(values[:, 5], stripe["failure_mode"] != "none")
            assert not values[:, 6].any()
    assert (peaks["failure_mode"] == "abutment").any()  # the collapse flag is exercised


@pytest.fixture(scope="module")
def pgv(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pgv")
    study = load_study(write_study(folder, bridges=("studied-hbar2.00",), records=("R2",),
                                   extra=PGV_STRIPES))  # fmt: skip
    run_study(study, workers=1)
    return study.output


def test_a_pgv_export_has_its_intensity_column(pgv, tmp_path):
    """pelicun's demand type of PGV is ``PGV`` and its unit of m/s ``mps`` (pelicun's
    default_units.json); the levels are the study's."""
    result = invoke("export", "pelicun", pgv, "-o", tmp_path / "demands")
    assert result.exit_code == 0, result.output
    assert "no intensity column" not in result.output
    for level in (0.1, 0.2):
        table = rows_of(tmp_path / "demands" / f"studied-hbar2.00+{level:g}mps.csv")
        assert (table[0][5], table[1][5]) == ("1-PGV-0-1", "mps")
        assert float(table[2][5]) == level


def test_a_measure_pelicun_has_no_type_for_is_said(tmp_path):
    """pelicun has no demand type for Arias intensity: no column, and one line saying so."""
    arias = load_study(write_study(tmp_path, bridges=("studied-hbar2.00",), records=("R2",),
                                   extra=PGV_STRIPES.replace("pgv", "arias")))  # fmt: skip
    run_study(arias, workers=1)
    result = invoke("export", "pelicun", arias.output, "-o", tmp_path / "demands")
    assert result.exit_code == 0, result.output
    assert "no intensity column: pelicun has no demand type for arias" in result.output
    table = rows_of(tmp_path / "demands" / "studied-hbar2.00+0.1mps.csv")
    assert table[0] == ["", "1-DEC-1-1", "1-ABP-1-1", "1-FNR-1-1", "1-FNR-2-1", "1-COL-0-1",
                        "1-ERROR-0-1"]  # fmt: skip


def test_pelicun_export_never_replaces_a_users_csv(ida, tmp_path):
    """A CSV of the user's with the name of a demand sample was overwritten (the only data the
    issue-39 audit saw destroyed): now refused before any file is written; a sample rockbridge
    wrote is replaced, and nothing else in the folder is touched."""
    folder = tmp_path / "demands"
    assert invoke("export", "pelicun", ida, "-o", folder).exit_code == 0
    names = sorted(path.name for path in folder.iterdir())
    mine = folder / names[-1]
    mine.write_text("my own numbers\n1,2,3\n")
    (folder / names[0]).unlink()
    result = invoke("export", "pelicun", ida, "-o", folder)
    assert result.exit_code == 2, result.output
    assert f"{mine.name}: exists and is not a pelicun demand sample" in result.output
    assert mine.read_text() == "my own numbers\n1,2,3\n"
    assert not (folder / names[0]).exists()  # nothing written before the refusal
    mine.unlink()
    assert invoke("export", "pelicun", ida, "-o", folder).exit_code == 0  # its own: replaced
    assert sorted(path.name for path in folder.iterdir()) == names


def test_pelicun_reads_the_demands(ida, tmp_path):
    """Where pelicun is installed (the optional extra ``interop``): its demand model loads each
    sample with the units stated, in SI."""
    pytest.importorskip("pelicun")
    from pelicun.assessment import Assessment

    peaks = read_peaks(ida)
    invoke("export", "pelicun", ida, "-o", tmp_path / "demands")
    assessment = Assessment({"PrintLog": False, "Verbose": False})
    assessment.demand.load_sample(str(tmp_path / "demands" / "studied-hbar2.00+0.9g.csv"))
    sample, units = assessment.demand.save_sample(save_units=True)
    stripe = peaks[(peaks["bridge"] == "studied-hbar2.00") & np.isclose(peaks["intensity"], 0.9)]
    np.testing.assert_allclose(sample["DEC"]["1"]["1"], stripe["u_deck_max"], rtol=1e-12)
    np.testing.assert_allclose(sample["FNR"]["2"]["1"], stripe["theta2_max"], rtol=1e-12)
    np.testing.assert_allclose(sample["PGA"]["0"]["1"], 0.9, rtol=1e-12)
    assert units["DEC"]["1"]["1"] == "m" and units["PGA"]["0"]["1"] == "g"


def test_pelicun_reads_the_collapsed_top_stripe_and_pgv(ida, pgv, tmp_path):
    """Where pelicun is installed: the IDA's top stripe (2.1 g, above both bridges' median
    abutment capacity) loads with every record collapsed (``COL`` 1: R1 failed at 1.3 g and
    below, R2 at 2.1 g), and a PGV sample loads its intensity in m/s (pelicun's SI)."""
    pytest.importorskip("pelicun")
    from pelicun.assessment import Assessment

    invoke("export", "pelicun", ida, "-o", tmp_path / "demands")
    invoke("export", "pelicun", pgv, "-o", tmp_path / "pgv")
    assessment = Assessment({"PrintLog": False, "Verbose": False})
    assessment.demand.load_sample(str(tmp_path / "demands" / "studied-hbar2.00+2.1g.csv"))
    sample = assessment.demand.save_sample()
    np.testing.assert_array_equal(sample["COL"]["0"]["1"], [1.0, 1.0])
    assessment.demand.load_sample(str(tmp_path / "pgv" / "studied-hbar2.00+0.2mps.csv"))
    sample, units = assessment.demand.save_sample(save_units=True)
    np.testing.assert_allclose(sample["PGV"]["0"]["1"], 0.2, rtol=1e-12)
    assert units["PGV"]["0"]["1"] == "mps"


def test_the_exports_go_beside_the_results_and_never_over_them(ida):
    assert invoke("export", "openquake", ida).exit_code == 0
    assert ida.with_name("ida-fragility.xml").is_file()
    assert invoke("export", "pelicun", ida).exit_code == 0
    assert len(list(ida.with_name("ida-pelicun").iterdir())) >= 2 * 3  # 0.1, 0.5, 0.9 g
    result = invoke("export", "openquake", ida, "-o", ida)
    assert result.exit_code == 2 and "is the file being read" in result.output


def test_openquakes_classical_damage_agrees_with_risk(ida, tmp_path):
    """Where the engine is installed: its classical damage calculation (a sum over the hazard's
    levels) on the exported model and the example site's curve, tabulated at 4000 levels over
    0.05–20 g, gives the 50-year probability of abutment failure that `assessment.risk` does,
    to 1 % (the engine clips the fragility at minIML and maxIML and drops the hazard beyond
    its levels; neither weighs 1 % here)."""
    pytest.importorskip("openquake.risklib.read_nrml")
    from openquake.hazardlib import nrml
    from openquake.risklib import read_nrml  # noqa: F401 (registers the fragility reader)
    from openquake.risklib.scientific import classical_damage

    openquake_fragility_model(ida, tmp_path / "model.xml")
    model = nrml.to_python(str(tmp_path / "model.xml"))
    curve = read_hazard_curve(EXAMPLE)
    levels = np.geomspace(0.05, 20.0, 4000)
    annual_poes = -np.expm1(-curve.rate(levels))
    expected = {(r.bridge.replace(".", "_"), r.limit_state): r for r in risks(ida, curve)}
    state = model.limitStates.index("abutment_failure")
    for (_, taxonomy), functions in model.items():
        occurrence = classical_damage(functions.build(model.limitStates), levels, annual_poes,
                                      1.0, 50.0)  # fmt: skip
        exceeded = float(np.sum(occurrence[state + 1 :]))
        assert exceeded == pytest.approx(expected[taxonomy, "abutment_failure"].probability,
                                         rel=0.01)  # fmt: skip

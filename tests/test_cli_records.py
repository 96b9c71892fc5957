"""`rockbridge generate-records` and `rockbridge plot spectra` through click's CliRunner."""

from __future__ import annotations

import json
import platform
import shutil
from pathlib import Path

import numpy as np
import pytest
import scipy
from click.testing import CliRunner

from rockbridge_cli.cli import main
from rockbridge_cli.records.set_files import MANIFEST

ROOT = Path(__file__).parents[1]
PAPER = ROOT / "configs" / "records" / "ec8-type1-C-ag0.6g.yaml"
BUNDLED = ROOT / "records" / "ec8-type1-C-ag0.6g"
DATA = Path(__file__).parent / "data" / "records"

SMALL = """\
target: {spectrum_type: 1, ground_type: B, ag_g: 0.2}
count: 3
duration: 12.0
time_step: 0.02
envelope: {rise: 1.0, stationary: 10.0, decay: 1.0}
band: [0.1, 2.0]
check_periods: 20
tolerance: 0.2
max_iterations: 2
attempts: 1
seed: 1
"""


def run(*args: str):
    return CliRunner().invoke(main, [str(arg) for arg in args])


def assert_user_error(result, *words):
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    for word in words:
        assert word in result.output


SAMPLE_TOLERANCE = 1e-9
"""Regenerated samples may differ from the bundled ones by this fraction of the PGA: the files
print 10 significant digits, and numpy/scipy releases move the last one (1.5e-10 of the PGA
between numpy 1.26/scipy 1.11 and numpy 2.4/scipy 1.17). A real change of the generator moves
samples by orders of magnitude more."""


def record_set_differences(made: Path, expected: Path) -> list[str]:
    """How a generated record set differs from an expected one, beyond library round-off.

    Record files: the same header lines, the same times, accelerations within
    ``SAMPLE_TOLERANCE`` of the PGA. Manifest: the same keys, texts, integers and verdicts;
    floats within 1e-8 relative (they are printed to 10 digits) or 1e-9 absolute (the final
    velocities and displacements are round-off, ~1e-16 m/s and ~1e-14 m). The manifest's
    ``environment`` (library versions) may differ, and so may each file's ``sha256``, which
    changes with the last printed digit that the samples are compared to within tolerance.
    """
    names = sorted(path.name for path in expected.iterdir())
    if sorted(path.name for path in made.iterdir()) != names:
        return [f"files: {sorted(p.name for p in made.iterdir())} != {names}"]
    found = []
    for name in names:
        if name == MANIFEST:
            continue
        lines = [(made / name).read_text().splitlines(), (expected / name).read_text().splitlines()]
        headers = [[line for line in text if line.startswith("#")] for text in lines]
        if headers[0] != headers[1]:
            found.append(f"{name}: header {headers[0]} != {headers[1]}")
        got, want = (np.loadtxt(text, ndmin=2) for text in lines)
        if got.shape != want.shape or not np.array_equal(got[:, 0], want[:, 0]):
            found.append(f"{name}: time column differs")
            continue
        error = np.max(np.abs(got[:, 1] - want[:, 1])) / np.max(np.abs(want[:, 1]))
        if error > SAMPLE_TOLERANCE:
            found.append(f"{name}: accelerations differ by {error:.2e} of the PGA")
    manifests = [json.loads((folder / MANIFEST).read_text()) for folder in (made, expected)]
    for manifest in manifests:
        manifest.pop("environment", None)
        for entry in manifest.get("records", []):
            entry.pop("sha256", None)
    found += _json_differences(MANIFEST, *manifests)
    return found


def _json_differences(where: str, got, want) -> list[str]:
    if isinstance(want, dict) and isinstance(got, dict):
        if got.keys() != want.keys():
            return [f"{where}: keys {sorted(got)} != {sorted(want)}"]
        return [d for key in want for d in _json_differences(f"{where}.{key}", got[key], want[key])]
    if isinstance(want, list) and isinstance(got, list) and len(got) == len(want):
        return [
            d
            for i, pair in enumerate(zip(got, want, strict=True))
            for d in _json_differences(f"{where}[{i}]", *pair)
        ]
    if isinstance(want, float) and isinstance(got, float):
        return (
            [] if got == pytest.approx(want, rel=1e-8, abs=1e-9) else [f"{where}: {got} != {want}"]
        )
    return [] if type(got) is type(want) and got == want else [f"{where}: {got!r} != {want!r}"]


@pytest.mark.slow
def test_regenerating_the_paper_set_reproduces_the_bundled_files(tmp_path):
    result = run("generate-records", PAPER, "--out", tmp_path / "set")
    assert result.exit_code == 0, result.output
    assert "overall: compliant" in result.output
    assert "(4)b mean zero-period value" in result.output
    # EN 1998-1 §3.2.2.4, type 1 ground C (S = 1.15, T_C = 0.6 s, T_D = 2 s), a_g = 0.6 g:
    # d_g = 0.025 · 5.886 · 1.15 · 0.6 · 2.0 = 0.2031 m
    assert "d_g = 0.025*a_g*S*T_C*T_D = 20.3 cm" in result.output
    assert "rockbridge's aim: every record's PGD within 2 d_g -> yes" in result.output
    assert record_set_differences(tmp_path / "set", BUNDLED) == []
    environment = json.loads((tmp_path / "set" / MANIFEST).read_text())["environment"]
    assert environment == {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
    }


def test_the_regeneration_check_catches_a_real_change(tmp_path):
    """A sample moved by 1e-8 of the PGA (10x the tolerance), a changed verdict, a changed count
    of iterations: each is reported."""
    copy = tmp_path / "copy"
    shutil.copytree(BUNDLED, copy)
    assert record_set_differences(copy, BUNDLED) == []
    lines = (copy / "AR03.txt").read_text().splitlines()
    index = next(i for i, line in enumerate(lines) if not line.startswith("#")) + 1000
    time_text, value = lines[index].split()
    pga = float(next(line for line in lines if line.startswith("# pga:")).split(":")[1])
    lines[index] = f"{time_text} {float(value) + 1e-8 * pga:.9e}"
    (copy / "AR03.txt").write_text("\n".join(lines) + "\n")
    manifest = json.loads((copy / MANIFEST).read_text())
    manifest["compliance"]["compliant"] = False
    manifest["records"][4]["iterations"] += 1
    (copy / MANIFEST).write_text(json.dumps(manifest))
    found = record_set_differences(copy, BUNDLED)
    assert len(found) == 3, found
    assert found[0].startswith("AR03.txt: accelerations differ by 1.0")
    assert "compliance.compliant" in found[1] + found[2]
    assert "records[4].iterations" in found[1] + found[2]


@pytest.mark.slow
def test_default_folder_and_plot(tmp_path, monkeypatch):
    (tmp_path / "small.yaml").write_text(SMALL)
    monkeypatch.chdir(tmp_path)
    result = run("generate-records", "small.yaml", "--plot")
    assert result.exit_code == 0, result.output
    folder = tmp_path / "records" / "small"
    assert sorted(path.name for path in folder.iterdir()) == [
        "AR01.txt",
        "AR02.txt",
        "AR03.txt",
        "manifest.json",
        "spectra.png",
    ]
    assert "(4)a at least 3 records: 3 -> yes" in result.output


def test_a_record_outside_the_tolerance_is_named_and_the_set_is_not_compliant(tmp_path):
    """Two matching iterations cannot bring a record within 1 % of the target: the report names
    each record that misses, by how much, and the verdict follows; the exit status too (it was
    0, so that a batch job could not tell: issue 39)."""
    (tmp_path / "tight.yaml").write_text(SMALL.replace("tolerance: 0.2", "tolerance: 0.01"))
    result = run("generate-records", tmp_path / "tight.yaml", "--out", tmp_path / "set")
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert result.output.strip().endswith(
        "set: written, but the records are NOT compliant with EN 1998-1 §3.2.3.1.2 (the report "
        "above says why)"
    )
    assert "every record within 1% of the target at 20 periods over 0.1-2 s -> NO" in result.output
    assert "AR01 misses it by" in result.output
    assert "overall: NOT compliant" in result.output
    manifest = json.loads((tmp_path / "set" / MANIFEST).read_text())["compliance"]
    assert manifest["tolerance"] == 0.01
    assert manifest["records_ok"] is False and manifest["compliant"] is False


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (("ag_g: 0.2", "ag_g: 0.2, pga_g: 0.3"), ["target", "exactly one of ag_g"]),
        (("ag_g: 0.2", "damping: 0.05"), ["target", "exactly one of ag_g"]),
        (("stationary: 10.0", "stationary: 8.0"), ["envelope", "at least 10 s"]),
        (("duration: 12.0", "duration: 13.0"), ["must equal the duration"]),
        (("seed: 1", "seed: -1"), ["seed"]),
        (("band: [0.1, 2.0]", "band: [0.05, 2.0]"), ["5 time steps"]),
        (("count: 3", "count: 3\nwhatever: 1"), ["whatever", "unknown key"]),
    ],
)
def test_bad_config_exits_2(tmp_path, change, words):
    config = tmp_path / "bad.yaml"
    config.write_text(SMALL.replace(*change))
    assert_user_error(run("generate-records", config, "--out", tmp_path / "out"), *words)


def test_missing_config_exits_2(tmp_path):
    assert_user_error(run("generate-records", tmp_path / "nope.yaml"), "file not found")


def test_plot_a_generated_set(tmp_path):
    result = run("plot", "spectra", BUNDLED, "-o", tmp_path / "fig.svg")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "fig.svg").read_text().startswith("<?xml")


def test_plot_files_of_a_set_and_plain_files(tmp_path):
    result = run(
        "plot",
        "spectra",
        BUNDLED / "AR01.txt",
        DATA / "two_columns.txt",
        "--units",
        "g",
        "-o",
        tmp_path / "fig.png",
    )
    assert result.exit_code == 0, result.output
    assert (tmp_path / "fig.png").stat().st_size > 0


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ((DATA / "two_columns.txt",), ["two_columns.txt", "--units"]),
        ((DATA / "non_numeric.txt", "--units", "g"), ["line 3", "value 2 is not a number"]),
        ((DATA / "one_column.txt", "--units", "g"), ["--time-step"]),
        ((DATA / "truncated.AT2",), ["truncated: NPTS = 7"]),
        ((DATA / "sample.AT2", "-o", "figure.jpg"), ["unknown figure format"]),
        ((DATA / "nothing_here",), ["file not found"]),
    ],
)
def test_plot_bad_input_exits_2(tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    assert_user_error(run("plot", "spectra", *args), *words)


def test_plot_record_marks_the_design_ground_displacement(tmp_path):
    """A generated set: acceleration, velocity and displacement, with ±d_g (20.3 cm for the
    paper's target, §3.2.2.4); plain files outside a set have no target, hence no d_g."""
    import matplotlib

    with matplotlib.rc_context({"svg.fonttype": "none"}):
        result = run("plot", "record", BUNDLED, "-o", tmp_path / "set.svg")
        plain = run("plot", "record", DATA / "two_columns.txt", "--units", "g",
                    "-o", tmp_path / "plain.svg")  # fmt: skip
    assert result.exit_code == 0 and plain.exit_code == 0, result.output + plain.output
    text = (tmp_path / "set.svg").read_text(encoding="utf-8")
    assert "10 records" in text and "20.3 cm (EN 1998-1 §3.2.2.4)" in text
    assert "EN 1998-1 §3.2.2.4" not in (tmp_path / "plain.svg").read_text(encoding="utf-8")


def test_plot_record_names_each_record_once(tmp_path):
    """Each record is drawn in the three panels, and named once in the legend (not three times)."""
    import re

    import matplotlib

    with matplotlib.rc_context({"svg.fonttype": "none"}):
        result = run("plot", "record", BUNDLED / "AR01.txt", BUNDLED / "AR07.txt",
                     "-o", tmp_path / "two.svg")  # fmt: skip
    assert result.exit_code == 0, result.output
    texts = re.findall(r"<text[^>]*>([^<]*)</text>", (tmp_path / "two.svg").read_text())
    assert texts.count("AR01") == 1 and texts.count("AR07") == 1


@pytest.mark.parametrize("command", ["record", "spectra"])
def test_a_named_file_beside_another_programs_manifest_is_drawn(tmp_path, command):
    """Issue 40: a manifest.json that is not a record set's (a web app's) made `plot record` and
    `plot spectra` refuse the files named beside it; it is no set, and the files plain ones."""
    shutil.copy(BUNDLED / "AR01.txt", tmp_path / "AR01.txt")
    (tmp_path / "manifest.json").write_text('{"name": "my-app", "version": "1.0"}')
    result = run("plot", command, tmp_path / "AR01.txt", "-o", tmp_path / "figure.png")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "figure.png").stat().st_size > 10_000


def small_set(tmp_path: Path, seed: int, out: Path, *options: str):
    config = tmp_path / f"small-{seed}.yaml"
    config.write_text(SMALL.replace("seed: 1", f"seed: {seed}"), encoding="utf-8")
    return run("generate-records", config, "--out", out, *options)


def study_on(tmp_path: Path, folder: Path) -> Path:
    study = tmp_path / "on-set.yaml"
    study.write_text(
        "bridges:\n  - {id: block, piers: {width: 1.3, heights: [13.0]}}\n"
        f"records: {{set: {folder}}}\noutput: {{histories: none}}\n",
        encoding="utf-8",
    )
    return study


def test_a_set_changed_after_it_was_written_is_refused(tmp_path):
    """The manifest keeps each file's SHA-256; a study refuses a file that differs (issue 32 #8:
    a generator killed while replacing files one by one left a mix a study accepted)."""
    assert small_set(tmp_path, 1, tmp_path / "set").exit_code == 0
    from rockbridge_cli.config.study import load_study

    assert len(load_study(study_on(tmp_path, tmp_path / "set")).records) == 3
    path = tmp_path / "set" / "AR02.txt"
    path.write_text(path.read_text().replace("e-", "e+", 1), encoding="utf-8")
    result = run("run", study_on(tmp_path, tmp_path / "set"), "-o", tmp_path / "x.h5")
    assert_user_error(result, "AR02.txt differs from the file the set was written with")
    assert not (tmp_path / "x.h5").exists()


def test_a_new_set_replaces_an_old_one_whole(tmp_path):
    """Generated beside the old set and swapped in: every file of the folder is the new set's,
    and nothing else of the parent folder is left behind."""
    assert small_set(tmp_path, 1, tmp_path / "set").exit_code == 0
    old = {p.name: p.read_bytes() for p in (tmp_path / "set").iterdir()}
    replaced = small_set(tmp_path, 2, tmp_path / "set", "--overwrite")
    assert replaced.exit_code == 1  # written, NOT compliant
    new = {p.name: p.read_bytes() for p in (tmp_path / "set").iterdir()}
    assert new.keys() == old.keys() and new["AR01.txt"] != old["AR01.txt"]
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_a_set_is_replaced_only_with_overwrite(tmp_path):
    """A record set may be a study's input: without --overwrite it is refused (exit 2) and left
    as it was, before any record is generated."""
    assert small_set(tmp_path, 1, tmp_path / "set").exit_code == 0
    old = {p.name: p.read_bytes() for p in (tmp_path / "set").iterdir()}
    result = small_set(tmp_path, 2, tmp_path / "set")
    assert_user_error(result, "holds a record set already: pass --overwrite to replace it")
    assert {p.name: p.read_bytes() for p in (tmp_path / "set").iterdir()} == old


def test_a_set_beside_other_files_is_not_replaced(tmp_path):
    """--overwrite replaces a set, never a user's file (or folder) that lies beside it: the
    set's folder is swapped whole, so such a folder is refused and every file kept."""
    assert small_set(tmp_path, 1, tmp_path / "set").exit_code == 0
    (tmp_path / "set" / "notes.txt").write_text("keep me", encoding="utf-8")
    (tmp_path / "set" / "mine").mkdir()
    old = sorted(p.name for p in (tmp_path / "set").iterdir())
    result = small_set(tmp_path, 2, tmp_path / "set", "--overwrite")
    assert_user_error(result, "holds mine, notes.txt, which the record set does not list")
    assert sorted(p.name for p in (tmp_path / "set").iterdir()) == old
    assert (tmp_path / "set" / "notes.txt").read_text(encoding="utf-8") == "keep me"


def test_a_folder_of_other_files_is_not_replaced(tmp_path):
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me", encoding="utf-8")
    result = small_set(tmp_path, 1, tmp_path / "mine")
    assert_user_error(result, "holds files that are not a record set")
    assert [p.name for p in (tmp_path / "mine").iterdir()] == ["notes.txt"]


@pytest.mark.slow
def test_a_killed_generator_never_leaves_a_set_a_study_accepts_mixed(tmp_path):
    """SIGKILL at staggered moments of a generator replacing a set: whatever is left is the old
    set, the new one, or no set, and a study that accepts the folder reads files that all agree
    with its manifest (it verifies their SHA-256)."""
    import os
    import signal
    import subprocess
    import sys
    import time

    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.errors import InputError

    assert small_set(tmp_path, 1, tmp_path / "set").exit_code == 0
    config = tmp_path / "small-2.yaml"
    config.write_text(SMALL.replace("seed: 1", "seed: 2"), encoding="utf-8")
    command = [sys.executable, "-c", "from rockbridge_cli.cli import main; main()",
               "generate-records", str(config), "--out", str(tmp_path / "set"),
               "--overwrite"]  # fmt: skip
    outcomes = set()
    for delay in (0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0):
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(delay)
        os.kill(process.pid, signal.SIGKILL)
        process.wait()
        try:
            study = load_study(study_on(tmp_path, tmp_path / "set"))
        except InputError:
            outcomes.add("refused")
            assert small_set(tmp_path, 1, tmp_path / "set").exit_code == 0  # start again
            continue
        manifest = json.loads((tmp_path / "set" / MANIFEST).read_text())
        outcomes.add(manifest["seed"])
        assert [r.id for r in study.records] == ["AR01", "AR02", "AR03"]
        for record in study.records:  # every file of the seed the manifest states
            assert record.record is not None and record.record.metadata["seed"] == manifest["seed"]
    assert outcomes <= {1, 2, "refused"}

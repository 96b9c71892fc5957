"""Inputs that used to hang, crash or be read wrongly (issue 14): each is now one readable
message naming the file (and the field or line), exit 2, no traceback — or read correctly."""

from __future__ import annotations

import json
import os
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from studies import REPO

from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.loading import read_yaml
from rockbridge_cli.config.plausibility import record_warnings
from rockbridge_cli.errors import InputError, nearest
from rockbridge_cli.records.files import read_record
from rockbridge_cli.results import read_peaks

BRIDGE = """\
piers: {width: 2.6, heights: [26.0, 20.8]}
deck: {depth: 1.7, area: 6.0}
spans: {side: 38.0, central: 60.0}
abutments: {gap: 0.12, stiffness: 132.0e6, damping: 48.0e6, ultimate_displacement: 0.10}
"""


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def refused(result, *fragments: str) -> None:
    assert result.exit_code == 2, result.output
    assert result.output.startswith("error: ") and "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in result.output, result.output


def test_the_bridge_used_here_is_valid(tmp_path):
    (tmp_path / "b.yaml").write_text(BRIDGE)
    assert invoke("describe", tmp_path / "b.yaml").exit_code == 0


def test_a_duplicate_key_names_the_key_and_its_line(tmp_path):
    path = tmp_path / "b.yaml"
    path.write_text(BRIDGE + "abutments: {gap: 0.5, stiffness: 1, damping: 1, "
                    "ultimate_displacement: 0.1}\n")  # fmt: skip
    refused(invoke("describe", path), "b.yaml: line 5", "duplicate key 'abutments'")


def test_deep_nesting_is_refused_with_the_file_name(tmp_path):
    """5000 nested lists: one clear error naming the file, never a RecursionError. Newer libyaml
    stops at its nesting limit ("exceeded maximum nesting depth"), PyYAML's pure-Python parser
    (where libyaml is missing) at Python's recursion limit ("nested too deeply"), and the libyaml
    of PyYAML 6.0 reads it, so that the unknown key is the error."""
    path = tmp_path / "deep.yaml"
    path.write_text("a: " + "[" * 5000 + "]" * 5000 + "\n")
    result = invoke("describe", path)
    refused(result, "deep.yaml")
    reasons = ("nesting depth", "nested too deeply", "a: unknown key")
    assert any(reason in result.output for reason in reasons), result.output


@pytest.mark.skipif(not os.path.exists("/dev/urandom"), reason="no /dev/urandom")
def test_a_device_is_refused_at_once():
    refused(invoke("describe", "/dev/urandom"), "/dev/urandom", "not a regular file")
    refused(invoke("plot", "spectra", "/dev/urandom", "--units", "g"), "not a regular file")


def test_a_huge_record_file_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from rockbridge_cli.records import files as records

    monkeypatch.setattr(records, "MAX_RECORD_BYTES", 100)
    path = tmp_path / "big.txt"
    path.write_text("# units: g\n" + "0.00 0.1\n" * 50)
    with pytest.raises(Exception, match="more than a record file can be"):
        read_record(path)


@pytest.mark.parametrize(
    ("header", "scale"),
    [
        ("ACCELERATION TIME SERIES IN UNITS OF G", 9.80665),
        ("ACCELERATION TIME SERIES IN UNITS OF CM/S/S", 0.01),
        ("Acceleration in cm/sec/sec", 0.01),
        ("UNITS: CM/S^2", 0.01),
        ("ACCELERATION IN M/S/S", 1.0),
        ("units of gal", 0.01),
    ],
)
def test_at2_and_cosmos_unit_spellings(tmp_path, header, scale):
    """PEER's line 3 states the units; cm/s² (= gal) was refused as "does not state its units"."""
    path = tmp_path / "r.AT2"
    path.write_text(f"PEER NGA STRONG MOTION DATABASE RECORD\nSOME EVENT\n{header}\n"
                    "NPTS=    4, DT=   .0100 SEC\n  0.0  10.0  -20.0  0.0\n")  # fmt: skip
    record = read_record(path)
    np.testing.assert_allclose(record.acceleration, scale * np.array([0.0, 10.0, -20.0, 0.0]))


def test_an_at2_without_units_still_asks_for_them(tmp_path):
    path = tmp_path / "r.AT2"
    path.write_text("PEER\nEVENT\nACCELERATION TIME SERIES\nNPTS=    2, DT=   .0100 SEC\n"
                    "  0.0  0.1\n")  # fmt: skip
    with pytest.raises(Exception, match="does not state its units"):
        read_record(path)
    assert read_record(path, units="cm/s2").acceleration[1] == pytest.approx(0.001)


@pytest.mark.parametrize(
    ("change", "warning"),
    [
        (("gap: 0.12", "gap: 200.0"), "abutments.gap: 200 m is not an expansion joint"),
        # a second reviewer (2026-11-28): a gap of 0.1 mm ran silently (0 is no joint: silent)
        (("gap: 0.12", "gap: 0.0001"), "abutments.gap: 0.0001 m is not an expansion joint"),
        (("stiffness: 132.0e6", "stiffness: 132000.0"), "abutments.stiffness: 132000 N/m"),
        (("heights: [26.0, 20.8]", "heights: [26.0, 3.6]"), "piers.heights.1: a pier 1.38"),
        # issue 32: values that were silently accepted
        (("spans:", "gravity: 98.1\nspans:"), "gravity: 98.1 m/s² is outside 9.76–9.84 m/s²"),
        (("spans:", "density: 25\nspans:"), "density: 25 kg/m³ is outside 1000–8000 kg/m³"),
        (("area: 6.0", "mass: 1000.0"), "deck.mass: 1000 kg is outside 10000–1e+09 kg"),
        (("ultimate_displacement: 0.10", "ultimate_displacement: 1000"),
         "abutments.ultimate_displacement: 1000 m is not a backfill's"),
        (("central: 60.0", "central: 1.0e5"), "spans.central: 100000 m is outside 0–2000 m"),
        # issue 39
        (("depth: 1.7", "depth: 100.0"), "deck.depth: a 100 m deep deck on a 20.8 m pier"),
    ],
)  # fmt: skip
def test_implausible_bridge_values_are_warnings_not_errors(tmp_path, change, warning):
    """Units typed wrong (mm as m, kN as N) still validate: the command warns and goes on."""
    path = tmp_path / "b.yaml"
    path.write_text(BRIDGE.replace(*change))
    assert change[1] in path.read_text()
    result = invoke("describe", path)
    assert result.exit_code == 0
    assert f"warning: {path}: {warning}" in result.output


def test_a_bridge_without_an_end_joint_is_not_warned_about(tmp_path):
    """A gap of 0 is a bridge without an end joint, not a slip of units: no warning (below the
    range of expansion joints, 0.1 mm is warned of)."""
    path = tmp_path / "b.yaml"
    path.write_text(BRIDGE.replace("gap: 0.12", "gap: 0.0"))
    result = invoke("describe", path)
    assert result.exit_code == 0 and "abutments.gap" not in result.output


@pytest.mark.parametrize(
    ("values", "unit", "warning"),
    [
        ("0.0 350.0 -200.0 0.0", "m/s2", "peak 35.69 g is not an earthquake's"),  # cm/s² as m/s²
        ("0.0 0.003 -0.002 0.0", "m/s2", "peak 0.0003059 g is not an earthquake's"),  # g as m/s²
        (
            "0.0 0.51 -0.3 0.0",
            "m/s2",
            "peak 0.052 g, weaker than most records that make a "
            "bridge rock: if the file's numbers are in g, it peaks at 0.51 g",
        ),  # g as m/s²
        ("0.0 3.0 -2.0 0.0", "m/s2 10", "time step 10 s is not a ground motion's"),  # ms as s
        ("0.0 3.0 -2.0 0.0", "m/s2 5e-5", "time step 5e-05 s is not a ground motion's"),
        ("0.0 3.0", "m/s2", "only 2 samples: a ground motion has thousands"),  # issue 39
    ],
)
def test_implausible_records_are_warned_about_once(tmp_path, values, unit, warning):
    record = tmp_path / "r.txt"
    unit, step = (*unit.split(), "0.01")[:2]
    record.write_text(f"# units: {unit}\n# time_step: {step}\n" + "".join(
        f"{v}\n" for v in values.split()))  # fmt: skip
    study = tmp_path / "s.yaml"
    (tmp_path / "b.yaml").write_text(BRIDGE)
    study.write_text(
        "bridges: [b.yaml]\nrecords:\n  files: [{path: r.txt}, {path: r.txt, id: again}]\n"
        f"output: {{path: {tmp_path / 'o.h5'}}}\n"
    )
    result = invoke("run", study, "--workers", "1")
    assert result.output.count(f"warning: r.txt: {warning}") == 1  # once per input file

    with h5py.File(tmp_path / "o.h5", "r") as file:
        assert any(warning in w for w in json.loads(file.attrs["warnings"]))


@pytest.mark.parametrize("command", ["analyze", "run"])
def test_a_record_beyond_any_ground_motion_is_refused_naming_its_units(tmp_path, command):
    """Issue 40: a 499 g record (a file of cm/s² numbers, 499 cm/s² = 0.51 g, stated in g) ran
    with a warning. Above 100 g (25 times the largest recorded, about 4 g) it is refused: one
    line naming the file and its units; `analyze` exits 2, a study runs none of the record's
    analyses (as for any record it cannot read: the others run; exit 1). 35.7 g (cm/s² as m/s²,
    above) stays a warning."""
    record = tmp_path / "r.txt"
    record.write_text("# units: g\n# time_step: 0.01\n" + "".join(
        f"{v}\n" for v in (0.0, 499.0, -310.0, 0.0) * 5))  # fmt: skip
    (tmp_path / "b.yaml").write_text(BRIDGE)
    study = tmp_path / "s.yaml"
    study.write_text(f"bridges: [b.yaml]\nrecords:\n  files: [{{path: r.txt}}]\n"
                     f"output: {{path: {tmp_path / 'o.h5'}}}\n")  # fmt: skip
    args = ["analyze", tmp_path / "b.yaml", record] if command == "analyze" else ["run", study]
    result = invoke(*args)
    assert result.exit_code == (2 if command == "analyze" else 1), result.output
    problem = "r.txt: units: peak 499 g in g is beyond any ground motion (100 g at most"
    lines = [line for line in result.output.splitlines() if problem in line]
    assert len(lines) == 1, result.output
    assert "Traceback" not in result.output
    if command == "run":
        assert list(read_peaks(tmp_path / "o.h5")["status"]) == ["error"]


def test_an_intensity_level_beyond_any_ground_motion_is_refused(tmp_path):
    """Issue 40: ``levels: [499]`` in g (cm/s² typed as g) ran with a scale-factor warning. Above
    100 g, the bound of a record file's peak, `run` refuses it before anything runs: one line
    naming the file and the level, exit 2 (the bounds of each measure: tests/test_intensity.py)."""
    from studies import write_study

    study = write_study(tmp_path, extra="intensity: {measure: pga_g, levels: [0.5, 499]}\n")
    result = invoke("run", study)
    refused(result, "study.yaml: intensity.levels.1: 499 g is beyond any ground motion's PGA "
            "(100 g at most", "(the 2nd entry of intensity.levels)")  # fmt: skip
    assert result.output.count("\n") == 1


@pytest.mark.parametrize(
    ("intensity", "warned"),
    [("{measure: pga_g, levels: [0.69, 6.77]}", "intensity.levels.1: 6.77 g exceeds the largest "
      "ground motion recorded (about 4 g): m/s² typed as g?"),
     ("{measure: pgv, levels: [0.5, 50]}", "intensity.levels.1: 50 m/s exceeds the largest ground "
      "motion recorded (about 3 m/s): cm/s typed as m/s?"),
     ("{measure: pga_g, levels: [0.69, 4.0]}", None),
     ("{measure: pga_g, ida: {start: 0.5, step: 1.0, max: 6.0}}", None)],
)  # fmt: skip
def test_a_level_above_any_recorded_motion_is_warned_of(tmp_path, intensity, warned):
    """Between the largest motions recorded (about 4 g of PGA, 3 m/s of PGV: a 25th of the
    refused bound) and that bound a level is legal, and likely a slip of units (a new user's
    6.77 g was 0.69 g in m/s², 50 m/s meant 50 cm/s): the study loads with a warning naming the
    file and the level. An IDA's scan, which scales records up to collapse, is not warned of."""
    from studies import write_study

    from rockbridge_cli.config.study import load_study

    study = load_study(write_study(tmp_path, extra=f"intensity: {intensity}\n"))
    found = [w for w in study.warnings if "exceeds the largest ground motion recorded" in w]
    assert found == ([] if warned is None else [f"{tmp_path / 'study.yaml'}: {warned}"])


def test_analyze_prints_the_pga_and_warns_of_g_read_as_metres(tmp_path):
    """A 0.51 g record whose file says m/s²: 0.51/9.80665 = 0.052 g, printed, and warned of."""
    (tmp_path / "b.yaml").write_text(BRIDGE)
    record = tmp_path / "r.txt"
    record.write_text("".join(f"{0.01 * i:.2f} {v}\n" for i, v in enumerate((0, 0.51, -0.3, 0))))
    result = invoke("analyze", tmp_path / "b.yaml", record, "--units", "m/s2")
    assert result.exit_code == 0, result.output
    assert "peak 0.052 g, weaker than most records" in result.output
    assert "r (0.03 s, PGA 0.052 g)" in result.output


def test_a_time_column_that_does_not_start_at_zero_is_noticed(tmp_path):
    path = tmp_path / "late.txt"
    path.write_text("# units: g\n5.00 0.0\n5.01 0.1\n5.02 0.0\n")
    record = read_record(path)
    assert record.metadata["notices"] == [
        "the time column starts at 5 s: the record is read as starting at t = 0"
    ]
    assert record_warnings(record)[0].startswith("the time column starts at 5 s")


# --- issue 32: YAML 1.2 numbers, merge keys, records that were read wrong or refused -----------


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (("density: 2500.0", "density: 02500"), 2500.0),  # YAML 1.1: octal, 1344
        (("density: 2500.0", "density: 0o4704"), 2500.0),  # 4·512 + 7·64 + 4 = 2500
        (("density: 2500.0", "density: 0x9C4"), 2500.0),  # 9·256 + 12·16 + 4 = 2500
        (("density: 2500.0", "density: 2_500"), 2500.0),
    ],
)
def test_yaml_integers_are_yaml_1_2(tmp_path, change, expected):
    path = tmp_path / "b.yaml"
    path.write_text((BRIDGE + "density: 2500.0\n").replace(*change))
    assert load_bridge(path).density == expected


def test_sexagesimal_is_text_not_sixty(tmp_path):
    """YAML 1.1 read ``central: 1:00`` as 60 (base 60)."""
    path = tmp_path / "b.yaml"
    path.write_text(BRIDGE.replace("central: 60.0", "central: 1:00"))
    refused(invoke("describe", path), "spans.central", "'1:00'")


def test_merge_keys_are_accepted_and_sets_refused(tmp_path):
    path = tmp_path / "b.yaml"
    path.write_text("defaults: &ab {gap: 0.12, stiffness: 132.0e6, damping: 48.0e6, "
                    "ultimate_displacement: 0.10}\n" + BRIDGE.replace("abutments: {gap: 0.12,",
                    "abutments: {<<: *ab, gap: 0.15,"))  # fmt: skip
    data = read_yaml(path)
    assert data["abutments"] == {"gap": 0.15, "stiffness": 132.0e6, "damping": 48.0e6,
                                 "ultimate_displacement": 0.10}  # fmt: skip
    path.write_text(BRIDGE + "description: !!set {a, b}\n")
    refused(invoke("describe", path), "line 5", "!!set is not supported")
    path.write_text(BRIDGE + "? [1, 2]\n: 3\n")  # a TypeError before
    refused(invoke("describe", path), "line 5", "a key must be a plain value")


@pytest.mark.parametrize("kind", ["VELOCITY", "DISPLACEMENT"])
def test_an_at2_of_velocities_or_displacements_is_refused(tmp_path, kind):
    """Read as accelerations when ``--units`` was given (PEER's .VT2 and .DT2 renamed)."""
    path = tmp_path / "r.AT2"
    header = f"PEER NGA STRONG MOTION DATABASE RECORD\nSOME EVENT\n{kind} TIME SERIES IN CM\n"
    path.write_text(header + "NPTS=    4, DT=   .0100 SEC\n  0.0  10.0  -20.0  0.0\n")
    with pytest.raises(InputError, match=f"line 3: the header says {kind}"):
        read_record(path, units="cm/s2")


def test_a_byte_order_mark_is_accepted(tmp_path):
    """Excel writes UTF-8 with a byte-order mark: the first header line was not a comment."""
    record = tmp_path / "r.txt"
    record.write_bytes("# units: g\n0.00 0.1\n0.01 0.2\n".encode("utf-8-sig"))
    assert read_record(record).acceleration[1] == pytest.approx(0.2 * 9.80665)
    bridge = tmp_path / "b.yaml"
    bridge.write_bytes(BRIDGE.encode("utf-8-sig"))
    assert load_bridge(bridge).piers.width == 2.6


def test_a_record_scaled_by_an_implausible_factor_is_warned_about(tmp_path):
    """Plausibility was checked on the files, not on their scaled copies (Sa at T = 1e6 s scaled
    a record by 7.5e7, status ok). R1 peaks at 5.0 m/s² (tests/studies.py): 100 g is
    100 · 9.80665 / 5.0 = 196.1 times it."""
    from studies import write_study

    from rockbridge_cli.config.study import load_study

    study = load_study(
        write_study(tmp_path, extra="intensity: {measure: pga_g, levels: [0.5, 100]}\n")
    )
    assert [w for w in study.warnings if "scaled by" in w] == [
        "R1+100g: scaled by 196 to reach its level (more than 100 or less than 0.01): is the "
        "level, the measure or its period right?",
        "R2+100g: scaled by 245 to reach its level (more than 100 or less than 0.01): is the "
        "level, the measure or its period right?",
    ]


# --- issue 32: raw exceptions that are now named refusals --------------------------------------


def test_an_all_zero_record_fails_only_its_analyses_in_an_intensity_study(tmp_path):
    """No factor scales a record without motion to a level: a ZeroDivisionError before."""
    from studies import write_study

    from rockbridge_cli.config.study import load_study

    (tmp_path / "zero.txt").write_text("# units: g\n# time_step: 0.01\n0\n0\n0\n")
    for section in ("levels: [0.5]", "ida: {start: 0.1, step: 0.1, max: 1.0}"):
        path = write_study(tmp_path, extra=f"intensity: {{measure: pga_g, {section}}}\n")
        path.write_text(path.read_text().replace("    - path: R2.txt", "    - path: zero.txt"))
        record = load_study(path).records[-1]
        assert record.record is None and "its pga_g is 0: it cannot be scaled" in record.error


def test_values_beyond_the_floating_point_range_are_refused(tmp_path):
    path = tmp_path / "huge.txt"
    path.write_text("# units: g\n# time_step: 0.01\n0\n1e308\n0\n")  # 9.8e308 m/s² is inf
    with pytest.raises(InputError, match="beyond the floating-point range once in m/s²"):
        read_record(path)


def test_analyze_refuses_what_it_cannot_run(tmp_path):
    """A 1e300 s time step ("negative dimensions") and --tail nan were raw exceptions, exit 1."""
    (tmp_path / "b.yaml").write_text(BRIDGE)
    (tmp_path / "slow.txt").write_text("# units: g\n# time_step: 1e300\n0\n0.3\n0\n")
    refused(invoke("analyze", tmp_path / "b.yaml", tmp_path / "slow.txt"), "slow.txt",
            "history samples, more than 2e+06")  # fmt: skip
    (tmp_path / "r.txt").write_text("# units: g\n# time_step: 0.01\n0\n0.3\n0\n")
    for tail in ("nan", "inf"):
        result = invoke("analyze", tmp_path / "b.yaml", tmp_path / "r.txt", "--tail", tail)
        assert (
            result.exit_code == 2
            and "--tail" in result.output
            and "Traceback" not in (result.output)
        )


@pytest.mark.parametrize("address", ["foo", "tcp://127.0.0.1:notaport"])
def test_a_malformed_scheduler_address_is_refused(tmp_path, monkeypatch, address):
    from studies import write_study

    monkeypatch.chdir(tmp_path)
    result = invoke("run", write_study(tmp_path), "--scheduler", address)
    refused(result, f"{address}: cannot reach the Dask scheduler: not an address like tcp://")
    assert "int()" not in result.output and "missing port" not in result.output  # (issue 39)


def test_a_full_disk_while_writing_the_results_names_the_file(tmp_path, monkeypatch):
    """h5py reports a full disk as a RuntimeError (errno = 28), which reached the user raw,
    without the hint that the journal keeps the analyses."""
    from studies import write_study

    from rockbridge_cli.results.writing import ResultsWriter

    def full(self, *args, **kwargs):
        raise RuntimeError("Can't write data (file write failed: errno = 28, No space left)")

    monkeypatch.setattr(ResultsWriter, "add", full)
    monkeypatch.chdir(tmp_path)
    result = invoke("run", write_study(tmp_path), "--workers", "1")
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert "results/study.h5: cannot write the results file (no space left on the device)" in (
        result.output
    )  # not HDF5's "Can't write data (file write failed: errno = 28, …)" (issue 39)
    assert "the finished analyses stay in the journal: rerun to resume" in result.output


def test_a_file_named_as_a_record_keeps_its_content_out_of_messages(tmp_path):
    """A config may name any readable file as a record: its first line was copied into the
    message, the results' message column and the report ('root:x:0:0:…' is not a number)."""
    secret = tmp_path / "passwd"
    secret.write_text("toor:x:0:0:toor:/toor:/bin/bash\ndaemon:x:1:1::/usr/sbin:/bin/false\n")
    for units in ("g", None):
        with pytest.raises(InputError) as refusal:
            read_record(secret, units=units, time_step=0.01)
        assert "toor" not in str(refusal.value) and "line 1: value 1 is not a number" in str(
            refusal.value
        )
    at2 = tmp_path / "r.AT2"
    at2.write_text("PEER\ntoor:x:0:0\nUNITS OF G\ntoor:x:0:0:secret\n0.1\n")
    with pytest.raises(InputError) as refusal:
        read_record(at2)
    assert "toor" not in str(refusal.value) and "line 4" in str(refusal.value)


def test_the_python_api_checks_its_arguments(tmp_path):
    """Wrong types gave generic errors (issue 32): ``run_study("study.yaml")`` an
    AttributeError, ``read_record(p, units=9.81)`` one on ``strip``, ``merge_results(out,
    "a.h5")`` iterated the characters, complex accelerations lost their imaginary part."""
    from studies import write_study

    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.core.analysis import analyze
    from rockbridge_cli.study.merge import merge_results
    from rockbridge_cli.study.run import run_study

    path = write_study(tmp_path, extra=f"output: {{path: {tmp_path / 'out.h5'}}}\n")
    with pytest.raises(TypeError, match="run_study takes a Study"):
        run_study(path)
    for workers in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match="workers is a count"):
            run_study(load_study(path), workers=workers)
    with pytest.raises(ValueError, match="shard is"):
        run_study(load_study(path), shard=(3, 2))
    with pytest.raises(TypeError, match="units is a name"):
        read_record(tmp_path / "R1.txt", units=9.81)
    with pytest.raises(TypeError, match="time_step is a number"):
        read_record(tmp_path / "R1.txt", time_step="0.01")
    with pytest.raises(TypeError, match="parts is a list"):
        merge_results(tmp_path / "m.h5", str(tmp_path / "a.h5"))
    (tmp_path / "b.yaml").write_text(BRIDGE)
    bridge = load_bridge(tmp_path / "b.yaml").to_bridge()
    with pytest.raises(TypeError, match="real accelerations"):
        analyze(bridge, np.array([0.0, 1.0j, 0.0]), 0.01)
    record = read_record(tmp_path / "R1.txt")  # the record, not its samples: numpy's float()
    with pytest.raises(TypeError, match=r"\(record.acceleration, record.time_step\), not the"):
        analyze(bridge, record, record.time_step)
    assert not (tmp_path / "out.h5").exists()


def test_the_python_api_names_what_it_takes_instead_of_a_path(tmp_path):
    """Issue 39: ``load_study(42)``, ``load_bridge({...})`` and ``read_record(None)`` raised
    ``open``'s "expected str, bytes or os.PathLike object", ``risks(path, "curve.csv")`` an
    AttributeError deep inside: each now names the function and what it takes."""
    from rockbridge_cli.assessment.risk import risks
    from rockbridge_cli.config.study import load_study

    with pytest.raises(TypeError, match="load_study takes the path of a study YAML file, not int"):
        load_study(42)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="load_bridge takes the path of a bridge YAML file"):
        load_bridge({"piers": {"width": 2.6}})  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="read_record takes the path of a record file, not None"):
        read_record(None)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="risks takes a HazardCurve .*, not str"):
        risks(tmp_path / "r.h5", "curve.csv")  # type: ignore[arg-type]


def test_a_file_of_another_kind_is_named_for_what_it_is(tmp_path):
    """Swapped arguments, a bridge given to run, a study given to describe, a results file given
    to run: each is told what the file is and what takes it, not read as a malformed one."""
    bridge, record = tmp_path / "b.yaml", tmp_path / "r.txt"
    bridge.write_text(BRIDGE)
    record.write_text("# units: m/s2\n0.0 0.0\n0.01 0.5\n0.02 -0.3\n0.03 0.0\n")
    refused(invoke("analyze", record, bridge), "r.txt: a record file where the bridge goes",
            "(the arguments are swapped)")  # fmt: skip
    refused(invoke("run", bridge), "b.yaml: this is a bridge file, not a study file")
    refused(invoke("analyze", bridge, bridge), "this is a bridge file, not a record file")
    study = tmp_path / "s.yaml"
    study.write_text(f"bridges: [{bridge.name}]\nrecords: {{files: [{{path: {record.name}}}]}}\n")
    refused(invoke("describe", study), "s.yaml: this is a study file, not a bridge file",
            "(a study file is for rockbridge run STUDY)")  # fmt: skip
    refused(invoke("run", record), "r.txt: this is a record file, not a study file")
    refused(invoke("generate-records", study), "this is a study file, not a record-set config")
    results = tmp_path / "out.h5"
    with h5py.File(results, "w"):
        pass
    refused(invoke("run", results), "out.h5: this is a results file, not a study file")
    broken = tmp_path / "broken.yaml"  # a malformed bridge is still told what is wrong with it
    broken.write_text(BRIDGE.replace("width: 2.6", "width: -2.6"))
    refused(invoke("describe", broken), "piers.width")


def test_the_manual_says_what_a_study_does_with_a_missing_or_unreadable_record(tmp_path):
    """The manual's sentence (docs/reliability.md, "Bad input at a glance", once README's) and the
    behaviour agree: a missing record file stops the study before it starts (exit 2), an
    unreadable one fails only its own analyses (exit 1, the others run)."""
    page = Path(__file__).parents[1] / "docs" / "reliability.md"
    readme = " ".join(page.read_text(encoding="utf-8").split())
    assert "a record file that is missing stops the study before it starts (exit 2" in readme
    assert "while one that exists but cannot be read (malformed, NaN" in readme
    (tmp_path / "b.yaml").write_text(BRIDGE)
    (tmp_path / "good.txt").write_text("# units: m/s2\n0.0 0.0\n0.01 1.0\n0.02 0.0\n")
    (tmp_path / "bad.txt").write_text("# units: m/s2\n0.0 0.0\n0.01 nan\n0.02 0.0\n")
    study = tmp_path / "s.yaml"
    study.write_text("bridges: [b.yaml]\nrecords: {files: [{path: good.txt}, {path: bad.txt}]}\n"
                     "fidelity: fast\noutput: {path: o.h5, histories: none}\n")  # fmt: skip
    unreadable = invoke("run", study, "--workers", 1)
    assert unreadable.exit_code == 1 and "1 ok" in unreadable.output
    (tmp_path / "bad.txt").unlink()
    refused(invoke("run", study, "--overwrite"), "record file not found: bad.txt")


@pytest.mark.parametrize(
    "command, config, expected",
    [
        ("run", "sweep: {fields: {abutments.gap: {start: a}}}",
         ["sweep.fields.abutments.gap.start: Input should be a valid number",
          "sweep.fields.abutments.gap.stop: Field required",
          "sweep.fields.abutments.gap.count: Field required"]),
        ("run", "sweep: {fields: {abutments.gap: 3}}",
         ["sweep.fields.abutments.gap: expected a list of values or a range {start, stop, count}"]),
        ("run", "sweep: {fields: {abutments.gap: [0.1, x]}}",
         ["sweep.fields.abutments.gap.1: Input should be a valid number"]),
        ("run", "fidelity: [1]",
         ["fidelity: expected a preset name (reference, default, fast, paper) or a mapping"]),
        ("generate-records", "seeds: [{path: missing.txt}]",
         ["seeds.0.path: record file not found: missing.txt"]),
        ("generate-records", "seeds: 3",
         ["seeds: expected a list of record files or {fema_p695: <set>}"]),
        ("generate-records", "seeds: {a: 1}",
         ["seeds: expected a list of record files or {fema_p695: <set>}"]),
    ],
)  # fmt: skip
def test_a_list_or_mapping_field_names_one_mistake_where_it_is_written(
    tmp_path, command, config, expected
):
    """A field that takes a list or a mapping (a sweep's values, a record set's seeds; the
    fidelity, a name or a mapping) named
    each mistake once for every member of its union, at paths with pydantic's labels in them
    (``sweep.fields.abutments.gap.list[float]: Input should be a valid list`` beside
    ``….function-after[_positive_for_log(), Range].start: …``): now once, for the kind given,
    at the path as the config is written."""
    from studies import write_study

    if command == "run":
        path = write_study(tmp_path, extra=config + "\n")
    else:
        path = tmp_path / "set.yaml"
        path.write_text(f"target: {{spectrum_type: 1, ground_type: C, ag_g: 0.6}}\n{config}\n")
    result = invoke(command, path, *(["--out", tmp_path / "set"] if command != "run" else []))
    refused(result, *expected)
    problems = result.output.count("\n") - (len(expected) > 1)  # a heading line above several
    assert problems == len(expected) and "[" not in result.output.replace("[0.1", "")


# Issue 40: a file of another kind is named for what it is; a mistyped name or id gets the nearest


def test_a_study_given_for_results_or_a_hazard_curve_is_named(tmp_path):
    study = REPO / "configs" / "studies" / "quick.yaml"
    refused(invoke("peaks", study), "this is a study file, not a results file")
    (tmp_path / "r.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(100))  # HDF5's signature only
    refused(
        invoke("risk", tmp_path / "r.h5", "--hazard", study),
        "this is a study file, not a hazard curve (a study file is for rockbridge run STUDY)",
    )


@pytest.mark.parametrize("command", ["peaks", "describe"])
def test_a_mistyped_file_name_gets_the_nearest(tmp_path, command):
    (tmp_path / "paper-fig9.h5").write_bytes(b"")
    (tmp_path / "paper-fig9.yaml").write_text(BRIDGE)
    typed = tmp_path / ("paper-fig9.hdf5" if command == "peaks" else "paper-fig9.yml")
    wanted = "paper-fig9.h5" if command == "peaks" else "paper-fig9.yaml"
    refused(invoke(command, typed), "file not found (did you mean ", wanted)
    refused(invoke(command, tmp_path / "other.h5"))
    assert "did you mean" not in invoke(command, tmp_path / "other.h5").output


def test_a_record_id_in_another_case_gets_the_id():
    assert nearest("ar07", ["AR01", "AR07", "AR10"], "records") == "nearest: AR07 (of 3 records)"
    assert nearest("AR7", ["AR01", "AR07"], "records").startswith("nearest: AR07")


@pytest.mark.parametrize(
    ("where", "entry"),
    [("records.files.1.path", " (the 2nd entry of records.files)"), ("bridges.0", " (the 1st "
     "entry of bridges)"), ("sweep.fields.piers.heights.11", " (the 12th entry of "
     "sweep.fields.piers.heights)"), ("line 3", ""), ("output.path", "")],
)  # fmt: skip
def test_a_list_entry_is_also_counted_as_a_reader_counts(where, entry):
    """Issue 40: `records.files.1` is the 2nd entry; the paths count from 0, as a sweep's fields
    do, and the message says which entry that is."""
    assert str(InputError("s.yaml", [(where, "why")])) == f"s.yaml: {where}: why{entry}"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs")
def test_a_fifo_named_on_the_command_line_is_refused_without_waiting(tmp_path):
    """A FIFO given as a command's file hung ``describe``, ``analyze``, ``run``,
    ``generate-records`` and ``plot onset`` (the kind of the refused file was sniffed by opening
    it, which waits for a writer), and ``peaks``, ``report``, ``fragility`` called it "file not
    found". A watchdog opens the FIFO's writing end whenever a reader waits on it: it counts the
    hang and lets the reader go on (to end of file), so a regression fails instead of hanging."""
    import threading

    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    bridge = tmp_path / "b.yaml"
    bridge.write_text(BRIDGE)
    hangs, done = [], threading.Event()

    def watchdog() -> None:
        while not done.wait(0.05):
            try:  # succeeds only where a reader has the FIFO open (or waits to)
                os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
                hangs.append(1)
            except OSError:
                pass

    thread = threading.Thread(target=watchdog, daemon=True)
    thread.start()
    try:
        for args in (("describe", fifo), ("analyze", fifo, fifo), ("analyze", bridge, fifo),
                     ("run", fifo, "--workers", 1), ("generate-records", fifo),
                     ("plot", "onset", fifo)):  # fmt: skip
            refused(invoke(*args), "fifo: is not a regular file")
        for args in (("peaks", fifo), ("report", fifo), ("fragility", fifo)):
            refused(invoke(*args), "fifo: is not a regular file", "not a results file")
    finally:
        done.set()
        thread.join()
    assert not hangs


def test_values_accepted_silently_before_are_refused(tmp_path):
    """Issue 39's silent accepts: ``risk --years inf`` (every probability 1), a spectrum whose
    frequencies fall (``10:1:40``), ``normalize: "yes"`` read as true, ``-o x.h5.journal.db``
    (a results file named as a journal), ``identify_pulse`` on NaN (came back "no pulse")."""
    from rockbridge_cli.assessment.risk import risks_of
    from rockbridge_cli.config.records import FemaSet
    from rockbridge_cli.config.spectrum import Spectrum
    from rockbridge_cli.motions.pulse_identification import identify_pulse

    with pytest.raises(InputError, match=r"positive number of years \(finite\), not inf"):
        risks_of([], {"measure": "pga_g"}, None, years=float("inf"))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="frequency ratios must rise"):
        Spectrum.model_validate({"pulse": "one-sine-a", "amplitudes": {"start": 1, "stop": 5,
                                 "count": 5}, "frequencies": {"start": 10, "stop": 1,
                                 "count": 40}})  # fmt: skip
    with pytest.raises(ValueError, match="normalize"):
        FemaSet.model_validate({"set": "far-field", "normalize": "yes"})
    with pytest.raises(ValueError, match="must be finite numbers"):
        identify_pulse(np.array([0.0, np.nan, 1.0, 0.0] * 100), 0.01)
    (tmp_path / "b.yaml").write_text(BRIDGE)
    shaking = 0.1 * (-1.0) ** np.arange(50)  # a mean of zero: no warning before the refusal
    np.savetxt(tmp_path / "R1.txt", np.column_stack([np.arange(50) * 0.01, shaking]))
    (tmp_path / "s.yaml").write_text("bridges: [b.yaml]\nrecords: {files: [{path: R1.txt, "
                                     "units: g}]}\n")  # fmt: skip
    result = invoke("run", tmp_path / "s.yaml", "-o", tmp_path / "x.h5.journal.db")
    refused(result, "x.h5.journal.db: is named as a results file's journal")
    assert not (tmp_path / "x.h5.journal.db").exists()


def test_a_record_with_an_offset_is_warned_about():
    """A horizontal record whose mean is not near zero (an uncorrected baseline, an offset in
    the file) ran without a word, while a vertical component's mean was checked (a second
    reviewer, 2026-11-28: AR07 with 2 m/s² added rocked from t = 0). The bound, 1 % of the
    peak, is 70 times the largest of the FEMA P695 sets' 100 components (0.015 %)."""
    from rockbridge_cli.config.plausibility import record_warnings
    from rockbridge_cli.records.files import Record

    t = np.arange(0.0, 20.0, 0.01)
    motion = 3.0 * np.sin(2.0 * np.pi * t)  # whole cycles: mean 0 to rounding
    assert not any("mean" in w for w in record_warnings(Record("R", 0.01, motion)))
    offset = record_warnings(Record("R", 0.01, motion + 0.5))
    assert any("its mean is 0.051 g, 14.3% of its peak" in w for w in offset)


def test_a_vertical_component_of_gravity_is_warned_about(tmp_path):
    """A vertical companion that is a constant −0.92 g (gravity written into the file) ran
    without a word (issue 39)."""
    from rockbridge_cli.config.plausibility import record_warnings
    from rockbridge_cli.records.files import Record

    samples = 3.0 * np.sin(np.linspace(0.0, 20.0, 500))
    gravity = np.full(500, -0.92 * 9.80665)
    record = Record("R", 0.01, samples, vertical=gravity)
    assert any("vertical component averages -0.92 g" in w for w in record_warnings(record))
    assert not any(
        "averages" in w for w in record_warnings(Record("R", 0.01, samples, vertical=0.1 * samples))
    )

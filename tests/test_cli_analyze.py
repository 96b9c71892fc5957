"""``rockbridge analyze``: one analysis from the command line, its JSON, its file and bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.records.files import read_record
from rockbridge_cli.results import read_events, read_peaks

REPO = Path(__file__).resolve().parents[1]
BRIDGE = REPO / "configs" / "bridges" / "studied-hbar1.25.yaml"
RECORD = REPO / "records" / "ec8-type1-C-ag0.6g" / "AR07.txt"
KEYS = ("u_deck_max", "v_deck_max", "theta_deck_max", "theta1_max", "theta2_max", "t_onset",
        "n_impacts", "n_poundings", "failure_mode", "fidelity", "solve_time_s")  # fmt: skip


def invoke(*args: str):
    return CliRunner().invoke(main, [str(a) for a in args])


def printed_json(result) -> dict:
    """The JSON object a command printed: CliRunner's output holds stderr too (click 8.2), where
    a first run on a cold numba cache says that it compiles."""
    text = result.output
    return json.loads(text[text.index("{") : text.rindex("}") + 1])


def test_json_has_the_keys_and_the_library_values():
    """The issue's keys, with the values the library call gives for the same inputs."""
    result = invoke("analyze", BRIDGE, RECORD, "--json")
    assert result.exit_code == 0, result.output
    data = printed_json(result)
    assert set(KEYS) <= set(data)
    record = read_record(RECORD)
    config = load_bridge(BRIDGE)
    response = analyze(config.to_bridge(), record.acceleration, record.time_step)
    for name in ("u_deck", "v_deck", "theta_deck", "theta1", "theta2"):
        assert data[f"{name}_max"] == pytest.approx(response.peaks[name][0], rel=1e-12)
    assert data["n_impacts"] == response.n_impacts and data["fidelity"] == "default"


def test_output_file_holds_the_same_analysis(tmp_path):
    out = tmp_path / "one.h5"
    text = invoke("analyze", BRIDGE, RECORD, "--fidelity", "fast", "-o", out)
    assert text.exit_code == 0, text.output
    printed = printed_json(invoke("analyze", BRIDGE, RECORD, "--fidelity", "fast", "--json"))
    with h5py.File(out, "r") as file:
        group = file["analyses/studied-hbar1.25/AR07"]
        assert group["histories/u_deck"].attrs["units"] == "m"
        assert np.max(np.abs(group["histories/u_deck"][()])) <= printed["u_deck_max"] * (1 + 1e-12)
        assert file["peaks/u_deck_max"][0] == pytest.approx(printed["u_deck_max"], rel=1e-12)


def test_output_file_with_a_tail_is_the_tailed_analysis(tmp_path):
    """-o runs the same analysis as the library call, tail included: the stored histories run
    to the record's end plus the tail, and the peaks agree with `analyze(..., tail=...)`."""
    out = tmp_path / "tail.h5"
    result = invoke("analyze", BRIDGE, RECORD, "--fidelity", "fast", "--tail", "5", "-o", out)
    assert result.exit_code == 0, result.output
    record = read_record(RECORD)
    bridge = load_bridge(BRIDGE).to_bridge()
    expected = analyze(bridge, record.acceleration, record.time_step, "fast", tail=5.0)
    with h5py.File(out, "r") as file:
        assert json.loads(file.attrs["knobs"])["tail"] == 5.0
        assert file["peaks/u_deck_max"][0] == pytest.approx(expected.peaks["u_deck"][0], rel=1e-12)
        assert file["peaks/n_impacts"][0] == expected.n_impacts


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("0.0 0.0\n0.01 nan\n0.02 0.0\n", "line 2: value 2 is not a finite number"),
        ("0.0 0.0\n0.01 0.1\n0.03 0.0\n", "step"),
        ("0.0 0.0\n0.01\n0.02 0.0\n", "line 2"),
        ("", "empty"),
    ],
)
def test_bad_record_exits_2_with_one_message(tmp_path, text, reason):
    path = tmp_path / "bad.txt"
    path.write_text(text)
    result = invoke("analyze", BRIDGE, path, "--units", "g")
    assert result.exit_code == 2
    assert "Traceback" not in result.output and "bad.txt" in result.output
    assert reason in result.output.lower()


def test_plain_file_without_units_is_refused(tmp_path):
    path = tmp_path / "plain.txt"
    path.write_text("0.0 0.0\n0.01 0.1\n0.02 0.0\n")
    result = invoke("analyze", BRIDGE, path)
    assert result.exit_code == 2 and "units" in result.output


def test_rocking_restitution_from_the_config_is_used(tmp_path):
    """A bridge config may give η (for example a measured one): every impact then scales θ̇1 by
    exactly that value, in both directions."""
    bridge = tmp_path / "bridge.yaml"
    bridge.write_text(BRIDGE.read_text() + "rocking_restitution: 0.9\n")
    out = tmp_path / "one.h5"
    assert invoke("analyze", bridge, RECORD, "-o", out).exit_code == 0
    events = read_events(out, "bridge", "AR07")
    impact = events["kind"] == "impact"
    ratio = events["rate_after"][impact] / events["rate_before"][impact]
    assert impact.sum() > 5
    np.testing.assert_allclose(ratio, 0.9, rtol=1e-12)
    described = printed_json(invoke("describe", bridge, "--json"))
    assert described["rocking_restitution"] == 0.9


def test_a_solver_failure_exits_1_with_nan_peaks(tmp_path, monkeypatch):
    """A record of 1e300 m/s² makes the integrator give up at once: the analysis says so, its
    peaks are NaN (never 0), and `analyze` exits 1, with or without a results file. (Such a
    file is refused at reading, above `ABSURD_PGA_G`: the bound is lifted here to reach the
    solver's own failure, which a pathological bridge could still meet.)"""
    from rockbridge_cli.records import files

    monkeypatch.setattr(files, "ABSURD_PGA_G", math.inf)
    t = np.arange(0.0, 2.0, 0.01)
    path = tmp_path / "huge.txt"
    path.write_text(
        "# units: m/s2\n" + "".join(f"{x:.2f} {float(1e300 * np.sin(x))!r}\n" for x in t)
    )
    result = invoke("analyze", BRIDGE, path, "--json")
    assert result.exit_code == 1
    text = result.output
    data = json.loads(text[text.index("{") : text.rindex("}") + 1])
    assert "warning: " in text and "is not an earthquake's" in text  # a 1e299 g record
    assert data["status"] == "solver_error"  # as in a study's peak table (one route)
    assert data["message"] == "the step size fell below 1e-14 s"
    assert data["u_deck_max"] is None and data["theta1_max"] is None  # NaN → null
    out = tmp_path / "huge.h5"
    stored = invoke("analyze", BRIDGE, path, "-o", out)
    assert stored.exit_code == 1 and "the integrator stopped early" in stored.output
    peaks = read_peaks(out)
    assert peaks["status"][0] == "solver_error" and np.isnan(peaks["u_deck_max"][0])


def test_non_finite_values_are_refused(tmp_path):
    bridge = tmp_path / "bridge.yaml"
    bridge.write_text(BRIDGE.read_text().replace("stiffness: 132.0e6", "stiffness: .inf"))
    assert ".inf" in bridge.read_text()
    result = invoke("describe", bridge)
    assert result.exit_code == 2
    assert "abutments.stiffness: Input should be a finite number" in result.output


def test_the_symmetric_deck_does_not_rotate_in_print():
    """h̄ = 1: the deck only translates (docs/model.md §3), but the arithmetic leaves ~1e-16 rad;
    the table shows 0, and --json keeps the computed value."""
    symmetric = REPO / "configs" / "bridges" / "studied-hbar1.00.yaml"
    text = invoke("analyze", symmetric, RECORD).output
    line = next(row for row in text.splitlines() if row.startswith("max theta_deck"))
    assert line.split()[2] == "0", line
    data = printed_json(invoke("analyze", symmetric, RECORD, "--json"))
    assert 0.0 <= data["theta_deck_max"] < 1e-12


FRAME = """\
piers: {width: 2.6, heights: [26.0, 20.8]}
deck: {depth: 1.7, area: 6.0}
spans: {side: 38.0, central: 60.0}
"""
"""The h̄ = 1.25 bridge without abutments: a rocking frame."""


def test_a_record_that_ends_while_the_bridge_rocks_hints_at_a_tail(tmp_path):
    """A 0.45 g half-sine pulse of 2 s period, cut at 2 s, leaves the frame rotating towards
    overturning (`test_solver`'s test: it overturns 0.44 s after the record): analyze says so and
    suggests --tail; with the tail, the failure is seen and nothing is suggested."""
    (tmp_path / "frame.yaml").write_text(FRAME)
    t = np.arange(0.0, 2.0 + 0.005, 0.01)
    pulse = np.where((t >= 0.5) & (t <= 1.5), 0.45 * 9.81 * np.sin(np.pi * (t - 0.5)), 0.0)
    record = tmp_path / "pulse.txt"
    lines = [f"{a:.2f} {b:.17g}\n" for a, b in zip(t, pulse, strict=True)]
    record.write_text("# units: m/s2\n" + "".join(lines))
    cut = invoke("analyze", tmp_path / "frame.yaml", record)
    assert cut.exit_code == 0, cut.output
    assert "failure                            none" in cut.output
    assert "note: the bridge still rocks as the record ends (θ1 up to" in cut.output
    assert "--tail 20 runs on with the ground at rest" in cut.output
    tailed = invoke("analyze", tmp_path / "frame.yaml", record, "--tail", "20")
    assert "failure                            overturning" in tailed.output
    assert "note:" not in tailed.output
    quiet = invoke("analyze", BRIDGE, RECORD)  # the bundled records end with the bridge near rest
    assert "note:" not in quiet.output


def test_json_states_units_and_the_solve_without_the_set_up():
    """Every number of --json has its unit (SI, as the peak table's); the solve time is the
    integration's alone, the one-time set-up (loading kernels, building tables) apart."""
    data = printed_json(invoke("analyze", BRIDGE, RECORD, "--json"))
    units = data["units"]
    assert units["u_deck_max"] == "m" and units["theta1_max"] == "rad"
    assert units["solve_time_s"] == units["setup_time_s"] == units["t_onset"] == "s"
    assert units["record_pga"] == "m/s2"
    assert data["record_pga"] == pytest.approx(read_record(RECORD).peak_acceleration, rel=1e-15)
    numbers = {k for k, v in data.items() if isinstance(v, (int, float)) and k != "units"}
    assert numbers <= set(units)
    assert data["setup_time_s"] > 0.0 and "set-up" not in data.get("status", "")
    text = invoke("analyze", BRIDGE, RECORD).output
    assert "set-up, once per process" in text and "solve time" in text


def test_a_block_prints_no_rows_for_the_parts_it_has_not(tmp_path):
    """Issue 40: a single block (no deck, no second pier) printed `nan m at nan s` for each of
    their peaks; the table now has rows for what the model has, whose values are the analysis's."""
    block = tmp_path / "block.yaml"
    block.write_text("name: block\npiers: {width: 1.2, heights: [3.0]}\n", encoding="utf-8")
    result = invoke("analyze", block, RECORD, "--fidelity", "fast")
    assert result.exit_code == 0, result.output
    assert "nan" not in result.output
    rows = [line.split()[1] for line in result.output.splitlines() if line.startswith("max ")]
    assert rows == ["theta1", "u_pier1"]
    motion = read_record(RECORD)
    bridge = load_bridge(block).to_bridge()
    response = analyze(bridge, motion.acceleration, motion.time_step, "fast")
    theta1 = next(line for line in result.output.splitlines() if line.startswith("max theta1"))
    assert f"{response.peak_row()['theta1_max']:.5g} rad" in theta1

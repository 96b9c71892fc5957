"""Bounds on work and memory (issue 32): every knob that sets how much an analysis or a study
computes or holds has a documented limit (`core.fidelity.LIMITS`,
`config.study_checks.MAX_ANALYSES`, `config.sweep.MAX_VARIANTS`,
`config.intensity.MAX_SCAN_LEVELS`, …) or a work estimate (`core.fidelity.check_work`), so that
what could not end, or not fit in memory, is refused at once with one line naming the file and
the field. Each case below ran until killed before."""

from __future__ import annotations

import os

import numpy as np
import pytest
from click.testing import CliRunner
from studies import BRIDGES, REPO, write_study

from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.fidelity import PRESETS, check_work, resolve


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # default outputs (results/<stem>.h5) land in tmp_path


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def refused(result, *fragments: str) -> None:
    assert result.exit_code == 2, result.output
    assert result.output.startswith("error: ") and "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in result.output, result.output


@pytest.mark.parametrize(
    ("extra", "fragments"),
    [
        ("fidelity: {max_step: 1.0e-9}", ("fidelity: max_step must be a number from 1e-05",)),
        ("fidelity: {event_tol: 1.0e-300}", ("event_tol must be a number from 1e-13",)),
        ("fidelity: {rtol: 0, atol: 0}", ("dopri5 needs rtol ≥ 1e-13 or atol ≥ 1e-16",)),
        ("fidelity: {tail: 1.0e7}", ("tail must be a number from 0 to 3600",)),
        ("output: {output_step: 1.0e-7}", ("output_step must be a number from 0.0001",)),
        ("fidelity: {max_events: 1000000000}", ("max_events must be a number from 1 to 1e+06",)),
        # each knob in range, together too much: 3606 s at 1e-5 s is 3.6e8 steps
        ("fidelity: {max_step: 1.0e-5, tail: 3600}", ("records (R1): 3605.99 s of analysis would "
                                                      "need 3.61e+08 steps, more than 1e+08",)),
        ("intensity: {measure: scale, ida: {start: 0.1, step: 1.0e-6, max: 10}}",
         ("intensity.ida", "at most 1000 scan levels")),
        ("intensity: {measure: scale, ida: {start: 1, step: 1, max: 1.0e12}}",
         ("at most 1000 scan levels",)),
        ("intensity: {measure: sa_g, period: 1.0e-9, levels: [0.5]}",
         ("intensity.period", "greater than or equal to 0.01")),
        ("sweep: {fields: {abutments.gap: {start: 0.1, stop: 0.2, count: 100000000}}}",
         ("sweep.fields.abutments.gap", "less than or equal to 10000")),
        ("sweep:\n  grid: true\n  fields:\n"
         + "".join(f"    {f}: {{start: 0.1, stop: 0.2, count: 1000}}\n"
                   for f in ("abutments.gap", "spans.side", "deck.depth")),
         ("1,000,000,000 variants of each bridge, more than 10,000",)),
    ],
)  # fmt: skip
def test_a_study_that_could_not_end_is_refused_at_once(tmp_path, extra, fragments):
    study = write_study(tmp_path, extra=extra + "\n")
    refused(invoke("run", study, "--workers", "1"), str(study), *fragments)
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize("tail", ["nan", "inf", "4000"])
def test_a_tail_out_of_range_is_refused_by_run(tmp_path, tail):
    """``run --tail nan`` was accepted, then every analysis failed (issue 32, finding 10)."""
    result = invoke("run", write_study(tmp_path), "--tail", tail, "--workers", "1")
    assert result.exit_code == 2 and "--tail" in result.output and "Traceback" not in result.output


def test_too_many_shards_are_refused_and_cost_no_memory(tmp_path):
    """``--shard 1/99999999999999999999999`` built a list of that many shards. N is bounded by
    the most analyses a study may hold, and shards beyond the analyses are empty: with 4
    analyses and 1000 shards, the first holds one analysis."""
    study = write_study(tmp_path)
    result = invoke("run", study, "--shard", "1/99999999999999999999999", "--workers", "1")
    assert result.exit_code == 2 and "N must be at most 1,000,000" in result.output
    result = invoke("run", study, "--shard", "1/1000", "--workers", "1")
    assert result.exit_code == 0 and "analyses: 1 (1 run now" in result.output, result.output


def test_too_many_analyses_are_refused(tmp_path, monkeypatch):
    """The size of a study is checked on bridges × records × levels, before the scaled copies of
    the records are made: 2 × 2 × 1000 = 4000 analyses against a limit lowered to 3999."""
    from rockbridge_cli.config import study_checks

    levels = ", ".join(f"{0.1 + 1e-4 * i:.4f}" for i in range(1000))
    study = write_study(tmp_path, extra=f"intensity: {{measure: pga_g, levels: [{levels}]}}\n")
    monkeypatch.setattr(study_checks, "MAX_ANALYSES", 3999)
    refused(invoke("run", study), "2 bridges × 2 records × 1000 levels are more than 3,999")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs")
def test_a_fifo_as_a_manifest_is_refused(tmp_path):
    """A record set whose manifest is a FIFO hung the study (the read waits for a writer)."""
    folder = tmp_path / "set"
    folder.mkdir()
    os.mkfifo(folder / "manifest.json")
    study = tmp_path / "s.yaml"
    study.write_text(f"bridges: [{(BRIDGES / 'studied-hbar1.00.yaml').as_posix()}]\n"
                     "records: {set: set}\n")  # fmt: skip
    refused(invoke("run", study), "manifest.json", "not a regular file")


def test_a_dashpot_beyond_reach_is_refused(tmp_path):
    """A 1e15 N·s/m backfill dashpot took minutes an analysis (steps of c / m_deck)."""
    text = (BRIDGES / "studied-hbar1.00.yaml").read_text().replace("damping: 48.0e6",
                                                                   "damping: 1.0e15")  # fmt: skip
    (tmp_path / "b.yaml").write_text(text)
    refused(invoke("describe", tmp_path / "b.yaml"), "abutments.damping: c / m_deck = 4.9e+08")


@pytest.mark.parametrize(
    ("overrides", "fragment"),
    [
        ({"max_step": 0.0}, "max_step must be a number"),
        ({"rtol": "x"}, "rtol must be a number"),
        ({"kinematics": None}, None),  # None leaves the preset's, as for every knob
        ({"kinematics": "fitted"}, "kinematics must be one of exact, tabulated, simplified"),
        ({"bisection": 1}, "bisection must be true or false"),
        ({"max_events": 2.5}, "max_events must be a number"),
        ({"tail": float("nan")}, "tail must be a number from 0 to 3600"),
    ],
)
def test_the_api_checks_its_knobs_like_the_cli(overrides, fragment):
    """`analyze` took ``max_step=0`` (and never ended) and ``rtol='x'`` (a numba TypingError)."""
    bridge = load_bridge(BRIDGES / "studied-hbar1.00.yaml").to_bridge()
    ground = np.zeros(100)
    if fragment is None:
        assert analyze(bridge, ground, 0.01, **overrides).status == "ok"
        return
    with pytest.raises(ValueError, match=fragment):
        analyze(bridge, ground, 0.01, **overrides)


def test_the_presets_are_within_the_limits_and_the_work_estimate_is_a_count():
    """Every preset passes its own limits. The estimate counts: 10 001 samples at 0.01 s and a
    20 s tail are 120 s, 12 001 ground samples, 12 000 history samples at 0.01 s, 1e7 steps at
    max_step 1.2e-5 s (within 1e8) and 1.2e8 at 1e-6 s (beyond)."""
    for preset in PRESETS:
        check_work(resolve(preset).knobs, 10001, 0.01)
    values = resolve("default", tail=20.0, max_step=1.2e-5).knobs
    check_work(values, 10001, 0.01)
    with pytest.raises(ValueError, match=r"120 s of analysis would need 1\.2e\+08 steps"):
        check_work({**values, "max_step": 1e-6}, 10001, 0.01)


BLOCK_STUDY = "bridges: [{id: block, piers: {width: 0.8, heights: [2.0]}}]\n"


@pytest.mark.parametrize(
    ("records", "fragments"),
    [
        ("records: {pulses: [{shape: one-sine-a, amplitude_g: 0.5, period: 1.0e-9}]}\n",
         ("records.pulses.0", "the pulse would need 2.01e+12 samples")),  # 10 s / (1e-9/200.5)
        ("records: {pulses: [{shape: one-sine-a, amplitude_g: 0.5, period: 1, cycles: 1.0e+9}]}\n",
         ("records.pulses.0", "the pulse would need 2e+11 samples")),
        ("records: {pulses: [{shape: mavroeidis-papageorgiou, amplitude_g: 0.5, period: 1, "
         "cycles: 1.0e+6}]}\n", ("records.pulses.0", "the pulse would need 2e+08 samples")),
        ("spectrum: {pulse: one-sine-a, frequencies: {start: 1.0e+6, stop: 1.0e+7, count: 3}, "
         "amplitudes: {start: 1, stop: 5, count: 5}}\n",
         ("spectrum.frequencies: the pulse would need", "more than 1e+07")),
        ("spectrum: {pulse: one-sine-a, frequencies: {start: 1, stop: 10, count: 10000}, "
         "amplitudes: {start: 1, stop: 10, count: 1000}}\n",
         ("spectrum: 10000 frequencies × 1000 amplitudes are more than 1,000,000 analyses",)),
        ("spectrum: {pulse: one-sine-a, frequencies: {start: 1, stop: 10, count: 3}, "
         "amplitudes: {start: 1, stop: 10, count: 5000}}\n",
         ("spectrum.amplitudes: at most 1000 amplitudes, not 5000",)),
    ],
)  # fmt: skip
def test_pulses_and_spectra_beyond_the_work_limit_are_refused_before_sampling(
    tmp_path, records, fragments
):
    """Issue 39: the work estimate ran after the samples were built, so a pulse of period 1e-9 s,
    1e9 cycles, a Mavroeidis–Papageorgiou pulse of 1e6 cycles (1.5 GiB), a spectrum at 1e6–1e7 Hz
    (15 GiB) ended in a MemoryError after taking the memory; a spectrum's map of 1e7 analyses
    (its first round) was not counted against the study's limit (10 min, no progress line); 5000
    amplitudes gave a 4-line pydantic dump about IDA scan levels, exit 1. Each is now one line,
    exit 2, at once."""
    import time

    study = tmp_path / "s.yaml"
    study.write_text(BLOCK_STUDY + records, encoding="utf-8")
    started = time.perf_counter()
    refused(invoke("run", study), "s.yaml: ", *fragments)
    assert time.perf_counter() - started < 5.0


def test_generated_records_beyond_the_work_limit_are_refused_before_sampling(tmp_path):
    """``generate-records`` with ``time_step: 1e-9`` ended in a MemoryError (issue 39)."""
    config = (REPO / "configs" / "records" / "ec8-type1-C-ag0.6g-vertical.yaml").read_text()
    (tmp_path / "fine.yaml").write_text(config.replace("time_step: 0.01", "time_step: 1.0e-9"))
    refused(invoke("generate-records", tmp_path / "fine.yaml", "--out", tmp_path / "set"),
            "fine.yaml: ", "a record of 20 s at 1e-09 s would hold 2e+10 samples")  # fmt: skip


@pytest.mark.parametrize(
    ("section", "where"),
    [
        ("spectrum: {pulse: one-sine-a, frequencies: {start: 1, stop: 5, count: 3}, "
         "amplitudes: {start: 1, stop: 5, count: 5}, limit_states: [gap_closure]}\n",
         "spectrum.limit_states"),
        ("records: {pulses: [{shape: one-sine-a, amplitude_g: 0.5, period: 1, rest: 1}]}\n"
         "intensity: {measure: pga_g, ida: {start: 0.1, step: 0.1, max: 1.0, "
         "limit_states: [gap_closure, overturning]}}\n", "intensity.ida.limit_states"),
        ("records: {pulses: [{shape: one-sine-a, amplitude_g: 0.5, period: 1, phase: 1.0e+300, "
         "rest: 1}]}\n", "records.pulses.0"),
    ],
)  # fmt: skip
def test_what_a_block_cannot_reach_or_a_phase_beyond_a_turn_is_refused(tmp_path, section, where):
    """Issue 39: ``limit_states: [gap_closure]`` for a block (no abutments: its boundary or IDA
    ran to the top of the scan) and a pulse ``phase: 1e300`` were accepted without a word."""
    study = tmp_path / "s.yaml"
    study.write_text(BLOCK_STUDY + section, encoding="utf-8")
    result = invoke("run", study)
    refused(result, f"s.yaml: {where}: ")
    assert "need abutments" in result.output or "within ±2π rad" in result.output

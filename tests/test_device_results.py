"""The devices in a study's results (issue 41; docs/results.md, "The device table"): the rows
each analysis packs, the ``/devices`` table written only where a bridge has devices, read back
for a resumed run, the journal that carries them, and the tendons' limit states
(``tendon_yield``, ``tendon_rupture``) they decide."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
from studies import BRIDGES

from rockbridge_cli.assessment.limit_states import Verdict, reached, stored_verdicts
from rockbridge_cli.core.devices import Damper, Tendon
from rockbridge_cli.core.quantities import check_limit_state
from rockbridge_cli.results.packing import (
    DEVICE_RECORD,
    AnalysisResult,
    device_rows,
    device_states,
)
from rockbridge_cli.results.reading import device_tables, peak_columns, stored_results
from rockbridge_cli.results.writing import ResultsWriter
from rockbridge_cli.study.grid import Cell
from rockbridge_cli.study.journal import Journal
from rockbridge_cli.study.work import Finished

# a tendon P0 = 4 MN, k = 100 MN/m, E·A = 1 GN (ε0 = 0.004), F_y = 5 MN, ε_u = 0.0055
LIMITED = Tendon(0, 0.2, 4.0e6, 1.0e8, yield_force=5.0e6, rupture_strain=0.0055, rigidity=1e9)
PLAIN = Tendon(1, 0.0, 4.0e6, 1.0e8)  # no limits, no rigidity
DAMPER = Damper(0, 0.5, 1.0e7)


def _peaks(stretch: float) -> dict[str, tuple[float, float]]:
    """Peaks of the three devices as `core.analysis.Response.peaks` names them, the tendons
    stretched by ``stretch`` [m] at 3 s (force P0 + k·Δ, as if elastic), the damper's 0.5 MN at
    2 s; whether the tendons yielded and broke is what the solver would say of `LIMITED`'s
    limits (T ≥ F_y, (P0 + k·Δ)/(E·A) ≥ ε_u), at 2.9 s."""
    force = 4.0e6 + 1.0e8 * stretch
    yielded = (1.0, 2.9) if force >= 5.0e6 else (0.0, math.nan)
    broken = (1.0, 2.9) if force / 1e9 >= 0.0055 else (0.0, math.nan)
    return {
        "tendon1_elongation": (stretch, 3.0), "tendon1_force": (force, 3.0),
        "tendon2_elongation": (stretch, 3.0), "tendon2_force": (force, 3.0),
        "tendon1_yielded": yielded, "tendon2_yielded": yielded,
        "tendon1_broken": broken, "tendon2_broken": broken,
        "damper1_elongation": (0.01, 2.5), "damper1_force": (5.0e5, 2.0),
    }  # fmt: skip


def test_a_devices_row_judges_a_tendon_against_its_limits():
    """Δ = 0.02 m: P0 + k·Δ = 4 + 0.1·20 = 6 MN ≥ F_y = 5 MN, ε = ε0 + Δ/L_free =
    (P0 + k·Δ)/(E·A) = 0.006 ≥ 0.0055: both reached. Δ = 0.012 m: 5.2 MN ≥ 5 MN, ε = 0.0052 <
    0.0055: yield only. Δ = 0.005 m: 4.5 MN, neither. The flags are the solver's states
    (`_peaks`); the tendon without limits and the damper state none (−1)."""
    devices = (LIMITED, PLAIN, DAMPER)
    for stretch, yielded, ruptured in ((0.02, 1, 1), (0.012, 1, 0), (0.005, 0, 0)):
        rows = device_rows(devices, _peaks(stretch))
        assert [name.decode() for name in rows["device"]] == ["tendon1", "tendon2", "damper1"]
        force = 4.0e6 + 1.0e8 * stretch
        assert rows["force_max"][0] == force and rows["elongation_max"][0] == stretch
        assert rows["strain_max"][0] == pytest.approx(force / 1e9, rel=1e-15)
        assert list(rows["yielded"]) == [yielded, -1, -1]
        assert list(rows["ruptured"]) == [ruptured, -1, -1]
        assert np.isnan(rows["strain_max"][1:]).all()
        assert (rows["force_max"][2], rows["force_time"][2]) == (5.0e5, 2.0)
        states = device_states(rows)
        assert (states["tendon_yield"], states["tendon_rupture"]) == (yielded, ruptured)
        assert math.isnan(states["dissipator_fracture"])  # no dissipator
    states = device_states(device_rows((PLAIN, DAMPER), {**_peaks(0.02)}))
    assert all(math.isnan(value) for value in states.values())  # no limit stated
    assert all(math.isnan(value) for value in device_states(np.zeros(0, DEVICE_RECORD)).values())


def test_the_tendons_limit_states_are_reached_where_their_column_says():
    assert check_limit_state("tendon_yield") == "tendon_yield"
    assert check_limit_state("tendon_rupture") == "tendon_rupture"
    columns = {
        "dcr_backfill": np.array([0.5, 0.0, 1.0]),
        "failure_mode": np.array(["none", "none", "abutment"]),
        "tendon_yield": np.array([1.0, 0.0, np.nan]),
    }
    assert list(reached("tendon_yield", columns)) == [True, False, False]
    assert list(reached("tendon_rupture", columns)) == [False] * 3  # no column: never
    verdict = Verdict("ok", "none", 0.2, tendon_yield=1.0, tendon_rupture=0.0)
    assert verdict.reaches(["tendon_yield", "tendon_rupture", "gap_closure"]) == {
        "tendon_yield", "gap_closure"
    }  # fmt: skip
    assert Verdict("ok", "none", 0.2).reaches(["tendon_yield"]) == frozenset()
    assert Verdict("error", "", math.nan, 1.0, 1.0).reaches(["tendon_yield"]) == frozenset()


def _result(bridge: str, record: str, devices=(), stretch: float = 0.02) -> AnalysisResult:
    """An analysis that ran (every peak-table value missing but its status), with the rows of
    ``devices`` at ``stretch``."""
    values = AnalysisResult.failed(bridge, record, "").values
    values.update(status="ok", failure_mode="none", dcr_backfill=0.25, n_events=0)
    events = {name: np.zeros(0) for name in ("time", "mode", "rate_before", "rate_after")}
    return AnalysisResult(
        bridge, record, values, events={**events, "kind": np.zeros(0, dtype=str)},
        devices=device_rows(devices, _peaks(stretch)),
    )  # fmt: skip


def _write(path, results) -> None:
    with h5py.File(path, "w") as file:
        file.create_group("bridges")
        writer = ResultsWriter(file, len(results))
        writer.add(result.pack() for result in results)
        writer.close("now")


def test_the_device_table_is_written_only_with_devices_and_read_back_as_written(tmp_path):
    """A file of a free-standing bridge's analyses has no /devices (it is the file devices did
    not exist for); a file with a restrained bridge's has one row per device of each of its
    analyses, which a resumed run reads back (`stored_results`) exactly, and the peak table's
    readers give each analysis its tendons' states (NaN for the free bridge)."""
    free = [_result("free", "r1"), _result("free", "r2")]
    _write(tmp_path / "free.h5", free)
    with h5py.File(tmp_path / "free.h5", "r") as file:
        assert "devices" not in file and device_tables(file) == {}
        assert "tendon_yield" not in peak_columns(file)

    mixed = [
        _result("free", "r1"),
        _result("tied", "r1", (LIMITED, PLAIN, DAMPER), 0.02),
        _result("tied", "r2", (LIMITED, PLAIN, DAMPER), 0.005),
    ]
    _write(tmp_path / "mixed.h5", mixed)
    with h5py.File(tmp_path / "mixed.h5", "r") as file:
        table = file["devices"]
        assert list(table["bridge"].asstr()[()]) == ["tied"] * 6
        assert list(table["record"].asstr()[()]) == ["r1"] * 3 + ["r2"] * 3
        assert list(table["device"].asstr()[()]) == ["tendon1", "tendon2", "damper1"] * 2
        assert table["force_max"].attrs["units"] == "N" and table["yielded"].dtype == np.int8
        assert list(table["yielded"][()]) == [1, -1, -1, 0, -1, -1]
        back = list(stored_results(file))
        for read, written in zip(back, mixed, strict=True):
            assert read.devices.tobytes() == written.devices.tobytes()
        columns = peak_columns(file)
        np.testing.assert_array_equal(columns["tendon_yield"], [np.nan, 1.0, 0.0])
        np.testing.assert_array_equal(columns["tendon_rupture"], [np.nan, 1.0, 0.0])
        verdicts = stored_verdicts(file)
        assert verdicts[("tied", "r1")].reaches(["tendon_rupture"]) == {"tendon_rupture"}
        assert math.isnan(verdicts[("free", "r1")].tendon_yield)
    _write(tmp_path / "again.h5", back)  # a resumed run writes its file from the stored ones
    with h5py.File(tmp_path / "mixed.h5", "r") as a, h5py.File(tmp_path / "again.h5", "r") as b:
        for name in a["devices"]:
            np.testing.assert_array_equal(a["devices"][name][()], b["devices"][name][()])


def test_the_journal_carries_the_device_rows_and_their_verdict(tmp_path):
    """What a worker journals comes back for the results file (`Journal.packed`) and for the IDA
    rule (`Journal.verdicts`), the tendons' states with it."""
    journal = Journal(tmp_path / "out.h5", "hash")
    tied = _result("tied", "r1", (LIMITED, DAMPER), 0.012)
    packed = tied.pack()
    states = device_states(tied.devices)
    finished = Finished(Cell(0, 0, 0), "tied", "r1", "ok", "", 1.0, "none", 0.25, 0.1,
                        *states.values())  # fmt: skip
    journal.add(
        [
            (finished, packed),
            (
                Finished(Cell(1, 1, 0), "free", "r1", "ok", "", 1.0, "none", 0.0),
                _result("free", "r1").pack(),
            ),
        ]
    )
    (_, first), (_, second) = journal.packed()
    assert first == packed and second.devices == b""
    verdicts = journal.verdicts()
    assert verdicts[("tied", "r1")] == finished.verdict
    assert verdicts[("tied", "r1")].reaches(["tendon_yield", "tendon_rupture"]) == {"tendon_yield"}
    assert math.isnan(verdicts[("free", "r1")].tendon_yield)
    journal.close()


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_a_studys_device_table_is_its_analyses_peaks_and_a_resumed_run_gives_it_again(
    tmp_path, monkeypatch
):
    """A study of the free bridge of h̄ = 1 and the bundled bridge with tendons (its yield force
    lowered to 5 MN, 0.31 MN above the prestress: about 8 mm of stretch) × two records: /devices
    holds the restrained bridge's two tendons for each record, their peaks those of `analyze`
    run here on the same record and bridge, their flags the solver's states there; a run
    interrupted after its first analysis and resumed writes the same file."""
    from studies import contents, write_study

    from rockbridge_cli.config.bridge import load_bridge
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.core.analysis import analyze
    from rockbridge_cli.records.files import read_record
    from rockbridge_cli.results import read_peaks
    from rockbridge_cli.study.run import run_study

    monkeypatch.chdir(tmp_path)
    bundled = BRIDGES / "studied-hbar1.25-tendons.yaml"
    tied = tmp_path / "tied.yaml"
    tied.write_text(bundled.read_text(encoding="utf-8").replace("yield_force: 8.43696e6",
                                                                "yield_force: 5.0e6"),
                    encoding="utf-8")  # fmt: skip
    path = write_study(tmp_path, bridges=("studied-hbar1.00",), bridge_files=(tied,),
                       extra="fidelity: {preset: fast}\noutput: {path: out.h5}\n")  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    expected = contents(study.output)
    bridge = load_bridge(tied).to_bridge()
    with h5py.File(study.output, "r") as file:
        table = {name: file["devices"][name][()] for name in file["devices"]}
    assert [b.decode() for b in table["bridge"]] == ["tied"] * 4
    assert [r.decode() for r in table["record"]] == ["R1", "R1", "R2", "R2"]
    for i, record in enumerate(("R1", "R1", "R2", "R2")):
        motion = read_record(tmp_path / f"{record}.txt")
        peaks = analyze(bridge, motion.acceleration, motion.time_step, "fast").peaks
        name = f"tendon{i % 2 + 1}"
        assert (table["elongation_max"][i], table["elongation_time"][i]) == peaks[
            f"{name}_elongation"
        ]
        assert table["force_max"][i] == peaks[f"{name}_force"][0]
        # ε = ε0 + Δ_max/L_free = (P0 + k·Δ_max)/(E·A), k = E·A/2H
        rigidity, height = 195e9 * 5.04e-3, 26.0 if i % 2 == 0 else 20.8
        stretch = 4.6872e6 + rigidity / height * table["elongation_max"][i]
        assert table["strain_max"][i] == pytest.approx(stretch / rigidity, rel=1e-12)
        assert table["yielded"][i] == int(peaks[f"{name}_yielded"][0])
        assert table["ruptured"][i] == int(peaks[f"{name}_broken"][0])
    assert table["yielded"].max() == 1  # the lowered yield force is reached
    peaks = read_peaks(study.output)
    assert peaks["tendon_yield"].isna().tolist() == [True, True, False, False]

    study.output.unlink()
    with pytest.raises(KeyboardInterrupt):
        run_study(study, workers=1, progress=_stop_after_one)
    run_study(study, workers=1)
    assert contents(study.output) == expected


def _stop_after_one(item, done, total):
    if done == 1:
        raise KeyboardInterrupt


def test_a_tendons_limit_state_is_asked_only_of_a_study_with_such_a_tendon(tmp_path):
    """An IDA for ``tendon_yield`` of free-standing bridges could never find it: refused naming
    the field; with the bundled tendons (which state F_y and ε_u) it loads."""
    from studies import write_study

    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.errors import InputError

    ida = ("intensity: {measure: pga_g, ida: {start: 0.1, step: 0.4, max: 2.5, "
           "limit_states: [abutment_failure, tendon_yield, tendon_rupture]}}\n")  # fmt: skip
    with pytest.raises(InputError, match="tendon_yield: no bridge has a tendon with a yield_force"):
        load_study(write_study(tmp_path, extra=ida))
    tied = (BRIDGES / "studied-hbar1.25-tendons.yaml",)
    study = load_study(write_study(tmp_path, extra=ida, bridge_files=tied))
    assert study.intensity is not None


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_an_ida_finds_the_capacity_of_tendon_yield(tmp_path, monkeypatch):
    """An IDA for tendon_yield and abutment_failure of the free bridge of h̄ = 1 and the bundled
    tendons' bridge (F_y lowered to 5 MN) × two records: the tendons' bridge gets a fragility of
    tendon_yield, the free bridge none; each record's capacity is a level whose analysis has a
    tendon yielded in /devices, with the level just below (within the tolerance) one where none
    has; the tendon yields before the abutment fails."""
    from studies import write_study

    from rockbridge_cli.assessment.fragility import fragilities
    from rockbridge_cli.config.study import load_study
    from rockbridge_cli.results.reading import open_results
    from rockbridge_cli.study.run import run_study

    monkeypatch.chdir(tmp_path)
    tied = tmp_path / "tied.yaml"
    tied.write_text((BRIDGES / "studied-hbar1.25-tendons.yaml").read_text(encoding="utf-8")
                    .replace("yield_force: 8.43696e6", "yield_force: 5.0e6"),
                    encoding="utf-8")  # fmt: skip
    ida = ("intensity: {measure: pga_g, ida: {start: 0.1, step: 0.4, max: 2.5, tolerance: 0.05, "
           "limit_states: [tendon_yield, abutment_failure]}}\nfidelity: fast\n"
           "output: {histories: none, path: out.h5}\n")  # fmt: skip
    study = load_study(write_study(tmp_path, bridges=("studied-hbar1.00",), bridge_files=(tied,),
                                   extra=ida))  # fmt: skip
    run_study(study, workers=1)
    found = {(f.bridge, f.limit_state): f for f in fragilities(study.output, bootstrap=0)}
    assert ("studied-hbar1.00", "tendon_yield") not in found
    assert ("studied-hbar1.00", "abutment_failure") in found
    yielding = found[("tied", "tendon_yield")]
    with open_results(study.output) as file:
        columns = peak_columns(file)
    for base, capacity in yielding.capacities.items():
        assert capacity is not None
        rows = (columns["bridge"] == "tied") & (columns["base_record"] == base)
        levels, flags = columns["intensity"][rows], columns["tendon_yield"][rows]
        assert flags[levels == capacity] == 1.0
        below = levels[levels < capacity].max()
        assert flags[levels == below] == 0.0 and (capacity - below) <= 0.05 * capacity + 1e-12
        failure = found[("tied", "abutment_failure")].capacities[base]
        assert failure is None or capacity <= failure

"""The results file: self-describing for plain h5py, and read back by the library's readers."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
from studies import BRIDGES, RECORDS, STUDIED, burst, write_study

from rockbridge_cli import __version__
from rockbridge_cli.config.study import load_study
from rockbridge_cli.core.quantities import EVENT_NAMES, HISTORY_UNITS, PEAK_UNITS
from rockbridge_cli.errors import InputError
from rockbridge_cli.records.files import read_record
from rockbridge_cli.results import (
    EVENT_COLUMNS,
    FORMAT,
    PEAK_COLUMNS,
    read_bridges,
    read_config_hash,
    read_events,
    read_history,
    read_peaks,
)
from rockbridge_cli.results.reading import ground_motion
from rockbridge_cli.study.run import run_study


@pytest.fixture(scope="module")
def done(tmp_path_factory):
    """A study of the two studied bridges × two records, run once: (study, results file)."""
    folder = tmp_path_factory.mktemp("results")
    study = load_study(write_study(folder, extra="output: {path: out.h5}\n"))
    run_study(study, workers=1)
    return study, study.output


def test_plain_h5py_reads_it(done):
    study, path = done
    with h5py.File(path, "r") as file:
        root = file.attrs
        assert root["format"] == FORMAT and root["rockbridge_version"] == __version__
        for name in ("numpy_version", "scipy_version", "h5py_version", "created", "finished"):
            assert root[name]
        assert root["complete"] and root["n_analyses"] == root["n_complete"] == 4
        assert root["config_hash"] == study.config_hash
        config = json.loads(root["config"])
        assert [b["id"] for b in config["bridges"]] == list(STUDIED)
        assert config["fidelity"]["preset"] == "default" == root["fidelity"]
        assert json.loads(root["knobs"])["scheme"] == "dopri5"
        assert root["study_yaml"] == study.path.read_text(encoding="utf-8")
        assert json.loads(root["units"])["output_step"] == "s"

        record = file["records/R1"]
        acceleration = record["acceleration"]
        assert acceleration.attrs["units"] == "m/s2" and acceleration.compression == "gzip"
        np.testing.assert_allclose(acceleration[()], burst(*RECORDS["R1"]), rtol=1e-9)
        assert record.attrs["time_step"] == 0.01 and record.attrs["source"] == "R1.txt"
        assert record.attrs["pga"] == pytest.approx(RECORDS["R1"][0], rel=1e-9)
        assert json.loads(record.attrs["units"]) == {
            "time_step": "s", "n_samples": "-", "duration": "s", "pga": "m/s2",
            "file_units": "-", "standard_gravity": "m/s2", "pga_g": "g", "pgv": "m/s",
            "pgd": "m", "arias": "m/s", "cav": "m/s",
        }  # fmt: skip
        assert "pulse_period_s" not in record.attrs  # synthetic: no pulse is looked for
        assert record.attrs["file_units"] == "m/s2" and record.attrs["standard_gravity"] == 9.80665
        assert record.attrs["pga_g"] == pytest.approx(RECORDS["R1"][0] / 9.80665, rel=1e-9)

        # Table 1 of the paper, h̄ = 2: m_deck = ρ·A·L_tot = 2500·6·136 kg; m_pier,2 = 21.97·10⁴ kg,
        # γ = 3.095, q = 0.7858·10⁻³ m/kN (docs/model.md §10)
        bridge = file["bridges/studied-hbar2.00"].attrs
        assert bridge["m_deck"] == pytest.approx(2500 * 6 * 136)
        assert bridge["m_pier2"] == pytest.approx(21.97e4, rel=1e-3)
        assert bridge["gamma"] == pytest.approx(3.095, rel=1e-3)
        assert bridge["q"] == pytest.approx(0.7858e-6, rel=1e-3)
        assert bridge["model_u_jo"] == 0.12 and bridge["model"] == "asymmetric-bridge"
        units = json.loads(bridge["units"])
        assert units["q"] == "m/N" and units["model_u_jo"] == "m" and units["ug_min_p"] == "m/s2"
        assert json.loads(bridge["config"])["piers"]["heights"] == [26.0, 13.0]

        peaks = file["peaks"]
        assert json.loads(peaks.attrs["columns"]) == list(PEAK_COLUMNS)
        for name, unit in PEAK_UNITS.items():
            assert peaks[f"{name}_max"].attrs["units"] == unit
            assert peaks[f"{name}_time"].attrs["units"] == "s"
        assert list(peaks["bridge"].asstr()[()]) == [b for b in STUDIED for _ in "12"]
        assert list(peaks["record"].asstr()[()]) == ["R1", "R2", "R1", "R2"]
        assert list(peaks["status"].asstr()[()]) == ["ok"] * 4

        # /events: a CF contiguous ragged array counted by /peaks/n_events
        counts = peaks["n_events"][()]
        assert peaks["n_events"].attrs["sample_dimension"] == "events"
        events = file["events"]
        for name, (unit, _) in EVENT_COLUMNS.items():
            assert events[name].attrs["units"] == unit and events[name].shape == (counts.sum(),)
        kind = events["kind"]  # a CF flag: int8 codes named by flag_meanings
        assert kind.dtype == np.int8 and list(kind.attrs["flag_values"]) == list(range(8))
        meanings = kind.attrs["flag_meanings"].split()
        assert meanings == list(EVENT_NAMES)
        kinds = [meanings[code] for code in kind[()]]
        starts = np.concatenate([[0], np.cumsum(counts)])
        assert all(kinds[start] == "onset" for start in starts[:-1])  # each analysis rocks first
        times = events["time"][()]
        for start, stop in zip(starts[:-1], starts[1:], strict=True):  # in time within each
            assert np.all(np.diff(times[start:stop]) >= 0)

        analysis = file["analyses/studied-hbar2.00/R2"]
        for name, unit in HISTORY_UNITS.items():
            dataset = analysis["histories"][name]
            assert dataset.attrs["units"] == unit and dataset.attrs["description"]
            assert dataset.compression == "gzip" and dataset.chunks is not None
        time = analysis["histories/time"][()]
        np.testing.assert_allclose(np.diff(time), study.fidelity.knobs["output_step"])


def test_readers(done):
    study, path = done
    peaks = read_peaks(path)
    assert list(peaks.columns) == list(PEAK_COLUMNS)
    assert peaks.attrs["units"]["theta2_max"] == "rad"
    assert peaks["n_impacts"].dtype == "Int64"
    with h5py.File(path, "r") as file:
        node = file["analyses/studied-hbar1.00/R2"]
        assert peaks.loc[1, "u_deck_max"] == file["peaks/u_deck_max"][1]
        history = read_history(path, "studied-hbar1.00", "R2")
        np.testing.assert_array_equal(history["theta1"], node["histories/theta1"][()])
        events = read_events(path, "studied-hbar1.00", "R2")
        start, count = file["peaks/n_events"][0], file["peaks/n_events"][1]
        np.testing.assert_array_equal(events["time"], file["events/time"][start : start + count])
    assert list(history.columns) == list(HISTORY_UNITS)
    assert history.index.name == "time" and history.attrs["units"]["u_deck"] == "m"
    assert events.attrs["units"]["rate_after"] == "rad/s"
    bridges = read_bridges(path)
    assert list(bridges.index) == list(STUDIED)
    assert bridges.loc["studied-hbar1.00", "name"] == "symmetric (h̄ = 1)"
    assert read_config_hash(path) == study.config_hash


def test_unknown_analysis(done):
    _, path = done
    with pytest.raises(InputError, match="no analysis studied-hbar1.00/R9: no record R9 under"):
        read_history(path, "studied-hbar1.00", "R9")


def test_histories_kept_as_asked(tmp_path):
    some = load_study(write_study(tmp_path, extra="output: {path: a.h5, histories: [v_deck]}\n"))
    run_study(some, workers=1)
    history = read_history(some.output, "studied-hbar1.00", "R1")
    assert list(history.columns) == ["v_deck"]
    none = load_study(write_study(tmp_path, extra="output: {path: b.h5, histories: none}\n"))
    run_study(none, workers=1)
    with pytest.raises(InputError, match="no histories: the study kept no histories"):
        read_history(none.output, "studied-hbar1.00", "R1")
    assert len(read_events(none.output, "studied-hbar1.00", "R1")) > 0  # events are kept
    pd.testing.assert_series_equal(
        read_peaks(none.output)["u_deck_max"], read_peaks(some.output)["u_deck_max"]
    )


def test_a_mistyped_id_gets_the_nearest_not_every_pair(tmp_path):
    """A file of 10 000 analyses (1000 bridges × 10 records): a mistyped record or bridge id is
    answered with the closest ids (difflib's ratio ≥ 0.6: AR1 → AR01, AR10), not with a list of
    every bridge/record pair (656 KB on such a file)."""
    path = tmp_path / "many.h5"
    bridges = [f"bridge+abutments.gap_{0.06 + 1e-4 * i:.4f}" for i in range(1000)]
    records = [f"AR{k:02d}" for k in range(1, 11)]
    with h5py.File(path, "w") as file:
        file.attrs.update({"format": FORMAT, "format_version": 4})
        strings = h5py.string_dtype()
        file["peaks/bridge"] = np.array([b for b in bridges for _ in records], dtype=strings)
        file["peaks/record"] = np.array(records * len(bridges), dtype=strings)
    with pytest.raises(InputError) as record:
        read_history(path, bridges[5], "AR1")
    message = str(record.value)
    assert f"no record AR1 under {bridges[5]}; nearest: AR10, AR01" in message  # equal ratios
    assert "(of 10 records)" in message and len(message) < 300
    with pytest.raises(InputError) as bridge:
        read_history(path, "brige+abutments.gap_0.0600", "AR01")
    assert (
        "no bridge brige+abutments.gap_0.0600; nearest: bridge+abutments.gap_0.0600"
        in str(bridge.value)
        and "(of 1000 bridges)" in str(bridge.value)
        and len(str(bridge.value)) < 400
    )


def test_one_file_listed_twice(tmp_path):
    """A record file listed under two ids is one group under both names (an HDF5 hard link):
    one description, one stored copy of its samples; another file gets its own."""
    write_study(tmp_path)
    text = (
        f"bridges: [{BRIDGES.as_posix()}/studied-hbar1.00.yaml]\n"
        "records:\n  files:\n    - {path: R1.txt, id: A}\n    - {path: R2.txt, id: B}\n"
        "    - {path: R1.txt, id: C}\noutput: {path: out.h5, histories: none}\n"
    )
    (tmp_path / "twice.yaml").write_text(text, encoding="utf-8")
    study = load_study(tmp_path / "twice.yaml")
    run_study(study, workers=1)
    with h5py.File(study.output, "r") as file:
        first, other, again = (file[f"records/{name}"] for name in "ABC")
        assert again == first and first.attrs["source"] == "R1.txt"
        assert other.attrs["source"] == "R2.txt" and other.attrs["sha256"] != first.attrs["sha256"]
        assert again["acceleration"] == first["acceleration"] != other["acceleration"]
        np.testing.assert_allclose(again["acceleration"][()], burst(*RECORDS["R1"]), rtol=1e-9)


def test_not_a_results_file(tmp_path):
    missing = tmp_path / "missing.h5"
    with pytest.raises(InputError, match="file not found"):
        read_peaks(missing)
    damaged = tmp_path / "damaged.h5"
    damaged.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(200))
    with pytest.raises(InputError, match="not a readable HDF5 file, or damaged"):
        read_peaks(damaged)
    foreign = tmp_path / "foreign.h5"
    with h5py.File(foreign, "w") as file:
        file["x"] = [1, 2, 3]
    with pytest.raises(InputError, match="not a rockbridge results file"):
        read_peaks(foreign)
    newer = tmp_path / "newer.h5"
    with h5py.File(newer, "w") as file:
        file.attrs.update({"format": FORMAT, "format_version": 99})
    with pytest.raises(InputError, match="newer rockbridge"):
        read_peaks(newer)
    older = tmp_path / "older.h5"
    with h5py.File(older, "w") as file:
        file.attrs.update({"format": FORMAT, "format_version": 1})
    with pytest.raises(InputError, match="older rockbridge .format 1.; run the study again"):
        read_peaks(older)


def test_format_2_is_still_read(done, tmp_path):
    """Format 2 differs only in /events/kind, stored as variable-length strings: a file
    rewritten that way reads back the same events and peaks."""
    _, path = done
    older = tmp_path / "format2.h5"
    older.write_bytes(path.read_bytes())
    with h5py.File(older, "r+") as file:
        meanings = file["events/kind"].attrs["flag_meanings"].split()
        names = [meanings[code] for code in file["events/kind"][()]]
        del file["events/kind"]
        file["events"].create_dataset("kind", data=names, dtype=h5py.string_dtype())
        file.attrs["format_version"] = 2
    for bridge in STUDIED:
        pd.testing.assert_frame_equal(
            read_events(older, bridge, "R2"), read_events(path, bridge, "R2")
        )
    pd.testing.assert_frame_equal(read_peaks(older), read_peaks(path))


def test_a_scaled_record_is_its_base_record_and_a_factor(tmp_path):
    """A stripe of a record holds its factor and links to the record's samples as read, stored
    once for every level (format 4 on); the ground motion read back is the motion analyzed, the
    factor times the file's samples (`read_record`), bit for bit. A format-3 file, which stored a
    scaled copy per level, reads back the same."""
    extra = ("intensity: {measure: pga_g, levels: [0.2, 0.4, 0.8]}\n"
             "fidelity: fast\noutput: {path: stripes.h5}\n")  # fmt: skip
    study = load_study(write_study(tmp_path, extra=extra))
    run_study(study, workers=1)
    peaks = read_peaks(study.output)
    with h5py.File(study.output, "r") as file:
        assert file.attrs["format_version"] == 5  # failure rotations named as such (format 5)
        groups = [file["records"][r] for r in ("R1+0.2g", "R1+0.4g", "R1+0.8g")]
        assert all("acceleration" not in g and g.attrs["base_record"] == "R1" for g in groups)
        assert len({g["base_acceleration"].id for g in groups}) == 1  # one dataset, linked
        samples = {node["base_acceleration"].id for node in file["records"].values()}
        assert len(samples) == 2  # once per record as read
        for row in peaks[peaks["bridge"] == STUDIED[0]].itertuples():
            node = file["records"][row.record]
            assert node.attrs["scale"] == row.scale
            step, motion = ground_motion(file, study.output, row.bridge, row.record)
            as_read = read_record(tmp_path / f"{row.base_record}.txt").acceleration
            np.testing.assert_array_equal(motion, row.scale * as_read)
            assert abs(motion).max() == pytest.approx(row.intensity * 9.80665, rel=1e-12)
    older = tmp_path / "format3.h5"
    older.write_bytes(study.output.read_bytes())
    with h5py.File(older, "r+") as file:
        file.attrs["format_version"] = 3
        for node in file["records"].values():
            node["acceleration"] = node.attrs["scale"] * node["base_acceleration"][()]
            del node["base_acceleration"]
        for row in peaks.itertuples():
            with h5py.File(study.output, "r") as new:
                expected = ground_motion(new, study.output, row.bridge, row.record)[1]
            np.testing.assert_array_equal(
                ground_motion(file, older, row.bridge, row.record)[1], expected
            )


def test_truncated_file_is_an_input_error(done, tmp_path):
    _, path = done
    cut = tmp_path / "cut.h5"
    cut.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    with pytest.raises(InputError) as excinfo:
        read_peaks(cut)
    assert excinfo.value.source == str(cut)


def test_packed_result_round_trips():
    """What a worker packs is what the results file is written from: every value (text, float,
    NaN, count), every event kind (as the file stores it, an int8 code) and every history sample
    come back exactly."""
    from rockbridge_cli.results.packing import AnalysisResult, Packed

    rng = np.random.default_rng(1)
    kinds = np.array([*EVENT_NAMES, "impact", "onset"], dtype=object)
    events = {name: rng.normal(size=kinds.size) for name in EVENT_COLUMNS if name != "kind"}
    time = np.arange(5) * 0.01
    values = AnalysisResult.failed("b", "r", "").values  # every column, missing
    values.update(status="ok", message="ünïcode, \"quoted\"", u_deck_max=0.1 / 3, steps=2**40,
                  n_events=kinds.size, base_record="r0", intensity=0.6, scale=1.25)  # fmt: skip
    result = AnalysisResult(
        "b", "r", values, time, {"u_deck": rng.normal(size=5)}, {**events, "kind": kinds}
    )
    packed = result.pack()
    assert isinstance(packed, Packed)
    unpacked = packed.values
    assert unpacked.keys() == values.keys()
    for name, value in values.items():
        assert unpacked[name] == value or (value != value and unpacked[name] != unpacked[name])
        assert type(unpacked[name]) is type(value), name
    assert [EVENT_NAMES[code] for code in packed.event_rows["kind"]] == list(kinds)
    for name, values in events.items():
        np.testing.assert_array_equal(packed.event_rows[name], values)
    np.testing.assert_array_equal(packed.chunks["time"].samples(), time)
    np.testing.assert_array_equal(packed.chunks["u_deck"].samples(), result.histories["u_deck"])
    # an analysis that could not run: no events, no histories; a NUL, which HDF5 strings cannot
    # hold, becomes U+FFFD
    failed = AnalysisResult.failed("b", "r", "a\0b").pack()
    assert failed.values["message"] == "a\ufffdb"
    assert failed.event_rows.size == 0 and not failed.chunks


# --- checksums (issue 32) ----------------------------------------------------------------------


def test_fletcher32_is_hdf5s(tmp_path):
    """The checksum a worker appends to each history chunk is the one HDF5's own fletcher32
    filter appends (read back raw with h5py), for chunks of odd and even lengths, all-zero and
    all-0xFF data (the two representations of a sum ≡ 0 mod 65535)."""
    from rockbridge_cli.results.packing import fletcher32

    rng = np.random.default_rng(7)
    arrays = [rng.integers(0, 256, n, dtype=np.uint8) for n in (1, 2, 3, 721, 1440, 5001)]
    arrays += [np.zeros(100, np.uint8), np.full(5000, 255, np.uint8)]
    with h5py.File(tmp_path / "f.h5", "w") as file:
        for number, values in enumerate(arrays):
            dataset = file.create_dataset(str(number), data=values, chunks=values.shape,
                                          fletcher32=True)  # fmt: skip
            raw = dataset.id.read_direct_chunk((0,))[1]
            assert raw[:-4] == values.tobytes()
            assert fletcher32(raw[:-4]) == int.from_bytes(raw[-4:], "little"), values.size


def test_a_flipped_byte_is_reported_not_read(done, tmp_path):
    """A flipped bit in /peaks changed a printed peak silently (no checksum): every numeric
    dataset now has HDF5's fletcher32 filter, which HDF5 verifies on every read."""
    from click.testing import CliRunner

    from rockbridge_cli.cli import main

    _, path = done
    with h5py.File(path, "r") as file:
        assert all(file[f"peaks/{name}"].fletcher32 for name in ("u_deck_max", "n_impacts"))
        assert file["events/time"].fletcher32 and file["records/R1/acceleration"].fletcher32
        history = file[f"analyses/{STUDIED[0]}/R1/histories/theta1"]
        assert history.fletcher32
        offsets = {"peaks": file["peaks/u_deck_max"].id.get_chunk_info(0).byte_offset,
                   "history": history.id.get_chunk_info(0).byte_offset}  # fmt: skip
    for where, offset in offsets.items():
        damaged = tmp_path / f"{where}.h5"
        data = bytearray(path.read_bytes())
        data[offset + 3] ^= 0x10
        damaged.write_bytes(bytes(data))
        if where == "peaks":
            result = CliRunner().invoke(main, ["peaks", str(damaged)])
            assert result.exit_code == 2 and "damaged" in result.output, result.output
        else:
            with pytest.raises(InputError, match="damaged"):
                read_history(damaged, STUDIED[0], "R1")


def test_read_intensity_types_the_section_as_stored(tmp_path):
    """One reader of the intensity section: what the file stores, typed, equal to the section
    the study's config validated; None without one; a malformed one is an input error."""
    from typing import get_args

    from rockbridge_cli.config.intensity import Intensity
    from rockbridge_cli.motions.intensity import MEASURES
    from rockbridge_cli.results.reading import read_intensity
    from rockbridge_cli.results.sections import (
        MEASURE_NAMES,
        IdaSection,
        IntensitySection,
    )

    stripes = {"measure": "sa_g", "levels": [0.2, 0.6], "period": 0.5, "design": 0.4}
    ida = {"measure": "avgsa_g", "period_range": [0.2, 1.0], "ida": {
        "start": 0.1, "step": 0.2, "max": 4.0, "tolerance": 0.02,
        "limit_states": ["gap_closure", "overturning"]}}  # fmt: skip
    with h5py.File(tmp_path / "r.h5", "w") as file:
        assert read_intensity(file) is None
        file.attrs["intensity"] = json.dumps(Intensity.model_validate(stripes).model_dump())
        assert read_intensity(file) == IntensitySection("sa_g", (0.2, 0.6), None, 0.5, None,
                                                        0.05, 0.4)  # fmt: skip
        file.attrs["intensity"] = json.dumps(Intensity.model_validate(ida).model_dump())
        found = read_intensity(file)
        assert found is not None and found.levels is None and found.period_range == (0.2, 1.0)
        assert found.ida == IdaSection(0.1, 0.2, 4.0, 0.02, ("gap_closure", "overturning"))
        assert found.spectral == (None, (0.2, 1.0), 0.05)
        for broken in ({"measure": "pga_g"}, {"measure": "pga", "levels": [1.0]},
                       {"measure": "pga_g", "levels": [1.0], "period": "1 s"}):  # fmt: skip
            file.attrs["intensity"] = json.dumps(broken)
            with pytest.raises(InputError, match="not an intensity section"):
                read_intensity(file)
    measure = Intensity.model_fields["measure"].annotation
    assert set(MEASURE_NAMES) == set(get_args(measure)) == set(MEASURES) - {"pga_tan_alpha"}


def test_no_reader_parses_the_intensity_attribute_itself():
    """The intensity and spectrum sections are read by `results.reading` alone (issue 38)."""
    import rockbridge_cli

    package = Path(rockbridge_cli.__file__).parent
    reader = package / "results" / "reading.py"
    for path in package.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        if path != reader:
            assert 'attrs.get("intensity"' not in text and 'attrs["intensity"]' not in text, path
            assert '["spectrum"]' not in text, path


def flipped(path, offset: int, target):
    """A copy of ``path`` at ``target`` with one bit flipped at ``offset``."""
    data = bytearray(path.read_bytes())
    data[offset] ^= 0x10
    target.write_bytes(bytes(data))
    return target


def test_run_verifies_a_file_before_it_calls_its_analyses_done(done, tmp_path):
    """Issue 39: a complete file with a flipped bit in /events, a history or a record's samples
    was called "already done" by ``run`` and kept (only /peaks was read); text columns had no
    check at all. Now ``run`` reads every dataset of a file it would call done (HDF5 verifies
    their Fletcher-32 checksums) and compares the text columns with their SHA-256: damaged,
    refused with the way out, the file left as it was."""
    import dataclasses

    study, path = done
    with h5py.File(path, "r") as file:
        history = file[f"analyses/{STUDIED[0]}/R1/histories/theta1"]
        offsets = {
            "events": file["events/time"].id.get_chunk_info(0).byte_offset + 3,
            "history": history.id.get_chunk_info(0).byte_offset + 3,
            "record": file["records/R1/acceleration"].id.get_chunk_info(0).byte_offset + 3,
        }
        assert json.loads(file["peaks"].attrs["text_sha256"]).keys() >= {"status", "message"}
    # a model's name in /peaks/model: its last copy, in HDF5's global heap written last
    offsets["text"] = path.read_bytes().rindex(b"asymmetric-bridge") + 1
    with h5py.File(flipped(path, offsets["text"], tmp_path / "t.h5"), "r") as file:
        assert "acymmetric-bridge" in file["peaks/model"].asstr()[()]  # read without a word
    intact = tmp_path / "intact.h5"
    intact.write_bytes(path.read_bytes())
    assert run_study(dataclasses.replace(study, output=intact), workers=1).resumed == 4
    for where, offset in offsets.items():
        damaged = flipped(path, offset, tmp_path / f"{where}.h5")
        before = damaged.read_bytes()
        with pytest.raises(InputError, match="damaged .*rerun with --overwrite") as refusal:
            run_study(dataclasses.replace(study, output=damaged), workers=1)
        assert str(damaged) in str(refusal.value), where
        assert damaged.read_bytes() == before, where


def test_a_file_of_no_analyses_is_verified_and_resumed(done, tmp_path):
    """A run refused by its scheduler leaves a file of no analyses (empty, extendable columns),
    whose verification met chunks outside the empty datasets: a raw ValueError from h5py."""
    import dataclasses

    study = dataclasses.replace(done[0], output=tmp_path / "empty.h5")
    with pytest.raises(InputError, match="Dask"):  # unreachable, or Dask not installed
        run_study(study, scheduler="foo")
    assert read_peaks(study.output).shape[0] == 0
    assert run_study(study, workers=1).ran == 4


def test_overwrite_replaces_a_results_file_cut_short(done, tmp_path):
    """Issue 39: a results file cut short (a copy interrupted) could not be replaced even with
    ``--overwrite`` (not readable, so not recognised as a results file). It is replaced where it
    still starts as rockbridge's (HDF5, its ``format`` attribute in its first bytes); a file cut
    before that is left alone, and so is any other file."""
    import dataclasses

    study, path = done
    cut = tmp_path / "cut.h5"
    cut.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    with pytest.raises(InputError, match="rerun with --overwrite"):
        run_study(dataclasses.replace(study, output=cut), workers=1)
    report = run_study(dataclasses.replace(study, output=cut), workers=1, overwrite=True)
    assert report.ran == 4 and read_peaks(cut).shape[0] == 4
    for head in (path.read_bytes()[:1000], b"my notes\n" * 1000):
        other = tmp_path / "other.h5"
        other.write_bytes(head)
        with pytest.raises(InputError, match="not a rockbridge results file: not replaced"):
            run_study(dataclasses.replace(study, output=other), workers=1, overwrite=True)
        assert other.read_bytes() == head

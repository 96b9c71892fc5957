"""Record files: PEER AT2, rockbridge and plain text; every bad file gives a precise InputError."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.errors import InputError
from rockbridge_cli.records.files import Record, read_record, read_stated_units, write_record
from rockbridge_cli.records.set_files import read_manifest, read_record_set
from rockbridge_cli.records.target import read_set_target

DATA = Path(__file__).parent / "data" / "records"
BUNDLED = Path(__file__).parents[1] / "records" / "ec8-type1-C-ag0.6g"
G = 9.80665  # the unit g of a record file: standard gravity (docs/model.md §1)


def test_reads_peer_at2():
    record = read_record(DATA / "sample.AT2")
    # the file: NPTS=7, DT=.0100, units of g, values 0 .1 -.2 .3 -.1 .05 0 over two lines
    assert record.name == "sample"
    assert record.time_step == 0.01
    np.testing.assert_allclose(
        record.acceleration, G * np.array([0, 0.1, -0.2, 0.3, -0.1, 0.05, 0])
    )
    assert record.duration == pytest.approx(0.06)
    assert record.metadata["format"] == "PEER NGA AT2"
    assert record.metadata["file_units"] == "g"


def test_reads_older_at2_header():
    record = read_record(DATA / "old_header.AT2")  # "4  0.02000  NPTS, DT"
    assert record.time_step == 0.02
    np.testing.assert_allclose(record.acceleration, G * np.array([0.0, 0.1, -0.1, 0.0]))


def test_reads_two_columns_with_units():
    record = read_record(DATA / "two_columns.txt", units="m/s2")
    assert record.time_step == pytest.approx(0.01)
    np.testing.assert_allclose(record.acceleration, [0.0, 0.5, -0.25, 0.0])
    in_g = read_record(DATA / "two_columns.txt", units="g")
    np.testing.assert_array_equal(in_g.acceleration, 9.80665 * np.array([0.0, 0.5, -0.25, 0.0]))


def test_reads_one_column_with_time_step():
    record = read_record(DATA / "one_column.txt", units="g", time_step=0.005)
    assert record.time_step == 0.005
    np.testing.assert_allclose(record.acceleration, G * np.array([0.0, 0.5, -0.25, 0.0]))


@pytest.mark.parametrize(
    ("name", "units"),
    [("sample.AT2", "g"), ("unknown_units.txt", "furlongs/fortnight^2"), ("two_columns.txt", None)],
)
def test_stated_units(name, units):
    assert read_stated_units(DATA / name) == units


def test_round_trip_is_byte_stable(tmp_path):
    rng = np.random.default_rng(0)
    record = Record("X1", 0.01, rng.normal(size=500), "test", {})
    first, second = tmp_path / "a.txt", tmp_path / "b.txt"
    write_record(first, record, {"seed": 7, "pga": 1.25})
    write_record(second, record, {"seed": 7, "pga": 1.25})
    assert first.read_bytes() == second.read_bytes()
    back = read_record(first)
    assert back.name == "X1" and back.time_step == 0.01
    np.testing.assert_allclose(back.acceleration, record.acceleration, rtol=1e-9)
    assert back.metadata["seed"] == 7 and back.metadata["pga"] == 1.25
    assert back.metadata["format"] == "rockbridge"


def test_header_must_be_simple(tmp_path):
    record = Record("X1", 0.01, np.zeros(3))
    with pytest.raises(ValueError):
        write_record(tmp_path / "a.txt", record, {"bad key": 1})
    with pytest.raises(ValueError):
        write_record(tmp_path / "a.txt", record, {"units": "g"})


def test_record_is_frozen_and_checked():
    record = Record("X", 0.01, [0.0, 1.0, 0.0])
    assert record.duration == pytest.approx(0.02)
    assert record.peak_acceleration == 1.0
    with pytest.raises(ValueError):
        record.acceleration[0] = 5.0
    with pytest.raises(AttributeError):
        record.name = "Y"
    for bad in ([0.0], [0.0, np.nan]):
        with pytest.raises(ValueError):
            Record("X", 0.01, bad)
    with pytest.raises(ValueError):
        Record("X", 0.0, [0.0, 1.0])


# (file, keyword arguments, expected location, words of the reason)
BAD_FILES = [
    ("missing.txt", {"units": "g"}, "", "not found"),
    ("empty.txt", {"units": "g"}, "", "empty"),
    ("header_only.txt", {}, "", "no samples"),
    ("single_sample.txt", {"units": "g"}, "line 1", "only one sample"),
    ("ragged.txt", {"units": "g"}, "line 3", "1 columns where line 1 has 2"),
    ("three_columns.txt", {"units": "g"}, "line 1", "1 or 2 columns"),
    ("non_numeric.txt", {"units": "g"}, "line 3", "value 2 is not a number"),
    ("nan.txt", {"units": "g"}, "line 2", "not a finite number"),
    ("inf.txt", {"units": "g"}, "line 3", "not a finite number"),
    ("non_uniform.txt", {"units": "g"}, "line 3", "must be uniform"),
    ("non_increasing.txt", {"units": "g"}, "line 3", "does not increase"),
    ("unknown_units.txt", {}, "units", "unknown"),
    ("two_columns.txt", {}, "units", "does not state its units"),
    ("two_columns.txt", {"units": "furlongs"}, "units", "unknown"),
    ("one_column.txt", {"units": "g"}, "time_step", "needs its time step"),
    ("two_columns.txt", {"units": "g", "time_step": 0.02}, "time_step", "0.02 s was given"),
    ("sample.AT2", {"units": "m/s2"}, "units", "the file says g"),
    ("truncated.AT2", {}, "line 5", "truncated: NPTS = 7"),
    ("bad_header.AT2", {}, "line 4", "NPTS"),
]


@pytest.mark.parametrize(("name", "kwargs", "where", "reason"), BAD_FILES)
def test_bad_files(name, kwargs, where, reason):
    with pytest.raises(InputError) as caught:
        read_record(DATA / name, **kwargs)
    assert caught.value.source.endswith(name)
    [(found_where, found_reason)] = caught.value.problems
    assert found_where == where
    assert reason in found_reason


def test_at2_with_too_many_values(tmp_path):
    path = tmp_path / "long.AT2"
    path.write_text((DATA / "sample.AT2").read_text() + "  .1  .2\n")
    with pytest.raises(InputError, match="NPTS = 7 but the file has 9 values"):
        read_record(path)


def test_folder_is_not_a_record(tmp_path):
    with pytest.raises(InputError, match="folder"):
        read_record(tmp_path, units="g")


def test_reads_the_bundled_set():
    records = read_record_set(BUNDLED)
    assert [r.name for r in records] == [f"AR{i:02d}" for i in range(1, 11)]
    assert all(r.time_step == 0.01 and r.acceleration.size == 3001 for r in records)
    target = read_set_target(BUNDLED)
    assert (target.spectrum_type, target.ground_type) == (1, "C")
    assert target.surface_pga == pytest.approx(0.6 * 1.15 * 9.81)  # the config's gravity


def copy_set(tmp_path) -> Path:
    folder = tmp_path / "set"
    shutil.copytree(BUNDLED, folder)
    return folder


def test_set_without_manifest(tmp_path):
    folder = copy_set(tmp_path)
    (folder / "manifest.json").unlink()
    with pytest.raises(InputError, match="generate-records"):
        read_record_set(folder)


def test_set_with_corrupt_manifest(tmp_path):
    folder = copy_set(tmp_path)
    (folder / "manifest.json").write_text('{"records": [\n  {"file": "AR01.txt"},,\n]}\n')
    with pytest.raises(InputError) as caught:
        read_record_set(folder)
    [(where, reason)] = caught.value.problems
    assert where.startswith("line 2") and "invalid JSON" in reason


def test_set_with_a_missing_file(tmp_path):
    folder = copy_set(tmp_path)
    (folder / "AR03.txt").unlink()
    with pytest.raises(InputError) as caught:
        read_record_set(folder)
    assert caught.value.problems == [("records[2].file", "AR03.txt not found")]


def test_set_manifest_without_records(tmp_path):
    folder = copy_set(tmp_path)
    (folder / "manifest.json").write_text(json.dumps({"format": "x"}))
    with pytest.raises(InputError, match="records"):
        read_manifest(folder)


def test_truncated_rockbridge_file(tmp_path):
    path = tmp_path / "cut.txt"
    write_record(path, Record("X1", 0.01, np.arange(10.0)))
    path.write_text("\n".join(path.read_text().splitlines()[:-3]) + "\n")  # 3 samples lost
    with pytest.raises(InputError, match="truncated: the header says 10 points but the file has 7"):
        read_record(path)


def test_a_record_in_g_and_the_same_in_m_s2_give_identical_analyses(tmp_path):
    """The unit g of a file is standard gravity, 9.80665 m/s², whatever the bridge's gravity:
    a record written in g and the same record written in m/s² with 9.80665 analyze bit for bit
    alike (issue 9: with 9.81 some peaks on recorded motions moved by up to 27 %)."""
    from conftest import studied_bridge

    from rockbridge_cli.core.analysis import analyze

    rng = np.random.default_rng(5)
    in_g = np.round(rng.normal(0.0, 0.2, 1500), 6)  # a "recorded" motion in g, 6 digits
    (tmp_path / "g.txt").write_text(
        "# units: g\n" + "".join(f"{0.01 * i:.2f} {a:.6f}\n" for i, a in enumerate(in_g))
    )
    (tmp_path / "si.txt").write_text(
        "# units: m/s2\n"
        + "".join(f"{0.01 * i:.2f} {float(a) * 9.80665!r}\n" for i, a in enumerate(in_g))
    )
    a, b = read_record(tmp_path / "g.txt"), read_record(tmp_path / "si.txt")
    np.testing.assert_array_equal(a.acceleration, b.acceleration)
    bridge = studied_bridge(2.0)
    first, second = (analyze(Bridge(bridge), r.acceleration, r.time_step) for r in (a, b))
    assert first.peak_row()["u_deck_max"] == second.peak_row()["u_deck_max"]
    np.testing.assert_array_equal(first.histories["theta1"], second.histories["theta1"])


HARD_DECIMALS = [
    "9007199254740993",  # 2^53 + 1: halfway between two doubles, rounds to even
    "2.2250738585072011e-308",  # just below the smallest normal double
    "4.9406564584124654e-324",  # the smallest subnormal
    "1e-320",
    "1.7976931348623157e308",  # the largest double
    "0.1000000000000000055511151231257827021181583404541015625",  # 0.1's double, exactly
    "+.5",
    "5.",
    "-0",
    "1E5",
]
"""Decimals whose correct rounding is delicate (halfway cases, subnormals, the extremes, long
expansions) or whose spelling is unusual; Python's ``float`` is the reference."""


@pytest.mark.parametrize("spec", ["r", ".7E", ".17g", ".3f", "+.5e"])
def test_rows_read_at_once_are_the_numbers_python_reads(tmp_path, spec):
    """A record's rows are read by numpy's parser at once, and line by line (naming the line of
    a problem) where it cannot: both must give the same float64 bit for bit, which is Python's
    ``float`` of each decimal. Random values over 600 decades in five spellings, and
    `HARD_DECIMALS`, in one- and two-column files separated by spaces or commas."""
    from rockbridge_cli.records import files

    rng = np.random.default_rng(2026)
    values = rng.normal(size=3000) * 10.0 ** rng.integers(-300, 300, size=3000)
    texts = [format(v, spec if spec != "r" else "") for v in values] + HARD_DECIMALS
    python = np.array([float(t) for t in texts])
    one = files._rows_at_once(texts)
    two = files._rows_at_once([f"{i * 0.01!r}, {t}" for i, t in enumerate(texts)])
    by_line = files._rows_line_by_line(tmp_path / "r.txt", texts, 0)
    assert one is not None and two is not None
    assert one[:, 0].tobytes() == python.tobytes() == by_line[:, 0].tobytes()
    assert two[:, 1].tobytes() == python.tobytes()


@pytest.mark.parametrize(
    "rows",
    [["1.0", "# a comment", "2.0"], ["1.0", "x"], ["1.0", "nan"], ["1.0 2.0", "3.0"],
     ["1 2 3", "4 5 6"], ["1.0"], ["1_0", "2"], ["0 1", ",", "1 2"], ["0 1", " , ,", "1 2"]],
)  # fmt: skip
def test_what_numpy_cannot_take_as_it_is_is_read_line_by_line(rows):
    """A comment among the rows, a word, a non-finite value, ragged rows, three columns, one row,
    Python's underscores and a row of commas alone (blank to numpy once commas are spaces) go
    line by line, which names the line of a problem or, for the comment and the underscores,
    reads them as before."""
    from rockbridge_cli.records import files

    assert files._rows_at_once(rows) is None


def test_bench_fidelity_reads_a_plain_folder_with_a_manifest_of_its_own(tmp_path):
    """``benchmarks/bench_fidelity.py --records DIR`` ended in a traceback when the folder held
    a ``manifest.json`` that is not a record set's (issue 39): the folder is read as plain
    record files, as without it."""
    import argparse
    import importlib.util

    from studies import REPO, write_records

    path = REPO / "benchmarks" / "bench_fidelity.py"
    spec = importlib.util.spec_from_file_location("bench_fidelity", path)
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    write_records(tmp_path)
    (tmp_path / "manifest.json").write_text('{"mine": 1}', encoding="utf-8")
    args = argparse.Namespace(fema=None, records=tmp_path, units=None, time_step=None, pga=None)
    name, records = bench.load_records(args)
    assert name == tmp_path.name and [r[0] for r in records] == ["R1", "R2"]

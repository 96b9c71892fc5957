"""`rockbridge generate-records` and `rockbridge plot spectra` through click's CliRunner."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from rockbridge_cli.cli import main

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


@pytest.mark.slow
def test_regenerating_the_paper_set_reproduces_the_bundled_files(tmp_path):
    result = run("generate-records", PAPER, "--out", tmp_path / "set")
    assert result.exit_code == 0, result.output
    assert "overall: compliant" in result.output
    assert "(4)b mean zero-period value" in result.output
    bundled = sorted(path.name for path in BUNDLED.iterdir())
    assert sorted(path.name for path in (tmp_path / "set").iterdir()) == bundled
    for name in bundled:
        assert (tmp_path / "set" / name).read_bytes() == (BUNDLED / name).read_bytes(), name


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
        ((DATA / "non_numeric.txt", "--units", "g"), ["line 3", "'abc' is not a number"]),
        ((DATA / "one_column.txt", "--units", "g"), ["--time-step"]),
        ((DATA / "truncated.AT2",), ["truncated: NPTS = 7"]),
        ((DATA / "sample.AT2", "-o", "figure.jpg"), ["unknown figure format"]),
        ((DATA / "nothing_here",), ["file not found"]),
    ],
)
def test_plot_bad_input_exits_2(tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    assert_user_error(run("plot", "spectra", *args), *words)

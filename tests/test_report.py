"""``rockbridge report``: the page is parsed and checked against the results file it was made from
(read back through `read_peaks`, `read_config_hash`, the HDF5 attributes), it stands alone (no
script, no link, every figure an embedded PNG), and a real browser (headless Chromium, where the
machine has it) loads every figure."""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
from html.parser import HTMLParser

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from studies import BRIDGES, REPO, SLENDER_BLOCK, write_records, write_study

from rockbridge_cli.cli import main
from rockbridge_cli.config.study import load_study
from rockbridge_cli.report import write_report
from rockbridge_cli.results import read_config_hash, read_peaks
from rockbridge_cli.study.run import run_study

BROWSERS = ("chromium", "chromium-browser", "google-chrome")


class Page(HTMLParser):
    """The parts of the page the tests read: headings, images, links, scripts and table rows."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.headings: list[str] = []
        self.images: list[str] = []
        self.references: list[str] = []
        self.scripts = 0
        self.tables: list[list[list[str]]] = []
        self._cell: list[str] | None = None
        self._heading: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        values = dict(attrs)
        if tag == "img":
            self.images.append(values.get("src", ""))
        if tag in ("link", "a", "iframe", "object", "embed") or "href" in values:
            self.references.append(values.get("href") or values.get("src") or tag)
        self.scripts += tag == "script"
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self._cell = []
        elif tag in ("h1", "h2", "h3"):
            self._heading = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.tables[-1][-1].append("".join(self._cell).strip())
            self._cell = None
        elif tag in ("h1", "h2", "h3") and self._heading is not None:
            self.headings.append("".join(self._heading).strip())
            self._heading = None

    def handle_data(self, data):
        for part in (self._cell, self._heading):
            if part is not None:
                part.append(data)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    study = load_study(write_study(folder, extra="output: {path: out.h5}\n"))
    run_study(study, workers=1)
    return study


@pytest.fixture(scope="module")
def page(study):
    path = write_report(study.output, study.output.with_name("report.html"))
    return path, Page(path.read_text(encoding="utf-8"))


def test_the_page_states_what_was_run(study, page):
    _, parsed = page
    with h5py.File(study.output, "r") as file:
        version = file.attrs["rockbridge_version"]
    assert "Provenance" in parsed.headings and "Peak table" in parsed.headings
    source = page[0].read_text(encoding="utf-8")
    assert read_config_hash(study.output) in source and f"rockbridge {version}" in source
    # issue 40: knobs as a reader reads them (no Python repr), the host by what it is
    assert "bisection = off" in source and "False" not in source and "None" not in source
    assert "step = 0.01 s" in source and "<dt>host name</dt>" in source


def test_the_input_records_are_listed_as_read(study, page):
    """One row per record: its source, units and sampling as the study's files state them, its
    PGA from the samples (tests/studies.py writes R1 at 5.0 m/s² and R2 at 4.0: 600 samples at
    0.01 s, the last at 5.99 s)."""
    _, parsed = page
    assert "Input records" in parsed.headings
    rows = next(t for t in parsed.tables if t[0][:2] == ["record", "source"])
    header, body = rows[0], {row[0]: row for row in rows[1:]}
    assert set(body) == {r.id for r in study.records}
    for name, (pga, _) in {"R1": (5.0, 1.0), "R2": (4.0, 0.7)}.items():
        row = body[name]
        assert row[header.index("dt [s]")] == "0.01" and row[header.index("duration [s]")] == "5.99"
        assert float(row[header.index("PGA [g]")]) == pytest.approx(pga / 9.80665, rel=2e-3)
    assert "earthquake" not in header  # no provenance without recorded motions


def test_the_peak_table_is_the_files(study, page):
    """Every analysis is a row, in the file's order, with u_deck in mm and the failure mode."""
    _, parsed = page
    rows = next(t for t in parsed.tables if "u_deck_max [mm]" in t[0])
    header, body = rows[0], rows[1:]
    peaks = read_peaks(study.output)
    assert len(body) == len(peaks)
    column = header.index("u_deck_max [mm]")
    for row, (_, expected) in zip(body, peaks.iterrows(), strict=True):
        assert row[0] == expected["bridge"] and row[1] == expected["record"]
        assert float(row[column]) == pytest.approx(expected["u_deck_max"] * 1e3, rel=1e-3)
        assert row[header.index("failure_mode")] == expected["failure_mode"]


def test_the_summary_is_the_files_demand_over_capacity(study, page):
    _, parsed = page
    summary = next(t for t in parsed.tables if "backfill d/c, largest" in t[0])
    peaks = read_peaks(study.output)
    for row in summary[1:]:
        with h5py.File(study.output, "r") as file:
            ids = [b for b in file["bridges"] if file["bridges"][b].attrs["name"] == row[0]]
        mine = peaks[peaks["bridge"] == ids[0]]["dcr_backfill"]
        assert row[2] == f"{100 * mine.max():.1f} %" and row[3] == f"{100 * mine.mean():.1f} %"


@pytest.mark.slow
def test_the_failures_are_listed(study, page, tmp_path):
    """No failure in the studied bridges under the two bursts: the page says so. A slender block
    (0.4 m × 4 m, α = 0.1 rad) overturns under R1 (0.51 g): it is listed with its time."""
    assert "No analysis ended in a failure" in page[0].read_text(encoding="utf-8")
    (tmp_path / "block.yaml").write_text(SLENDER_BLOCK, encoding="utf-8")
    path = write_study(tmp_path, bridges=(), extra="output: {path: out.h5}\n",
                       bridge_files=(tmp_path / "block.yaml",))  # fmt: skip
    study = load_study(path)
    run_study(study, workers=1)
    parsed = Page(write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8"))
    table = next(t for t in parsed.tables if t[0][:3] == ["bridge", "record", "failure"])
    peaks = read_peaks(study.output)
    failed = peaks[peaks["failure_mode"] != "none"]
    assert len(table) - 1 == len(failed) >= 1
    assert table[1][2] == "overturning_pier1"
    assert float(table[1][3]) == pytest.approx(failed["failure_time"].iloc[0], rel=1e-3)


def test_the_page_stands_alone(page):
    """Fig. 9 and Fig. 10 as embedded PNGs; nothing fetched, nothing run."""
    _, parsed = page
    assert len(parsed.images) == 2 and parsed.scripts == 0 and not parsed.references
    for source in parsed.images:
        assert source.startswith("data:image/png;base64,")
        assert base64.b64decode(source.split(",", 1)[1])[:4] == b"\x89PNG"


def test_the_page_prints_on_a4(page):
    """Issue 40: README says A4, a browser printed on its default, US Letter, without a page
    size in the page's CSS (CSS Paged Media: `@page { size: A4 }`, 210 × 297 mm)."""
    assert re.search(r"@page \{ size: A4;", page[0].read_text(encoding="utf-8"))


@pytest.mark.slow
def test_a_study_with_stripes_gets_its_fragility(tmp_path):
    extra = (
        "intensity: {measure: pga_g, levels: [0.2, 0.6]}\n"
        "output: {path: stripes.h5, histories: none}\n"
    )
    study = load_study(write_study(tmp_path, extra=extra))
    run_study(study, workers=1)
    text = write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8")
    parsed = Page(text)
    assert any(h.startswith("Fragility") for h in parsed.headings)
    assert len(parsed.images) == 1  # the fragility curves; no Fig. 9 over both levels at once
    fits = next(t for t in parsed.tables if t[0][:2] == ["bridge", "limit state"])
    assert len(fits) - 1 == 2 * 4  # two bridges × the four default limit states
    assert "8 analyses of 2 bridges under 2 records at 2 levels of PGA" in text
    summary = next(t for t in parsed.tables if "backfill d/c, largest" in t[0])
    assert summary[0][:3] == ["bridge", "level, PGA [g]", "ran ok"]
    assert [row[1:3] for row in summary[1:]] == [["0.2", "2/2"], ["0.6", "2/2"]] * 2
    peaks = read_peaks(study.output)
    for row, ((_, level), rows) in zip(summary[1:], peaks.groupby(["bridge", "intensity"]),
                                       strict=True):  # fmt: skip
        assert float(row[1]) == level
        assert row[3] == f"{100 * rows['dcr_backfill'].max():.1f} %"


def test_fig10_of_a_stripe_study_is_under_the_design_motion(tmp_path):
    """Of a record's copies scaled to a study's stripes, the history figure is under the one at
    the design level, as the paper's Fig. 10 (it was under the lowest stripe's, 0.2 g, where
    the bridges barely rock; a second reviewer, 2026-11-28)."""
    extra = (
        "intensity: {measure: pga_g, design: 0.6, levels: [0.2, 0.6, 1.5]}\n"
        "output: {path: stripes.h5, histories: [theta1]}\n"
    )
    study = load_study(write_study(tmp_path, extra=extra))
    run_study(study, workers=1)
    first = read_peaks(study.output)["record"].iloc[0].split("+")[0]
    parsed = Page(write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8"))
    assert f"Response histories under {first}+0.6g (as the paper's Fig. 10)" in parsed.headings


@pytest.mark.slow
def test_a_sweep_is_drawn_against_its_field_and_fig10_is_under_ar07(tmp_path):
    """A sweep's variants get a figure against the swept field instead of Fig. 9, and the history
    figure is under the paper's record, AR07, where the study has it (not the first record)."""
    for name, source in (("AR01", "R1"), ("AR07", "R2")):
        write_records(tmp_path, (source,))
        (tmp_path / f"{source}.txt").rename(tmp_path / f"{name}.txt")
    study_file = tmp_path / "sweep.yaml"
    study_file.write_text(
        f"bridges: [{(BRIDGES / 'studied-hbar1.25.yaml').as_posix()}]\n"
        "records: {files: [{path: AR01.txt}, {path: AR07.txt}]}\n"
        "sweep: {fields: {abutments.gap: [0.06, 0.12, 0.24]}}\n"
        "fidelity: fast\noutput: {path: sweep.h5}\n", encoding="utf-8",
    )  # fmt: skip
    study = load_study(study_file)
    run_study(study, workers=1)
    parsed = Page(write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8"))
    assert "Against abutments.gap" in parsed.headings
    assert "Peaks per record (as the paper's Fig. 9)" not in parsed.headings
    assert "Response histories under AR07 (as the paper's Fig. 10)" in parsed.headings


@pytest.mark.slow
def test_the_command_writes_beside_the_results_and_never_over_them(study):
    runner = CliRunner()
    result = runner.invoke(main, ["report", str(study.output)])
    assert result.exit_code == 0, result.output
    assert study.output.with_name("out-report.html").is_file()
    refused = runner.invoke(main, ["report", str(study.output), "-o", str(study.output)])
    assert refused.exit_code == 2 and "would overwrite the results file" in refused.output
    missing = runner.invoke(main, ["report", str(study.output), "--record", "nope"])
    assert missing.exit_code == 2 and "no record nope" in missing.output
    with h5py.File(study.output, "r") as file:  # the results are intact
        assert file.attrs["complete"] in (True, "True", np.True_)


@pytest.mark.skipif(not any(map(shutil.which, BROWSERS)), reason="no headless Chromium here")
def test_a_browser_renders_every_figure(page, tmp_path):
    """Chromium loads the page; a probe added to a copy counts the figures it decoded."""
    browser = next(b for b in map(shutil.which, BROWSERS) if b)
    probe = tmp_path / "probe.html"
    text = page[0].read_text(encoding="utf-8")
    script = (
        "<script>addEventListener('load', () => { const i = [...document.images]; "
        "document.title = 'decoded ' + i.filter(x => x.naturalWidth > 0).length + ' of ' "
        "+ i.length; });</script>"
    )
    probe.write_text(text.replace("</body>", script + "</body>"), encoding="utf-8")
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=10000"]
    dom = subprocess.run([browser, *flags, "--dump-dom", probe.as_uri()], capture_output=True,
                         text=True, timeout=180, check=True).stdout  # fmt: skip
    assert re.search(r"<title>decoded 2 of 2</title>", dom), dom[:300]
    shot = tmp_path / "page.png"
    subprocess.run([browser, *flags, "--hide-scrollbars", "--window-size=1000,1400",
                    f"--screenshot={shot}", page[0].as_uri()], capture_output=True, timeout=180,
                   check=True)  # fmt: skip
    assert shot.read_bytes()[:4] == b"\x89PNG" and shot.stat().st_size > 20_000


@pytest.mark.slow
def test_a_generated_set_brings_its_compliance_and_ground_displacement(tmp_path):
    """A study on the bundled set: the page shows the set's EN 1998-1 check from its manifest,
    with each record's PGD over d_g (0.2031 m, §3.2.2.4) as the manifest gives them."""
    bundled = REPO / "records" / "ec8-type1-C-ag0.6g"
    study_file = tmp_path / "set.yaml"
    study_file.write_text(
        f"bridges: [{(BRIDGES / 'studied-hbar1.25.yaml').as_posix()}]\n"
        f"records: {{set: {bundled.as_posix()}}}\n"
        "fidelity: fast\noutput: {path: set.h5, histories: none}\n", encoding="utf-8"
    )  # fmt: skip
    study = load_study(study_file)
    run_study(study, workers=1)
    parsed = Page(write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8"))
    assert "Record sets: EN 1998-1 §3.2.3.1.2" in parsed.headings
    table = next(t for t in parsed.tables if t[0][:2] == ["record", "PGA/(a_g·S)"])
    manifest = json.loads((bundled / "manifest.json").read_text(encoding="utf-8"))
    dg = manifest["target"]["ground_displacement_m"]
    assert dg == pytest.approx(0.025 * 5.886 * 1.15 * 0.6 * 2.0, rel=1e-6)
    column = table[0].index("PGD/d_g")
    for row, entry in zip(table[1:-1], manifest["records"], strict=True):
        assert row[0] == entry["name"] and row[column] == f"{entry['pgd_m'] / dg:.2f}"


def test_a_study_that_keeps_some_histories_gets_its_page_and_its_figure(tmp_path):
    """Issue 39: ``report`` and ``plot history`` refused a study that keeps some histories (the
    bundled vertical-example.yaml among them: "no theta_deck history", exit 2, no page). Now
    Fig. 10 draws what the file holds and the page, the figure and the command say what is
    left out."""
    kept = "output: {path: some.h5, histories: [u_deck, theta1, theta2]}\n"
    study = load_study(write_study(tmp_path, records=("R1",), extra="fidelity: fast\n" + kept))
    run_study(study, workers=1)
    text = write_report(study.output, tmp_path / "r.html").read_text(encoding="utf-8")
    parsed = Page(text)
    assert "Response histories under R1 (as the paper's Fig. 10)" in parsed.headings
    assert len(parsed.images) == 2
    assert "Not kept by the study (output.histories): v_deck, θ_deck." in text
    result = CliRunner().invoke(main, ["plot", "history", str(study.output), "--record", "R1",
                                       "-o", str(tmp_path / "h.svg")])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "left out: v_deck, θ_deck (not kept by the study: output.histories)" in result.output
    figure = (tmp_path / "h.svg").read_text(encoding="utf-8")
    assert "(D)" in figure and "(E)" not in figure  # ground, u_deck, θ1, θ2

"""The manual (issue 44): README is the front page, every section it had is a page's section, and
the site builds offline in strict mode with its generated references.

Expected values: README's headings before the manual (listed here as they were, from git history
at commit a1dc6b9), the paper's defaults of a bridge config (docs/model.md §2) and click's own list
of the commands.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

FORMER_README_HEADINGS = (
    "Quickstart: the paper's Figs. 9 and 10", "The one-page report", "From Python", "Units",
    "Bridge config", "Study config", "Intensity and fragility",
    "How sure is a fragility, and how many records are enough", "Intensity measures",
    "Recorded motions: the paper's question on the FEMA P695 sets",
    "Uncertain parameters: sampled bridges and which one matters", "Risk at a site, and exports",
    "Pulses and overturning spectra", "Vertical ground motion", "Ground motions",
    "Recorded motions: the FEMA P695 sets", "Pulses in recorded motions",
    "Recorded motions matched or scaled to EN 1998-1", "Selecting recorded motions (EN 1998-1)",
    "Synthetic records matched to EN 1998-1", "Fidelity: speed against accuracy",
    "Results file (HDF5)", "Reliability: bad input and faults", "Validation", "Docker",
    "Development", "How to cite", "References",
)  # fmt: skip
"""README's section headings when it held the whole manual (1 673 lines)."""


def reference_hook():
    """docs/hooks/reference.py, the MkDocs hook that generates the reference pages."""
    spec = importlib.util.spec_from_file_location("reference", REPO / "docs/hooks/reference.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def headings(text: str) -> list[str]:
    """A Markdown page's headings (outside code blocks), without their #s."""
    prose = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return [line.lstrip("#").strip() for line in prose.splitlines() if re.match(r"#{1,6} ", line)]


def nav_pages() -> set[str]:
    """The pages mkdocs.yml's nav names."""
    return set(re.findall(r":\s*(\S+\.md)\s*$", (REPO / "mkdocs.yml").read_text(), re.M))


def test_every_former_readme_section_is_a_section_of_a_page_in_the_nav():
    found = {}
    for page in sorted(nav_pages()):
        for heading in headings((REPO / "docs" / page).read_text(encoding="utf-8")):
            found.setdefault(heading, page)
    missing = [h for h in FORMER_README_HEADINGS if h not in found]
    assert missing == [], f"README's former sections not in the manual: {missing}"


def test_readme_is_a_front_page_linking_into_the_manual():
    text = (REPO / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 200
    linked = set(re.findall(r"\]\(docs/([^)#]+\.md)", text))
    assert linked <= nav_pages(), linked - nav_pages()
    for page in ("install.md", "quickstart.md", "fragility.md", "records.md", "reliability.md",
                 "reference/cli.md", "reference/config.md", "reference/api.md"):  # fmt: skip
        assert page in linked, page


def slug(heading: str) -> str:
    """A heading's anchor as MkDocs' and GitHub's renderers make it for these headings: lower
    case, punctuation dropped, spaces as hyphens."""
    return re.sub(r"\s+", "-", re.sub(r"[^\w\s-]", "", heading.lower()).strip())


def test_readme_links_to_anchors_that_exist():
    text = (REPO / "README.md").read_text(encoding="utf-8")
    links = re.findall(r"\]\(docs/([^)#]+\.md)#([^)]+)\)", text)
    assert links, "README links to no section of a page"
    for page, anchor in links:
        anchors = {slug(h) for h in headings((REPO / "docs" / page).read_text(encoding="utf-8"))}
        assert anchor in anchors, (page, anchor)


def reference_cells(target: str) -> dict[str, list[str]]:
    """The generated config reference of ``MODULE:MODEL``: each field's path → its cells (type,
    default, unit, meaning)."""
    table = reference_hook().config_fields(target)
    rows = {r.split("|")[1].strip(" `"): r.split("|")[2:-1] for r in table.splitlines()[2:]}
    return {path: [c.strip() for c in cells] for path, cells in rows.items()}


def test_the_config_reference_gives_each_field_its_unit_and_default():
    cell = reference_cells("rockbridge_cli.config.bridge:BridgeConfig")
    # docs/model.md §2: ρ = 2500 kg/m³, g = 9.81 m/s², e = 0.6, ρ_s 2000 kg/m³, L_cr 1 m,
    # B_abut 9.5 m, h_bw 2 m
    assert cell["density"][1:3] == ["2500.0", "kg/m³"]
    assert cell["gravity"][1:3] == ["9.81", "m/s²"]
    assert cell["abutments.pounding.restitution"][1] == "0.6"
    assert cell["abutments.pounding.soil_density"][1:3] == ["2000.0", "kg/m³"]
    assert cell["abutments.pounding.critical_length"][1:3] == ["1.0", "m"]
    assert cell["abutments.pounding.backwall_width"][1:3] == ["9.5", "m"]
    assert cell["abutments.pounding.backwall_height"][1:3] == ["2.0", "m"]
    assert cell["piers.width"][1:3] == ["required", "m"]
    assert cell["abutments.damping"][2] == "N·s/m"


def test_the_config_reference_follows_lists_mappings_and_alternatives():
    table = reference_hook().config_fields("rockbridge_cli.config.study:StudyConfig")
    paths = {row.split("|")[1].strip(" `") for row in table.splitlines()[2:]}
    assert {"records.files[].path", "sweep.fields.<key>.spacing", "intensity.ida.tolerance",
            "uncertainty.fields.<key>.<uniform>.low", "fidelity.rtol",
            "output.histories", "records.orientation.angles.step"} <= paths  # fmt: skip


CONFIG_MODELS = (
    "rockbridge_cli.config.bridge:BridgeConfig", "rockbridge_cli.config.study:StudyConfig",
    "rockbridge_cli.config.record_sets:RecordSetConfig",
    "rockbridge_cli.config.selection:SelectionConfig",
)  # fmt: skip
"""The four kinds of config file, as docs/reference/config.md lists them."""


def test_every_field_that_holds_numbers_states_its_unit():
    # the house style: a quantity with its unit in brackets, [-] for a pure
    # number; numbers that are no quantity: a pier's place in piers.heights, FEMA P695 record ids
    labels = (".pier", "fema_p695.records", "fema_p695[].records")
    for target in CONFIG_MODELS:
        for path, cells in reference_cells(target).items():
            if re.search(r"number|integer", cells[0]) and not path.endswith(labels):
                assert cells[2], f"{target}: {path} gives no unit"


def test_the_config_reference_gives_each_kind_of_device_its_fields():
    cell = reference_cells("rockbridge_cli.config.bridge:BridgeConfig")
    # docs/studies.md's example of devices: elastic_modulus 195.0e9 [Pa] the default,
    # interface base (default); docs/model.md §13: P0 a force, c of F = c·Δ̇ a dashpot's
    assert cell["devices[].<tendon>.kind"][:2] == ['"tendon"', "required"]
    assert cell["devices[].<tendon>.prestress"][1:3] == ["required", "N"]
    assert cell["devices[].<tendon>.area"][2] == "m²"
    assert float(cell["devices[].<tendon>.elastic_modulus"][1]) == 195.0e9
    assert cell["devices[].<tendon>.elastic_modulus"][2] == "Pa"
    assert cell["devices[].<tendon>.offset"][1:3] == ["0.0", "m"]
    assert cell["devices[].<damper>.coefficient"][1:3] == ["required", "N·s/m"]
    assert cell["devices[].<damper>.interface"][1] == '"base"'
    assert "devices[].<damper>.prestress" not in cell  # each kind its own fields


def test_the_config_reference_gives_the_seeds_as_a_file_writes_them():
    cell = reference_cells("rockbridge_cli.config.record_sets:RecordSetConfig")
    # docs/records.md: seeds are a list of record files or {fema_p695: <set>}
    assert cell["seeds[].path"][1] == "required"
    assert cell["seeds.fema_p695.set"][1] == "required"
    assert cell["band"][0] == "[number, number]"
    assert not any(path.startswith("seeds.set") for path in cell)


def test_the_config_reference_says_a_fema_set_may_be_named_alone():
    # docs/records.md: a study's records are `{fema_p695: far-field}`, a pool's `fema_p695:
    # [far-field, near-field-pulse, ...]`: the name alone, short for {set: <name>}
    study = reference_cells("rockbridge_cli.config.study:StudyConfig")["records.fema_p695"]
    pool = reference_cells("rockbridge_cli.config.selection:SelectionConfig")["pool.fema_p695"]
    names = "one of far-field, near-field-pulse, near-field-no-pulse"
    assert study[0] == f"FemaSet or {names}" and pool[0] == f"list of FemaSet or {names}"
    assert "its name alone" in study[3] and "short for {set: &lt;name>}" in study[3]


def test_the_notebook_page_is_the_script_cell_by_cell(tmp_path):
    script = "# ---\n# jupyter: x\n# ---\n\n# %% [markdown]\n# # Title\n#\n# Text.\n\n# %%\nx = 1\n"
    (tmp_path / "cells.py").write_text(script, encoding="utf-8")
    page = reference_hook().notebook(str(tmp_path / "cells.py"))  # an absolute path: as it is
    assert page == "## Title\n\nText.\n\n```python\nx = 1\n```"


@pytest.mark.slow
def test_the_site_builds_offline_in_strict_mode(tmp_path):
    pytest.importorskip("mkdocs")
    pytest.importorskip("material")
    pytest.importorskip("mkdocstrings_handlers.python")
    pytest.importorskip("mkdocs_click")
    path = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p)
    environment = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "PYTHONPATH": path}
    built = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path)],
        cwd=REPO, env=environment, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert built.returncode == 0, built.stderr[-3000:]
    commands = (tmp_path / "reference" / "cli" / "index.html").read_text(encoding="utf-8")
    from rockbridge_cli.cli import main

    for name in main.commands:  # click's own list of the commands
        assert f"rockbridge {name}" in commands, name
    fields = (tmp_path / "reference" / "config" / "index.html").read_text(encoding="utf-8")
    assert "abutments.pounding.soil_density" in fields and "uncertainty.design" in fields
    api = (tmp_path / "reference" / "api" / "index.html").read_text(encoding="utf-8")
    assert "run_study" in api and "Parameters" in api

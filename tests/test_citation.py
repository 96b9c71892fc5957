"""CITATION.cff says how to cite rockbridge (issue 44, item 4): it is valid YAML with the keys
Citation File Format 1.2.0 requires, and its version is the package's, so the two cannot drift."""

from __future__ import annotations

import re

import pytest
import yaml
from studies import REPO

import rockbridge_cli

CFF_REQUIRED = ("cff-version", "message", "title", "authors")
"""The keys CFF 1.2.0 requires of a citation file (its schema's ``required``)."""


@pytest.fixture(scope="module")
def citation() -> dict:
    return yaml.safe_load((REPO / "CITATION.cff").read_text(encoding="utf-8"))


def test_the_citation_file_has_the_keys_cff_requires(citation):
    assert citation["cff-version"] == "1.2.0"
    missing = [key for key in CFF_REQUIRED if not citation.get(key)]
    assert not missing, f"CITATION.cff lacks {missing}"
    for author in citation["authors"]:  # a person has family-names, an entity a name
        assert author.get("family-names") or author.get("name"), author
    assert citation["license"] == "MIT"


def test_the_citation_names_the_paper_rockbridge_implements(citation):
    paper = citation["preferred-citation"]
    assert paper["title"] == "Dynamics and seismic performance of asymmetric rocking bridges"
    assert [a["family-names"] for a in paper["authors"]] == ["Thomaidis", "Camara", "Kappos"]
    published = ("Journal of Engineering Mechanics", 2022, 148, 3)  # README's References
    assert (paper["journal"], paper["year"], paper["volume"], paper["issue"]) == published
    assert paper["start"] == "04022003"
    assert paper["doi"].lower() == "10.1061/(asce)em.1943-7889.0002074"  # printed on the paper


def test_the_citation_version_is_the_package_version(citation):
    """The version of CITATION.cff, of pyproject.toml and of ``rockbridge_cli.__version__`` (which
    ``rockbridge --version`` prints and a results file stores as ``rockbridge_version``) agree."""
    pyproject = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    project = re.search(r'^\[project\]$.*?^version = "([^"]+)"$', pyproject, re.M | re.S)
    assert project, "pyproject.toml's [project] has no version"
    assert str(citation["version"]) == project.group(1) == rockbridge_cli.__version__

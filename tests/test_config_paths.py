"""Paths in configs reach the config's project (its folder's tree, or the tree of the nearest
folder above it marked by a .rockbridge file), the working folder's tree and the folders
named in ROCKBRIDGE_PATHS, nothing else (issue 32: "paths in configs confined to the config's
folder tree unless the user says otherwise"); paths on the command line are not confined.

Layout of every test: ``tmp/project/`` holds the config (and is the working folder unless said),
``tmp/elsewhere/`` a file the config should not reach without the user's word.
"""

from __future__ import annotations

import json
import shutil

import pytest
from click.testing import CliRunner
from studies import BRIDGES, REPO, write_records

from rockbridge_cli.cli import main
from rockbridge_cli.config.loading import (
    PATHS_VARIABLE,
    PROJECT_MARKER,
    ConfigFolder,
    project_root,
)
from rockbridge_cli.config.study import load_study
from rockbridge_cli.errors import InputError

BRIDGE = BRIDGES / "studied-hbar1.00.yaml"


@pytest.fixture
def places(tmp_path, monkeypatch):
    """(project, elsewhere): the config's folder, the working folder, and a folder beside them
    holding the records R1, R2 and a copy of the bridge."""
    project, elsewhere = tmp_path / "project", tmp_path / "elsewhere"
    project.mkdir()
    write_records(elsewhere)
    shutil.copy(BRIDGE, elsewhere / "bridge.yaml")
    shutil.copy(BRIDGE, project / "bridge.yaml")
    monkeypatch.delenv(PATHS_VARIABLE, raising=False)
    monkeypatch.chdir(project)
    return project, elsewhere


def study(project, bridge="bridge.yaml", record="../elsewhere/R1.txt", extra=""):
    path = project / "study.yaml"
    path.write_text(f"bridges: [{bridge}]\nrecords: {{files: [{{path: {record}}}]}}\n{extra}")
    return path


def refused(path) -> tuple[str, str]:
    """The (field, reason) of the one refusal of the study at ``path``."""
    with pytest.raises(InputError) as caught:
        load_study(path)
    assert len(caught.value.problems) == 1
    return caught.value.problems[0]


def test_a_record_outside_is_refused_naming_the_field_and_the_way_out(places):
    project, _ = places
    where, why = refused(study(project))
    assert where == "records.files.0.path"
    assert "../elsewhere/R1.txt leads outside the config's project and the working folder" in why
    assert why.endswith(f", to {(project.parent / 'elsewhere' / 'R1.txt').resolve()}")


def test_the_command_line_says_it_in_one_line_with_exit_2(places):
    project, _ = places
    result = CliRunner().invoke(main, ["run", str(study(project)), "-o", "out.h5"])
    assert result.exit_code == 2
    assert "records.files.0.path" in result.output and "Traceback" not in result.output
    assert not (project / "out.h5").exists()


def test_the_refusal_is_short_and_ends_with_the_command_that_works(places, monkeypatch):
    """Issue 40: the message was 330 characters and gave no command; now its last line is the
    same command with the folder the path leads to named, and that command runs."""
    project, elsewhere = places
    path = study(project)
    result = CliRunner().invoke(main, ["run", "study.yaml", "-o", "out.h5", "--fidelity", "fast"])
    assert result.exit_code == 2
    first, last = result.output.strip().splitlines()
    real = str((elsewhere / "R1.txt").resolve())
    assert first.endswith(f"{real} (the 1st entry of records.files)")
    assert len(first) - len(real) < 170, first
    assert last.strip() == (
        f"to let it through: {PATHS_VARIABLE}={elsewhere.resolve()} "
        "rockbridge run study.yaml -o out.h5 --fidelity fast"
    )
    monkeypatch.setenv(PATHS_VARIABLE, str(elsewhere.resolve()))
    assert load_study(path).records[0].id == "R1"


def test_a_marked_project_is_reached_from_any_folder(places, tmp_path, monkeypatch):
    """The bundled studies' layout (configs/studies/x.yaml reading ../../records/...), run from
    a folder that holds neither: the project's root is marked, its whole tree reachable."""
    project, elsewhere = places
    (tmp_path / "work").mkdir()
    monkeypatch.chdir(tmp_path / "work")
    path = study(project)
    assert refused(path)[0] == "records.files.0.path"
    (tmp_path / PROJECT_MARKER).write_text("")
    assert project_root(path) == tmp_path.resolve()
    assert load_study(path).records[0].id == "R1"


def test_a_marker_opens_its_own_project_only(places, tmp_path, monkeypatch):
    """A config handed over with its own marked tree still reaches nothing beyond it."""
    project, elsewhere = places
    (project / PROJECT_MARKER).write_text("")
    (tmp_path / "work").mkdir()
    monkeypatch.chdir(tmp_path / "work")
    (project / "sub").mkdir()
    write_records(project / "data")
    path = study(project / "sub", bridge="../bridge.yaml", record="../data/R1.txt")
    assert load_study(path).records[0].id == "R1"
    where, why = refused(study(project / "sub", "../bridge.yaml", "../../elsewhere/R1.txt"))
    assert where == "records.files.0.path" and "leads outside" in why


def test_a_marker_in_the_home_folder_is_passed_over(places, tmp_path, monkeypatch):
    """It would open every file of the user to any config."""
    project, _ = places
    monkeypatch.setenv("HOME", str(tmp_path))
    (tmp_path / PROJECT_MARKER).write_text("")
    assert project_root(project / "study.yaml") == project.resolve()
    assert refused(study(project))[0] == "records.files.0.path"


@pytest.mark.parametrize(
    "bridge, record, extra, field",
    [
        ("../elsewhere/bridge.yaml", "R1.txt", "", "bridges.0"),
        ("bridge.yaml", "R1.txt", "output: {path: ../elsewhere/out.h5}", "output.path"),
        ("bridge.yaml", "/etc/hostname", "", "records.files.0.path"),
    ],
)
def test_every_path_of_a_study_is_confined(places, bridge, record, extra, field):
    project, _ = places
    write_records(project)
    where, why = refused(study(project, bridge, record, extra))
    assert where == field and "leads outside the config's project" in why


def test_an_output_path_replaced_on_the_command_line_is_not_checked(places):
    """`-o` (``output``) replaces the study's ``output.path``: the one the study names is not
    used, so it is not refused."""
    project, _ = places
    write_records(project)
    path = study(project, record="R1.txt", extra="output: {path: ../elsewhere/out.h5}")
    assert load_study(path, output="mine.h5").output.name == "mine.h5"


def test_a_vertical_companion_outside_is_refused(places):
    project, _ = places
    write_records(project)
    path = project / "study.yaml"
    path.write_text("bridges: [bridge.yaml]\nrecords: {files: [{path: R1.txt, vertical: "
                    "../elsewhere/R2.txt}], vertical: true}\n")  # fmt: skip
    where, why = refused(path)
    assert where == "records.files.0.vertical" and "leads outside" in why


def test_a_record_set_outside_is_refused(places):
    project, elsewhere = places
    (elsewhere / "manifest.json").write_text(json.dumps({"records": [{"file": "R1.txt"}]}))
    path = project / "study.yaml"
    path.write_text("bridges: [bridge.yaml]\nrecords: {set: ../elsewhere}\n")
    where, why = refused(path)
    assert where == "records.set" and "leads outside" in why


def test_a_symbolic_link_out_of_the_tree_is_refused(places):
    """The check follows links: a link inside the project to a file outside is outside."""
    project, elsewhere = places
    (project / "R1.txt").symlink_to(elsewhere / "R1.txt")
    where, _ = refused(study(project, record="R1.txt"))
    assert where == "records.files.0.path"


def test_the_working_folder_reaches_where_the_config_folder_does_not(places, monkeypatch):
    """The bundled studies' layout: configs/studies/x.yaml reads ../../records/... and is run
    from the folder that holds both."""
    project, elsewhere = places
    monkeypatch.chdir(project.parent)
    assert load_study(study(project)).records[0].id == "R1"


def test_rockbridge_paths_reaches_further(places, monkeypatch):
    project, elsewhere = places
    monkeypatch.setenv(PATHS_VARIABLE, f"/nonexistent:{elsewhere}")
    path = study(project, bridge="../elsewhere/bridge.yaml")
    loaded = load_study(path)
    assert [r.id for r in loaded.records] == ["R1"] and loaded.bridges[0].id == "bridge"


@pytest.mark.parametrize("where", ["root", "studies", "elsewhere"])
def test_the_bundled_studies_load_from_any_folder(monkeypatch, tmp_path, where):
    """Issue 40: from the repository's root, from configs/studies and from a folder outside
    the repository (the repository's root is marked by its .rockbridge file)."""
    monkeypatch.delenv(PATHS_VARIABLE, raising=False)
    folders = {"root": REPO, "studies": REPO / "configs" / "studies", "elsewhere": tmp_path}
    monkeypatch.chdir(folders[where])
    assert (REPO / PROJECT_MARKER).is_file()
    for path in sorted((REPO / "configs" / "studies").glob("*.yaml")):
        if "fema" not in path.name:  # FEMA sets are read from the package, not from a path
            load_study(path)


def test_a_record_set_config_confines_its_seeds(places):
    project, _ = places
    config = project / "set.yaml"
    config.write_text("target: {spectrum_type: 1, ground_type: C, ag_g: 0.6}\n"
                      "seeds: [{path: ../elsewhere/R1.txt}]\n")  # fmt: skip
    result = CliRunner().invoke(main, ["generate-records", str(config), "--out", "set"])
    assert result.exit_code == 2, result.output
    assert "seeds.0.path" in result.output and "leads outside" in result.output
    assert not (project / "set").exists()


@pytest.mark.parametrize("name", ["../R1.txt", "/etc/hostname", "sub/R1.txt", ".."])
def test_a_manifest_names_files_of_its_own_folder_only(places, name):
    project, elsewhere = places
    (project / "set").mkdir()
    (project / "set" / "manifest.json").write_text(json.dumps({"records": [{"file": name}]}))
    path = project / "study.yaml"
    path.write_text("bridges: [bridge.yaml]\nrecords: {set: set}\n")
    with pytest.raises(InputError, match="must name a file in the set's folder"):
        load_study(path)


def test_a_set_file_linked_out_of_the_set_is_refused(places):
    """The set's folder is within reach, but a file in it that links elsewhere is not read."""
    project, elsewhere = places
    (project / "set").mkdir()
    (project / "set" / "R1.txt").symlink_to(elsewhere / "R1.txt")
    (project / "set" / "manifest.json").write_text(json.dumps({"records": [{"file": "R1.txt"}]}))
    path = project / "study.yaml"
    path.write_text("bridges: [bridge.yaml]\nrecords: {set: set}\n")
    with pytest.raises(InputError, match="must name a file in the set's folder"):
        load_study(path)


def test_a_sets_manifest_linked_out_of_the_set_is_refused(places):
    """Issue 39: a set's manifest.json that links out of the set was followed (its files were
    then read from the set's folder, as the manifest elsewhere listed them)."""
    project, elsewhere = places
    (project / "set").mkdir()
    shutil.copy(elsewhere / "R1.txt", project / "set" / "R1.txt")
    (elsewhere / "manifest.json").write_text(json.dumps({"records": [{"file": "R1.txt"}]}))
    (project / "set" / "manifest.json").symlink_to(elsewhere / "manifest.json")
    path = project / "study.yaml"
    path.write_text("bridges: [bridge.yaml]\nrecords: {set: set}\n")
    with pytest.raises(InputError, match="manifest.json: is a link out of the set's folder"):
        load_study(path)


def test_a_nul_in_a_manifests_file_name_is_refused(places):
    """A NUL in a manifest's file name ended in a raw "embedded null byte" (issue 39)."""
    project, elsewhere = places
    (project / "set").mkdir()
    (project / "set" / "manifest.json").write_text('{"records": [{"file": "R1\\u0000.txt"}]}')
    path = project / "study.yaml"
    path.write_text("bridges: [bridge.yaml]\nrecords: {set: set}\n")
    with pytest.raises(InputError, match=r"records\[0\]\.file: holds a NUL character"):
        load_study(path)


def test_command_line_paths_are_the_users_own(places, tmp_path):
    """`analyze BRIDGE RECORD` reads files anywhere: the user named them."""
    project, elsewhere = places
    result = CliRunner().invoke(
        main, ["analyze", str(elsewhere / "bridge.yaml"), str(elsewhere / "R1.txt"),
               "--fidelity", "fast", "-o", str(elsewhere / "one.h5")],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (elsewhere / "one.h5").is_file()


def test_an_unconfined_folder_reaches_anywhere(tmp_path):
    assert ConfigFolder(tmp_path, None).path("/etc/hostname").as_posix() == "/etc/hostname"
    with pytest.raises(ValueError, match="leads outside"):
        ConfigFolder(tmp_path, (tmp_path.resolve(),)).path("/etc/hostname")


def test_the_docker_image_reaches_its_bundled_records():
    """The image copies configs/ and records/ into /opt/rockbridge and runs from /work."""
    docker = (REPO / "Dockerfile").read_text(encoding="utf-8")
    assert f"{PATHS_VARIABLE}=/opt/rockbridge" in docker
    assert "COPY records ./records" in docker and "WORKDIR /opt/rockbridge" in docker

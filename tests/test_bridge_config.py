"""The bridge YAML config: loading, the `Model` it gives, mirroring, and every kind of bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import (
    BAD_BRIDGES,
    CONFIGS,
    M_ABUT,
    RefLinkage,
    fig78_bridge,
    make_bridge,
    ref_onset,
    ref_restitution,
    studied_bridge,
)

from rockbridge_cli.config.bridge import BridgeConfig, load_bridge
from rockbridge_cli.core.analysis import analyze
from rockbridge_cli.core.geometry import kind
from rockbridge_cli.core.summary import describe, summarize
from rockbridge_cli.errors import InputError

# Each config against the Model built here from the paper's data (conftest docstring).
EXPECTED_MODELS = {
    "studied-hbar1.00.yaml": studied_bridge(1.0),
    "studied-hbar1.25.yaml": studied_bridge(1.25),
    "studied-hbar1.25-tendons.yaml": studied_bridge(1.25),  # its devices: tests/test_devices.py
    "studied-hbar1.25-dampers.yaml": studied_bridge(1.25),
    "studied-hbar1.25-dissipators.yaml": studied_bridge(1.25),
    "studied-hbar2.00.yaml": studied_bridge(2.0),
    "fig3-hbar6.4.yaml": studied_bridge(6.4),
    "fig8-hbar1.5.yaml": fig78_bridge(1.5),
}


def test_every_shipped_config_is_checked():
    assert {p.name for p in CONFIGS.glob("*.yaml")} == set(EXPECTED_MODELS)


@pytest.mark.parametrize("name", sorted(EXPECTED_MODELS))
def test_config_gives_the_papers_model(name):
    config = load_bridge(CONFIGS / name)
    assert isinstance(config, BridgeConfig)
    assert not config.mirrored
    model = config.to_bridge().model
    expected = EXPECTED_MODELS[name]
    for field in expected._fields:
        assert getattr(model, field) == pytest.approx(getattr(expected, field), rel=1e-12), field


def yaml_file(tmp_path, text, name="bridge.yaml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


BRIDGE_TEXT = """
piers:
  width: 2.6
  heights: [{left}, {right}]
deck:
  depth: 1.7
  area: 6.0
spans:
  side: 38.0
  central: 60.0
abutments:
  gap: 0.12
  stiffness: 1.32e+8
  damping: 4.8e+7
  ultimate_displacement: 0.10
"""


def test_defaults(tmp_path):
    model = (
        load_bridge(yaml_file(tmp_path, BRIDGE_TEXT.format(left=26.0, right=20.8)))
        .to_bridge()
        .model
    )
    # docs/model.md §2: ρ = 2500, g = 9.81, e = 0.6, m_abut = 38 000 kg, I_deck = m(L² + (2h)²)/12
    expected = studied_bridge(1.25)
    assert model.m_abut == pytest.approx(M_ABUT, rel=1e-14)
    assert model.e == 0.6 and model.g == 9.81
    assert model.Id == pytest.approx(expected.Id, rel=1e-14)
    assert model.md == pytest.approx(2.04e6, rel=1e-14)


def test_mirrored_bridge(tmp_path):
    # docs/model.md §1: the tall pier on the right is the mirror image of the tall pier on the left
    left = load_bridge(yaml_file(tmp_path, BRIDGE_TEXT.format(left=26.0, right=20.8), "a.yaml"))
    right = load_bridge(yaml_file(tmp_path, BRIDGE_TEXT.format(left=20.8, right=26.0), "b.yaml"))
    assert not left.mirrored and right.mirrored
    assert right.to_bridge().model == left.to_bridge().model  # same Model, tall pier first
    a = summarize(left.to_bridge())
    b = summarize(right.to_bridge())
    for key in ("m_pier1", "m_pier2", "m_deck", "gamma", "q", "h_bar", "pounding_ratio"):
        assert b[key] == a[key], key
    swaps = [("ug_min_p", "ug_min_n"), ("eta_pn", "eta_np"), ("eta_frame_pn", "eta_frame_np")]
    for p, n in swaps:
        assert b[p] == a[n] and b[n] == a[p]
    assert b["mirrored"] is True and a["mirrored"] is False
    for limit, rotation in b["failure_rotations"].items():
        # user's p (counter-clockwise) is the model's n: rotations change sign
        assert rotation["p"] == -a["failure_rotations"][limit]["n"]
        assert rotation["n"] == -a["failure_rotations"][limit]["p"]
        assert rotation["p"] > 0 > rotation["n"]


def test_single_block_config(tmp_path):
    config = load_bridge(yaml_file(tmp_path, "piers:\n  width: 1.0\n  heights: [8.0]\n"))
    model = config.to_bridge().model
    assert kind(model) == "single-block" and not config.mirrored
    assert model.m1 == pytest.approx(2500.0 * 1.0 * 1.0 * 8.0, rel=1e-14)


def test_frame_config(tmp_path):
    text = BRIDGE_TEXT.format(left=26.0, right=13.0).split("abutments:")[0]
    model = load_bridge(yaml_file(tmp_path, text)).to_bridge().model
    assert kind(model) == "asymmetric-frame"
    assert model.has_abutments == 0.0 and math.isinf(model.u_jo) and model.k == 0.0


def test_deck_given_by_mass_and_inertia(tmp_path):
    text = BRIDGE_TEXT.format(left=30.0, right=20.0).replace(
        "  area: 6.0", "  mass: 2.4e+6\n  inertia: 3.6e+9"
    )
    model = load_bridge(yaml_file(tmp_path, text)).to_bridge().model
    assert model.md == 2.4e6 and model.Id == 3.6e9


def test_exponent_without_sign_is_read_as_a_number(tmp_path):
    # PyYAML (YAML 1.1) reads "132.0e6" as a *string*; the shipped configs write numbers that way
    # and rely on the validation turning them into floats
    text = BRIDGE_TEXT.format(left=26.0, right=20.8).replace("1.32e+8", "132.0e6")
    model = load_bridge(yaml_file(tmp_path, text)).to_bridge().model
    assert model.k == 132.0e6 and isinstance(model.k, float)


def test_overrides(tmp_path):
    text = BRIDGE_TEXT.format(left=26.0, right=20.8) + (
        "  pounding:\n    restitution: 0.0\n    mass: 1.0e+5\ndensity: 2400.0\ngravity: 9.80665\n"
    )
    model = load_bridge(yaml_file(tmp_path, text)).to_bridge().model
    expected = make_bridge(2.6, 26.0, 20.8, 38.0, 60.0, 1.7, area=6.0, density=2400.0, g=9.80665,
                           e=0.0, m_abut=1.0e5)  # fmt: skip
    for field in expected._fields:
        assert getattr(model, field) == pytest.approx(getattr(expected, field), rel=1e-12), field


# ---------------------------------------------------------------------------------------------
# Bad configs: every file names itself, the field path (when there is one) and the reason
# ---------------------------------------------------------------------------------------------

BAD = {  # file → fragments its message must contain (besides the file's name)
    "syntax_error.yaml": ["line 5", "invalid YAML"],
    "empty.yaml": ["empty"],
    "list_not_mapping.yaml": ["mapping", "list"],
    "unknown_key_top.yaml": ["densty", "unknown key"],
    "unknown_key_nested.yaml": ["abutments.pounding.colour", "unknown key"],
    "wrong_type.yaml": ["piers.width", "number", "wide"],
    "negative_length.yaml": ["spans.central", "greater than 0", "-60"],
    "zero_width.yaml": ["piers.width", "greater than 0"],
    "restitution_above_one.yaml": [
        "abutments.pounding.restitution",
        "less than or equal to 1",
        "1.5",
    ],
    "width_not_below_height.yaml": ["piers.heights", "width", "must exceed"],
    "height_beyond_floating_point.yaml": ["piers.heights", "more than 1e+06 times the width"],
    "deck_area_and_mass.yaml": ["deck", "area", "mass"],
    "two_piers_no_deck.yaml": ["two piers", "deck"],
    "single_pier_with_abutments.yaml": ["single pier", "abutments"],
    "central_span_not_above_width.yaml": ["central span", "width"],
    "three_heights.yaml": ["piers.heights", "at most 2"],
    "missing_required.yaml": ["deck.depth", "required"],
    "bool_for_number.yaml": ["deck.depth"],
}


def bad_cases():
    return [pytest.param(name, id=name) for name in sorted(BAD)]


def test_every_bad_file_is_listed():
    assert {p.name for p in BAD_BRIDGES.glob("*.yaml")} == set(BAD)
    assert len(BAD) >= 12


@pytest.mark.parametrize("name", bad_cases())
def test_bad_config_raises_an_input_error(name):
    path = BAD_BRIDGES / name
    with pytest.raises(InputError) as info:
        load_bridge(path)
    message = str(info.value)
    assert name in message and info.value.source == str(path)
    for fragment in BAD[name]:
        assert fragment in message, (fragment, message)


def test_missing_file():
    path = BAD_BRIDGES / "no_such_bridge.yaml"
    with pytest.raises(InputError) as info:
        load_bridge(path)
    assert "no_such_bridge.yaml" in str(info.value) and "not found" in str(info.value)


def test_mirrored_bridge_against_the_mirrored_geometry(tmp_path):
    """The user's drawing (short pier on the left) solved directly on the reference kinematics:
    the user's mode p turns the left pier counter-clockwise."""
    config = load_bridge(yaml_file(tmp_path, BRIDGE_TEXT.format(left=20.8, right=26.0)))
    model = config.to_bridge().model
    summary = summarize(config.to_bridge())
    drawing = RefLinkage(model.B, model.H2, model.H1, model.L2, model.h)  # left = short pier
    masses = (model.m2, model.m1, model.md)
    inertias = (model.I2, model.I1, model.Id)
    assert summary["ug_min_p"] == pytest.approx(ref_onset(drawing, masses, model.g, 1.0), rel=1e-9)
    assert summary["ug_min_n"] == pytest.approx(
        -ref_onset(drawing, masses, model.g, -1.0), rel=1e-9
    )
    for key, s in (("eta_pn", 1.0), ("eta_np", -1.0)):
        expected = ref_restitution(drawing, masses, inertias, model.L1, s)
        assert summary[key] == pytest.approx(expected, rel=1e-10)
        expected = ref_restitution(drawing, masses, inertias, model.L1, s, seats=False)
        assert summary[key.replace("eta", "eta_frame")] == pytest.approx(expected, rel=1e-10)


def test_central_span_error_names_its_field_path():
    """A cross-field check is reported at the field it constrains, without a dump of the config."""
    with pytest.raises(InputError) as info:
        load_bridge(BAD_BRIDGES / "central_span_not_above_width.yaml")
    message = str(info.value)
    assert ": spans: the central span (2.6 m)" in message and "{" not in message


def test_the_bridge_as_analysed_carries_the_mirror_and_the_restitution(tmp_path):
    """The issue-13 trap: a bare Model does not say that the tall pier is on the right, so
    analyze refuses it; describe and the results file report the η the analysis uses."""
    text = BRIDGE_TEXT.format(left=20.8, right=26.0) + "rocking_restitution: 0.9\n"
    bridge = load_bridge(yaml_file(tmp_path, text)).to_bridge()
    assert bridge.mirrored and bridge.restitution == 0.9
    with pytest.raises(TypeError, match="mirrored"):
        analyze(bridge.model, np.zeros(10), 0.01)
    summary = summarize(bridge)
    assert summary["eta_pn"] == summary["eta_np"] == 0.9  # the override, as in bridge.laws()
    assert bridge.laws().eta_p == bridge.laws().eta_n == 0.9
    assert summary["eta_frame_pn"] != 0.9  # the law's frame value stays as computed


def test_describe_gives_what_the_ratios_divide_by(tmp_path):
    """`describe` (``rockbridge describe``): the gap, backfill capacity and half-width are the
    paper's u_jo = 0.12 m, u_ab = 0.10 m and B = 1.3 m of the studied bridge ("Failure
    Criteria"; 2B = 2.6 m); a frame has none of the first two, and no restitution is set."""
    described = describe(load_bridge(CONFIGS / "studied-hbar1.25.yaml").to_bridge())
    assert described["gap"] == pytest.approx(0.12, rel=1e-12)
    assert described["backfill_capacity"] == pytest.approx(0.10, rel=1e-12)
    assert described["half_width"] == pytest.approx(1.3, rel=1e-12)
    assert described["rocking_restitution"] is None and described["eta_pn"] > 0.0
    text = BRIDGE_TEXT.format(left=26.0, right=13.0).split("abutments:")[0]
    frame = describe(load_bridge(yaml_file(tmp_path, text)).to_bridge())
    assert frame["gap"] is None and frame["backfill_capacity"] is None

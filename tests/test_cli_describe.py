"""``rockbridge describe``: the published quantities as JSON, the table, mirroring and bad input."""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner
from conftest import (
    BAD_BRIDGES,
    CONFIGS,
    M_ABUT,
    RefLinkage,
    eq30,
    fig78_bridge,
    ref_restitution,
    studied_bridge,
)
from test_bridge_config import BAD, BRIDGE_TEXT, bad_cases
from test_impacts import eq8

REQUIRED = {
    "model", "m_pier1", "m_pier2", "m_deck", "gamma", "q", "ug_min_p_g", "ug_min_n_g",
    "eta_pn", "eta_np", "eta_frame_pn", "pounding_ratio",
}  # fmt: skip


def pounding(md):
    """Eq. (20) with e = 0.6 and m_abut = 38 000 kg (docs/model.md §2)."""
    return 1 - 1.6 * M_ABUT / (M_ABUT + md)


def frame_eta(model, s):
    """The frame's η on the independent body-by-body reference (conftest)."""
    return ref_restitution(
        RefLinkage.of(model), (model.m1, model.m2, model.md), (model.I1, model.I2, model.Id),
        model.L1, s, seats=False,
    )  # fmt: skip


# Published values (docs/model.md §10, paper's Table 1) with the absolute tolerance of their digits;
# where nothing is published, an independent computation from conftest.
PUBLISHED = {
    "studied-hbar1.00.yaml": {
        "model": "symmetric-bridge",
        "m_pier1": (43.94e4, 5e1),
        "m_pier2": (43.94e4, 5e1),
        "m_deck": (204e4, 5e3),
        "gamma": (2.321, 5e-4),
        "q": (0.7612e-6, 5e-11),
        "ug_min_p_g": (0.1000, 5e-5),
        "ug_min_n_g": (0.1000, 5e-5),
        "eta_pn": (0.9856, 5e-5),
        "eta_np": (0.9856, 5e-5),
        "eta_frame_pn": (frame_eta(studied_bridge(1.0), 1.0), 1e-10),
        "pounding_ratio": (pounding(204e4), 1e-12),
    },
    "studied-hbar1.25.yaml": {
        "model": "asymmetric-bridge",
        "m_pier1": (43.94e4, 5e1),
        "m_pier2": (35.15e4, 5e1),
        "m_deck": (204e4, 5e3),
        "gamma": (2.579, 5e-4),
        "q": (0.7708e-6, 5e-11),
        "ug_min_p_g": (0.1118, 5e-5),
        "ug_min_n_g": (0.1128, 5e-5),
        "eta_pn": (0.9822, 5e-5),
        "eta_np": (0.9811, 5e-5),
        "eta_frame_pn": (frame_eta(studied_bridge(1.25), 1.0), 1e-10),
        "pounding_ratio": (pounding(204e4), 1e-12),
    },
    "studied-hbar2.00.yaml": {
        "model": "asymmetric-bridge",
        "m_pier1": (43.94e4, 5e1),
        "m_pier2": (21.97e4, 5e1),
        "m_deck": (204e4, 5e3),
        "gamma": (3.095, 5e-4),
        "q": (0.7858e-6, 5e-11),
        "ug_min_p_g": (0.1456, 5e-5),
        "ug_min_n_g": (0.1497, 5e-5),
        "eta_pn": (0.9666, 5e-5),
        "eta_np": (0.9621, 5e-5),
        "eta_frame_pn": (frame_eta(studied_bridge(2.0), 1.0), 1e-10),
        "pounding_ratio": (pounding(204e4), 1e-12),
    },
    "fig3-hbar6.4.yaml": {
        "model": "asymmetric-bridge",
        "m_pier1": (43.94e4, 5e1),
        "m_deck": (204e4, 5e3),
        # 0.3355 g: docs/model.md's "0.336" rounds 0.335496 (see test_impacts)
        "ug_min_p_g": (0.336, 5.1e-4),
        "ug_min_n_g": (0.361, 5e-4),
        "m_pier2": (studied_bridge(6.4).m2, 1e-6),
        "gamma": (2.04e6 / (439400 + 68656.25), 1e-12),
        "q": (studied_bridge(6.4).R1 * 4 / (9.81 * (439400 + 68656.25 + 3 * 2.04e6)), 1e-18),
        "eta_pn": (eq30(studied_bridge(6.4), 1.0), 1e-12),
        "eta_np": (eq30(studied_bridge(6.4), -1.0), 1e-12),
        "eta_frame_pn": (frame_eta(studied_bridge(6.4), 1.0), 1e-10),
        "pounding_ratio": (pounding(204e4), 1e-12),
    },
    "fig8-hbar1.5.yaml": {
        # paper: m_pier,1 = 47·10⁴ kg (46.875), m_deck = 240·10⁴ kg
        "model": "asymmetric-bridge",
        "m_pier1": (47e4, 5e3),
        "m_pier2": (31.25e4, 1e-6),
        "m_deck": (240e4, 1e-6),
        "gamma": (2.4e6 / (46.875e4 + 31.25e4), 1e-12),
        "q": (fig78_bridge(1.5).R1 * 4 / (9.81 * (46.875e4 + 31.25e4 + 7.2e6)), 1e-18),
        "ug_min_p_g": (eq8(fig78_bridge(1.5), 1.0) / 9.81, 1e-12),  # Eq. (8) as printed
        "ug_min_n_g": (-eq8(fig78_bridge(1.5), -1.0) / 9.81, 1e-12),
        "eta_pn": (eq30(fig78_bridge(1.5), 1.0), 1e-12),
        "eta_np": (eq30(fig78_bridge(1.5), -1.0), 1e-12),
        "eta_frame_pn": (frame_eta(fig78_bridge(1.5), 1.0), 1e-10),
        "pounding_ratio": (pounding(240e4), 1e-12),
    },
}


@pytest.fixture(scope="module")
def cli():
    from rockbridge_cli.cli import main

    try:  # click < 8.2 mixes stderr into stdout unless told not to; 8.2 keeps them apart
        runner = CliRunner(mix_stderr=False)
    except TypeError:
        runner = CliRunner()

    def run(*args):
        return runner.invoke(main, ["describe", *map(str, args)])

    return run


def test_every_shipped_config_has_published_values():
    """Every bridge of the paper; the variants with devices (issue 41, not the paper's)
    are checked in tests/test_devices.py and tests/test_yielding_devices.py."""
    from rockbridge_cli.config.bridge import load_bridge

    paper = {p.name for p in CONFIGS.glob("*.yaml") if not load_bridge(p).devices}
    assert paper == set(PUBLISHED)


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_describe_json(cli, name):
    result = cli(CONFIGS / name, "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)  # one JSON object and nothing else
    assert isinstance(data, dict)
    assert REQUIRED <= set(data)
    expected = PUBLISHED[name]
    assert set(expected) == REQUIRED
    assert data["model"] == expected["model"]
    for key, spec in expected.items():
        if key != "model":
            value, tolerance = spec
            assert data[key] == pytest.approx(value, abs=tolerance), key


def test_describe_table(cli):
    result = cli(CONFIGS / "studied-hbar1.25.yaml")
    assert result.exit_code == 0, result.output
    assert "moderately asymmetric" in result.stdout
    assert "asymmetric-bridge" in result.stdout and "governing failure" in result.stdout
    assert "0.1118 g / 0.1128 g" in result.stdout  # docs/model.md §10
    assert "0.9822 / 0.9811" in result.stdout


def test_describe_lists_a_bridges_devices(cli):
    """Each device of the bundled tendon bridge, named as in the results (tendon1, tendon2), on
    its pier with its prestress and its axial stiffness E·A/L: 195 GPa × 5.04e-3 m² over the
    pier's height (26.0 and 20.8 m, the config's), computed here by hand; a free-standing
    bridge lists none (it used to print the same table for both)."""
    result = cli(CONFIGS / "studied-hbar1.25-tendons.yaml")
    assert result.exit_code == 0, result.output
    for name, pier, height in (("tendon1", 1, 26.0), ("tendon2", 2, 20.8)):
        (row,) = [line for line in result.stdout.splitlines() if line.startswith(name)]
        assert f"pier {pier}, offset 0 m: P0 4.687e+06 N" in row
        assert f"E·A/L {195e9 * 5.04e-3 / height:.4g} N/m" in row
    data = json.loads(cli(CONFIGS / "studied-hbar1.25-tendons.yaml", "--json").stdout)
    assert [d["prestress"] for d in data["devices"]] == [4.6872e6, 4.6872e6]
    free = cli(CONFIGS / "studied-hbar1.25.yaml").stdout
    assert "tendon" not in free and "pier 1, offset" not in free


def test_describe_mirrored(cli, tmp_path):
    left, right = tmp_path / "left.yaml", tmp_path / "right.yaml"
    left.write_text(BRIDGE_TEXT.format(left=26.0, right=20.8))
    right.write_text(BRIDGE_TEXT.format(left=20.8, right=26.0))
    a = json.loads(cli(left, "--json").stdout)
    b = json.loads(cli(right, "--json").stdout)
    for key in ("m_pier1", "m_pier2", "m_deck", "gamma", "q", "pounding_ratio", "model"):
        assert b[key] == a[key], key
    for p, n in (
        ("ug_min_p_g", "ug_min_n_g"),
        ("eta_pn", "eta_np"),
        ("eta_frame_pn", "eta_frame_np"),
    ):
        assert b[p] == a[n] and b[n] == a[p]
    assert b["mirrored"] is True and a["mirrored"] is False
    # docs/model.md §10 values with p and n swapped
    assert b["ug_min_p_g"] == pytest.approx(0.1128, abs=5e-5)
    assert b["eta_pn"] == pytest.approx(0.9811, abs=5e-5)
    assert "mirrored" in cli(right).stdout


@pytest.mark.parametrize("name", bad_cases())
def test_describe_bad_config_exits_2(cli, name):
    path = BAD_BRIDGES / name
    result = cli(path, "--json")
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    assert isinstance(result.exception, SystemExit)
    assert result.stdout == ""
    message = result.stderr
    assert message.startswith("error: ") and name in message
    for fragment in BAD[name]:
        assert fragment in message, (fragment, message)


def test_describe_missing_file_exits_2(cli):
    result = cli(BAD_BRIDGES / "no_such_bridge.yaml")
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    assert "no_such_bridge.yaml" in result.stderr and "not found" in result.stderr


def test_describe_single_block(cli, tmp_path):
    path = tmp_path / "block.yaml"
    path.write_text("piers:\n  width: 1.0\n  heights: [8.0]\n")
    result = cli(path, "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    alpha = math.atan(0.5 / 4.0)
    assert data["model"] == "single-block"
    assert data["m_pier1"] == pytest.approx(2500.0 * 1.0 * 1.0 * 8.0)  # ρ·(2B)²·2H
    # Housner (1963): onset g·tan α, η = 1 − 1.5 sin²α
    assert data["ug_min_p_g"] == pytest.approx(math.tan(alpha), rel=1e-12)
    assert data["ug_min_n_g"] == pytest.approx(math.tan(alpha), rel=1e-12)
    assert data["eta_pn"] == pytest.approx(1 - 1.5 * math.sin(alpha) ** 2, rel=1e-12)
    assert data["pounding_ratio"] == 1.0
    assert data["governing_failure"] == "overturning_pier1"


def test_describe_frame(cli, tmp_path):
    path = tmp_path / "frame.yaml"
    path.write_text(BRIDGE_TEXT.format(left=26.0, right=13.0).split("abutments:")[0])
    result = cli(path, "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["model"] == "asymmetric-frame"
    assert data["eta_pn"] == data["eta_frame_pn"] and data["pounding_ratio"] == 1.0
    assert "abutment" not in data["failure_rotations"]


def test_describe_prints_what_the_model_has(cli, tmp_path):
    """A block has no deck, pier 2, ratios or abutments; a frame has no abutments (no q, no
    pounding, no seat impulses: one η). The block's row gives Housner's R and α: a 0.4 m × 4 m
    block has R = √(0.2² + 2²) = 2.010 m and α = atan(0.1) = 0.0997 rad."""
    block = tmp_path / "block.yaml"
    block.write_text("piers:\n  width: 0.4\n  heights: [4.0]\n")
    text = cli(block).stdout
    for absent in ("m_pier2", "h_bar", "gamma", "q ", "pounding", "eta bridge", "eta frame"):
        assert absent not in text, absent
    assert "R, alpha" in text and "2.01 m, 0.0997 rad" in text and "eta p→n / n→p" in text
    frame = tmp_path / "frame.yaml"
    frame.write_text(BRIDGE_TEXT.format(left=26.0, right=13.0).split("abutments:")[0])
    text = cli(frame).stdout
    for absent in ("\nq ", "pounding", "eta bridge", "eta frame", "dcr_backfill"):
        assert absent not in text, absent
    assert "gamma = m_deck/(m1 + m2)" in text and "eta p→n / n→p" in text
    bridge = cli(CONFIGS / "studied-hbar1.25.yaml").stdout
    assert "pounding ratio" in bridge and "eta frame" in bridge and "\nq " in bridge

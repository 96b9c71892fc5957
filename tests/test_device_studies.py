"""Devices in sweeps and sampled bridges (issue 41's "Done when": each device kind runs from a
bridge config in sweeps and sampled bridges too; docs/studies.md, "Restrained piers").

Expected values: a swept or sampled variant is the bridge file with the named fields set to the
value (so its devices are those of the edited file); the units are the fields' descriptions'; a
tendon's largest force in `/devices` is P0 + k·Δ_max of its own prestress, with k = E·A/L_free
computed here from the bridge file's steel (docs/model.md §13), not from the code.
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
from studies import write_study

from rockbridge_cli.config.study import load_study
from rockbridge_cli.config.sweep import field_unit, field_value
from rockbridge_cli.errors import InputError
from rockbridge_cli.results import read_peaks
from rockbridge_cli.results.reading import device_tables
from rockbridge_cli.study.run import run_study

TENDONS = "studied-hbar1.25-tendons"
DAMPERS = "studied-hbar1.25-dampers"
P0 = 4.6872e6  # the bundled tendons' prestress [N] (studied-hbar1.25-tendons.yaml)
RIGIDITY = 195.0e9 * 5.04e-3  # E·A of the bundled tendons [N]
HEIGHTS = (26.0, 20.8)  # their free lengths, the piers' heights 2H [m]
YIELD_FORCE = 0.9 * 1860.0e6 * 5.04e-3  # their F_y, 0.9·f_pu·A, as the bridge file states [N]


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def _prestresses(bridge) -> list[float]:
    return [device.prestress for device in bridge.config.devices]


def test_a_sweep_sets_a_device_field_in_one_device_or_with_a_star_in_every_one(tmp_path):
    extra = (
        "sweep:\n  fields:\n    devices.*.prestress: [0.0, 2.5e6]\n"
        "    devices.1.prestress: [3.0e6]\n"
    )
    study = load_study(write_study(tmp_path, bridges=(TENDONS,), extra=extra))
    assert [b.id for b in study.bridges] == [
        f"{TENDONS}+devices.all.prestress_0", f"{TENDONS}+devices.all.prestress_2.5e+06",
        f"{TENDONS}+devices.1.prestress_3e+06",
    ]  # fmt: skip
    assert [_prestresses(b) for b in study.bridges] == [[0.0, 0.0], [2.5e6, 2.5e6], [P0, 3.0e6]]
    assert study.bridges[2].swept == {"devices.*.prestress": P0, "devices.1.prestress": 3.0e6}
    assert study.bridges[1].varied == ("devices.*.prestress",)
    core = study.bridges[1].config.to_bridge().devices
    assert [tendon.prestress for tendon in core] == [2.5e6, 2.5e6]
    assert field_unit("devices.*.prestress") == "N" == field_unit("devices.0.prestress")
    assert field_unit("devices.0.coefficient") == "N·s/m"  # a damper's field, found in the union
    assert field_unit("devices.0.free_length") == "m"


def test_a_star_over_items_that_differ_has_no_one_value(tmp_path):
    extra = "sweep:\n  fields:\n    devices.1.prestress: [3.0e6]\n"
    variant = load_study(write_study(tmp_path, bridges=(TENDONS,), extra=extra)).bridges[0]
    assert math.isnan(field_value(variant.config, "devices.*.prestress"))
    assert field_value(variant.config, "devices.*.area") == 5.04e-3


@pytest.mark.parametrize(
    ("bridge", "fields", "message"),
    [
        (TENDONS, "{devices.*.coefficient: [1.0e6]}", "no item of devices has coefficient"),
        ("studied-hbar1.25", "{devices.*.prestress: [1.0e6]}", "is not a field of this bridge"),
        (TENDONS, "{devices.2.prestress: [1.0e6]}", "devices.2.prestress is not a field"),
        (TENDONS, "{devices.*.kind: [1.0]}", "devices.0.kind is not a number"),
        (
            TENDONS,
            "{devices.*.prestress: [9.0e6]}",
            r"invalid bridge: devices.0.yield_force: 8.43696e\+06 N does not exceed the prestress",
        ),
    ],
)
def test_bad_device_sweeps_name_the_field(tmp_path, bridge, fields, message):
    extra = f"sweep: {{fields: {fields}}}\n"
    with pytest.raises(InputError, match=message) as error:
        load_study(write_study(tmp_path, bridges=(bridge,), extra=extra))
    assert "sweep.fields" in str(error.value)


def _sampling(field: str) -> str:
    return f"uncertainty:\n  design: lhs\n  size: 4\n  seed: 7\n  fields:\n    {field}\n"


def test_sampled_bridges_draw_device_fields(tmp_path):
    prestress = "devices.*.prestress: {distribution: uniform, low: 2.0e6, high: 6.0e6}"
    tendons = load_study(write_study(tmp_path, bridges=(TENDONS,), extra=_sampling(prestress)))
    for bridge in tendons.bridges:
        drawn = bridge.swept["devices.*.prestress"]
        assert 2.0e6 <= drawn <= 6.0e6 and _prestresses(bridge) == [drawn, drawn]
    assert len({b.swept["devices.*.prestress"] for b in tendons.bridges}) == 4
    coefficient = "devices.0.coefficient: {distribution: uniform, low: 1.0e7, high: 3.0e7}"
    dampers = load_study(write_study(tmp_path, bridges=(DAMPERS,), name="d.yaml",
                                     extra=_sampling(coefficient)))  # fmt: skip
    for bridge in dampers.bridges:
        drawn = bridge.swept["devices.0.coefficient"]
        coefficients = [device.coefficient for device in bridge.config.devices]
        assert coefficients == [drawn, 20.0e6, 20.0e6, 20.0e6]


def test_a_draw_that_makes_an_impossible_tendon_is_refused(tmp_path):
    extra = """uncertainty:
  design: lhs
  size: 4
  fields:
    devices.*.prestress: {distribution: uniform, low: 2.0e6, high: 20.0e6}
"""
    refusal = r"sample s\d: devices.\*.prestress = .*devices.0.yield_force"
    with pytest.raises(InputError, match=refusal):
        load_study(write_study(tmp_path, bridges=(TENDONS,), extra=extra))


def _tendon_forces_are_their_own_prestress_plus_k_delta(output, prestress: dict[str, float]):
    """Each tendon's largest force in ``output``'s /devices is P0 + k·Δ_max of its bridge's P0,
    or, where it yielded, its yield force F_y (to 1e-8: the yield is an event located a fraction
    of the event tolerance after it, the force just past F_y)."""
    with h5py.File(output, "r") as file:
        tables = device_tables(file)
    assert {bridge for bridge, _ in tables} == set(prestress)
    for (bridge, _), rows in tables.items():
        for row in rows:
            pier = int(row["device"].decode().removeprefix("tendon")) - 1
            stiffness = RIGIDITY / HEIGHTS[pier]
            assert row["elongation_max"] > 0.0
            if row["yielded"] == 1:
                assert row["force_max"] == pytest.approx(YIELD_FORCE, rel=1e-8)
                continue
            expected = prestress[bridge] + stiffness * row["elongation_max"]
            assert row["force_max"] == pytest.approx(expected, rel=1e-12)


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
def test_a_swept_and_a_sampled_tendon_study_run_with_their_own_prestress(tmp_path):
    sweep = "sweep:\n  fields:\n    devices.*.prestress: [0.0, 7.5e6]\n"
    common = "fidelity: fast\noutput: {histories: none}\n"
    study = load_study(write_study(tmp_path, bridges=(TENDONS,), records=("R1",),
                                   extra=sweep + common))  # fmt: skip
    output = run_study(study, workers=1).output
    peaks = read_peaks(output)
    assert peaks.attrs["units"]["devices.*.prestress"] == "N"
    assert sorted(peaks["devices.*.prestress"]) == [0.0, 7.5e6]
    _tendon_forces_are_their_own_prestress_plus_k_delta(
        output, {b.id: b.swept["devices.*.prestress"] for b in study.bridges}
    )
    sampled = """uncertainty:
  design: lhs
  size: 2
  fields:
    devices.*.prestress: {distribution: uniform, low: 2.0e6, high: 6.0e6}
"""
    study = load_study(write_study(tmp_path, bridges=(TENDONS,), records=("R1",),
                                   name="sampled.yaml", extra=sampled + common))  # fmt: skip
    output = run_study(study, workers=1).output
    drawn = {b.id: b.swept["devices.*.prestress"] for b in study.bridges}
    assert np.array_equal(read_peaks(output)["devices.*.prestress"], list(drawn.values()))
    _tendon_forces_are_their_own_prestress_plus_k_delta(output, drawn)

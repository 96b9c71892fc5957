"""Each device's force, elongation and plastic elongation in the histories (issue 41;
docs/results.md, "Histories"): checked against the θ1 history through the exact linkage
(`elongation`), the devices' laws written out here, and the results file's names and units."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner
from conftest import G, studied_bridge

from rockbridge_cli.cli import main
from rockbridge_cli.config.bridge import load_bridge
from rockbridge_cli.config.study_models import Output
from rockbridge_cli.core.analysis import _before_flight, analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.device_mechanics import elongation
from rockbridge_cli.core.devices import Damper, Dissipator, Tendon, table
from rockbridge_cli.core.quantities import HISTORY_UNITS, history_unit, kept_history
from rockbridge_cli.core.solver import NO_ERROR, NOT_FAILED, Integration
from rockbridge_cli.plots import history as history_plot
from rockbridge_cli.records.files import read_record
from rockbridge_cli.results.layout import FORMAT, FORMAT_VERSION
from rockbridge_cli.results.packing import AnalysisResult
from rockbridge_cli.results.reading import read_history
from rockbridge_cli.results.writing import ResultsWriter

REPO = Path(__file__).resolve().parents[1]
DT = 0.01
P0, K = 2.0e6, 3.0e8  # the tendon's prestress [N] and stiffness [N/m]
K1, FY, K2 = 5.0e8, 2.0e5, 5.0e7  # the dissipator's k1 [N/m], F_y [N], k2 [N/m]
C = 2.0e6  # the damper's coefficient [N·s/m]
DEVICES = (Tendon(0, 0.3, P0, K), Dissipator(1, -0.5, K1, FY, K2), Damper(0, -0.6, C))


@pytest.fixture(scope="module")
def restrained():
    """A studied frame (h̄ = 1.25) without abutments, so that nothing pounds, with an elastic
    tendon, a dissipator that yields and a damper, under a 0.45 g, 1.2 s sine for 4 s, at the
    reference preset (exact kinematics)."""
    model = studied_bridge(1.25, abutments=False)
    t = np.arange(0.0, 8.0, DT)
    acc = 0.45 * G * np.sin(2 * np.pi * t / 1.2) * (t < 4.0)
    response = analyze(Bridge(model, devices=DEVICES), acc, DT, "reference")
    assert response.status == "ok" and response.failure_mode == "none"
    assert "pounding" not in list(response.events["kind"])
    assert response.peaks["dissipator1_yielded"][0] == 1.0  # so its plastic branch is checked
    return model, response, acc


def _exact(model, response):
    """Each device's Δ [m] and Δ̇ [m/s] at the samples from the θ1, θ̇1 and mode histories and
    the exact linkage (`elongation`: Δ and ∂Δ/∂φ); 0 at rest."""
    h = response.histories
    rows = table(DEVICES)
    theta, rate, mode = h["theta1"], h["theta1_rate"], h["mode"]
    length, speed = np.zeros((theta.size, len(DEVICES))), np.zeros((theta.size, len(DEVICES)))
    for j in np.flatnonzero(mode):
        for i, row in enumerate(rows):
            delta, lever = elongation(model, row, float(mode[j]), float(theta[j]))
            length[j, i], speed[j, i] = delta, lever * rate[j]
    return length, speed


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_the_device_histories_are_their_laws_at_the_elongations_of_the_theta1_history(restrained):
    """The elastic tendon's force is P0 + k·Δ, the damper's c·Δ̇ (Δ̇ = ∂Δ/∂φ·θ̇1), Δ from θ1 by
    the exact linkage, to 1e-12 (relative to P0, to c times the largest Δ̇); the dissipator's
    force stays within its bilinear bounds k2·Δ ± (1 − k2/k1)·F_y and is k1·(Δ − Δp) wherever
    that lies inside them (its elastic stretches); a tendon and a damper have no Δp to speak of
    (the tendon's stays 0, the damper has no ``_plastic``)."""
    model, response, _ = restrained
    h = response.histories
    length, speed = _exact(model, response)
    for i, name in enumerate(("tendon1", "dissipator1", "damper1")):
        np.testing.assert_allclose(h[f"{name}_elongation"], length[:, i], rtol=0, atol=1e-12)
    np.testing.assert_allclose(h["tendon1_force"], P0 + K * length[:, 0], rtol=0, atol=1e-12 * P0)
    assert not h["tendon1_plastic"].any()
    scale = C * np.abs(speed[:, 2]).max()
    np.testing.assert_allclose(h["damper1_force"], C * speed[:, 2], rtol=0, atol=1e-12 * scale)
    assert "damper1_plastic" not in h
    force, delta, plastic = h["dissipator1_force"], length[:, 1], h["dissipator1_plastic"]
    upper, lower = (K2 * delta + side * (1 - K2 / K1) * FY for side in (1.0, -1.0))
    assert np.all(force <= upper + 1e-9 * FY) and np.all(force >= lower - 1e-9 * FY)
    elastic = K1 * (delta - plastic)
    inside = (elastic < upper - 1e-6 * FY) & (elastic > lower + 1e-6 * FY)
    assert inside.sum() > 10 and (~inside).sum() > 10  # elastic stretches and yielding ones
    np.testing.assert_allclose(force[inside], elastic[inside], rtol=0, atol=1e-9 * FY)
    assert plastic.max() > 0.0  # it yielded: a plastic elongation is carried


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_a_results_file_holds_the_device_histories_of_a_bridge_with_devices_only(
    restrained, tmp_path
):
    """`output.histories: all` keeps each device's histories, with units N, m, m; a
    free-standing bridge's analysis has none (its file is as before devices existed); a list may
    name one device history."""
    model, response, _ = restrained
    free = analyze(Bridge(model), np.zeros(300), DT, "fast")
    assert list(free.histories) == list(HISTORY_UNITS)
    everything = Output().kept()
    results = [
        AnalysisResult.from_response("tied", "R1", response, everything, 1.0, DEVICES),
        AnalysisResult.from_response("free", "R1", free, everything, 1.0),
    ]
    path = tmp_path / "out.h5"
    with h5py.File(path, "w") as file:
        file.create_group("bridges")
        file.attrs.update(format=FORMAT, format_version=FORMAT_VERSION)
        writer = ResultsWriter(file, len(results))
        writer.add(result.pack() for result in results)
        writer.close("now")
    tied = read_history(path, "tied", "R1")
    names = [f"{d}_{q}" for d in ("tendon1", "dissipator1") for q in ("force", "elongation",
             "plastic")] + ["damper1_force", "damper1_elongation"]  # fmt: skip
    assert set(tied.columns) == set(HISTORY_UNITS) | set(names)
    units = {"force": "N", "elongation": "m", "plastic": "m"}
    for name in names:
        assert tied.attrs["units"][name] == units[name.rsplit("_", 1)[1]]
        np.testing.assert_array_equal(tied[name].to_numpy(), response.histories[name])
    with h5py.File(path) as file:
        assert file["analyses/tied/R1/histories/tendon1_force"].attrs["units"] == "N"
    assert list(read_history(path, "free", "R1").columns) == list(HISTORY_UNITS)
    listed = Output(histories=["theta1", "tendon1_force"]).kept()
    assert listed == ("theta1", "tendon1_force")
    kept = AnalysisResult.from_response("tied", "R1", response, listed, 1.0, DEVICES).histories
    assert list(kept) == ["theta1", "tendon1_force"]


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_a_devices_histories_are_the_same_in_a_mirror_image(restrained):
    """The mirror image (tall pier on the right) under the opposite motion runs the same core
    analysis: θ1 changes sign in the user's frame, a force or an elongation does not."""
    model, response, acc = restrained
    mirror = analyze(Bridge(model, mirrored=True, devices=DEVICES), -acc, DT, "reference")
    np.testing.assert_array_equal(mirror.histories["theta1"], -response.histories["theta1"])
    for name, values in response.histories.items():
        if name.startswith(("tendon", "dissipator", "damper")):
            np.testing.assert_array_equal(mirror.histories[name], values)


def test_device_history_names_have_units_and_are_checked_as_a_study_lists_them():
    """Units: a force in N, an elongation and a plastic elongation in m; a damper has no plastic
    elongation; `all` keeps every device's history, a list only those it names."""
    assert [history_unit(n) for n in ("tendon2_force", "dissipator1_plastic", "damper3_elongation")
            ] == ["N", "m", "m"]  # fmt: skip
    assert history_unit("u_deck") == "m"
    for wrong in ("damper1_plastic", "tendon0_force", "tendon1_strain", "spring1_force"):
        with pytest.raises(KeyError):
            history_unit(wrong)
        with pytest.raises(ValueError, match="unknown histories"):
            Output(histories=["theta1", wrong])
    assert kept_history("tendon1_force", Output().kept())
    assert not kept_history("tendon1_force", Output(histories=["theta1"]).kept())
    assert not kept_history("tendon1_force", Output(histories="none").kept())


def test_the_device_histories_of_an_analysis_stopped_before_a_free_flight_run_to_the_records_end():
    """An integration of 5 samples of a record of 11 (0.01 s, sampled every 0.01 s: 11 samples)
    stopped before a free flight: its device histories have the record's 11 samples, its own 5
    then NaN, as θ1 (docs/model.md §12)."""
    forces = np.arange(5 * 2 * 3, dtype=float).reshape(5, 2, 3)
    stopped = Integration(
        np.zeros(5), np.zeros(5), np.ones(5), np.zeros((0, 5)), np.zeros((7, 2)), 0.04,
        NOT_FAILED, 4, 0, NO_ERROR, np.zeros((2, 4)), None, forces,
    )  # fmt: skip
    stretched = _before_flight(stopped, 5, 11, 0.01, 0.01)
    assert stretched.device_histories.shape == (11, 2, 3)
    np.testing.assert_array_equal(stretched.device_histories[:5], forces)
    assert np.isnan(stretched.device_histories[5:]).all() and np.isnan(stretched.theta1[5:]).all()


@pytest.mark.slow  # compiles the kernels of a bridge with devices (about 1–3 min cold)
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_the_bundled_dissipators_stay_within_their_bilinear_bounds_under_ar07():
    """The bundled dissipator bridge under AR07 at ``fast`` (it pounds): every dissipator's force
    history within k2·Δ ± (1 − k2/k1)·F_y of its elongation history (the bilinear law's bounds,
    written out here), to 1e-9 F_y. Before issue 41's fix dissipator2 crossed its yield line
    unseen at 9.02 s, after an impact, and reached 4.96 MN (a 0.44 MN bound) at 14.78 s."""
    bridge = load_bridge(REPO / "configs/bridges/studied-hbar1.25-dissipators.yaml").to_bridge()
    motion = read_record(REPO / "records/ec8-type1-C-ag0.6g/AR07.txt")
    response = analyze(bridge, motion.acceleration, motion.time_step, "fast")
    assert "pounding" in list(response.events["kind"])
    for i, device in enumerate(bridge.devices, 1):
        force = response.histories[f"dissipator{i}_force"]
        delta = response.histories[f"dissipator{i}_elongation"]
        k1, fy, k2 = device.stiffness, device.yield_force, device.hardening
        reach = (1 - k2 / k1) * fy + 1e-9 * fy
        assert np.all(np.abs(force - k2 * delta) <= reach), f"dissipator{i}"


@pytest.mark.slow  # an analysis of a bridge with devices, written and drawn
@pytest.mark.usefixtures("device_kernels")  # compiled once a suite (conftest)
def test_plot_history_draws_each_devices_force_in_a_last_panel(tmp_path, monkeypatch):
    """`rockbridge analyze -o` of the bundled dissipator bridge, then `plot history`: the figure
    has Fig. 10's six panels and a seventh with the four dissipators' forces, in MN, each line
    the force history the file holds (×1e-6); a free-standing bridge's figure has none."""
    drawn = []
    monkeypatch.setattr(history_plot, "save", lambda figure, output: drawn.append(figure) or output)
    record = REPO / "records/ec8-type1-C-ag0.6g/AR07.txt"
    for bridge, forces in (("studied-hbar1.25-dissipators", 4), ("studied-hbar1.25", 0)):
        path = tmp_path / f"{bridge}.h5"
        args = ["analyze", str(REPO / f"configs/bridges/{bridge}.yaml"), str(record),
                "--fidelity", "fast", "-o", str(path)]  # fmt: skip
        assert CliRunner().invoke(main, args).exit_code == 0
        history_plot.plot_history(path, "AR07", tmp_path / "h.png")
        axes = drawn[-1].axes
        assert len(axes) == 6 + bool(forces)
        if forces:
            stored = read_history(path, bridge, "AR07")
            assert axes[-1].get_ylabel() == "device force [MN]"
            lines = axes[-1].get_lines()
            assert [line.get_label() for line in lines] == [f"dissipator{i}" for i in range(1, 5)]
            colours = {tuple(np.atleast_1d(line.get_color())) for line in lines}
            assert len(colours) == 4  # one shade each, beside the line styles
            for i, line in enumerate(lines, 1):
                np.testing.assert_array_equal(
                    line.get_ydata(), stored[f"dissipator{i}_force"] * 1e-6
                )

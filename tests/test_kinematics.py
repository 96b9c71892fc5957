"""Kinematics of the linkage: positions against the paper's Eqs. (1)–(6) and an independent
rigid-body formulation, every derivative against finite differences (docs/model.md §3)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import BRIDGES, RefLinkage, make_bridge, python, studied_bridge

from rockbridge_cli.core import kinematics
from rockbridge_cli.core.kinematics import (
    EXACT,
    centres,
    displacements,
    linkage,
    simplified,
    simplified_fits,
)

MODES = (1.0, -1.0)
FRACTIONS = (0.0, 0.02, 0.3, 0.6, 0.9)  # s·θ1 as a fraction of α1 (overturning of the tall pier)


def states(model, modes=MODES):
    """(s, θ1) over the range of rocking in the given modes."""
    return [(s, s * f * model.alpha1) for s in modes for f in FRACTIONS]


def d1_fd(f, x, step):
    """Five-point central first derivative (error O(step⁴))."""
    return (f(x - 2 * step) - 8 * f(x - step) + 8 * f(x + step) - f(x + 2 * step)) / (12 * step)


def d2_fd(f, x, step):
    """Five-point central second derivative (error O(step⁴))."""
    return (
        -f(x - 2 * step) + 16 * f(x - step) - 30 * f(x) + 16 * f(x + step) - f(x + 2 * step)
    ) / (12 * step * step)


def paper_eqs_2_to_6(model, s, theta1):
    """The paper's Eqs. (1)–(6) as printed: φ_CD, θ_deck and the displacements of the CGs."""
    B, H1, H2, L2, h = model.B, model.H1, model.H2, model.L2, model.h
    R1, R2 = math.hypot(H1, B), math.hypot(H2, B)
    phi = math.pi / 2 - s * math.atan(B / H1) + theta1  # Eq. (1), φ1^{p/n} = π/2 ∓ α1
    r_ac = math.hypot(2 * H1 - 2 * H2, L2) / 2
    phi_ac = math.atan((2 * H1 - 2 * H2) / L2)
    bc = math.sqrt((2 * R1) ** 2 + (2 * r_ac) ** 2 - 8 * R1 * r_ac * math.cos(phi - phi_ac))
    phi_cd = (
        math.pi
        + math.atan(
            (R1 * math.sin(phi) - r_ac * math.sin(phi_ac))
            / (R1 * math.cos(phi) - r_ac * math.cos(phi_ac))
        )
        - math.acos((bc**2 + 4 * R2**2 - L2**2) / (4 * R2 * bc))
    )  # Eq. (2)
    theta_deck = math.atan(
        (-R1 * math.sin(phi) + r_ac * math.sin(phi_ac) + R2 * math.sin(phi_cd))
        / (-R1 * math.cos(phi) + r_ac * math.cos(phi_ac) + R2 * math.cos(phi_cd))
    )  # Eq. (3)
    r_bd = math.sqrt(h**2 + (L2 / 2 - s * B) ** 2)
    psi_bd = math.atan(h / (L2 / 2 - s * B))
    return {
        "phi": phi,
        "phi_cd": phi_cd,
        "theta2": phi_cd - (math.pi / 2 - s * math.atan(B / H2)),
        "theta_deck": theta_deck,
        "u1": R1 * math.cos(phi) - s * B,  # Eq. (4), "∓B": −B for p
        "v1": R1 * math.sin(phi) - H1,
        "u2": R2 * math.cos(phi_cd) - s * B,  # Eq. (5)
        "v2": R2 * math.sin(phi_cd) - H2,
        "ud": 2 * R1 * math.cos(phi) + r_bd * math.cos(theta_deck + psi_bd) - s * B - L2 / 2,
        "vd": 2 * R1 * math.sin(phi) + r_bd * math.sin(theta_deck + psi_bd) - 2 * H1 - h,  # Eq. (6)
    }


@pytest.mark.parametrize("s", MODES)
def test_loop_closure(any_bridge, s):
    m = any_bridge
    R1, R2 = math.hypot(m.H1, m.B), math.hypot(m.H2, m.B)
    for _, theta1 in states(m, (s,)):
        phi, psi, theta, *_ = linkage(m, s, theta1, EXACT)
        # docs/model.md §3: 2R1·e(φ) + L2·e(θ) − 2R2·e(ψ) = C − A = (L2, 2H1 − 2H2)
        gap_x = 2 * R1 * math.cos(phi) + m.L2 * math.cos(theta) - 2 * R2 * math.cos(psi) - m.L2
        gap_z = (
            2 * R1 * math.sin(phi) + m.L2 * math.sin(theta) - 2 * R2 * math.sin(psi)
            - 2 * (m.H1 - m.H2)
        )  # fmt: skip
        assert abs(gap_x) < 1e-12 * m.L2 and abs(gap_z) < 1e-12 * m.L2


@pytest.mark.parametrize("s", MODES)
def test_paper_eqs_2_to_6_as_printed(any_bridge, s):
    m = any_bridge
    for _, theta1 in states(m, (s,)):
        ref = paper_eqs_2_to_6(m, s, theta1)
        phi, psi, theta, *_ = linkage(m, s, theta1, EXACT)
        u1, v1, u2, v2, ud, vd, theta2, theta_deck = displacements(m, s, theta1, EXACT)
        assert phi == pytest.approx(ref["phi"], abs=1e-13)
        assert psi == pytest.approx(ref["phi_cd"], abs=1e-12)
        assert theta == pytest.approx(ref["theta_deck"], abs=1e-12)
        assert theta2 == pytest.approx(ref["theta2"], abs=1e-12)
        assert theta_deck == pytest.approx(ref["theta_deck"], abs=1e-12)
        keys = ("u1", "v1", "u2", "v2", "ud", "vd")
        for got, key in zip((u1, v1, u2, v2, ud, vd), keys, strict=True):
            assert got == pytest.approx(ref[key], abs=1e-11), key


@pytest.mark.parametrize("s", MODES)
def test_positions_against_rigid_body_reference(any_bridge, s):
    m = any_bridge
    link = RefLinkage.of(m)
    for _, theta1 in states(m, (s,)):
        pos, _, _, ang = centres(m, s, theta1, EXACT)
        ref = link.solve(s, theta1)
        for got, key in zip(pos, ("xl", "zl", "xr", "zr", "xd", "zd"), strict=True):
            assert got == pytest.approx(ref[key], abs=1e-11), key
        assert ang[5] == pytest.approx(ref["theta_deck"], abs=1e-12)
        theta2 = displacements(m, s, theta1, EXACT)[6]
        assert theta2 == pytest.approx(ref["theta_right"], abs=1e-12)


def test_at_rest_the_bridge_is_where_the_model_puts_it(any_bridge):
    m = any_bridge
    for s in MODES:
        # docs/model.md §1: CGs at rest (0, H1), (L2, 2H1 − H2), (L2/2, 2H1 + h); zero displacements
        pos = centres(m, s, 0.0, EXACT)[0]
        expected = (0.0, m.H1, m.L2, 2 * m.H1 - m.H2, m.L2 / 2, 2 * m.H1 + m.h)
        assert np.allclose(pos, expected, rtol=0, atol=1e-12)
        assert np.allclose(displacements(m, s, 0.0, EXACT), 0.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("s", MODES)
def test_first_derivatives_against_finite_differences(any_bridge, s):
    m = any_bridge
    link = RefLinkage.of(m)
    step = 1e-4 * m.alpha1
    for _, theta1 in states(m, (s,)):
        _, d1, _, ang = centres(m, s, theta1, EXACT)
        for i in range(6):
            fd = d1_fd(lambda t, i=i: centres(m, s, t, EXACT)[0][i], theta1, step)
            assert d1[i] == pytest.approx(fd, abs=1e-8 * m.R1), i
        # ψ' and θ' against FD of the angles, from the code and from the reference
        fd_psi = d1_fd(lambda t: linkage(m, s, t, EXACT)[1], theta1, step)
        fd_theta = d1_fd(lambda t: linkage(m, s, t, EXACT)[2], theta1, step)
        ref_psi = d1_fd(lambda t: link.solve(s, t)["theta_right"], theta1, step)
        ref_theta = d1_fd(lambda t: link.solve(s, t)["theta_deck"], theta1, step)
        assert ang[0] == pytest.approx(fd_psi, abs=1e-8)
        assert ang[0] == pytest.approx(ref_psi, abs=1e-8)
        assert ang[1] == pytest.approx(fd_theta, abs=1e-9)
        assert ang[1] == pytest.approx(ref_theta, abs=1e-9)
        # the CG velocities against the independent reference
        names = ("xl", "zl", "xr", "zr", "xd", "zd")
        for i, key in enumerate(names):
            fd = d1_fd(lambda t, key=key: link.solve(s, t)[key], theta1, step)
            assert d1[i] == pytest.approx(fd, abs=1e-8 * m.R1), key


@pytest.mark.parametrize("s", MODES)
def test_second_derivatives_against_finite_differences(any_bridge, s):
    m = any_bridge
    step = 1e-3  # rad: round-off ~ε·ψ/step² ≈ 1e-10, truncation ~step⁴
    for _, theta1 in states(m, (s,)):
        _, _, d2, ang = centres(m, s, theta1, EXACT)
        for i in range(6):
            fd = d2_fd(lambda t, i=i: centres(m, s, t, EXACT)[0][i], theta1, step)
            assert d2[i] == pytest.approx(fd, abs=1e-6 * m.R1), i
        fd_psi = d2_fd(lambda t: linkage(m, s, t, EXACT)[1], theta1, step)
        fd_theta = d2_fd(lambda t: linkage(m, s, t, EXACT)[2], theta1, step)
        assert ang[2] == pytest.approx(fd_psi, abs=1e-6 * (1 + abs(fd_psi)))
        assert ang[3] == pytest.approx(fd_theta, abs=1e-6 * (1 + abs(fd_theta)))
        # and against FD of the analytic first derivatives
        fd_psi1 = d1_fd(lambda t: linkage(m, s, t, EXACT)[3], theta1, 1e-4 * m.alpha1)
        fd_theta1 = d1_fd(lambda t: linkage(m, s, t, EXACT)[4], theta1, 1e-4 * m.alpha1)
        assert ang[2] == pytest.approx(fd_psi1, abs=1e-8 * (1 + abs(fd_psi1)))
        assert ang[3] == pytest.approx(fd_theta1, abs=1e-8 * (1 + abs(fd_theta1)))


def test_at_rest_values(any_bridge):
    m = any_bridge
    h_bar, b_bar = m.H1 / m.H2, m.B / m.L2
    for s in MODES:
        _, _, _, dpsi, dtheta, _, _ = linkage(m, s, 0.0, EXACT)
        # docs/model.md §3: ψ' = h̄ and θ' = ±2b̄(h̄ − 1); the sign is + in mode p, − in mode n
        # (first order: the deck pivots move alike horizontally, so 2H1 = 2H2·ψ'; vertically the
        # short pier's top rises 2sB·h̄ against 2sB, so the deck turns by 2sB(h̄ − 1)/L2)
        assert dpsi == pytest.approx(h_bar, rel=1e-12)
        assert dtheta == pytest.approx(s * 2 * b_bar * (h_bar - 1), abs=1e-12 * max(1.0, h_bar))


def test_deck_turns_with_the_mode():
    # mode p: counter-clockwise pier rotation (θ1 > 0), deck to the left (docs/model.md §1). The
    # short pier turns more (ψ' ≈ h̄) and its top rises more than the tall pier's in either mode,
    # so the deck turns counter-clockwise in both modes: θ_deck ≈ θ'·θ1 with θ' = s·2b̄(h̄ − 1).
    m = studied_bridge(2.0)
    t = 0.5 * m.alpha1
    u = displacements(m, 1.0, t, EXACT)
    assert t > 0 and u[4] < 0 and u[7] > 0 and u[6] > t
    u = displacements(m, -1.0, -t, EXACT)
    assert u[4] > 0 and u[7] > 0 and u[6] < -t


@pytest.mark.parametrize("s", MODES)
def test_symmetric_bridge_deck_does_not_turn(s):
    # h̄ = 1: the linkage is a parallelogram, θ_deck ≡ 0, ψ = φ, ψ' = 1 (docs/model.md §8 limit)
    for m in (studied_bridge(1.0), make_bridge(2.0, 12.0, 12.0, 5.0, 20.0, 1.0, area=3.0)):
        for f in np.linspace(0.0, 0.95, 20):
            theta1 = s * f * m.alpha1
            phi, psi, theta, dpsi, dtheta, d2psi, d2theta = linkage(m, s, theta1, EXACT)
            assert abs(theta) < 1e-12 and abs(dtheta) < 1e-12 and abs(d2theta) < 1e-12
            assert abs(psi - phi) < 1e-12 and abs(dpsi - 1) < 1e-12 and abs(d2psi) < 1e-12
            assert abs(displacements(m, s, theta1, EXACT)[7]) < 1e-12


def test_deck_rotation_grows_like_2b_hbar_minus_1(any_bridge):
    # docs/model.md §8: θ_deck ≈ 2b̄(h̄ − 1)·θ1 for small rotations (≈ 10⁻⁴ rad for the studied
    # bridges) — in mode p. In mode n (θ1 < 0) θ' = −2b̄(h̄ − 1), so θ_deck ≈ 2b̄(h̄ − 1)·|θ1|: the deck
    # always turns counter-clockwise (the short pier's end rises more), never with the sign of θ1.
    m = any_bridge
    theta1 = 1e-4
    expected = 2 * m.B / m.L2 * (m.H1 / m.H2 - 1) * theta1
    assert displacements(m, 1.0, theta1, EXACT)[7] == pytest.approx(expected, abs=1e-3 * theta1)
    assert displacements(m, -1.0, -theta1, EXACT)[7] == pytest.approx(expected, abs=1e-3 * theta1)


def test_compiled_and_python_agree():
    m = studied_bridge(2.0)
    for s in MODES:
        for theta1 in (0.0, s * 0.03, s * 0.08):
            a = linkage(m, s, theta1, EXACT)
            b = python(linkage)(m, s, theta1, EXACT)
            assert np.allclose(a, b, rtol=1e-13, atol=1e-15)
            a = displacements(m, s, theta1, EXACT)
            b = python(displacements)(m, s, theta1, EXACT)
            assert np.allclose(a, b, rtol=1e-13, atol=1e-15)
            ca, cb = centres(m, s, theta1, EXACT), python(centres)(m, s, theta1, EXACT)
            for part_a, part_b in zip(ca, cb, strict=True):
                assert np.allclose(part_a, part_b, rtol=1e-13, atol=1e-15)


def test_exact_selector_has_neither_fits_nor_tables():
    assert kinematics.EXACT.fits.shape[0] == 0 and kinematics.EXACT.table.shape[0] == 0


# Measured worst errors of the fitted ψ' (relative) and θ' (relative to 2b̄(h̄ − 1)) over
# 0 ≤ s·θ1 ≤ α1: h̄ = 1.25: 3e-6 / 4e-4; h̄ = 2: 4e-5 / 1e-3; h̄ = 6.4: 4e-3 / 1.0e-2;
# stocky: 6e-3 / 2.3e-2. The bounds below are those, rounded up.
FIT_BOUNDS = {"hbar1.25": 1e-3, "hbar2": 2e-3, "hbar6.4": 1.5e-2, "fig78": 1e-3, "slender": 1e-3,
              "stocky": 3e-2}  # fmt: skip


@pytest.mark.parametrize("name", sorted(FIT_BOUNDS))
def test_simplified_fits_error_is_small_and_measured(name):
    # the paper's simplified procedure: fitted ψ', θ' (docs/model.md §3); positions stay exact
    m = dict(BRIDGES)[name]
    fits = simplified_fits(m)
    assert fits.shape == (2, 2, 3) and np.all(np.isfinite(fits))
    scale = 2 * m.B / m.L2 * (m.H1 / m.H2 - 1)
    worst = 0.0
    for s in MODES:
        for f in np.linspace(0.0, 1.0, 41):
            theta1 = s * f * m.alpha1
            exact = linkage(m, s, theta1, EXACT)
            fitted = linkage(m, s, theta1, simplified(m))
            assert np.allclose(exact[:3], fitted[:3], rtol=0, atol=1e-15)
            worst = max(
                worst, abs(fitted[3] - exact[3]) / exact[3], abs(fitted[4] - exact[4]) / scale
            )
            # the second derivatives are the fits' derivatives
            f_ = fits[0 if s > 0 else 1]
            assert fitted[5] == pytest.approx(f_[0, 1] + 2 * theta1 * f_[0, 2], rel=1e-14)
            assert fitted[6] == pytest.approx(f_[1, 1] + 2 * theta1 * f_[1, 2], rel=1e-14)
    assert worst < FIT_BOUNDS[name]


def test_simplified_fits_are_exact_for_a_symmetric_bridge():
    m = studied_bridge(1.0)
    fits = simplified_fits(m)
    # parallelogram: ψ' ≡ 1, θ' ≡ 0
    assert np.allclose(fits[:, 0], [1.0, 0.0, 0.0], atol=1e-12)
    assert np.allclose(fits[:, 1], 0.0, atol=1e-12)

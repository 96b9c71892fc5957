"""Equation of motion: the code's Lagrangian form against the paper's corrected Eq. (18), against
Lagrange's equations built by finite differences of T and V on an independent kinematics, and the
energy balance (docs/model.md §4, §6)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import BRIDGES, RefLinkage, python, studied_bridge, with_

from rockbridge_cli.core.dynamics import acceleration, coefficients, energy
from rockbridge_cli.core.kinematics import EXACT, centres, linkage

MODES = (1.0, -1.0)


def d1_fd(f, x, step):
    """Five-point central first derivative."""
    return (f(x - 2 * step) - 8 * f(x - step) + 8 * f(x + step) - f(x + 2 * step)) / (12 * step)


def random_states(model, s, count, rng, low=0.0, high=0.9):
    """(θ1, θ̇1, ü_g) with s·θ1 in [low, high]·α1, |θ̇1| up to 3√(g/R1), |ü_g| up to g."""
    p = math.sqrt(model.g / model.R1)
    return [
        (
            s * rng.uniform(low, high) * model.alpha1,
            rng.uniform(-3, 3) * p,
            rng.uniform(-1, 1) * model.g,
        )
        for _ in range(count)
    ]


# ---------------------------------------------------------------------------------------------
# The paper's Eq. (18), written out from the text with the two fixes of docs/model.md §4
# ---------------------------------------------------------------------------------------------


def eq18_terms(model, s, theta1):
    """T_f1, T_f2, V_inf, Q_inf, S, and the deck displacement, as printed after Eq. (18).

    I_pier,i^Pivot = 4m_i·R_i²/3 and I_deck^Pivot = I_deck^CG + m_deck·r_BD² (the square missing
    from the printed text, docs/model.md §4). ψ', θ', ψ'', θ'' are the linkage's (tested
    separately).
    """
    B, H1, H2, L2, h = model.B, model.H1, model.H2, model.L2, model.h
    m1, m2, md, Id = model.m1, model.m2, model.md, model.Id
    phi, psi, th, dpsi, dth, d2psi, d2th = linkage(model, s, theta1, EXACT)
    R1, R2 = math.hypot(H1, B), math.hypot(H2, B)
    r_bd = math.sqrt(h**2 + (L2 / 2 - s * B) ** 2)
    psi_bd = math.atan(h / (L2 / 2 - s * B))
    rbar, Rbar = r_bd / (2 * R1), R2 / R1
    I1p, I2p, Idp = 4 * m1 * R1**2 / 3, 4 * m2 * R2**2 / 3, Id + md * r_bd**2
    tf1 = (
        I1p / R1**2
        + I2p / R1**2 * dpsi**2
        + md * (4 + 8 * rbar * math.cos(phi - th - psi_bd) * dth)
        + Idp / R1**2 * dth**2
    )
    tf2 = (
        I2p / R1**2 * dpsi * d2psi
        + 4 * md * rbar
        * (math.cos(phi - th - psi_bd) * d2th - math.sin(phi - th - psi_bd) * dth * (1 - dth))
        + Idp / R1**2 * dth * d2th
    )  # fmt: skip
    v_inf = (
        (m1 + 2 * md) * math.cos(phi)
        + m2 * Rbar * math.cos(psi) * dpsi
        + 2 * md * rbar * math.cos(th + psi_bd) * dth
    )
    q_inf = (
        (m1 + 2 * md) * math.sin(phi)
        + m2 * Rbar * math.sin(psi) * dpsi
        + 2 * md * rbar * math.sin(th + psi_bd) * dth
    )
    S = math.sin(phi) + rbar * math.sin(th + psi_bd) * dth
    u_deck = 2 * R1 * math.cos(phi) + r_bd * math.cos(th + psi_bd) - s * B - L2 / 2  # Eq. (6)
    return {
        "R1": R1, "tf1": tf1, "tf2": tf2, "v_inf": v_inf, "q_inf": q_inf, "S": S,
        "phi": phi, "th": th, "rbar": rbar, "psi_bd": psi_bd, "u_deck": u_deck,
    }  # fmt: skip


def eq18(model, s, theta1, omega, ground, contact, printed_sign=False):
    """φ̈ from Eq. (18): +(R1/g)(T_f2/T_f1)φ̇² inside the bracket (printed: −), Q_adf with S²."""
    t = eq18_terms(model, s, theta1)
    g, R1 = model.g, t["R1"]
    sign = -1.0 if printed_sign else 1.0
    frame = -(g / R1) * (
        sign * (R1 / g) * t["tf2"] / t["tf1"] * omega**2
        + t["v_inf"] / t["tf1"]
        - ground / g * t["q_inf"] / t["tf1"]
    )
    if not contact:
        return frame
    total = model.m1 + model.m2 + 3 * model.md
    q = 4 * R1 / (g * total)  # docs/model.md §2, with the parentheses
    # V_asf: "±B/(2R1)" and "∓u_jo/(2R1)" take the upper signs in mode p (deck on the left)
    v_asf = (
        total
        * (
            -math.cos(t["phi"])
            - t["rbar"] * math.cos(t["th"] + t["psi_bd"])
            + s * model.B / (2 * R1)
            + model.L2 / (4 * R1)
            - s * model.u_jo / (2 * R1)
        )
        * t["S"]
    )
    q_adf = total * t["S"] ** 2  # docs/model.md §4: S², not S
    return frame - (g / R1) * q * (model.k * v_asf / t["tf1"] + model.c * q_adf / t["tf1"] * omega)


def eq18_scale(model, s, theta1, omega, ground, contact=True):
    """Size of the largest term of Eq. (18) (the abutment's only in contact), for tolerances."""
    t = eq18_terms(model, s, theta1)
    R1, g = t["R1"], model.g
    terms = [
        t["tf2"] / t["tf1"] * omega**2,
        g / R1 * t["v_inf"] / t["tf1"],
        abs(ground) / R1 * abs(t["q_inf"]) / t["tf1"],
        4 * model.k / t["tf1"] * abs(t["u_deck"]) / (2 * R1) * abs(t["S"]),
        4 * model.c / t["tf1"] * t["S"] ** 2 * abs(omega),
    ]
    if not contact:
        terms = terms[:3]
    return max(abs(x) for x in terms)


@pytest.mark.parametrize("s", MODES)
def test_tf1_tf2_are_m_over_r1_squared(any_bridge, s):
    # docs/model.md §4: T_f1 = M/R1², T_f2 = M'/(2R1²) — the paper's expressions, written out above
    m = any_bridge
    for f in (0.0, 0.2, 0.5, 0.8):
        theta1 = s * f * m.alpha1
        mass, dmass, *_ = coefficients(m, s, theta1, EXACT)
        t = eq18_terms(m, s, theta1)
        assert t["tf1"] == pytest.approx(mass / t["R1"] ** 2, rel=1e-12)
        assert t["tf2"] == pytest.approx(dmass / (2 * t["R1"] ** 2), abs=1e-11 * t["tf1"])


@pytest.mark.parametrize("s", MODES)
def test_acceleration_equals_corrected_eq18_out_of_contact(any_bridge, s):
    m = any_bridge
    rng = np.random.default_rng(18)
    for theta1, omega, ground in random_states(m, s, 12, rng):
        got = acceleration(m, s, theta1, omega, ground, False, EXACT)
        expected = eq18(m, s, theta1, omega, ground, False)
        scale = eq18_scale(m, s, theta1, omega, ground, False)
        assert got == pytest.approx(expected, abs=1e-10 * scale)


@pytest.mark.parametrize("compiled", [True, False], ids=["numba", "py_func"])
@pytest.mark.parametrize("s", MODES)
def test_acceleration_equals_corrected_eq18_in_contact(any_bridge, s, compiled):
    m = any_bridge
    rng = np.random.default_rng(19)
    checked = 0
    for theta1, omega, ground in random_states(m, s, 16, rng, low=0.3):
        u = coefficients(m, s, theta1, EXACT)[4]
        if abs(u) < m.u_jo:
            continue
        checked += 1
        kernel = acceleration if compiled else python(acceleration)
        got = kernel(m, s, theta1, omega, ground, True, EXACT)
        expected = eq18(m, s, theta1, omega, ground, True)
        scale = eq18_scale(m, s, theta1, omega, ground)
        assert got == pytest.approx(expected, abs=1e-10 * scale)
    assert checked >= 8


def test_printed_sign_of_the_velocity_term_is_wrong_only_when_asymmetric():
    # docs/model.md §4: the φ̇² sign error vanishes at h̄ = 1 (M' ≡ 0): only an asymmetric bridge
    # sees it
    sym, asym = studied_bridge(1.0), studied_bridge(2.0)
    theta1, omega = 0.5 * sym.alpha1, 0.8
    assert coefficients(sym, 1.0, theta1, EXACT)[1] == pytest.approx(0.0, abs=1e-9 * sym.m1)
    code = acceleration(sym, 1.0, theta1, omega, 0.0, False, EXACT)
    assert code == pytest.approx(eq18(sym, 1.0, theta1, omega, 0.0, False, printed_sign=True))
    code = acceleration(asym, 1.0, theta1, omega, 0.0, False, EXACT)
    printed = eq18(asym, 1.0, theta1, omega, 0.0, False, printed_sign=True)
    assert abs(code - printed) > 1e-4 * abs(code)


# ---------------------------------------------------------------------------------------------
# Coefficients against finite differences
# ---------------------------------------------------------------------------------------------


def ref_mass(link, model, s, theta1):
    """M = 2T at unit velocity, from the reference kinematics' finite-difference velocities."""
    d = link.derivative(s, theta1)
    return (
        model.m1 * (d["xl"] ** 2 + d["zl"] ** 2)
        + model.m2 * (d["xr"] ** 2 + d["zr"] ** 2)
        + model.md * (d["xd"] ** 2 + d["zd"] ** 2)
        + model.I1
        + model.I2 * d["theta_right"] ** 2
        + model.Id * d["theta_deck"] ** 2
    )


@pytest.mark.parametrize("s", MODES)
def test_coefficients_against_finite_differences(any_bridge, s):
    m = any_bridge
    link = RefLinkage.of(m)
    step = 1e-3 * m.alpha1
    for f in (0.0, 0.1, 0.4, 0.7, 0.9):
        theta1 = s * f * m.alpha1
        mass, dmass, gravity, inertia, u, du = coefficients(m, s, theta1, EXACT)
        # M against the kinetic energy of the independent kinematics
        assert mass == pytest.approx(ref_mass(link, m, s, theta1), rel=1e-9)
        # M' against FD of the code's M and of the reference M
        fd = d1_fd(lambda t: coefficients(m, s, t, EXACT)[0], theta1, step)
        assert dmass == pytest.approx(fd, abs=1e-7 * mass)
        fd = d1_fd(lambda t: ref_mass(link, m, s, t), theta1, step)
        assert dmass == pytest.approx(fd, abs=1e-6 * mass)

        # ∂V/∂φ against FD of V = g·Σ m·z (reference positions)
        def potential(t):
            p = link.solve(s, t)
            return m.g * (m.m1 * p["zl"] + m.m2 * p["zr"] + m.md * p["zd"])

        weight = m.g * (m.m1 + m.m2 + m.md) * m.R1
        assert gravity == pytest.approx(d1_fd(potential, theta1, step), abs=1e-9 * weight)

        # Σ m·∂x/∂φ against FD of Σ m·x
        def moment(t):
            p = link.solve(s, t)
            return m.m1 * p["xl"] + m.m2 * p["xr"] + m.md * p["xd"]

        lever = (m.m1 + m.m2 + m.md) * m.R1
        assert inertia == pytest.approx(d1_fd(moment, theta1, step), abs=1e-9 * lever)
        # u_deck and its derivative
        assert u == pytest.approx(link.solve(s, theta1)["xd"] - m.L2 / 2, abs=1e-11)
        fd = d1_fd(lambda t: link.solve(s, t)["xd"], theta1, step)
        assert du == pytest.approx(fd, abs=1e-9 * m.R1)


@pytest.mark.parametrize("s", MODES)
def test_gravity_term_is_the_derivative_of_the_energy(any_bridge, s):
    # energy(θ1, 0) is the potential above rest: its φ-derivative is the gravity coefficient
    m = any_bridge
    step = 1e-3 * m.alpha1
    for f in (0.05, 0.5, 0.85):
        theta1 = s * f * m.alpha1
        gravity = coefficients(m, s, theta1, EXACT)[2]
        fd = d1_fd(lambda t: energy(m, s, t, 0.0, False, EXACT), theta1, step)
        assert gravity == pytest.approx(fd, abs=1e-9 * m.g * (m.m1 + m.m2 + m.md) * m.R1)


def test_mass_at_rest_closed_form(any_bridge):
    """At rest, per unit φ̇: pier 1 turns about its pivot (4m1R1²/3), pier 2 at ψ' = h̄, the deck
    translates with the pier top (−2H1, 2sB) and turns at t = θ' = s·2b̄(h̄ − 1) about it, so
    its CG moves at (−2H1 − t·h, 2sB + t·(L2/2 − sB))."""
    m = any_bridge
    h_bar, b_bar = m.H1 / m.H2, m.B / m.L2
    R1sq, R2sq = m.H1**2 + m.B**2, m.H2**2 + m.B**2
    masses = {}
    for s in MODES:
        t = s * 2 * b_bar * (h_bar - 1)
        vx = -2 * m.H1 - t * m.h
        vz = 2 * s * m.B + t * (m.L2 / 2 - s * m.B)
        expected = (
            m.m1 * R1sq + m.I1 + (m.m2 * R2sq + m.I2) * h_bar**2
            + m.md * (vx**2 + vz**2) + m.Id * t**2
        )  # fmt: skip
        masses[s] = coefficients(m, s, 0.0, EXACT)[0]
        assert masses[s] == pytest.approx(expected, rel=1e-12)
    # docs/model.md §6: M differs between the modes at rest unless h̄ = 1
    if m.H1 == m.H2:
        assert masses[1.0] == pytest.approx(masses[-1.0], rel=1e-14)
    else:
        assert abs(masses[1.0] / masses[-1.0] - 1) > 1e-6


@pytest.mark.parametrize("s", MODES)
def test_energy_is_continuous_across_an_impact_with_eta_sqrt_mass_ratio(any_bridge, s):
    # docs/model.md §6: with η = √(M_from/M_to), ½M_from·φ̇² = ½M_to·(ηφ̇)²
    m = any_bridge
    m_from = coefficients(m, s, 0.0, EXACT)[0]
    m_to = coefficients(m, -s, 0.0, EXACT)[0]
    eta = math.sqrt(m_from / m_to)
    omega = -s * 0.3  # returning to rest
    before = energy(m, s, 0.0, omega, False, EXACT)
    after = energy(m, -s, 0.0, eta * omega, False, EXACT)
    assert before == pytest.approx(0.5 * m_from * omega**2, rel=1e-12)
    assert after == pytest.approx(before, rel=1e-12)
    if m.H1 != m.H2:  # and η = 1 would not conserve it
        assert abs(energy(m, -s, 0.0, omega, False, EXACT) / before - 1) > 1e-6


# ---------------------------------------------------------------------------------------------
# Lagrange's equations by finite differences of T and V, on the independent kinematics
# ---------------------------------------------------------------------------------------------


def lagrange_acceleration(link, model, s, theta1, omega, ground, contact):
    """θ̈1 from d/dt(∂T/∂θ̇) − ∂T/∂θ + ∂V/∂θ = Q with every partial by finite differences."""

    def kinetic(t, w):
        d = link.derivative(s, t)
        return (
            0.5
            * w
            * w
            * (
                model.m1 * (d["xl"] ** 2 + d["zl"] ** 2)
                + model.m2 * (d["xr"] ** 2 + d["zr"] ** 2)
                + model.md * (d["xd"] ** 2 + d["zd"] ** 2)
                + model.I1
                + model.I2 * d["theta_right"] ** 2
                + model.Id * d["theta_deck"] ** 2
            )
        )

    def potential(t):
        p = link.solve(s, t)
        v = model.g * (model.m1 * p["zl"] + model.m2 * p["zr"] + model.md * p["zd"])
        if contact:
            v += 0.5 * model.k * (abs(p["xd"] - model.L2 / 2) - model.u_jo) ** 2
        return v

    def x_moment(t):
        p = link.solve(s, t)
        return model.m1 * p["xl"] + model.m2 * p["xr"] + model.md * p["xd"]

    step, dw = 2e-3 * model.alpha1, 0.5
    t_w = lambda t: (kinetic(t, omega + dw) - kinetic(t, omega - dw)) / (2 * dw)  # noqa: E731
    t_ww = (
        kinetic(theta1, omega + dw) - 2 * kinetic(theta1, omega) + kinetic(theta1, omega - dw)
    ) / dw**2
    t_wt = d1_fd(t_w, theta1, step)
    t_t = d1_fd(lambda t: kinetic(t, omega), theta1, step)
    v_t = d1_fd(potential, theta1, step)
    force = -ground * d1_fd(x_moment, theta1, step)
    if contact:
        du = d1_fd(lambda t: link.solve(s, t)["xd"], theta1, step)
        force -= model.c * du * du * omega
    # d/dt(∂T/∂θ̇) = ∂²T/∂θ̇∂θ·θ̇ + ∂²T/∂θ̇²·θ̈
    return (force - v_t + t_t - t_wt * omega) / t_ww


@pytest.mark.parametrize(("name", "model"), BRIDGES[1:6], ids=[n for n, _ in BRIDGES[1:6]])
@pytest.mark.parametrize("s", MODES)
def test_acceleration_against_lagrange_by_finite_differences(name, model, s):
    link = RefLinkage.of(model)
    rng = np.random.default_rng(9)
    for contact in (False, True):
        for theta1, omega, ground in random_states(model, s, 3, rng, low=0.3, high=0.8):
            if contact and abs(coefficients(model, s, theta1, EXACT)[4]) < model.u_jo:
                continue
            got = acceleration(model, s, theta1, omega, ground, contact, EXACT)
            expected = lagrange_acceleration(link, model, s, theta1, omega, ground, contact)
            scale = eq18_scale(model, s, theta1, omega, ground, contact)
            assert got == pytest.approx(expected, abs=1e-6 * scale), (name, contact)


@pytest.mark.parametrize("s", MODES)
def test_power_balance(any_bridge, s):
    """dE/dt = θ̇·Q: the energy (with the spring while in contact) changes only by the work of the
    ground's inertia forces and of the dashpot; dE/dt from FD of `energy` and `acceleration`."""
    m = any_bridge
    link = RefLinkage.of(m)
    rng = np.random.default_rng(7)
    step = 1e-3 * m.alpha1
    for theta1, omega, ground in random_states(m, s, 4, rng, low=0.3):
        contact = abs(coefficients(m, s, theta1, EXACT)[4]) >= m.u_jo
        acc = acceleration(m, s, theta1, omega, ground, contact, EXACT)
        e_t = d1_fd(lambda t, w=omega, c=contact: energy(m, s, t, w, c, EXACT), theta1, step)
        e_w = d1_fd(lambda w, t=theta1, c=contact: energy(m, s, t, w, c, EXACT), omega, 0.1)
        d = link.derivative(s, theta1)
        lever = m.m1 * d["xl"] + m.m2 * d["xr"] + m.md * d["xd"]
        power = omega * (-ground * lever - (m.c * d["xd"] ** 2 * omega if contact else 0.0))
        mass = coefficients(m, s, theta1, EXACT)[0]
        scale = abs(omega) * mass * eq18_scale(m, s, theta1, omega, ground, contact)
        assert e_t * omega + e_w * acc == pytest.approx(power, abs=1e-7 * scale)


def test_energy_at_rest_and_above():
    m = studied_bridge(2.0)
    for s in MODES:
        assert energy(m, s, 0.0, 0.0, False, EXACT) == pytest.approx(0.0, abs=1e-6)
        for f in (0.1, 0.5, 0.9):
            assert energy(m, s, s * f * m.alpha1, 0.0, False, EXACT) > 0.0
    # the spring adds ½k(|u| − u_jo)²
    theta1 = 0.5 * m.alpha1
    u = coefficients(m, 1.0, theta1, EXACT)[4]
    extra = energy(m, 1.0, theta1, 0.0, True, EXACT) - energy(m, 1.0, theta1, 0.0, False, EXACT)
    assert extra == pytest.approx(0.5 * m.k * (abs(u) - m.u_jo) ** 2, rel=1e-9)


def test_onset_is_where_the_acceleration_changes_sign():
    # at rest, θ̈1 = 0 exactly at the Eq. (8) threshold: gravity balances the inertia force
    m = studied_bridge(1.25)
    for s in MODES:
        _, _, gravity, inertia, _, _ = coefficients(m, s, 0.0, EXACT)
        threshold = -gravity / inertia
        assert acceleration(m, s, 0.0, 0.0, threshold, False, EXACT) == pytest.approx(
            0.0, abs=1e-12
        )
        assert s * acceleration(m, s, 0.0, 0.0, threshold * 1.01, False, EXACT) > 0


def test_contact_spring_pushes_the_deck_back():
    m = studied_bridge(2.0)
    for s in MODES:
        theta1 = s * 0.3 * m.alpha1
        free = acceleration(m, s, theta1, 0.0, 0.0, False, EXACT)
        held = acceleration(m, s, theta1, 0.0, 0.0, True, EXACT)
        assert s * (held - free) < 0  # toward rest
        # the dashpot opposes the motion
        moving = acceleration(m, s, theta1, s * 0.1, 0.0, True, EXACT)
        assert s * (moving - held) < 0


def test_compiled_and_python_agree():
    m = studied_bridge(2.0)
    for s in MODES:
        for theta1, omega, ground, contact in (
            (s * 0.03, 0.2, 1.0, False),
            (s * 0.06, -0.5, -2.0, True),
        ):
            a = acceleration(m, s, theta1, omega, ground, contact, EXACT)
            b = python(acceleration)(m, s, theta1, omega, ground, contact, EXACT)
            assert a == pytest.approx(b, rel=1e-12)
            a = coefficients(m, s, theta1, EXACT)
            b = python(coefficients)(m, s, theta1, EXACT)
            assert np.allclose(a, b, rtol=1e-12, atol=0)
            a = energy(m, s, theta1, omega, contact, EXACT)
            b = python(energy)(m, s, theta1, omega, contact, EXACT)
            assert a == pytest.approx(b, rel=1e-12)


def test_simplified_kinematics_error_on_the_acceleration_is_measured():
    # the paper's simplified procedure changes θ̈1 by well under 1 % for the studied bridges
    from rockbridge_cli.core.kinematics import simplified

    for h_bar in (1.25, 2.0):
        m = studied_bridge(h_bar)
        fits = simplified(m)
        for s in MODES:
            for f in (0.1, 0.5, 0.9):
                theta1 = s * f * m.alpha1
                exact = acceleration(m, s, theta1, 0.5, 1.0, False, EXACT)
                fitted = acceleration(m, s, theta1, 0.5, 1.0, False, fits)
                assert fitted == pytest.approx(exact, rel=1e-2)


def test_frame_ignores_the_abutment_terms_when_not_in_contact():
    m = studied_bridge(2.0)
    frame = with_(m, has_abutments=0.0, k=0.0, c=0.0)
    theta1 = 0.4 * m.alpha1
    a = acceleration(m, 1.0, theta1, 0.3, 2.0, False, EXACT)
    b = acceleration(frame, 1.0, theta1, 0.3, 2.0, False, EXACT)
    assert a == b
    assert centres(m, 1.0, theta1, EXACT)[0] == centres(frame, 1.0, theta1, EXACT)[0]

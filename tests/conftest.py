"""Shared fixtures and an independent reference of the mechanics for the core's tests.

Nothing here calls the code under test except to build its `Model` tuple. The reference kinematics
(`RefLinkage`) is a different formulation from the code's: each body is rotated rigidly about its
active pivot (no diagonal angles, no closed-form derivatives), the short pier's rotation comes from
a two-circle intersection, and derivatives are taken by finite differences. It handles either pier
being the tall one, which the mirror tests need.

Sources of the data (Thomaidis, Camara & Kappos 2022; docs/model.md §2, §10):
* studied bridges (Table 1): 2B = 2.6, 2H1 = 26, 2H2 = 26 / 20.8 / 13, L1 = 38, L2 = 60, 2h = 1.7,
  A = 6 m², ρ = 2500, k = 132 MN/m, c = 48 MN·s/m, u_jo = 0.12, u_ab = 0.10, e = 0.6;
* Fig. 3 bridge: the studied bridge with 2H2 = 26/6.4 (h̄ = 6.4);
* Fig. 7/8 bridge: 2B = 2.5, 2H1 = 30, L1 = L2 = 45, 2h = 2, m_deck = 240·10⁴ kg,
  I_deck = 360·10⁷ kg·m², ρ = 2500.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys

# One BLAS/OpenMP thread, as the command line sets (rockbridge_cli/cli/__init__.py), before numpy
# loads: the references that call scipy's optimisers would otherwise spin threads against the
# other processes of a shared machine and take seconds instead of milliseconds (issue 31).
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

from pathlib import Path

import numpy as np
import pytest

from rockbridge_cli.core.geometry import Model

REPO = Path(__file__).resolve().parents[1]

# The tests' studies, written in temporary folders (often also the working folder), name the
# repository's bridges and records: the suite names the repository as a folder a config may
# reach, as a user would (README, "Paths in configs"; tests/test_config_paths.py unsets it).
os.environ["ROCKBRIDGE_PATHS"] = os.pathsep.join(
    filter(None, (os.environ.get("ROCKBRIDGE_PATHS"), str(REPO)))
)
CONFIGS = REPO / "configs" / "bridges"
BAD_BRIDGES = Path(__file__).resolve().parent / "data" / "bad_bridges"

RHO = 2500.0  # ρ of piers and deck, "Description of the Studied Bridges" [kg/m³]
G = 9.81  # docs/model.md §1 [m/s²]
STUDIED_HEIGHTS = {1.0: 26.0, 1.25: 20.8, 2.0: 13.0}  # h̄ → 2H2, Table 1 [m]
M_ABUT = 2000.0 * 1.0 * 9.5 * 2.0  # docs/model.md §2 defaults ρ_s·L_cr·B_abut·h_bw = 38 000 kg


def make_bridge(
    width: float,
    height1: float,
    height2: float,
    side: float,
    central: float,
    depth: float,
    *,
    area: float | None = None,
    deck_mass: float | None = None,
    deck_inertia: float | None = None,
    density: float = RHO,
    g: float = G,
    abutments: bool = True,
    gap: float = 0.12,
    k: float = 132.0e6,
    c: float = 48.0e6,
    u_ab: float = 0.10,
    e: float = 0.6,
    m_abut: float = M_ABUT,
) -> Model:
    """A `Model` from the full dimensions a drawing gives (2B, 2H1 ≥ 2H2, L1, L2, 2h).

    Masses and inertias are written out here from first principles: a pier 2B × 2B × 2H has mass
    ρ·(2B)²·(2H) and inertia m·((2B)² + (2H)²)/12 about its centre; the deck has mass ρ·A·(2L1 + L2)
    (docs/model.md §2) and, by default, m·(L_tot² + (2h)²)/12.
    """
    B, H1, H2, h = width / 2, height1 / 2, height2 / 2, depth / 2
    length = 2 * side + central
    m1 = density * width**2 * height1
    m2 = density * width**2 * height2
    md = deck_mass if deck_mass is not None else density * area * length
    Id = deck_inertia if deck_inertia is not None else md * (length**2 + depth**2) / 12
    return Model(
        B=B, H1=H1, H2=H2, L1=side, L2=central, h=h,
        m1=m1, m2=m2, md=md,
        I1=m1 * (width**2 + height1**2) / 12, I2=m2 * (width**2 + height2**2) / 12, Id=Id, g=g,
        has_abutments=1.0 if abutments else 0.0,
        u_jo=gap if abutments else math.inf, k=k if abutments else 0.0,
        c=c if abutments else 0.0, u_ab=u_ab if abutments else math.inf,
        e=e if abutments else 1.0, m_abut=m_abut if abutments else 0.0,
    )  # fmt: skip


def studied_bridge(h_bar: float, **kw) -> Model:
    """One of the three studied bridges (Table 1), or the same family at another h̄."""
    return make_bridge(2.6, 26.0, 26.0 / h_bar, 38.0, 60.0, 1.7, area=6.0, **kw)


def conservative_laws(frame: Model, devices: np.ndarray | None = None):
    """Event laws of a frame whose impacts keep its energy (`solver.Laws`): η_s = √(M_s/M_−s)
    (docs/model.md §6) and Eq. 8's onset thresholds, with the prestress of ``devices`` (a
    `core.devices.table`) where given."""
    from rockbridge_cli.core import impacts
    from rockbridge_cli.core.dynamics import coefficients
    from rockbridge_cli.core.kinematics import EXACT
    from rockbridge_cli.core.solver import Laws

    mass = {s: coefficients(frame, s, 0.0, EXACT)[0] for s in (1.0, -1.0)}
    return Laws(
        onset_p=impacts.onset_threshold(frame, 1.0, devices),
        onset_n=impacts.onset_threshold(frame, -1.0, devices),
        eta_p=math.sqrt(mass[1.0] / mass[-1.0]),
        eta_n=math.sqrt(mass[-1.0] / mass[1.0]),
        pounding=1.0,
    )


def fig78_bridge(h_bar: float = 1.5, side: float = 45.0, central: float = 45.0, **kw) -> Model:
    """The bridge of Figs. 7 and 8 (deck mass and inertia as given, kept constant in the sweeps)."""
    return make_bridge(
        2.5, 30.0, 30.0 / h_bar, side, central, 2.0, deck_mass=240.0e4, deck_inertia=360.0e7, **kw
    )


def with_(model: Model, **changes) -> Model:
    """The model with some fields replaced."""
    return model._replace(**changes)


# A spread of geometries for the kinematic and dynamic checks: (id, model).
BRIDGES = [
    ("symmetric", studied_bridge(1.0)),
    ("hbar1.25", studied_bridge(1.25)),
    ("hbar2", studied_bridge(2.0)),
    ("hbar6.4", studied_bridge(6.4)),
    ("fig78", fig78_bridge(1.5)),
    # very slender (α1 ≈ 0.02) and stocky (α1 ≈ 0.38, α2 ≈ 0.67) piers, short and long spans
    ("slender", make_bridge(1.0, 50.0, 30.0, 20.0, 80.0, 2.0, area=5.0)),
    ("stocky", make_bridge(4.0, 10.0, 5.0, 5.0, 12.0, 1.0, area=8.0)),
]


@pytest.fixture(params=[b for _, b in BRIDGES], ids=[name for name, _ in BRIDGES])
def any_bridge(request) -> Model:
    return request.param


def rot(vx: float, vz: float, angle: float) -> tuple[float, float]:
    """(vx, vz) rotated counter-clockwise by angle."""
    c, s = math.cos(angle), math.sin(angle)
    return c * vx - s * vz, s * vx + c * vz


class RefLinkage:
    """Reference kinematics of the two-pier frame, either pier the taller.

    Left pier centred at x = 0, right pier at x = L2, deck top at z = 2·max(H); each pier's base is
    raised so that the deck is level at rest. Mode s = +1 pivots on the bottom-left / top-right
    corners, s = −1 on the mirror ones. The degree of freedom is the left pier's rotation θ_L
    (counter-clockwise positive).
    """

    def __init__(self, B: float, H_left: float, H_right: float, L2: float, h: float):
        self.B, self.Hl, self.Hr, self.L2, self.h = B, H_left, H_right, L2, h
        self.top = 2.0 * max(H_left, H_right)
        self.zl = self.top - 2.0 * H_left
        self.zr = self.top - 2.0 * H_right

    @classmethod
    def of(cls, model: Model) -> RefLinkage:
        """The code's bridge (tall pier on the left)."""
        return cls(model.B, model.H1, model.H2, model.L2, model.h)

    def pivots(self, s: float):
        """Base and top pivots of both piers in mode s, at rest: A, P (left), C, D (right)."""
        B, L2 = self.B, self.L2
        return (-s * B, self.zl), (s * B, self.top), (L2 - s * B, self.zr), (L2 + s * B, self.top)

    def solve(self, s: float, theta_left: float) -> dict[str, float]:
        """Positions of the centres of gravity and the rotations, for a left-pier rotation θ_L."""
        (ax, az), (p0x, p0z), (cx, cz), (d0x, d0z) = self.pivots(s)
        dx, dz = rot(p0x - ax, p0z - az, theta_left)
        px, pz = ax + dx, az + dz
        # D: on the circle about C through D0, and at L2 from P; take the intersection nearest
        # to D0 moved with P (the branch of the rest state).
        r1 = math.hypot(d0x - cx, d0z - cz)
        r2 = self.L2
        ux, uz = px - cx, pz - cz
        dist = math.hypot(ux, uz)
        along = (dist**2 + r1**2 - r2**2) / (2.0 * dist)
        across = math.sqrt(r1**2 - along**2)
        ex, ez = ux / dist, uz / dist
        candidates = [
            (cx + along * ex - sign * across * ez, cz + along * ez + sign * across * ex)
            for sign in (1.0, -1.0)
        ]
        guess = (d0x + px - p0x, d0z + pz - p0z)
        qx, qz = min(candidates, key=lambda q: math.hypot(q[0] - guess[0], q[1] - guess[1]))
        theta_right = math.atan2(qz - cz, qx - cx) - math.atan2(d0z - cz, d0x - cx)
        theta_deck = math.atan2(qz - pz, qx - px)
        lx, lz = rot(0.0 - ax, self.zl + self.Hl - az, theta_left)
        rx, rz = rot(self.L2 - cx, self.zr + self.Hr - cz, theta_right)
        gx, gz = rot(self.L2 / 2 - p0x, self.top + self.h - p0z, theta_deck)
        return {
            "xl": ax + lx, "zl": az + lz, "xr": cx + rx, "zr": cz + rz,
            "xd": px + gx, "zd": pz + gz,
            "theta_left": theta_left, "theta_right": theta_right, "theta_deck": theta_deck,
            "px": px, "pz": pz, "qx": qx, "qz": qz,
        }  # fmt: skip

    def derivative(self, s: float, theta_left: float, step: float = 1e-4) -> dict[str, float]:
        """Five-point finite-difference derivative of every quantity of `solve` w.r.t. θ_L."""
        values = [self.solve(s, theta_left + k * step) for k in (-2, -1, 1, 2)]
        return {
            key: (values[0][key] - 8 * values[1][key] + 8 * values[2][key] - values[3][key])
            / (12.0 * step)
            for key in values[0]
        }


def ref_rest_jacobian(link: RefLinkage, s: float) -> np.ndarray:
    """(ẋ, ż, ω) of left pier, right pier and deck per unit θ̇_L at rest in mode s, by FD."""
    d = link.derivative(s, 0.0)
    return np.array(
        [
            [d["xl"], d["zl"], 1.0],
            [d["xr"], d["zr"], d["theta_right"]],
            [d["xd"], d["zd"], d["theta_deck"]],
        ]
    )


def ref_restitution(
    link: RefLinkage,
    masses: tuple[float, float, float],
    inertias: tuple[float, float, float],
    L1: float,
    s: float,
    seats: bool = True,
) -> float:
    """η = θ̇_L,after / θ̇_L,before of the impact ending mode s, body by body (docs/model.md §6).

    Impulse–momentum of the three bodies (left pier, right pier, deck; x, z and moment about each
    centre of gravity) with impulses from the ground at the new base pivots, between piers and deck
    at the new top pivots, and vertical impulses at the abutment seats that take L1/(L1 + L2) of the
    pier–deck vertical impulse on their side (Eqs. 21–22). Written here independently of the code,
    on the reference kinematics.
    """
    before = ref_rest_jacobian(link, s)
    after = ref_rest_jacobian(link, -s)
    rest = link.solve(s, 0.0)
    cgs = [(rest["xl"], rest["zl"]), (rest["xr"], rest["zr"]), (rest["xd"], rest["zd"])]
    # New pivots = the pivots of mode −s.
    base_l, top_l, base_r, top_r = link.pivots(-s)
    share = L1 / (L1 + link.L2) if seats else 0.0
    # Unknowns: Λ_l (x, z), Λ_r (x, z) from the ground; Λ_P (x, z), Λ_Q (x, z) on the deck from the
    # left and right pier; Λ_E, Λ_E' on the deck; the velocity after (velocity before = 1).
    n = 11
    rows, rhs = [], []

    def moment(point, cg, column_x):
        row = np.zeros(n)
        row[column_x] = -(point[1] - cg[1])
        row[column_x + 1] = point[0] - cg[0]
        return row

    # pier bodies: ground impulse at the base (+), deck reaction at the top (−)
    for body, (base, top, col_g, col_t) in enumerate(
        ((base_l, top_l, 0, 4), (base_r, top_r, 2, 6))
    ):
        m, inertia = masses[body], inertias[body]
        for axis in range(2):
            row = np.zeros(n)
            row[col_g + axis], row[col_t + axis] = 1.0, -1.0
            row[10] = -m * after[body, axis]
            rows.append(row)
            rhs.append(-m * before[body, axis])
        row = moment(base, cgs[body], col_g) - moment(top, cgs[body], col_t)
        row[10] = -inertia * after[body, 2]
        rows.append(row)
        rhs.append(-inertia * before[body, 2])
    # deck: the two pier impulses and the seats
    md, Id = masses[2], inertias[2]
    seat_x = (-L1, link.L2 + L1)
    row = np.zeros(n)
    row[4], row[6], row[10] = 1.0, 1.0, -md * after[2, 0]
    rows.append(row)
    rhs.append(-md * before[2, 0])
    row = np.zeros(n)
    row[5], row[7], row[8], row[9], row[10] = 1.0, 1.0, 1.0, 1.0, -md * after[2, 1]
    rows.append(row)
    rhs.append(-md * before[2, 1])
    row = moment(top_l, cgs[2], 4) + moment(top_r, cgs[2], 6)
    row[8], row[9] = seat_x[0] - cgs[2][0], seat_x[1] - cgs[2][0]
    row[10] = -Id * after[2, 2]
    rows.append(row)
    rhs.append(-Id * before[2, 2])
    # Eqs. 21–22: seats take L1/(L1 + L2) of the vertical pier–deck impulse on their side
    row = np.zeros(n)
    row[8], row[5] = 1.0, -share
    rows.append(row)
    rhs.append(0.0)
    row = np.zeros(n)
    row[9], row[7] = 1.0, -share
    rows.append(row)
    rhs.append(0.0)
    return float(np.linalg.solve(np.array(rows), np.array(rhs))[10])


def ref_onset(link: RefLinkage, masses: tuple[float, float, float], g: float, s: float) -> float:
    """Onset ground acceleration of mode s by virtual work at rest (Eq. 7), signed [m/s²]."""
    d = link.derivative(s, 0.0)
    work_gravity = masses[0] * d["zl"] + masses[1] * d["zr"] + masses[2] * d["zd"]
    work_inertia = masses[0] * d["xl"] + masses[1] * d["xr"] + masses[2] * d["xd"]
    return g * work_gravity / -work_inertia


def eq30(model: Model, s: float, printed: bool = False) -> float:
    """Eq. (30) of the paper with the bracket fix of docs/model.md §6 (upper signs s = +1: p→n).

    Written out here from the paper's text, term by term; the ∓2α6·b̄(h̄² − 1) and ±2α8·b̄(h̄² − 1)
    terms are moved inside the B²(…) brackets. ``printed=True`` leaves them where the paper prints
    them (inside the m_deck bracket but outside B²(…)).
    """
    B, H1, H2, h = model.B, model.H1, model.H2, model.h
    m1, m2, md, I1, I2, Id = model.m1, model.m2, model.md, model.I1, model.I2, model.Id
    hb, bb, Lb = H1 / H2, B / model.L2, model.L1 / model.L2
    a1 = 4 * Lb**3 + 6 * Lb**2 + 4 * Lb + 1
    a2 = 4 * Lb**3 + 4 * Lb**2 + Lb
    a3 = 2 * Lb**2 + 3 * Lb + 1
    a4 = 2 * Lb**3 + 4 * Lb**2 + 3 * Lb + 1
    a5 = (Lb + 1) ** 2
    a6 = 2 * Lb**3 + 3 * Lb**2 + Lb
    a7 = 4 * Lb**3 + 8 * Lb**2 + 7 * Lb + 2
    a8 = 2 * Lb**3 + 5 * Lb**2 + 5 * Lb + 2
    upper = s  # +1 selects the upper of "±", −1 the lower; "∓" is −upper
    inside, outside = (0.0, 1.0) if printed else (1.0, 0.0)
    n6 = -upper * 2 * a6 * bb * (hb**2 - 1)  # "∓2α6·b̄(h̄² − 1)"
    d8 = upper * 2 * a8 * bb * (hb**2 - 1)  # "±2α8·b̄(h̄² − 1)"
    num = (
        a1 * (H1**2 - B**2) * m1
        + a1 * I1
        + a1 * (H1**2 - hb**2 * B**2) * m2
        + a1 * hb**2 * I2
        + md
        * (
            4 * a1 * H1**2
            + upper * 4 * a2 * H1 * h * bb * (hb - 1)
            - 4 * a3 * h**2 * bb**2 * (hb - 1) ** 2
            - B**2 * (a4 * (hb + 1) ** 2 - 4 * a5 * bb**2 * (hb - 1) ** 2 + inside * n6)
            + outside * n6
        )
        - 4 * a3 * bb**2 * (hb - 1) ** 2 * Id
    )
    den = (
        a1 * (H1**2 + B**2) * m1
        + a1 * I1
        + a1 * (H1**2 + hb**2 * B**2) * m2
        + a1 * hb**2 * I2
        + md
        * (
            4 * a1 * H1**2
            - upper * 4 * a7 * H1 * h * bb * (hb - 1)
            + 4 * a3 * h**2 * bb**2 * (hb - 1) ** 2
            + B**2 * (a4 * (hb + 1) ** 2 + 4 * a5 * bb**2 * (hb - 1) ** 2 + inside * d8)
            + outside * d8
        )
        + 4 * a3 * bb**2 * (hb - 1) ** 2 * Id
    )
    return num / den


def fresh_python(code: str) -> str:
    """What ``code`` prints, stripped, run by a fresh interpreter (this one): which modules an
    import loads shows only in a process that has loaded nothing else. The test fails with the
    child's error output if it fails."""
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


def python(kernel):
    """The plain-Python version of a compiled kernel (the kernel itself under NUMBA_DISABLE_JIT)."""
    return getattr(kernel, "py_func", kernel)


def _prepared(vertical: bool = False, devices: bool = False) -> None:
    """The kernels made ready in this process by `study.kernels.prepare`: loaded from numba's
    cache, or compiled under the installation's kernel lock, one process at a time. On a cold
    cache (CI's, a fresh clone's) two pytest-xdist workers that first analyze at once would
    otherwise each compile the same kernels (about 60–80 s of CPU time a variant, measured with
    ``time.process_time`` on this 2-core host); with the lock one compiles, the other waits and
    loads them from the cache it filled."""
    if os.environ.get("NUMBA_DISABLE_JIT") == "1":
        return
    from rockbridge_cli.study import kernels

    kernels.prepare(vertical=vertical, devices=devices)


_horizontal_ready = False
"""Whether this process has made the analysis kernels ready (`pytest_runtest_setup`)."""


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item: pytest.Item) -> None:
    """The analysis kernels, once per process before its first test that may analyze (nearly
    every test file does), ahead of that test's fixtures, which may analyze: 0.6 s of CPU time
    loaded from a warm cache. Not for a test marked ``no_kernels`` (it analyzes nothing in this
    process, or compiles into a cache of its own): on a cold cache its worker runs it at once
    instead of waiting for the other worker's compiles."""
    global _horizontal_ready
    if not _horizontal_ready and item.get_closest_marker("no_kernels") is None:
        _prepared()
        _horizontal_ready = True


@pytest.fixture(scope="session")
def vertical_kernels() -> None:
    """The kernels of an analysis with a vertical ground motion (`core.schemes.VerticalGround`),
    for the tests that run one."""
    _prepared(vertical=True)


@pytest.fixture(scope="session")
def device_kernels() -> None:
    """The kernels of a bridge with tendons or dampers (`core.device_mechanics`), for the tests
    that analyze one. (Those of such a bridge under a vertical ground motion as well, another
    60–70 s of compile, only the warm-up's reach test calls: its process compiles them.)"""
    _prepared(devices=True)


# The order the test files are handed to pytest-xdist's workers (README's `-n auto --dist
# loadfile`: each file to one worker, the next file to the first worker free). The suite's wall
# time is set by how the long files pack onto two workers and by the compiles: on a cold cache
# (CI's) each kernel variant is compiled by one process at a time under the installation's lock
# (`study.kernels`), and every process that loads kernels meanwhile, a run's workers included,
# waits for it. So the file that compiles on a cache of its own starts at once on one worker
# while the other compiles the suite's kernels and the devices', and the first then matches
# records, which needs none of them; the other long files follow, longest first (wall
# times of a cold whole-suite run, 2026-11-28); then the rest, most tests first, as
# pytest-xdist orders them by default.
FIRST_FILES = (
    "test_cold_cache.py",  # 154 s: compiles every kernel on a cache and a lock of its own
    "test_devices.py",  # 93 s: the analysis kernels, then the devices'
    "test_matching.py",  # 58 s: record matching, no analysis (no_kernels): no lock to wait for
    "test_cli_study.py",  # 132 s: the vertical motion's kernels
    "test_cli_records.py",  # 65 s
    "test_packaging.py",  # 53 s: the warm-up's reach (devices under a vertical motion)
    "test_scale_out.py",  # 134 s: Dask workers, restarted, load the kernels
    "test_run_signals.py",  # 68 s
    "test_batch_docs.py",  # 52 s
    "test_plots.py",  # 40 s
    "test_readme_examples.py",  # 32 s
    "test_config_paths.py",  # 28 s
    "test_uncertainty.py",  # 26 s
    "test_report.py",  # 23 s
    "test_benchmarks.py",  # 23 s
    "test_seeds.py",  # 20 s
)


def pytest_configure(config: pytest.Config) -> None:
    """The ``no_kernels`` marker; the files in this module's order (`FIRST_FILES`), not
    reordered by pytest-xdist (≥ 3.7 hands out the files with the most tests first)."""
    config.addinivalue_line(
        "markers",
        "no_kernels: analyzes nothing in this process, or only on a numba cache of its own: its"
        " worker does not make the suite's analysis kernels ready first",
    )
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The tests ordered by file: `FIRST_FILES` in their order, then the other files with the
    most tests first; within a file, as written."""
    files: dict[str, list[pytest.Item]] = {}
    for item in items:
        files.setdefault(item.path.name, []).append(item)
    first = {name: rank for rank, name in enumerate(FIRST_FILES)}
    order = sorted(files, key=lambda name: (first.get(name, len(first)), -len(files[name])))
    items[:] = [item for name in order for item in files[name]]

"""EN 1998-1 §3.2.2.2 elastic spectra and the §3.2.3.1.2 check of artificial records.

Expected values are worked by hand from EN 1998-1 Eqs. (3.2)-(3.6) and Tables 3.2/3.3, with
a_g = 1 m/s² so that each value is the bracket of the formula times S.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rockbridge_cli.motions import ec8

# EN 1998-1 Table 3.2 (Type 1) and Table 3.3 (Type 2), copied from the standard.
TABLES = {
    (1, "A"): (1.0, 0.15, 0.4, 2.0),
    (1, "B"): (1.2, 0.15, 0.5, 2.0),
    (1, "C"): (1.15, 0.20, 0.6, 2.0),
    (1, "D"): (1.35, 0.20, 0.8, 2.0),
    (1, "E"): (1.4, 0.15, 0.5, 2.0),
    (2, "A"): (1.0, 0.05, 0.25, 1.2),
    (2, "B"): (1.35, 0.05, 0.25, 1.2),
    (2, "C"): (1.5, 0.10, 0.25, 1.2),
    (2, "D"): (1.8, 0.10, 0.30, 1.2),
    (2, "E"): (1.6, 0.05, 0.25, 1.2),
}


@pytest.mark.parametrize(("key", "expected"), TABLES.items())
def test_tables_3_2_and_3_3(key, expected):
    shape = ec8.get_spectrum_shape(*key)
    assert (shape.soil_factor, shape.corner_b, shape.corner_c, shape.corner_d) == expected


# Type 1, ground C: S = 1.15, TB = 0.2, TC = 0.6, TD = 2.0; η = 1 at 5%; a_g = 1 m/s².
TYPE_1_C = [
    (0.0, 1.15),  # Eq. 3.2 at T = 0: a_g·S = 1.15
    (0.1, 2.0125),  # Eq. 3.2: 1.15·(1 + 0.1/0.2·(2.5 − 1)) = 1.15·1.75
    (0.2, 2.875),  # T = TB: 1.15·2.5
    (0.4, 2.875),  # Eq. 3.3 plateau
    (0.6, 2.875),  # T = TC
    (1.0, 1.725),  # Eq. 3.4: 2.875·0.6/1.0
    (2.0, 0.8625),  # T = TD: 2.875·0.6/2.0
    (4.0, 0.215625),  # Eq. 3.5: 2.875·0.6·2.0/16
]

# Type 2, ground A: S = 1.0, TB = 0.05, TC = 0.25, TD = 1.2; η = 1; a_g = 1 m/s².
TYPE_2_A = [
    (0.0, 1.0),  # a_g·S
    (0.025, 1.75),  # 1·(1 + 0.025/0.05·1.5)
    (0.05, 2.5),  # T = TB
    (0.25, 2.5),  # T = TC
    (0.5, 1.25),  # 2.5·0.25/0.5
    (1.2, 0.5208333333333334),  # T = TD: 2.5·0.25/1.2 = 0.625/1.2
    (3.0, 0.08333333333333333),  # 2.5·0.25·1.2/9 = 0.75/9
]


@pytest.mark.parametrize(("period", "expected"), TYPE_1_C)
def test_type_1_ground_c(period, expected):
    value = ec8.compute_elastic_spectrum(period, 1, "C", design_acceleration=1.0)
    assert value == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(("period", "expected"), TYPE_2_A)
def test_type_2_ground_a(period, expected):
    value = ec8.compute_elastic_spectrum(period, 2, "A", design_acceleration=1.0)
    assert value == pytest.approx(expected, rel=1e-12)


def test_vectorised_over_periods():
    periods = np.array([row[0] for row in TYPE_1_C])
    values = ec8.compute_elastic_spectrum(periods, 1, "C", design_acceleration=1.0)
    assert values.shape == periods.shape
    np.testing.assert_allclose(values, [row[1] for row in TYPE_1_C], rtol=1e-12)


def test_surface_pga_is_a_g_times_s():
    # pga = a_g·S = 0.69 g gives the same spectrum as a_g = 0.6 g on ground C (S = 1.15)
    periods = np.linspace(0.0, 4.0, 41)
    from_ag = ec8.compute_elastic_spectrum(periods, 1, "C", design_acceleration=0.6 * 9.81)
    from_pga = ec8.compute_elastic_spectrum(periods, 1, "C", surface_pga=0.69 * 9.81)
    np.testing.assert_allclose(from_ag, from_pga, rtol=1e-12)
    assert from_ag[0] == pytest.approx(0.69 * 9.81)


@pytest.mark.parametrize(
    ("damping", "eta"),
    [
        (0.05, 1.0),  # √(10/10)
        (0.10, math.sqrt(10 / 15)),  # 0.8165
        (0.02, math.sqrt(10 / 7)),  # 1.195
        (0.30, 0.55),  # √(10/35) = 0.5345 < 0.55: the floor of Eq. 3.6
    ],
)
def test_damping_correction(damping, eta):
    assert ec8.compute_damping_correction(damping) == pytest.approx(eta, rel=1e-12)
    plateau = ec8.compute_elastic_spectrum(0.4, 1, "C", design_acceleration=1.0, damping=damping)
    assert plateau == pytest.approx(1.15 * 2.5 * eta, rel=1e-12)


def test_beyond_4_s_needs_extrapolate():
    with pytest.raises(ValueError, match="Annex A"):
        ec8.compute_elastic_spectrum(5.0, 1, "C", design_acceleration=1.0)
    # Eq. 3.5 continued: 2.875·0.6·2.0/25
    value = ec8.compute_elastic_spectrum(5.0, 1, "C", design_acceleration=1.0, extrapolate=True)
    assert value == pytest.approx(0.138, rel=1e-12)


@pytest.mark.parametrize(
    "kwargs",
    [
        {},  # neither a_g nor the PGA
        {"design_acceleration": 1.0, "surface_pga": 1.15},  # both
        {"design_acceleration": -1.0},
        {"design_acceleration": 1.0, "damping": 1.2},
    ],
)
def test_refuses_bad_arguments(kwargs):
    with pytest.raises(ValueError):
        ec8.compute_elastic_spectrum(1.0, 1, "C", **kwargs)


@pytest.mark.parametrize(("spectrum_type", "ground"), [(3, "C"), (1, "S1"), (2, "c")])
def test_refuses_unknown_spectrum(spectrum_type, ground):
    with pytest.raises(ValueError):
        ec8.get_spectrum_shape(spectrum_type, ground)


def test_refuses_negative_period():
    with pytest.raises(ValueError):
        ec8.compute_elastic_spectrum([-0.1, 1.0], 1, "C", design_acceleration=1.0)


class TestCompliance:
    target = np.array([1.0, 2.0, 4.0])

    def test_passing_suite(self):
        spectra = np.array([[0.95, 2.1, 4.0], [1.05, 1.9, 3.6], [1.0, 2.0, 4.4]])
        report = ec8.check_compliance(spectra, self.target, np.full(3, 1.15), 1.15, 15.0)
        assert report.count_ok and report.zero_period_ok and report.mean_ok
        assert report.stationary_ok and report.compliant
        assert report.record_min_ratio == pytest.approx((0.95, 0.9, 1.0))
        assert report.record_max_ratio == pytest.approx((1.05, 1.05, 1.1))
        # mean spectrum (1.0, 2.0, 4.0) / target
        assert report.mean_min_ratio == pytest.approx(1.0)
        assert report.mean_max_ratio == pytest.approx(1.0)

    def test_each_rule_can_fail(self):
        # two records, mean 0.85·target, PGA 1% low, stationary part of 8 s
        spectra = 0.85 * np.array([self.target, self.target])
        report = ec8.check_compliance(spectra, self.target, np.full(2, 0.99), 1.0, 8.0)
        assert not report.count_ok  # (4)a needs 3
        assert not report.zero_period_ok  # (4)b mean 0.99 < 1.0
        assert not report.mean_ok  # (4)c 0.85 < 0.9
        assert report.stationary_ok is False  # (3) 8 s < 10 s
        assert not report.compliant

    def test_a_record_outside_the_stated_tolerance_makes_the_set_non_compliant(self):
        # The passing suite's records span 0.90-1.10 of the target: inside ±11 %; at ±5 % the
        # second misses by 0.05 below (0.90) and the third by 0.05 above (1.10).
        spectra = np.array([[0.95, 2.1, 4.0], [1.05, 1.9, 3.6], [1.0, 2.0, 4.4]])
        loose = ec8.check_compliance(spectra, self.target, np.full(3, 1.15), 1.15, 15.0, 0.11)
        assert loose.records_ok and loose.compliant
        assert loose.record_misses == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
        tight = ec8.check_compliance(spectra, self.target, np.full(3, 1.15), 1.15, 15.0, 0.05)
        assert tight.record_misses == pytest.approx((0.0, 0.05, 0.05))
        assert tight.records_ok is False and not tight.compliant
        assert tight.mean_ok  # EN 1998-1's own rules still hold: the tolerance alone fails it
        unstated = ec8.check_compliance(spectra, self.target, np.full(3, 1.15), 1.15, 15.0)
        assert unstated.records_ok is None and unstated.compliant

    def test_zero_period_allows_file_rounding(self):
        # PGAs scaled exactly to a_g·S then written with 10 digits may read back 1e-10 low
        spectra = np.array([self.target] * 3)
        report = ec8.check_compliance(spectra, self.target, np.full(3, 1.0 - 1e-10), 1.0)
        assert report.zero_period_ok
        assert report.stationary_ok is None

    def test_shapes_must_agree(self):
        with pytest.raises(ValueError, match="shapes"):
            ec8.check_compliance(np.ones((3, 2)), self.target, np.ones(3), 1.0)


@pytest.mark.parametrize(
    ("spectrum_type", "period", "expected"),
    [
        # EN 1998-1 §3.2.2.3, Table 3.4 and Eqs. (3.8)-(3.11), by hand for a_g = 1, ξ = 5 % (η = 1):
        # type 1: a_vg = 0.90, T_B 0.05, T_C 0.15, T_D 1.0 s; type 2: a_vg = 0.45, same corners.
        (1, 0.0, 0.90),  # Sve(0) = a_vg
        (1, 0.025, 0.90 * (1.0 + 0.5 * 2.0)),  # halfway up the rising branch: a_vg·(1 + ½(3η − 1))
        (1, 0.10, 2.70),  # the plateau a_vg·η·3.0
        (1, 0.30, 2.70 * 0.15 / 0.30),  # a_vg·η·3.0·T_C/T
        (1, 2.0, 2.70 * 0.15 * 1.0 / 4.0),  # a_vg·η·3.0·T_C·T_D/T²
        (2, 0.10, 1.35),
        (2, 0.50, 1.35 * 0.15 / 0.50),
    ],
)
def test_the_vertical_spectrum_by_hand(spectrum_type, period, expected):
    value = ec8.compute_vertical_spectrum(period, spectrum_type, design_acceleration=1.0)
    assert float(value) == pytest.approx(expected, rel=1e-12)


def test_the_vertical_spectrum_is_continuous_and_damped_like_the_horizontal():
    """Continuous at its corners; 10 % damping scales the plateau by η = sqrt(10/15) (Eq. 3.6)."""
    for corner in (0.05, 0.15, 1.0):
        below, above = ec8.compute_vertical_spectrum(
            np.array([corner - 1e-12, corner + 1e-12]), 1, design_acceleration=3.0
        )
        assert below == pytest.approx(above, rel=1e-9)
    ratio = ec8.compute_vertical_spectrum(0.1, 1, 1.0, damping=0.10) / 2.7
    assert ratio == pytest.approx((10.0 / 15.0) ** 0.5, rel=1e-12)

"""Hazard curves: the two formats read, units, the log-log interpolation and its extension, and
the refusals.

Expected values: OpenQuake's annual rate is −ln(1 − poe)/T (the engine's
``annual_frequency_of_exceedence``), computed here from the file's numbers; the interpolation is a
power law between points, checked on curves that are one; the bundled example site is its stated
construction, (1/475)·(pga/0.69 g)^−3 (EN 1998-1 §2.1(4)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from studies import REPO

from rockbridge_cli.assessment.hazard import HazardCurve, read_hazard_curve
from rockbridge_cli.errors import InputError

EXAMPLE = REPO / "configs" / "hazard" / "example-site-pga.csv"

OPENQUAKE = (
    "#,,,,,\"generated_by='OpenQuake engine 3.18', start_date='2024-01-01T00:00:00', "
    "checksum=1, kind='mean', investigation_time=50.0, imt='SA(0.5)'\"\n"
    "lon,lat,depth,poe-0.05,poe-0.1,poe-0.2,poe-0.4,poe-0.8\n"
    "21.0,38.0,-0.1,0.95,0.6,0.2,0.04,0.0\n"
    "22.0,39.0,-0.1,1.0,0.5,0.1,0.01,0.001\n"
)
"""An OpenQuake 3.x mean hazard curve of SA(0.5 s) at two sites in 50 years (made-up numbers in
the engine's layout: the comment line, lon/lat/depth, poe-<iml> columns)."""


def write(tmp_path, text: str, name: str = "curve.csv"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_the_bundled_example_site_is_its_stated_construction():
    curve = read_hazard_curve(EXAMPLE)
    assert (curve.measure, curve.unit, curve.period) == ("pga_g", "g", None)
    expected = (1.0 / 475.0) * (curve.intensities / 0.69) ** -3.0
    np.testing.assert_allclose(curve.rates, expected, rtol=5e-6)  # 6 significant digits
    assert float(curve.rate(0.69)) == pytest.approx(1.0 / 475.0, rel=5e-6)


def test_a_two_column_curve_is_read_with_its_measure_and_unit(tmp_path):
    path = write(tmp_path, "# a site\n\nSA(1.0) [m/s2], annual_rate [1/year]\n0.5, 0.01\n2, 1e-4\n")
    curve = read_hazard_curve(path)
    assert (curve.measure, curve.unit, curve.period) == ("sa_g", "m/s2", 1.0)
    assert curve.intensities.tolist() == [0.5, 2.0] and curve.rates.tolist() == [0.01, 1e-4]
    in_g = curve.matched("sa_g", "g", 1.0)
    np.testing.assert_allclose(in_g.intensities, [0.5 / 9.80665, 2.0 / 9.80665], rtol=1e-15)
    assert in_g.rates is curve.rates


@pytest.mark.parametrize("name", ["pga", "PGA", "Pga", "pga_g"])
def test_openquakes_names_are_read_in_any_case_in_the_unit_given(tmp_path, name):
    """Issue 40: a header `pga [m/s2]` was read as an unknown measure `pga`."""
    path = write(tmp_path, f"{name} [m/s2], annual_rate [1/year]\n0.981, 0.01\n9.81, 1e-4\n")
    curve = read_hazard_curve(path)
    assert (curve.measure, curve.unit, curve.period) == ("pga_g", "m/s2", None)
    in_g = curve.matched("pga_g", "g")
    np.testing.assert_allclose(in_g.intensities, [0.981 / 9.80665, 9.81 / 9.80665], rtol=1e-15)


def test_openquake_probabilities_become_annual_rates(tmp_path):
    path = write(tmp_path, OPENQUAKE)
    curve = read_hazard_curve(path, site=0)
    assert (curve.measure, curve.unit, curve.period) == ("sa_g", "g", 0.5)
    # poe 0 at 0.8 g is left out: no rate to interpolate in log-log space
    assert curve.intensities.tolist() == [0.05, 0.1, 0.2, 0.4]
    expected = [-math.log(1.0 - poe) / 50.0 for poe in (0.95, 0.6, 0.2, 0.04)]
    np.testing.assert_allclose(curve.rates, expected, rtol=1e-15)
    second = read_hazard_curve(path, site=1)  # poe 1 at 0.05 g: an infinite rate, left out
    assert second.intensities.tolist() == [0.1, 0.2, 0.4, 0.8]
    assert second.rates[0] == pytest.approx(math.log(2.0) / 50.0, rel=1e-15)


def test_openquake_velocities_are_in_centimetres_per_second(tmp_path):
    text = OPENQUAKE.replace("imt='SA(0.5)'", "imt='PGV'")
    curve = read_hazard_curve(write(tmp_path, text), site=0)
    assert (curve.measure, curve.unit) == ("pgv", "cm/s")
    in_si = curve.matched("pgv", "m/s")
    np.testing.assert_allclose(in_si.intensities, [5e-4, 1e-3, 2e-3, 4e-3], rtol=1e-15)


def test_between_and_beyond_its_points_the_curve_is_a_power_law():
    """λ = 1e-3·x^−2 up to 1 g and 1e-3·x^−4 above: each piece, and the extensions below 0.5 g
    and above 2 g, follow their power law exactly."""
    x = np.array([0.5, 1.0, 2.0])
    curve = HazardCurve("pga_g", "g", None, x, np.array([4e-3, 1e-3, 1e-3 / 16.0]), "test")
    probes = np.array([0.1, 0.5, 0.7, 1.0, 1.5, 2.0, 7.0])
    expected = np.where(probes <= 1.0, 1e-3 * probes**-2.0, 1e-3 * probes**-4.0)
    np.testing.assert_allclose(curve.rate(probes), expected, rtol=1e-13)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("# only a comment\n", "no header line"),
        ("pga_g, annual_rate\n0.1, 1\n", "'<measure> \\[<unit>\\]'"),
        ("pga_g [furlong], annual_rate\n0.1, 1\n", "unknown unit 'furlong'"),
        ("acc [g], annual_rate\n0.1, 1\n", "unknown intensity measure 'acc': use one of pga_g"),
        ("pga_g [g], poe [-]\n0.1, 1\n", "second column is 'annual_rate"),
        ("sa_g [g], annual_rate\n0.1, 1\n0.2, 0.1\n", "names its period"),
        ("pga_g [g], annual_rate\n0.1, 1\n0.2, x\n", "line 3: expected 2 finite numbers"),
        ("pga_g [g], annual_rate\n0.2, 1\n0.1, 0.1\n", "increase strictly"),
        ("pga_g [g], annual_rate\n0.1, 0.1\n0.2, 1\n", "must not increase"),
        ("pga_g [g], annual_rate\n0.1, 1\n0.2, 0.1\n0.4, 0.1\n", "last two rates are equal"),
        ("pga_g [g], annual_rate\n0.1, 1\n0.2, 0\n", "at least two intensities"),
        (OPENQUAKE, "2 sites: choose one"),
        (OPENQUAKE.replace("investigation_time=50.0, ", ""), "investigation_time and imt"),
        (OPENQUAKE.replace("SA(0.5)", "MMI"), "'MMI': rockbridge reads PGA, SA\\(T\\)"),
    ],
)  # fmt: skip
def test_a_bad_curve_is_refused_with_the_reason(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(InputError, match=message) as raised:
        read_hazard_curve(path)
    assert str(path) in str(raised.value)


def test_a_curve_of_another_measure_or_period_is_refused():
    curve = read_hazard_curve(EXAMPLE)
    with pytest.raises(InputError, match=r"of pga_g, the fragilities of sa_g\(1 s\)"):
        curve.matched("sa_g", "g", 1.0)
    with pytest.raises(InputError, match="the curve is in g, the fragilities of pga_g in m/s"):
        curve.matched("pga_g", "m/s")

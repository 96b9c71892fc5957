"""Seismic hazard curves: the annual rate at which an intensity measure is exceeded at a site, read
from a file and expressed in the measure and unit of a fragility.

Two formats are read:

- **rockbridge's two-column CSV**: lines starting with ``#`` are comments; the first other line is
  the header, ``<measure> [<unit>], annual_rate [1/year]``, then one line per intensity::

      # an example site (its source or construction)
      pga_g [g], annual_rate [1/year]
      0.1, 0.69
      0.2, 0.086

  The measure is rockbridge's name (``pga_g``, ``sa_g``, …) or OpenQuake's, in any case
  (``PGA``, ``pga``, ``SA(1.0)``, ``PGV``), in the unit the brackets give; a spectral
  acceleration names its period, ``sa_g(1.0)`` or ``SA(1.0)``.
- **OpenQuake's hazard-curve CSV** (``hazard_curve-mean-PGA.csv``, engine 3.x): a first comment
  line holding ``investigation_time=T`` and ``imt='PGA'``, a header ``lon,lat[,depth],poe-<iml>…``
  and one row per site of probabilities of exceedance in T years; the annual rate is
  −ln(1 − poe)/T, as the engine's own ``annual_frequency_of_exceedence``. Its units are the
  engine's: g for PGA and SA, cm/s for PGV, cm for PGD.

Intensities are strictly increasing and positive; rates must not increase with the intensity,
and a two-column file's are 0 or at least `LOWEST_RATE` (1e-10 per year).
Points with a rate of zero (OpenQuake writes poe 0 beyond its precision) or an infinite one
(poe 1) are left out: the curve is interpolated in log-log space, where they have no place.

**Between and beyond the points** the curve is a power law on each segment, λ(im) =
λ_i·(im/im_i)^(−k_i) (linear in log-log space), and the first and the last segment's power laws go
on below and above the curve's range. A last segment with equal rates cannot be extended
(it would put its rate at an infinite intensity) and is refused.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError
from ..motions.intensity import MEASURES
from ..paths import read_input_text

MAX_BYTES = 16 * 2**20
"""Largest hazard-curve file read."""

LOWEST_RATE = 1e-10
"""Lowest annual rate a two-column curve's point may have, zero aside [1/year]: a return period
of 1e10 years, the order of the age of the universe (1.4e10 years). A lower rate (1e-300) is
not a site's hazard, and its segment's power law, hundreds of decades steep, makes every risk
overflow."""

UNITS = {
    "g": ("acceleration", STANDARD_GRAVITY), "m/s2": ("acceleration", 1.0),
    "cm/s2": ("acceleration", 0.01), "m/s": ("velocity", 1.0), "cm/s": ("velocity", 0.01),
    "m": ("length", 1.0), "cm": ("length", 0.01), "s": ("time", 1.0), "-": ("ratio", 1.0),
}  # fmt: skip
"""Units an intensity may be given in: what they measure and their size in SI (g: standard
gravity, the g of record files)."""

OPENQUAKE_MEASURES = {
    "PGA": ("pga_g", "g"), "SA": ("sa_g", "g"), "PGV": ("pgv", "cm/s"), "PGD": ("pgd", "cm"),
}  # fmt: skip
"""OpenQuake's intensity measure types: rockbridge's name and the engine's unit."""

_OPENQUAKE_ANY_CASE = {name.lower(): known for name, known in OPENQUAKE_MEASURES.items()}
"""A two-column file's header may write OpenQuake's names in any case (``pga [m/s2]``)."""

_MEASURE = re.compile(r"^\s*([A-Za-z][A-Za-z0-9_]*)\s*(?:\(\s*([^)]*?)\s*(?:s\s*)?\))?\s*$")
_NAMED = re.compile(r"^(.*?)\[([^\]]*)\]\s*$")
_ATTRIBUTE = re.compile(r"""(\w+)\s*=\s*(?:'([^']*)'|"([^"]*)"|([^,\s"]+))""")


@dataclass(frozen=True)
class HazardCurve:
    """The annual rate of exceedance of an intensity measure at a site.

    Attributes
    ----------
    measure : rockbridge's name of the intensity measure (``pga_g``, ``sa_g``, …)
    unit : unit of the intensities (a key of `UNITS`)
    period : period of a spectral acceleration [s]; None for other measures
    intensities : strictly increasing, positive [unit]
    rates : annual rates of exceedance, positive and not increasing [1/year]
    source : the file it was read from
    """

    measure: str
    unit: str
    period: float | None
    intensities: np.ndarray
    rates: np.ndarray
    source: str

    def rate(self, intensity: np.ndarray | float) -> np.ndarray:
        """λ(im) [1/year]: log-log interpolation, the end segments' power laws beyond."""
        y = np.log(np.asarray(intensity, dtype=float))
        _, _, anchors, log_rates, slopes = self.pieces()
        piece = np.searchsorted(np.log(self.intensities), y, side="right")
        return np.exp(log_rates[piece] - slopes[piece] * (y - anchors[piece]))

    def pieces(self) -> tuple[np.ndarray, ...]:
        """The curve as n + 1 power laws λ = exp(ln λ_a − k·(y − y_a)) in y = ln im: the
        extension below the first point, the n − 1 segments, the extension above the last.

        Returns
        -------
        lows, highs : each piece's range of y (−inf and +inf at the ends)
        anchors, log_rates : y_a and ln λ_a, the piece's lower point (the first for the lower
            extension)
        slopes : k = −d ln λ/d ln im [-]
        """
        logs, log_rates = np.log(self.intensities), np.log(self.rates)
        slopes = -np.diff(log_rates) / np.diff(logs)
        return (
            np.concatenate([[-np.inf], logs]),
            np.concatenate([logs, [np.inf]]),
            np.concatenate([logs[:1], logs]),
            np.concatenate([log_rates[:1], log_rates]),
            np.concatenate([slopes[:1], slopes, slopes[-1:]]),
        )

    def describe(self) -> str:
        """One line: measure, unit, range and the number of points."""
        return (
            f"{measure_label(self.measure, self.period)} [{self.unit}], "
            f"{self.intensities[0]:.3g}–{self.intensities[-1]:.3g} {self.unit}, "
            f"{self.intensities.size} points"
        )

    def matched(self, measure: str, unit: str, period: float | None = None) -> HazardCurve:
        """The curve in ``unit``, once its measure is checked to be ``measure`` (at ``period``).

        Raises
        ------
        InputError
            The curve is of another measure or period, or its unit measures something else.
        """
        wanted = measure_label(measure, period)
        if self.measure != measure or not _same_period(self.period, period):
            reason = (
                f"the curve is of {measure_label(self.measure, self.period)}, the fragilities "
                f"of {wanted}: give a hazard curve of {wanted}"
            )
            raise InputError(self.source, [("", reason)])
        if unit not in UNITS or UNITS[unit][0] != UNITS[self.unit][0]:
            reason = f"the curve is in {self.unit}, the fragilities of {wanted} in {unit}"
            raise InputError(self.source, [("", reason)])
        factor = UNITS[self.unit][1] / UNITS[unit][1]
        return replace(self, unit=unit, intensities=self.intensities * factor)


def measure_label(measure: str, period: float | None) -> str:
    """``pga_g``, or ``sa_g(1 s)`` for a measure with a period."""
    return measure if period is None else f"{measure}({period:g} s)"


def read_hazard_curve(path: str | Path, site: int | None = None) -> HazardCurve:
    """Read a hazard curve, two-column or OpenQuake's (the module's docstring gives both).

    Parameters
    ----------
    path
        The CSV file.
    site
        Row of an OpenQuake file with several sites (0-based); None for a file of one site.

    Raises
    ------
    InputError
        The file is missing or malformed: the message names the line and the reason.
    """
    from ..kinds import expecting

    with expecting(path, "hazard curve"):  # a study or a results file given for it is named
        text = read_input_text(path, MAX_BYTES, "a hazard curve")
        lines = [(n, line) for n, line in enumerate(text.splitlines(), 1) if line.strip()]
        header = next(((n, line) for n, line in lines if not line.lstrip().startswith("#")), None)
        if header is None:
            raise InputError(path, [("", "no header line: nothing but comments")])
        if any(cell.strip().startswith("poe-") for cell in header[1].split(",")):
            curve = _openquake(path, lines, header, site)
        else:
            if site is not None:
                raise InputError(path, [("", "a site is chosen only in OpenQuake's files")])
            curve = _two_columns(path, lines, header)
    return _cleaned(curve)


def _two_columns(path, lines, header) -> HazardCurve:
    number, text = header
    cells = [cell.strip() for cell in text.split(",")]
    if len(cells) != 2:
        reason = "the header has two columns: '<measure> [<unit>], annual_rate [1/year]'"
        raise InputError(path, [(f"line {number}", reason)])
    measure, unit, period = _measure(path, number, cells[0])
    rate_name = _NAMED.match(cells[1])
    name, rate_unit = (rate_name.group(1).strip(), rate_name.group(2).strip()) if rate_name else (
        cells[1], "1/year")  # fmt: skip
    if name != "annual_rate" or rate_unit not in ("1/year", "1/yr"):
        reason = f"the second column is 'annual_rate [1/year]', not {cells[1]!r}"
        raise InputError(path, [(f"line {number}", reason)])
    rows = [(n, line) for n, line in lines if n > number and not line.lstrip().startswith("#")]
    values = _numbers(path, rows, 2)
    for (row, _), rate in zip(rows, values[:, 1], strict=True):
        if 0.0 < rate < LOWEST_RATE:
            reason = (f"annual_rate {rate:g} per year is below {LOWEST_RATE:g}: a return "
                      "period beyond the age of the universe; give annual rates (0 for "
                      "none)")  # fmt: skip
            raise InputError(path, [(f"line {row}", reason)])
    return HazardCurve(measure, unit, period, values[:, 0], values[:, 1], str(path))


def _openquake(path, lines, header, site: int | None) -> HazardCurve:
    number, text = header
    comment = next((line for n, line in lines if n < number), "")
    attributes = {m.group(1): next(g for g in m.groups()[1:] if g is not None)
                  for m in _ATTRIBUTE.finditer(comment)}  # fmt: skip
    if "investigation_time" not in attributes or "imt" not in attributes:
        reason = "an OpenQuake hazard curve states investigation_time and imt in its first line"
        raise InputError(path, [("line 1", reason)])
    try:
        years = float(attributes["investigation_time"])
    except ValueError:
        years = math.nan
    if not years > 0.0:
        reason = f"investigation_time must be a positive number of years, not {years}"
        raise InputError(path, [("line 1", reason)])
    kind, period = _openquake_measure(path, attributes["imt"])
    cells = [cell.strip() for cell in text.split(",")]
    columns = [i for i, cell in enumerate(cells) if cell.startswith("poe-")]
    levels = _numbers(path, [(number, ",".join(cells[i][4:] for i in columns))], len(columns))[0]
    rows = [(n, line) for n, line in lines if n > number]
    if site is None and len(rows) != 1:
        reason = f"{len(rows)} sites: choose one (0 to {len(rows) - 1}) with --site"
        raise InputError(path, [("", reason)])
    chosen = 0 if site is None else site
    if not 0 <= chosen < len(rows):
        raise InputError(path, [("", f"no site {chosen}: the file has {len(rows)} (from 0)")])
    row_number, row = rows[chosen]
    cells = row.split(",")
    if len(cells) != len(header[1].split(",")):
        raise InputError(path, [(f"line {row_number}", "not as many values as the header")])
    poes = _numbers(path, [(row_number, ",".join(cells[i] for i in columns))], len(columns))[0]
    if np.any((poes < 0.0) | (poes > 1.0)):
        raise InputError(path, [(f"line {row_number}", "probabilities must lie in 0–1")])
    with np.errstate(divide="ignore"):
        rates = -np.log1p(-poes) / years
    name, unit = OPENQUAKE_MEASURES[kind]
    return HazardCurve(name, unit, period, levels, rates, str(path))


def _openquake_measure(path, imt: str) -> tuple[str, float | None]:
    """OpenQuake's IMT (``PGA``, ``SA(0.3)``) as its kind and period."""
    match = _MEASURE.match(imt)
    if not match or match.group(1) not in OPENQUAKE_MEASURES:
        known = ", ".join(f"{k}(T)" if k == "SA" else k for k in OPENQUAKE_MEASURES)
        raise InputError(path, [("imt", f"{imt!r}: rockbridge reads {known}")])
    return match.group(1), _period(path, "imt", match.group(1), match.group(2))


def _measure(path, number: int, cell: str) -> tuple[str, str, float | None]:
    """The header's ``<measure> [<unit>]`` as rockbridge's measure name, its unit and period."""
    named = _NAMED.match(cell)
    match = _MEASURE.match(named.group(1)) if named else None
    if not named or not match:
        reason = f"the first column is '<measure> [<unit>]', e.g. 'pga_g [g]', not {cell!r}"
        raise InputError(path, [(f"line {number}", reason)])
    unit = named.group(2).strip()
    if unit not in UNITS:
        reason = f"unknown unit {unit!r}: use one of {', '.join(UNITS)}"
        raise InputError(path, [(f"line {number}", reason)])
    given = match.group(1)
    name = _OPENQUAKE_ANY_CASE.get(given.lower(), (given,))[0]  # `pga [m/s2]` is PGA in m/s2
    if name not in MEASURES or name == "scale":
        known = ", ".join(m for m in MEASURES if m != "scale")
        reason = (f"unknown intensity measure {given!r}: use one of {known} (or OpenQuake's "
                  "PGA, SA(T), PGV, PGD), its unit in brackets, e.g. 'pga_g [g]'")  # fmt: skip
        raise InputError(path, [(f"line {number}", reason)])
    return name, unit, _period(path, f"line {number}", name, match.group(2))


def _period(path, where: str, name: str, text: str | None) -> float | None:
    """The period of a spectral acceleration [s] (required for it, refused for others)."""
    if (text is None) != (name not in ("sa_g", "SA")):
        reason = "a spectral acceleration names its period, e.g. sa_g(1.0); other measures none"
        raise InputError(path, [(where, reason)])
    if text is None:
        return None
    try:
        period = float(text)
    except ValueError:
        period = math.nan
    if not period > 0.0:
        raise InputError(path, [(where, f"the period must be a positive number, not {text!r}")])
    return period


def _numbers(path, rows: list[tuple[int, str]], count: int) -> np.ndarray:
    """The rows as a (rows × count) array of finite numbers."""
    values = []
    for number, line in rows:
        cells = line.split(",")
        try:
            numbers = [float(cell) for cell in cells]
        except ValueError:
            numbers = []
        if len(numbers) != count or not all(map(math.isfinite, numbers)):
            reason = f"expected {count} finite numbers separated by commas, got {line.strip()!r}"
            raise InputError(path, [(f"line {number}", reason)])
        values.append(numbers)
    return np.array(values, dtype=float).reshape(len(values), count)


def _cleaned(curve: HazardCurve) -> HazardCurve:
    """The curve without its points of zero or infinite rate, once checked."""
    problems = []
    if curve.intensities.size and not np.all(curve.intensities > 0.0):
        problems.append("intensities must be positive")
    if np.any(np.diff(curve.intensities) <= 0.0):
        problems.append("intensities must increase strictly")
    if np.any(curve.rates < 0.0):
        problems.append("rates must not be negative")
    kept = np.isfinite(curve.rates) & (curve.rates > 0.0)
    intensities, rates = curve.intensities[kept], curve.rates[kept]
    if not problems and intensities.size < 2:
        problems.append("at least two intensities with a positive, finite rate are needed")
    if not problems and np.any(np.diff(rates) > 0.0):
        problems.append("rates must not increase with the intensity")
    if not problems and rates[-1] == rates[-2]:
        problems.append(
            f"the last two rates are equal: the curve cannot be extended beyond "
            f"{intensities[-1]:g} {curve.unit} (rates must decrease at the end)"
        )
    if problems:
        raise InputError(curve.source, [("", problem) for problem in problems])
    return replace(curve, intensities=intensities, rates=rates)


def _same_period(first: float | None, second: float | None) -> bool:
    if first is None or second is None:
        return first is second
    return math.isclose(first, second, rel_tol=1e-9)

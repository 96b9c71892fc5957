"""Record files: reading and writing accelerograms (the sets of them that
`sets.generate_record_set` writes are read by `set_files`).

Inside the package a record is a `Record` in SI units (m/s², s). Files may be in g or m/s², but
the units must be stated — by the file (PEER ``.AT2`` and rockbridge files do) or by the caller —
never guessed. Formats read by `read_record`:

- PEER NGA ``.AT2``: four header lines (units on line 3, ``NPTS=…, DT=…`` on line 4), then the
  accelerations, several per line;
- rockbridge's own text format (written by `write_record`): ``# key: value`` header lines with at
  least ``units`` and ``time_step``, then two columns, time [s] and acceleration;
- plain two-column text, time [s] and acceleration (``#`` lines are comments);
- plain one-column text of accelerations, with the time step given by the caller.
"""

from __future__ import annotations

import io
import itertools
import math
import numbers
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError, check_path_argument
from ..paths import read_input_text

#: Accepted spellings of the two units, mapped to their canonical names.
UNIT_NAMES = {
    "g": "g",
    **dict.fromkeys(("m/s2", "m/s^2", "m/s**2", "m/s²", "m/s/s", "m/sec/sec", "m/sec2"), "m/s2"),
    **dict.fromkeys(
        ("cm/s2", "cm/s^2", "cm/s**2", "cm/s²", "cm/s/s", "cm/sec/sec", "cm/sec2", "gal"), "cm/s2"
    ),
}

#: m/s² per unit of each canonical unit (g: standard gravity).
UNIT_SCALES = {"g": STANDARD_GRAVITY, "m/s2": 1.0, "cm/s2": 0.01}

ABSURD_PGA_G = 100.0
"""Largest peak a record file may hold [g]: 25 times the largest recorded (about 4 g). A record
above it is a slip of units — cm/s² or mm/s² read as g or m/s² (a 490 cm/s² record read as g
peaks at 490 g) — refused, where a merely implausible one (`config.plausibility.RECORD_PGA_G`,
a 36 g record of cm/s² read as m/s²) is only warned of."""

#: Largest record file read [bytes] (a 3-component 200 Hz hour is ~100 MiB of text).
MAX_RECORD_BYTES = 256 * 2**20

#: Tolerance on the spacing of a time column, relative to the time step [-].
TIME_STEP_TOLERANCE = 1e-3

FORMAT_TAG = "rockbridge-record 1"

PROVENANCE = {
    "set": "-", "fema_record": "-", "earthquake": "-", "year": "-", "magnitude": "-",
    "station": "-", "nga_record": "-", "component": "-", "site_class": "-", "vs30_m_s": "m/s",
    "fault_type": "-", "distance_rrup_km": "km", "distance_rjb_km": "km",
    "normalization_factor": "-", "lowest_usable_frequency_hz": "Hz", "scale_factor": "-",
    "pulse_period_s": "s", "pulse_indicator": "-", "pulse_shape": "-", "pulse_amplitude": "m/s2",
    "pulse_phase": "rad", "pulse_cycles": "-", "pulse_rest": "s", "pair": "-", "angle_deg": "deg",
}  # fmt: skip
"""Where a recorded motion comes from, as a record's metadata, a file's header, a set's manifest
and the results file (``/records/<id>``) name it, with units: the FEMA P695 sets give them all
(`fema`); magnitude and distance are what the sufficiency of an intensity measure is tested
against. Distances in km and NGA numbers, as the field quotes them. The velocity pulse's period
(NaN without a pulse) and indicator are the component's as the study applies it
(`motions.pulse_identification.pulse_provenance`). An analytic pulse (`pulses`) gives its
period and its shape, amplitude, phase, cycles and rest instead."""

#: How line 3 of a PEER AT2 file (or a COSMOS-like header) states its units: "UNITS OF G",
#: "UNITS OF CM/S/S", "IN CM/SEC/SEC", "(CM/S^2)"…
AT2_UNITS = re.compile(
    r"(?:UNITS\s+OF|\bIN|\bUNITS?:?)\s+(G|GAL|C?M/S(?:EC)?(?:/S(?:EC)?|\^2|\*\*2|2|²))(?![\w/])",
    re.IGNORECASE,
)


@dataclass(frozen=True, eq=False)
class Record:
    """A ground-motion record at a uniform time step, in SI units.

    Attributes
    ----------
    name
        short name, e.g. ``AR01``.
    time_step
        time step [s].
    acceleration
        ground acceleration from t = 0, read-only [m/s²].
    source
        where the record came from (usually its file).
    metadata
        anything else the file said (header keys, format, original units).
    vertical
        vertical ground acceleration at the same samples, positive up, read-only [m/s²]; None
        without a vertical component (`vertical`).
    second
        the other horizontal ground acceleration at the same samples, at +90° from
        ``acceleration``, read-only [m/s²]; None for a single component (`components`).
    """

    name: str
    time_step: float
    acceleration: np.ndarray
    source: str = ""
    metadata: dict[str, Any] = field(default_factory=dict)
    vertical: np.ndarray | None = None
    second: np.ndarray | None = None

    def __post_init__(self) -> None:
        values = np.array(self.acceleration, dtype=float)
        if values.ndim != 1 or values.size < 2:
            raise ValueError("a record needs a 1-D array of at least two accelerations")
        if not np.all(np.isfinite(values)):
            raise ValueError("a record's accelerations must be finite")
        if not (math.isfinite(self.time_step) and self.time_step > 0.0):
            raise ValueError(f"the time step must be positive, got {self.time_step!r}")
        values.setflags(write=False)
        object.__setattr__(self, "acceleration", values)
        for name in ("vertical", "second"):
            given = getattr(self, name)
            if given is None:
                continue
            other = np.array(given, dtype=float)
            if other.shape != values.shape or not np.all(np.isfinite(other)):
                raise ValueError(f"a record's {name} component needs a finite value per sample")
            other.setflags(write=False)
            object.__setattr__(self, name, other)

    @property
    def duration(self) -> float:
        """Time of the last sample [s]."""
        return (self.acceleration.size - 1) * self.time_step

    @property
    def peak_acceleration(self) -> float:
        """Peak ground acceleration max|a| [m/s²]."""
        return float(np.max(np.abs(self.acceleration)))


# ---------------------------------------------------------------------------------------------
# Reading


def read_record(
    path: str | Path,
    units: str | None = None,
    time_step: float | None = None,
) -> Record:
    """Read a record file (PEER ``.AT2``, rockbridge, two-column or one-column text).

    Parameters
    ----------
    path
        the file.
    units
        ``"g"``, ``"m/s2"`` or ``"cm/s2"``: the units of a file that does not state them; must
        agree with the file when it does.
    time_step
        time step of a one-column file [s]; must agree with the file when it states one.

    Returns
    -------
    Record
        The ground acceleration in SI [m/s²] and its time step [s]; values in g are converted
        with `STANDARD_GRAVITY`.

    Raises
    ------
    InputError
        The file is missing, unreadable or malformed, its units or time step are unknown or
        contradict the arguments (the message names the line), or it peaks above
        `ABSURD_PGA_G`.
    TypeError
        ``path`` is not a path, ``units`` is not a name, or ``time_step`` not a number.
    """
    if units is not None and not isinstance(units, str):
        raise TypeError(f"units is a name (g, m/s2 or cm/s2), not {units!r}")
    if time_step is not None and (
        isinstance(time_step, bool) or not isinstance(time_step, numbers.Real)
    ):
        raise TypeError(f"time_step is a number of seconds, not {time_step!r}")
    check_path_argument(path, "read_record", "a record file")
    path = Path(path)
    lines = _read_lines(path)
    if path.suffix.lower() == ".at2":
        values, header, step, file_units = _parse_at2(path, lines)
        name, file_format = path.stem, "PEER NGA AT2"
    else:
        values, header, step, file_units = _parse_text(path, lines)
        name = str(header.pop("name", path.stem))
        file_format = "rockbridge" if header.get("format") == FORMAT_TAG else "text"
    resolved_units = _resolve_units(path, file_units, units)
    resolved_step = _resolve_time_step(path, step, time_step)
    scale = UNIT_SCALES[resolved_units]
    metadata = {**header, "format": file_format, "file_units": resolved_units}
    with np.errstate(over="ignore"):
        acceleration = values * scale
    if not np.all(np.isfinite(acceleration)):
        reason = f"a value is beyond the floating-point range once in m/s² (from {resolved_units})"
        raise InputError(path, [("", reason)])
    peak = float(np.max(np.abs(acceleration), initial=0.0)) / STANDARD_GRAVITY
    if peak > ABSURD_PGA_G:
        reason = (f"peak {peak:.4g} g in {resolved_units} is beyond any ground motion "
                  f"({ABSURD_PGA_G:g} g at most; the largest recorded are about 4 g): are the "
                  "numbers in cm/s2 or mm/s2?")  # fmt: skip
        raise InputError(path, [("units", reason)])
    return Record(name, resolved_step, acceleration, str(path), metadata)


def read_stated_units(path: str | Path) -> str | None:
    """The units a record file states (an AT2 header, a ``# units:`` line), or None.

    Raises
    ------
    InputError
        The file is missing, unreadable or empty.
    """
    path = Path(path)
    lines = _read_lines(path)
    if path.suffix.lower() == ".at2":
        return _at2_units(lines[2]) if len(lines) > 2 else None
    for raw in lines:
        line = raw.strip()
        if line and not line.startswith("#"):
            break
        if ":" in line:
            key, value = line[1:].split(":", 1)
            if key.strip() == "units":
                return value.strip()
    return None


def _read_lines(path: Path) -> list[str]:
    text = read_input_text(path, MAX_RECORD_BYTES, "a record file")
    if not text.strip():
        raise InputError(path, [("", "the file is empty")])
    return text.splitlines()


def _parse_at2(path: Path, lines: list[str]):
    """PEER NGA AT2: returns values, header, time step [s] and units (or None)."""
    if len(lines) < 4:
        raise InputError(path, [(f"line {len(lines)}", "an AT2 file needs four header lines")])
    kind = re.search(r"\b(VELOCITY|DISPLACEMENT)\b", lines[2], re.IGNORECASE)
    if kind is not None:
        reason = f"the header says {kind.group(1).upper()}: an AT2 file holds accelerations"
        raise InputError(path, [("line 3", reason)])
    points, step = _parse_at2_counts(path, lines[3])
    units = _at2_units(lines[2])
    values: list[float] = []
    for number, line in enumerate(lines[4:], start=5):
        values.extend(_parse_numbers(path, number, line.split()))
    if len(values) < points:
        raise InputError(
            path,
            [
                (
                    f"line {len(lines)}",
                    f"truncated: NPTS = {points} but the file ends after {len(values)} values",
                )
            ],
        )
    if len(values) > points:
        raise InputError(
            path, [("line 4", f"NPTS = {points} but the file has {len(values)} values")]
        )
    header = {"description": lines[1].strip(), "npts": points}
    return np.array(values), header, step, units


def _parse_at2_counts(path: Path, line: str) -> tuple[int, float]:
    points = re.search(r"NPTS\s*=\s*(\d+)", line, re.IGNORECASE)
    step = re.search(r"DT\s*=\s*([0-9.Ee+-]+)", line, re.IGNORECASE)
    if points is None or step is None:  # the older layout: "5590  0.0050  NPTS, DT"
        old = re.match(r"\s*(\d+)\s+([0-9.Ee+-]+)\s+NPTS\s*,\s*DT", line, re.IGNORECASE)
        if old is None:
            raise InputError(path, [("line 4", "expected 'NPTS= ..., DT= ...'")])
        numbers = old.groups()
    else:
        numbers = (points.group(1), step.group(1))
    try:
        count, dt = int(numbers[0]), float(numbers[1])
    except ValueError:
        raise InputError(path, [("line 4", "cannot read NPTS and DT")]) from None
    if count < 2:
        raise InputError(path, [("line 4", f"NPTS = {count}: a record needs at least two points")])
    if not (math.isfinite(dt) and dt > 0.0):
        raise InputError(path, [("line 4", f"DT = {numbers[1]} is not a positive time step")])
    return count, dt


def _parse_text(path: Path, lines: list[str]):
    """Our format or plain columns: returns values, header, time step [s] or None, units or None."""
    header, table = _read_table(path, lines)
    points = header.pop("points", None)
    if points is not None and points != table.shape[0]:
        raise InputError(
            path,
            [
                (
                    f"line {len(lines)}",
                    f"truncated: the header says {points} points but the file has {table.shape[0]}",
                )
            ],
        )
    step = _read_header_time_step(path, header)
    if table.shape[1] == 2:
        column_step = _check_time_column(path, table[:, 0], lines)
        if step is not None and not _agree(step, column_step):
            raise InputError(
                path,
                [
                    (
                        "",
                        f"the header says time_step {step:g} s but the time column steps by "
                        f"{column_step:g} s",
                    )
                ],
            )
        step = column_step if step is None else step
        if abs(table[0, 0]) > TIME_STEP_TOLERANCE * step:
            header["notices"] = [f"the time column starts at {table[0, 0]:g} s: the record is "
                                 "read as starting at t = 0"]  # fmt: skip
    units = header.pop("units", None)
    return table[:, -1], header, step, None if units is None else str(units)


def _read_table(path: Path, lines: list[str]) -> tuple[dict[str, Any], np.ndarray]:
    """``# key: value`` lines before the data, and the rows of one or two numbers."""
    header: dict[str, Any] = {}
    first = 0  # the first line of data
    while first < len(lines) and (not lines[first].strip() or lines[first].lstrip()[0] == "#"):
        line = lines[first].strip()
        if ":" in line:
            key, value = line[1:].split(":", 1)
            header[key.strip()] = _parse_header_value(value.strip())
        first += 1
    table = _rows_at_once(lines[first:])
    return header, _rows_line_by_line(path, lines, first) if table is None else table


_COMMAS_ONLY = re.compile(r"^[^\S\n]*,[\s,]*$", re.MULTILINE)
"""A line of commas (and spaces) alone: line by line, it is a row of no values."""


def _rows_at_once(lines: list[str]) -> np.ndarray | None:
    """The rows of numbers read by numpy's parser in C, 20× faster than line by line and the
    same numbers (both read a decimal as Python's ``float`` does); None where it cannot take them
    as they are (a comment among them, a value that is not a finite number, rows of unequal
    length, a row of commas alone, fewer than two rows, more than two columns), for
    `_rows_line_by_line` to name the line of the problem."""
    text = "\n".join(lines)
    if "#" in text or _COMMAS_ONLY.search(text):  # a row of commas alone is not blank
        return None
    text = text.replace(",", " ")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # no data: numpy warns; line by line refuses it
            table = np.loadtxt(io.StringIO(text), ndmin=2, comments=None)
    except ValueError:
        return None
    taken = table.shape[0] >= 2 and table.shape[1] in (1, 2) and np.isfinite(table).all()
    return table if taken else None


def _rows_line_by_line(path: Path, lines: list[str], first: int) -> np.ndarray:
    """The rows of numbers from line ``first`` (0-based) on, ``#`` lines skipped; InputError
    naming the first line that is not a row like the others."""
    rows: list[list[float]] = []
    for number, raw in enumerate(lines[first:], start=first + 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        row = _parse_numbers(path, number, line.replace(",", " ").split())
        if not rows:
            first = number
        if not rows and len(row) not in (1, 2):
            raise InputError(
                path, [(f"line {number}", f"expected 1 or 2 columns, found {len(row)}")]
            )
        if rows and len(row) != len(rows[0]):
            raise InputError(
                path,
                [(f"line {number}", f"{len(row)} columns where line {first} has {len(rows[0])}")],
            )
        rows.append(row)
    if not rows:
        raise InputError(path, [("", "no data: the file has no samples")])
    if len(rows) < 2:
        raise InputError(path, [(f"line {first}", "only one sample: a record needs two or more")])
    return np.array(rows)


def _parse_header_value(text: str) -> Any:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def _read_header_time_step(path: Path, header: dict[str, Any]) -> float | None:
    if "time_step" not in header:
        return None
    step = header.pop("time_step")
    if not isinstance(step, (int, float)) or not (math.isfinite(step) and step > 0.0):
        raise InputError(path, [("header", "time_step is not a positive number")])
    return float(step)


def _parse_numbers(path: Path, number: int, tokens: list[str]) -> list[float]:
    """The numbers of one line; a message names the line and the value's place in it, never the
    text (a config may name any readable file as a record: its content stays out of messages,
    results and reports)."""
    values = []
    for place, token in enumerate(tokens, start=1):
        try:
            value = float(token)
        except ValueError:
            raise InputError(path, [(f"line {number}", f"value {place} is not a number")]) from None
        if not math.isfinite(value):
            raise InputError(path, [(f"line {number}", f"value {place} is not a finite number")])
        values.append(value)
    return values


def _check_time_column(path: Path, times: np.ndarray, lines: list[str]) -> float:
    """The uniform time step of a time column [s]; InputError naming the first bad line."""
    steps = np.diff(times)
    backwards = np.flatnonzero(steps <= 0.0)
    if backwards.size:
        k = int(backwards[0]) + 1
        why = f"time {times[k]:g} s does not increase (previous {times[k - 1]:g} s)"
        raise InputError(path, [(f"line {_data_line(lines, k)}", why)])
    typical = float(np.median(steps))
    uneven = np.flatnonzero(np.abs(steps - typical) > TIME_STEP_TOLERANCE * typical)
    if uneven.size:
        k = int(uneven[0]) + 1
        why = (f"time step {steps[k - 1]:g} s differs from the record's {typical:g} s: the time "
               "column must be uniform")  # fmt: skip
        raise InputError(path, [(f"line {_data_line(lines, k)}", why)])
    return float((times[-1] - times[0]) / (times.size - 1))


def _data_line(lines: list[str], k: int) -> int:
    """The line number (1-based) of row ``k`` (0-based) of the data: neither blank nor ``#``."""
    rows = (n for n, raw in enumerate(lines, start=1) if raw.strip() and raw.lstrip()[0] != "#")
    return next(itertools.islice(rows, k, None))


def _agree(first: float, second: float) -> bool:
    return abs(first - second) <= TIME_STEP_TOLERANCE * max(first, second)


def _at2_units(line: str) -> str | None:
    """The units line 3 of an AT2 file states (canonical name, see `UNIT_NAMES`), or None."""
    found = AT2_UNITS.search(line)
    return UNIT_NAMES.get(found.group(1).lower()) if found else None


def _resolve_units(path: Path, in_file: str | None, given: str | None) -> str:
    file_units = None if in_file is None else _canonical_units(path, in_file, "the file's")
    given_units = None if given is None else _canonical_units(path, given, "the given")
    if file_units and given_units and file_units != given_units:
        raise InputError(
            path, [("units", f"the file says {file_units} but {given_units} was given")]
        )
    resolved = file_units or given_units
    if resolved is None:
        raise InputError(
            path,
            [
                (
                    "units",
                    "the file does not state its units: pass them (units='g', 'm/s2' or "
                    "'cm/s2'; --units on the command line)",
                )
            ],
        )
    return resolved


def _canonical_units(path: Path, text: str, whose: str) -> str:
    name = UNIT_NAMES.get(text.strip().lower().replace(" ", ""))
    if name is None:
        stated = f" {text!r}" if whose == "the given" else ""  # the file's text stays out
        reason = f"{whose} units{stated} are unknown: use g, m/s2 or cm/s2"
        raise InputError(path, [("units", reason)])
    return name


def _resolve_time_step(path: Path, in_file: float | None, given: float | None) -> float:
    if given is not None and not (math.isfinite(given) and given > 0.0):
        raise InputError(path, [("time_step", f"the given time step {given!r} is not positive")])
    if in_file is not None and given is not None and not _agree(in_file, given):
        raise InputError(
            path, [("time_step", f"the file says {in_file:g} s but {given:g} s was given")]
        )
    resolved = in_file if in_file is not None else given
    if resolved is None:
        raise InputError(
            path,
            [
                (
                    "time_step",
                    "one column of accelerations needs its time step: pass time_step "
                    "(--time-step on the command line)",
                )
            ],
        )
    return float(resolved)


# ---------------------------------------------------------------------------------------------
# Writing


def write_record(path: str | Path, record: Record, header: dict[str, Any] | None = None) -> None:
    """Write a record in rockbridge's text format, byte for byte reproducibly.

    Header lines are ``# key: value``: the format tag, ``name``, ``units`` (m/s2),
    ``time_step`` and ``points``, then the items of ``header`` in order; then two columns, time
    [s] (fixed decimals) and acceleration [m/s²] (10 significant digits).

    Parameters
    ----------
    path
        the file to write.
    record
        the record.
    header
        extra header items (e.g. seed, pga); keys are words, values single-line.
    """
    items: dict[str, Any] = {
        "format": FORMAT_TAG,
        "name": record.name,
        "units": "m/s2",
        "time_step": record.time_step,
        "points": record.acceleration.size,
    }
    for key, value in (header or {}).items():
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key) or key in items:
            raise ValueError(f"header key {key!r} must be a new word (letters, digits, _)")
        if "\n" in str(value):
            raise ValueError(f"header value of {key!r} must fit on one line")
        items[key] = value
    lines = [f"# {key}: {_format_header_value(value)}" for key, value in items.items()]
    lines.append("# columns: time [s], acceleration [m/s2]")
    decimals = max(6, math.ceil(-math.log10(record.time_step)) + 4)
    times = np.arange(record.acceleration.size) * record.time_step
    lines += [f"{t:.{decimals}f} {a:.9e}" for t, a in zip(times, record.acceleration, strict=True)]
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


def _format_header_value(value: Any) -> str:
    if isinstance(value, float):
        return format(value, ".10g")
    return str(value)

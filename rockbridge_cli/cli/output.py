"""Printing helpers shared by the commands: JSON with SI values, aligned tables, CSV.

They need numpy only (no pandas), so that the commands that print results start quickly."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import click
import numpy as np


def say(text: str = "", err: bool = False, nl: bool = True) -> None:
    """``click.echo`` for a command that must go on whoever reads it (``run``): a stream whose
    reader has gone (``rockbridge run … | head -1``) is pointed at the null device, so that
    what is said to it is dropped and the work goes on."""
    try:
        click.echo(text, err=err, nl=nl)
    except BrokenPipeError:
        stream = sys.stderr if err else sys.stdout
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, stream.fileno())
        os.close(null)


def to_jsonable(value: Any) -> Any:
    """Plain JSON types; non-finite floats become null (JSON has no infinity)."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def echo_json(value: Any) -> None:
    """Print one JSON object."""
    click.echo(json.dumps(to_jsonable(value), indent=2))


def echo_table(rows: list[tuple[str, str]]) -> None:
    """Print ``label  value`` rows with aligned values."""
    width = max(len(label) for label, _ in rows)
    for label, value in rows:
        click.echo(f"{label:<{width}}  {value}")


def table_text(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """Columns under their headers: numbers right-aligned with 4 significant digits, text
    left-aligned; NaN and missing counts (−1 is not used: pass None) as "-"."""
    cells = [[_cell(value) for value in row] for row in rows]
    widths = [max([len(h)] + [len(row[i]) for row in cells]) for i, h in enumerate(headers)]
    numeric = [all(_is_number(row[i]) for row in rows) and rows for i in range(len(headers))]
    lines = []
    for row in [list(headers), *cells]:
        lines.append(
            "  ".join(
                text.rjust(width) if right else text.ljust(width)
                for text, width, right in zip(row, widths, numeric, strict=True)
            ).rstrip()
        )
    return "\n".join(lines)


def write_csv(stream: IO[str], columns: dict[str, np.ndarray]) -> None:
    """One row per index of the columns, a header of their names; floats at full precision
    (shortest round trip), NaN as an empty field."""
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(columns)
    for row in zip(*columns.values(), strict=True):
        writer.writerow("" if _missing(v) else repr(float(v)) if _is_float(v) else v for v in row)


def export_csv(target: str, columns: dict[str, np.ndarray], source: Path) -> None:
    """Write the columns as CSV to the file ``target``, or to the standard output for ``-``. An
    existing file is replaced only if it is a table of the same columns (as rockbridge writes
    them), never ``source``, the file they were read from (`paths.checked_output`)."""
    from ..paths import checked_output

    if target == "-":
        write_csv(sys.stdout, columns)
        return
    header = io.StringIO()
    csv.writer(header, lineterminator="\n").writerow(columns)
    first_line = header.getvalue().encode()

    def same_table(path: Path) -> bool:
        with open(path, "rb") as file:
            return file.readline(len(first_line) + 1) == first_line

    output = checked_output(target, source, ours=same_table, what="a table of these columns")
    with open(output, "w", encoding="utf-8", newline="") as stream:
        write_csv(stream, columns)
    click.echo(f"CSV: {target}")


class ResultsFile(click.ParamType):
    """A results file a command reads, as a path. If its run did not finish (interrupted, or
    merged from parts that miss analyses), the command says so first, on stderr: ``warning:
    FILE: incomplete: N of M analyses …`` (`results.reading.incompleteness`), and then does its
    work on what the file holds, exiting as it would on a complete file."""

    name = "results"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Path:
        path = Path(value)
        note = incomplete(path)
        if note is not None:
            click.echo(f"warning: {path}: {note}; run its study again to resume it", err=True)
        return path


def results_argument():
    """The ``RESULTS`` argument of a command that reads a results file (`ResultsFile`)."""
    return click.argument("results", type=ResultsFile())


def incomplete(path: Path) -> str | None:
    """`results.reading.incompleteness` of a results file; None for a complete one, or one the
    command will refuse with its own message (missing, unreadable)."""
    from ..errors import InputError
    from ..results.reading import incompleteness, open_results

    if not path.is_file():
        return None
    try:
        with open_results(path) as file:
            return incompleteness(file.attrs)
    except InputError:
        return None


def figure_option(default: str):
    """The ``-o/--output`` option of a figure command; ``default`` says where the figure goes
    without it."""
    return click.option(
        "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
        help=f"Figure file, .png, .pdf or .svg [default: {default}].",
    )  # fmt: skip


def _cell(value: Any) -> str:
    if _missing(value):
        return "-"
    if _is_float(value):
        return f"{value:.4g}"
    return str(value)


def _missing(value: Any) -> bool:
    return value is None or (_is_float(value) and math.isnan(value))


def _is_float(value: Any) -> bool:
    return isinstance(value, (float, np.floating))


def _is_number(value: Any) -> bool:
    return value is None or isinstance(value, (int, float, np.integer, np.floating))


def shown(value: float) -> float:
    """A peak for display: 0 where it is round-off (`quantities.ROUND_OFF`), else as it is."""
    from ..core.quantities import ROUND_OFF

    return 0.0 if abs(value) < ROUND_OFF else value

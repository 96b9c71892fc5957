"""One self-contained HTML page of a study's results (``rockbridge report``): what was run and
with what (provenance), the demand/capacity summary, the paper's Figs. 9 and 10, the peak table
with units, the failures with their messages, the record set's EN 1998-1 compliance and, for a
study with an intensity section, the IDA and fragility curves and, given a site's hazard curve,
the annual frequency of each limit state there; for a sampled study, which field matters; for
a study with an orientation, each row's angle and the summary over angles. Its inputs' sections
are `inputs`', its tables' markup `markup`'s, the IDA, fragility and risk sections
`intensity`'s, a sampled study's section `sampled`'s, an orientation's `orientation`'s.

Figures are PNG images embedded as data URIs and the style sheet is inline, so the one file can be
mailed, archived or opened offline; the layout reflows to a phone's width and prints on A4.
"""

from __future__ import annotations

import base64
import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import __version__
from ..assessment.levels import IDA_POINTER, record_count, summary_groups
from ..assessment.orientation import ANGLE_UNITS, angles_in, with_angles
from ..core.quantities import NO_FAILURE, display_unit
from ..errors import InputError, nearest
from ..motions.intensity import MEASURES
from ..paths import MARK, checked_output, replace_atomically
from ..results.reading import (
    bridge_attributes,
    incompleteness,
    open_results,
    peak_columns,
    peak_units,
    read_intensity,
    swept_values,
)
from ..results.sections import IntensitySection
from .inputs import record_sets, records_table
from .intensity import capacity_table, intensity_section, is_ida, measure_name, section
from .markup import MAX_ROWS, cell, escaped, number, table_html
from .orientation import orientation_section
from .sampled import sampled_section

if TYPE_CHECKING:
    from ..assessment.hazard import HazardCurve

TABLE_COLUMNS = (
    "bridge", "record", "pair", "angle_deg", "u_deck_max", "v_deck_max", "theta_deck_max",
    "theta1_max", "theta2_max", "t_onset", "n_impacts_significant", "n_poundings",
    "failure_mode", "dcr_backfill", "status",
)  # fmt: skip
"""The peak table's columns the page shows (all of them are in the results file; a pair and its
angle, from each record's group, only for a study with an orientation: `assessment.orientation.
with_angles`)."""

STYLE = """
body { font: 16px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: #111;
       max-width: 64rem; margin: 0 auto; padding: 1rem; }
h1 { font-size: 1.6rem; margin-bottom: 0.2rem; } h2 { font-size: 1.25rem; margin-top: 2rem;
       border-bottom: 1px solid #ccc; }
figure { margin: 1rem 0; break-inside: avoid; } figure img { width: 100%; height: auto; }
figcaption { font-size: 0.9rem; color: #444; }
.scroll { overflow-x: auto; } table { border-collapse: collapse; font-size: 0.85rem; }
th, td { padding: 0.2rem 0.5rem; border-bottom: 1px solid #e4e4e4; text-align: right;
         white-space: nowrap; } th { background: #f4f4f4; } td.text, th.text { text-align: left; }
dl { display: grid; grid-template-columns: max-content 1fr; gap: 0.2rem 1rem; }
dt { font-weight: 600; } dd { margin: 0; overflow-wrap: anywhere; }
.bad { color: #a00; font-weight: 600; } .note { color: #555; font-size: 0.9rem; }
@page { size: A4; margin: 15mm; }
@media print { body { max-width: none; font-size: 11pt; } h2 { break-after: avoid; } }
"""


def write_report(
    results: str | Path, output: str | Path, record: str | None = None,
    hazard: HazardCurve | None = None, years: float = 50.0,
) -> Path:  # fmt: skip
    """Write the HTML report of a results file.

    Parameters
    ----------
    results
        The HDF5 results file (`rockbridge_cli.results`).
    output
        The HTML file to write.
    record
        The record of the history figure (Fig. 10); default the paper's, AR07, where the study
        has it, else its first record, and of its copies scaled to the study's levels the one
        nearest the design level. A study that kept no histories gets none.
    hazard, years
        A site's hazard curve (`assessment.hazard`): the page then gives each limit state's
        annual frequency there and its probability in ``years`` (`assessment.risk`).

    Returns
    -------
    pathlib.Path
        The page.

    Raises
    ------
    InputError
        ``output`` is the results file itself or a file that is not a report rockbridge wrote
        (`paths.checked_output`), ``record`` is not in the file, or a hazard curve is given for
        a study without an intensity section or in another measure.
    """
    results, output = Path(results), Path(output)
    if output.resolve() == results.resolve():
        raise InputError(output, [("", "the report would overwrite the results file it reads")])
    output = checked_output(output, what="a report rockbridge wrote")
    with open_results(results) as file:
        attributes = {key: _plain(value) for key, value in file.attrs.items()}
        angles = angles_in(file)
        columns, bridges = with_angles(peak_columns(file), angles), bridge_attributes(file)
        units = {**peak_units(file), **(ANGLE_UNITS if angles else {})}
        sources = {
            name: str(file["records"][name].attrs.get("source", "")) for name in file["records"]
        }
        inputs = records_table(file["records"])
        kept = bool(json.loads(attributes.get("histories", "[]")))
        swept = list(dict.fromkeys(f for values in swept_values(file).values() for f in values))
        intensity = read_intensity(file)
    design = json.loads(attributes.get("config", "{}")).get("uncertainty")
    swept = [] if design else swept  # sampled values: drawn by their own section
    records = list(dict.fromkeys(columns["record"]))
    if record is not None and record not in records:
        raise InputError(
            results, [("", f"no record {record}; {nearest(record, records, 'records')}")]
        )
    if hazard is not None and intensity is None:
        reason = "the study has no intensity section: no fragility to integrate with the hazard"
        raise InputError(results, [("", reason)])
    design_level = None if intensity is None else intensity.design
    default = _default_record(records, columns, design_level)
    chosen = record or (default if kept and not is_ida(intensity) else None)
    title = _description(attributes) or Path(str(attributes.get("study_file", results))).stem
    parts = [
        f"<h1>{escaped(title)}</h1>",
        _incomplete(attributes),
        _written_by(results, attributes, columns, len(bridges), intensity),
        _provenance(attributes),
        inputs,
        _summary(columns, bridges, intensity),
        orientation_section(results, units) if angles else "",
    ]
    with tempfile.TemporaryDirectory() as folder:
        figure = _figure_maker(Path(folder))
        under = list(dict.fromkeys(columns["bridge"][columns["record"] == chosen]))  # partial
        parts += _figures(results, figure, intensity, swept, chosen, under, bool(design))
        if design:
            parts.append(sampled_section(results, design, intensity, figure))
        drawn = design is None or design.get("design") == "tornado"  # else one per sample
        if intensity is not None and drawn:
            parts.append(intensity_section(results, intensity, figure, hazard, years))
    parts += [
        capacity_table(results, intensity, len(columns["bridge"]))
        if intensity is not None and is_ida(intensity)
        else _peak_table(columns, units),
        _failures(columns),
        record_sets(attributes, sources),
        _warnings(attributes),
    ]
    return _write_page(output, title, parts)


def _written_by(
    results: Path,
    attributes: dict,
    columns: dict,
    bridges: int,
    intensity: IntensitySection | None,
) -> str:
    """The line under the title: what the file holds, and which rockbridge wrote it when."""
    return (
        f'<p class="note">{escaped(results.name)}: {len(columns["bridge"])} analyses of '
        f"{bridges} bridges under {record_count(columns)} records{_levels(intensity, columns)}"
        f", written by rockbridge {escaped(attributes.get('rockbridge_version', '?'))} on "
        f"{escaped(attributes.get('finished', attributes.get('created', '?')))}</p>"
    )


def _write_page(output: Path, title: str, parts: list[str]) -> Path:
    """Write the page of ``parts`` (HTML fragments, empty ones left out) to ``output``, whole
    or not at all (a temporary file renamed over it)."""
    page = (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f'<meta name="generator" content="{MARK} {__version__}">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{escaped(title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
        + "\n".join(part for part in parts if part)
        + "\n</body>\n</html>\n"
    )
    temporary = output.with_name(f".{output.name}.{os.getpid()}.tmp")
    try:
        temporary.write_text(page, encoding="utf-8")
        replace_atomically(temporary, output)
    finally:
        temporary.unlink(missing_ok=True)
    return output


PAPER_RECORD = "AR07"
"""The record of the paper's Fig. 10: the history figure's default where the study has it."""

MAX_SWEPT = 3
"""Swept fields drawn at most (one figure each)."""


def _default_record(
    records: list[str], columns: dict[str, np.ndarray], design: float | None
) -> str | None:
    """The record of the history figure: the paper's (`PAPER_RECORD`), else the first; of its
    scaled copies, the one at the design level, or nearest it (the paper's Fig. 10 is under
    the design motion; the first copy, the lowest stripe's, left the bridges barely rocking)."""
    first = next(iter([r for r in records if r.split("+", 1)[0] == PAPER_RECORD] + records), None)
    if first is None or design is None:
        return first
    level = dict(zip(columns["record"].tolist(), columns["intensity"].tolist(), strict=True))
    copies = [r for r in records if r.split("+", 1)[0] == first.split("+", 1)[0]]
    return min(copies, key=lambda r: abs(level[r] - design))  # the first of equals


def _levels(intensity: IntensitySection | None, columns: dict[str, np.ndarray]) -> str:
    """How the analyses scale the records: " at N levels of pga_g", " in an IDA of pga_g"."""
    if intensity is None:
        return ""
    if intensity.ida is not None:
        return f" in an IDA of {measure_name(intensity.measure)}"
    levels = len(set(columns["intensity"].tolist()))
    return f" at {levels} levels of {measure_name(intensity.measure)}"


def _figures(
    results: Path, figure: Callable[..., str], intensity: IntensitySection | None,
    swept: list[str], chosen: str | None, under: list[str], sampled: bool = False,
) -> list[str]:  # fmt: skip
    """Fig. 9 (a study without a sweep and without an IDA; with stripes, at their design level if
    it is one of them), or the swept fields' figures; then Fig. 10 under ``chosen``, of the
    bridges ``under`` it (all of them, unless the run stopped early)."""
    parts = []
    level = None if intensity is None else intensity.design
    if swept:
        parts += [_sweep_section(results, figure, intensity, field) for field in swept[:MAX_SWEPT]]
    elif sampled:  # a marker per sampled bridge would be noise: their section says what matters
        pass
    elif intensity is None or intensity.ida is None and level in (intensity.levels or ()):
        from ..plots.peaks import plot_peaks

        at = (f" at {measure_name(intensity.measure)} = {level:g} "
              f"{MEASURES[intensity.measure].unit}") if intensity is not None else ""  # fmt: skip
        try:
            image = figure(plot_peaks, results, level=level if intensity is not None else None)
        except InputError as exc:  # too many bridges for one figure: said in its place
            image = f'<p class="note">{escaped(exc.problems[0][1])}</p>'
        parts.append(section(f"Peaks per record{at} (as the paper's Fig. 9)", image,
                              "One marker per bridge and record; right: the means over the "
                              "records. (A) with the end-joint gap (dotted) and the "
                              "abutment–backfill failure (dashed)."))  # fmt: skip
    if chosen is not None:
        from ..plots.history import plot_history

        parts.append(section(f"Response histories under {chosen} (as the paper's Fig. 10)",
                              figure(plot_history, results, chosen, bridges=under),
                              "Ground motion with each bridge's onset of rocking, then the "
                              "responses; × marks a pounding on the backwall."
                              + _left_out(results)))  # fmt: skip
    return parts


def _left_out(results: Path) -> str:
    """What Fig. 10 leaves out of its responses because the study did not keep their
    histories, as a sentence for its caption (empty where it leaves nothing out)."""
    from ..plots.history import left_out

    with open_results(results) as file:
        absent = left_out(json.loads(file.attrs.get("histories", "[]")))
    return f" Not kept by the study (output.histories): {', '.join(absent)}." if absent else ""


def _sweep_section(
    results: Path, figure: Callable[..., str], intensity: IntensitySection | None, field: str
) -> str:
    """One swept field's figure: the median capacity of the abutment's failure (or of the study's
    first limit state) in an intensity study, else the median peak deck displacement."""
    from ..plots.sweep import plot_sweep

    if intensity is None:
        quantity, what = "u_deck_max", "the median over the records of the peak deck displacement"
    else:
        states = ("abutment_failure",) if intensity.ida is None else intensity.ida.limit_states
        quantity = "abutment_failure" if "abutment_failure" in states else states[0]
        what = f"the median capacity of {quantity.replace('_', ' ')} (90 % interval)"
    return section(f"Against {field}", figure(plot_sweep, results, field=field,
                                               quantity=quantity),
                    f"Each bridge file's variants: {what} against the swept {field}; one line "
                    "per bridge file and value of the other swept fields.")  # fmt: skip


def _description(attributes: dict[str, Any]) -> str:
    """The study's ``description``, from the study YAML the results file keeps."""
    import yaml

    try:
        study = yaml.safe_load(str(attributes.get("study_yaml", "")))
    except yaml.YAMLError:
        return ""
    return str(study.get("description") or "") if isinstance(study, dict) else ""


def _figure_maker(folder: Path) -> Callable[..., str]:
    """A function that draws a figure with a plot function into ``folder`` and returns it as an
    embedded ``<img>``."""
    count = iter(range(1000))

    def figure(draw: Callable[..., Path], results: Path, *args: Any, **options: Any) -> str:
        path = draw(results, *args, folder / f"figure{next(count)}.png", **options)
        encoded = base64.b64encode(path.read_bytes()).decode("ascii")
        return f'<img alt="figure" src="data:image/png;base64,{encoded}">'

    return figure


KNOB_UNITS = {"rest_velocity": "rad/s", "output_step": "s", "tail": "s", "step": "s",
              "max_step": "s", "event_tol": "s", "atol": "rad, rad/s"}  # fmt: skip
"""Units of the fidelity knobs as the provenance shows them (`core.fidelity`)."""


def _knob(name: str, value: Any) -> str:
    """A fidelity knob as a reader reads it: on/off, none, a number with its unit."""
    if isinstance(value, bool):
        return "on" if value else "off"
    if value is None:
        return "none"
    unit = KNOB_UNITS.get(name)
    return f"{value:g} {unit}" if unit and isinstance(value, (int, float)) else str(value)


def _provenance(attributes: dict[str, Any]) -> str:
    knobs = json.loads(attributes.get("knobs", "{}"))
    items = [
        ("study", attributes.get("study_file", "-")),
        ("config hash", attributes.get("config_hash", "-")),
        ("fidelity", f"{attributes.get('fidelity', '-')}: "
                     + ", ".join(f"{k} = {_knob(k, v)}" for k, v in knobs.items())),
        ("versions", ", ".join(f"{name} {attributes[f'{name}_version']}" for name in
                               ("rockbridge", "python", "numpy", "scipy", "h5py", "hdf5")
                               if f"{name}_version" in attributes)),
        ("host name", attributes.get("host", "-")),
        ("run", f"{attributes.get('created', '-')} to {attributes.get('finished', '-')}"),
        ("complete", f"{attributes.get('n_complete', '-')} of {attributes.get('n_analyses', '-')} "
                     "analyses"),
    ]  # fmt: skip
    rows = "".join(f"<dt>{escaped(k)}</dt><dd>{escaped(v)}</dd>" for k, v in items)
    return f"<h2>Provenance</h2>\n<dl>{rows}</dl>"


def _summary(
    columns: dict[str, np.ndarray], bridges: dict[str, dict], intensity: IntensitySection | None
) -> str:
    """Per bridge (and intensity level, in a multiple-stripe study): analyses that ran, the
    backfill's demand/capacity ratio (largest and mean over the records) and the failures by
    mode; an IDA's pointer to its capacities."""
    heading = (
        "<h2>Demand and capacity</h2>\n<p>The paper's demand/capacity ratio is the backfill's "
        "deformation over its capacity, max(0, |u<sub>deck</sub>| − u<sub>jo</sub>)/u<sub>ab"
        "</sub>: 0 while the end joint stays open, 100 % at abutment failure (docs/model.md §8)."
    )
    try:
        groups = summary_groups(columns, intensity)
    except ValueError:
        pointer = IDA_POINTER.split(":")[0]
        return f"{heading} Here {escaped(pointer)}: their capacities are under Fragility.</p>"
    names = [bridges[b]["name"] if b in bridges else b for b in dict.fromkeys(columns["bridge"])]
    shared = {name for name in names if names.count(name) > 1}  # sampled bridges share theirs
    rows = []
    for group in groups[:MAX_ROWS]:
        mine = group.rows
        name = bridges[group.bridge]["name"] if group.bridge in bridges else group.bridge
        ratio = columns["dcr_backfill"][mine]
        ratio = ratio[np.isfinite(ratio)]
        modes = columns["failure_mode"][mine]
        failed = {
            m: int(np.sum(modes == m)) for m in dict.fromkeys(modes) if m not in ("", NO_FAILURE)
        }
        rows.append([
            f"{name} ({group.bridge})" if name in shared else name,
            *([] if group.level is None else [number(group.level)]),
            f"{int(np.sum(columns['status'][mine] == 'ok'))}/{int(np.sum(mine))}",
            f"{100 * ratio.max():.1f} %" if ratio.size else "-",
            f"{100 * ratio.mean():.1f} %" if ratio.size else "-",
            ", ".join(f"{n} {m}" for m, n in failed.items()) or "none",
        ])  # fmt: skip
    level = [] if intensity is None else [f"level, {MEASURES[intensity.measure].label}"]
    headers = ["bridge", *level, "ran ok", "backfill d/c, largest", "backfill d/c, mean",
               "failures"]  # fmt: skip
    more = f'<p class="note">{len(groups) - MAX_ROWS} more rows.</p>' if (
        len(groups) > MAX_ROWS) else ""  # fmt: skip
    per = " Each row is one intensity level: the records scaled to it." if level else ""
    return (
        f"{heading}{per}</p>\n{table_html(headers, rows, text_columns=(0, len(headers) - 1))}{more}"
    )


def _peak_table(columns: dict[str, np.ndarray], units: dict[str, str]) -> str:
    shown = [name for name in TABLE_COLUMNS if name in columns]
    headers, scales = [], []
    for name in shown:
        unit = units.get(name, "-")
        unit, scale = display_unit(unit)
        headers.append(name if unit in ("-", "") else f"{name} [{unit}]")
        scales.append(scale)
    count = len(columns["bridge"])
    rows = [
        [cell(columns[name][i], scale) for name, scale in zip(shown, scales, strict=True)]
        for i in range(min(count, MAX_ROWS))
    ]
    more = f'<p class="note">{count - MAX_ROWS} more rows in the results file.</p>' if (
        count > MAX_ROWS) else ""  # fmt: skip
    texts = tuple(i for i, name in enumerate(shown) if columns[name].dtype.kind in "OUS")
    return (
        '<h2>Peak table</h2>\n<p class="note">Largest values over each analysis; the results '
        "file has every column (rockbridge peaks RESULTS).</p>\n"
        f"{table_html(headers, rows, text_columns=texts)}{more}"
    )


def _failures(columns: dict[str, np.ndarray]) -> str:
    failed = (columns["failure_mode"] != NO_FAILURE) | (columns["status"] != "ok")
    if not failed.any():
        return "<h2>Failures</h2>\n<p>No analysis ended in a failure of the bridge or an error.</p>"
    messages = columns.get("message", np.full(failed.size, ""))
    rows = [
        [columns["bridge"][i], columns["record"][i], columns["failure_mode"][i],
         cell(columns["failure_time"][i], 1.0), columns["status"][i], messages[i] or "-"]
        for i in np.flatnonzero(failed)
    ]  # fmt: skip
    headers = ["bridge", "record", "failure", "at [s]", "status", "message"]
    return f"<h2>Failures</h2>\n{table_html(headers, rows, text_columns=(0, 1, 2, 4, 5))}"


def _incomplete(attributes: dict[str, Any]) -> str:
    """A line at the top of the page if the run did not finish (`results.incompleteness`)."""
    note = incompleteness(attributes)
    return "" if note is None else (
        f'<p class="bad">{escaped(note)}: the run did not finish; this page shows what the file '
        "holds.</p>"
    )  # fmt: skip


def _warnings(attributes: dict[str, Any]) -> str:
    warnings = json.loads(attributes.get("warnings", "[]"))
    if not warnings:
        return ""
    items = "".join(f"<li>{escaped(w)}</li>" for w in warnings)
    return f"<h2>Warnings</h2>\n<ul>{items}</ul>"


def _plain(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value

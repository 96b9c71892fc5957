"""One self-contained HTML page of a study's results (``rockbridge report``): what was run and
with what (provenance), the demand/capacity summary, the paper's Figs. 9 and 10, the peak table
with units, the failures with their messages, the record set's EN 1998-1 compliance and, for a
study with an intensity section, the IDA and fragility curves and, given a site's hazard curve,
the annual frequency of each limit state there.

Figures are PNG images embedded as data URIs and the style sheet is inline, so the one file can be
mailed, archived or opened offline; the layout reflows to a phone's width and prints on A4.
"""

from __future__ import annotations

import base64
import html
import json
import os
import tempfile
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import __version__
from .assessment.levels import IDA_POINTER, record_count, summary_groups
from .core.quantities import NO_FAILURE, ROUND_OFF
from .errors import InputError, nearest
from .paths import MARK, checked_output, replace_atomically
from .results.reading import (
    bridge_attributes,
    open_results,
    peak_columns,
    peak_units,
    swept_values,
)

if TYPE_CHECKING:
    from .assessment.hazard import HazardCurve

TABLE_COLUMNS = (
    "bridge", "record", "u_deck_max", "v_deck_max", "theta_deck_max", "theta1_max", "theta2_max",
    "t_onset", "n_impacts_significant", "n_poundings", "failure_mode", "dcr_backfill", "status",
)  # fmt: skip
"""The peak table's columns the page shows (all of them are in the results file)."""

DISPLAY_UNITS = {"m": ("mm", 1e3), "rad": ("mrad", 1e3)}
"""SI units shown in smaller ones, with the factor."""

MAX_ROWS = 500
"""Rows of the peak table shown at most; the page says how many more the file holds."""

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
        The record of the history figure (Fig. 10); default the study's first record. A study
        that kept no histories gets none.
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
        columns, bridges = peak_columns(file), bridge_attributes(file)
        units = peak_units(file)
        sources = {
            name: str(file["records"][name].attrs.get("source", "")) for name in file["records"]
        }
        inputs = _records_table(file["records"])
        kept = bool(json.loads(attributes.get("histories", "[]")))
        swept = list(dict.fromkeys(f for values in swept_values(file).values() for f in values))
    intensity = json.loads(attributes.get("intensity", "null"))
    records = list(dict.fromkeys(columns["record"]))
    if record is not None and record not in records:
        raise InputError(
            results, [("", f"no record {record}; {nearest(record, records, 'records')}")]
        )
    if hazard is not None and intensity is None:
        reason = "the study has no intensity section: no fragility to integrate with the hazard"
        raise InputError(results, [("", reason)])
    chosen = record or (_default_record(records) if kept and not _is_ida(intensity) else None)
    title = _description(attributes) or Path(str(attributes.get("study_file", results))).stem
    parts = [
        f"<h1>{_text(title)}</h1>",
        f'<p class="note">{_text(results.name)}: {len(columns["bridge"])} analyses of '
        f"{len(bridges)} bridges under {record_count(columns)} records{_levels(intensity, columns)}"
        f", written by rockbridge {_text(attributes.get('rockbridge_version', '?'))} on "
        f"{_text(attributes.get('finished', attributes.get('created', '?')))}</p>",
        _provenance(attributes),
        inputs,
        _summary(columns, bridges, intensity),
    ]
    with tempfile.TemporaryDirectory() as folder:
        figure = _figure_maker(Path(folder))
        parts += _figures(results, figure, intensity, swept, chosen)
        if intensity is not None:
            parts.append(_intensity_section(results, intensity, figure, hazard, years))
    parts += [
        _peak_table(columns, units),
        _failures(columns),
        _record_sets(attributes, sources),
        _warnings(attributes),
    ]
    page = (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f'<meta name="generator" content="{MARK} {__version__}">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{_text(title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
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


def _default_record(records: list[str]) -> str | None:
    """The record of the history figure: the paper's (`PAPER_RECORD`, or a scaled copy of it),
    else the first."""
    paper = [r for r in records if r.split("+", 1)[0] == PAPER_RECORD]
    return next(iter(paper + records), None)


def _levels(intensity: dict | None, columns: dict[str, np.ndarray]) -> str:
    """How the analyses scale the records: " at N levels of pga_g", " in an IDA of pga_g"."""
    if not intensity:
        return ""
    if _is_ida(intensity):
        return f" in an IDA of {intensity['measure']}"
    return f" at {len(set(columns['intensity'].tolist()))} levels of {intensity['measure']}"


def _figures(
    results: Path, figure: Callable[..., str], intensity: dict | None, swept: list[str],
    chosen: str | None,
) -> list[str]:  # fmt: skip
    """Fig. 9 (a study without a sweep and without an IDA), or the swept fields' figures; then
    Fig. 10 under ``chosen``."""
    parts = []
    if swept:
        parts += [_sweep_section(results, figure, intensity, field) for field in swept[:MAX_SWEPT]]
    elif not _is_ida(intensity):
        from .plots.peaks import plot_peaks

        parts.append(_section("Peaks per record (Fig. 9)", figure(plot_peaks, results),
                              "One marker per bridge and record; right: the means over the "
                              "records. (A) with the end-joint gap (dotted) and the "
                              "abutment–backfill failure (dashed)."))  # fmt: skip
    if chosen is not None:
        from .plots.history import plot_history

        parts.append(_section(f"Response histories under {chosen} (Fig. 10)",
                              figure(plot_history, results, chosen),
                              "Ground motion with each bridge's onset of rocking, then the "
                              "responses; × marks a pounding on the backwall."))  # fmt: skip
    return parts


def _sweep_section(
    results: Path, figure: Callable[..., str], intensity: dict | None, field: str
) -> str:
    """One swept field's figure: the median capacity of the abutment's failure (or of the study's
    first limit state) in an intensity study, else the median peak deck displacement."""
    from .plots.sweep import plot_sweep

    if intensity is None:
        quantity, what = "u_deck_max", "the median over the records of the peak deck displacement"
    else:
        states = (intensity.get("ida") or {}).get("limit_states") or ["abutment_failure"]
        quantity = "abutment_failure" if "abutment_failure" in states else states[0]
        what = f"the median capacity of {quantity.replace('_', ' ')} (90 % interval)"
    return _section(f"Against {field}", figure(plot_sweep, results, field=field,
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


def _is_ida(intensity: dict | None) -> bool:
    return bool(intensity and intensity.get("ida"))


def _figure_maker(folder: Path) -> Callable[..., str]:
    """A function that draws a figure with a plot function into ``folder`` and returns it as an
    embedded ``<img>``."""
    count = iter(range(1000))

    def figure(draw: Callable[..., Path], results: Path, *args: Any, **options: Any) -> str:
        path = draw(results, *args, folder / f"figure{next(count)}.png", **options)
        encoded = base64.b64encode(path.read_bytes()).decode("ascii")
        return f'<img alt="figure" src="data:image/png;base64,{encoded}">'

    return figure


def _section(heading: str, image: str, caption: str) -> str:
    return (
        f"<h2>{_text(heading)}</h2>\n<figure>{image}"
        f"<figcaption>{_text(caption)}</figcaption></figure>"
    )


def _provenance(attributes: dict[str, Any]) -> str:
    knobs = json.loads(attributes.get("knobs", "{}"))
    items = [
        ("study", attributes.get("study_file", "-")),
        ("config hash", attributes.get("config_hash", "-")),
        ("fidelity", f"{attributes.get('fidelity', '-')}: "
                     + ", ".join(f"{k} = {v}" for k, v in knobs.items())),
        ("versions", ", ".join(f"{name} {attributes[f'{name}_version']}" for name in
                               ("rockbridge", "python", "numpy", "scipy", "h5py", "hdf5")
                               if f"{name}_version" in attributes)),
        ("machine", attributes.get("host", "-")),
        ("run", f"{attributes.get('created', '-')} to {attributes.get('finished', '-')}"),
        ("complete", f"{attributes.get('n_complete', '-')} of {attributes.get('n_analyses', '-')} "
                     "analyses"),
    ]  # fmt: skip
    rows = "".join(f"<dt>{_text(k)}</dt><dd>{_text(v)}</dd>" for k, v in items)
    return f"<h2>Provenance</h2>\n<dl>{rows}</dl>"


def _summary(
    columns: dict[str, np.ndarray], bridges: dict[str, dict], intensity: dict | None
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
        return f"{heading} Here {_text(pointer)}: their capacities are under Fragility.</p>"
    rows = []
    for group in groups[:MAX_ROWS]:
        mine = group.rows
        ratio = columns["dcr_backfill"][mine]
        ratio = ratio[np.isfinite(ratio)]
        modes = columns["failure_mode"][mine]
        failed = {
            m: int(np.sum(modes == m)) for m in dict.fromkeys(modes) if m not in ("", NO_FAILURE)
        }
        rows.append([
            bridges[group.bridge]["name"] if group.bridge in bridges else group.bridge,
            *([] if group.level is None else [_number(group.level)]),
            f"{int(np.sum(columns['status'][mine] == 'ok'))}/{int(np.sum(mine))}",
            f"{100 * ratio.max():.1f} %" if ratio.size else "-",
            f"{100 * ratio.mean():.1f} %" if ratio.size else "-",
            ", ".join(f"{n} {m}" for m, n in failed.items()) or "none",
        ])  # fmt: skip
    level = [] if intensity is None else [f"level [{intensity['measure']}]"]
    headers = ["bridge", *level, "ran ok", "backfill d/c, largest", "backfill d/c, mean",
               "failures"]  # fmt: skip
    more = f'<p class="note">{len(groups) - MAX_ROWS} more rows.</p>' if (
        len(groups) > MAX_ROWS) else ""  # fmt: skip
    per = " Each row is one intensity level: the records scaled to it." if level else ""
    return f"{heading}{per}</p>\n{_table(headers, rows, text_columns=(0, len(headers) - 1))}{more}"


def _intensity_section(
    results: Path, intensity: dict, figure: Callable[..., str], hazard: HazardCurve | None,
    years: float,
) -> str:  # fmt: skip
    from .assessment.fragility import fragilities
    from .plots.fragility import plot_fragility
    from .plots.ida import plot_ida

    found = fragilities(results)
    design = intensity.get("design")
    rows = [[item.bridge, item.limit_state, _number(item.median), _number(item.beta),
             "-" if item.median_90 is None else f"{item.median_90[0]:.3g}–{item.median_90[1]:.3g}"]
            + ([_number(None if item.median is None else item.median / design)] if design else [])
            for item in found]  # fmt: skip
    measure = intensity["measure"]
    margin = (f"The design level is {design:g} ({measure}); the last column is each median's "
              "margin over it.") if design else ""  # fmt: skip
    parts = [
        _section(f"IDA curves ({measure})", figure(plot_ida, results),
                 "Each record's peak against its intensity level; a cross ends a curve where "
                 "the bridge failed.") if _is_ida(intensity) else "",
        _section(f"Fragility ({measure})", figure(plot_fragility, results, found=found),
                 "Share of the records reaching each limit state, and the fitted lognormal."),
        f"<p>{margin}</p>" if margin else "",
        _table(["bridge", "limit state", "median", "β", "median, 5–95 %"]
               + (["median / design"] if design else []), rows, text_columns=(0, 1)),
        _unreachable(found),
        _efficiency_section(results) if _is_ida(intensity) else "",
        "" if hazard is None else _risk_section(found, intensity, hazard, years),
    ]  # fmt: skip
    return "\n".join(part for part in parts if part)


def _unreachable(found: list) -> str:
    """The limit states a failure kept some IDA curves from reaching, one line each."""
    from .assessment.fragility import unreachable_note

    notes = [f"{item.bridge}: {unreachable_note(item)}" for item in found if item.unreachable]
    if not notes:
        return ""
    items = "".join(f"<li>{_text(note)}</li>" for note in notes)
    return (
        '<p class="note">A failure ends an analysis, so on a curve that ended in one, the states '
        f"not reached by then cannot be observed:</p><ul>{items}</ul>"
    )


def _efficiency_section(results: Path) -> str:
    """β of the IDA's capacities in each intensity measure (`assessment.efficiency`)."""
    from .assessment.efficiency import compare

    rows = compare(results)
    measures = list(dict.fromkeys(row.measure for row in rows))
    beta = {(row.bridge, row.limit_state, row.measure): row.beta for row in rows}
    cases = list(dict.fromkeys((row.bridge, row.limit_state) for row in rows))
    table = [[*case, *(_number(beta[case + (m,)]) for m in measures)] for case in cases]
    table = [row for row in table if any(cell != "-" for cell in row[2:])]
    text = (
        "β of the capacities converted to each measure (Sa at 1 s, AvgSa over 0.2–3 s): the "
        "smaller β, the fewer records fix the median (its standard error is β/√n). Arias "
        "intensity grows as the square of a record's factor: compare half its β. rockbridge "
        "fragility RESULTS --compare-measures adds the trends with magnitude and distance."
    )
    return f"<h2>Which intensity measure</h2>\n<p>{_text(text)}</p>\n" + _table(
        ["bridge", "limit state", *measures], table, text_columns=(0, 1)
    )


def _risk_section(found: list, intensity: dict, hazard: HazardCurve, years: float) -> str:
    """Each limit state's annual frequency at the site of the hazard curve, its return period and
    its probability in ``years``."""
    from .assessment.risk import risk_table, risks_of

    rates = risks_of(found, intensity, hazard, years)
    headers, rows = risk_table(rates, years)
    notes = "".join(f"<li>{_text(f'{r.bridge}: {r.note}')}</li>" for r in rates if r.note)
    return (
        f"<h2>Risk at the site of {_text(Path(hazard.source).name)}</h2>\n<p>Hazard curve: "
        f"{_text(hazard.describe())}; beyond its range it goes on as the power laws of its end "
        "segments. λ is the mean annual frequency of each limit state, ∫ P(LS | im) |dλ<sub>IM"
        "</sub>(im)| (Cornell et al. 2002), the return period 1/λ and P the probability of at "
        f"least one occurrence in {years:g} years, 1 − exp(−λ·{years:g}); the 5–95 % intervals "
        "are those of the bootstrap over the records. &lt; marks an upper bound: no record "
        "reaches the state up to the highest level run, or up to where a failure ended its "
        "curve.</p>\n"
        + _table(headers, rows, text_columns=(0, 1))
        + (f'<ul class="note">{notes}</ul>' if notes else "")
    )


def _peak_table(columns: dict[str, np.ndarray], units: dict[str, str]) -> str:
    shown = [name for name in TABLE_COLUMNS if name in columns]
    headers, scales = [], []
    for name in shown:
        unit = units.get(name, "-")
        unit, scale = DISPLAY_UNITS.get(unit, (unit, 1.0))
        headers.append(name if unit in ("-", "") else f"{name} [{unit}]")
        scales.append(scale)
    count = len(columns["bridge"])
    rows = [
        [_cell(columns[name][i], scale) for name, scale in zip(shown, scales, strict=True)]
        for i in range(min(count, MAX_ROWS))
    ]
    more = f'<p class="note">{count - MAX_ROWS} more rows in the results file.</p>' if (
        count > MAX_ROWS) else ""  # fmt: skip
    texts = tuple(i for i, name in enumerate(shown) if columns[name].dtype.kind in "OUS")
    return (
        '<h2>Peak table</h2>\n<p class="note">Largest values over each analysis; the results '
        "file has every column (rockbridge peaks RESULTS).</p>\n"
        f"{_table(headers, rows, text_columns=texts)}{more}"
    )


def _failures(columns: dict[str, np.ndarray]) -> str:
    failed = (columns["failure_mode"] != NO_FAILURE) | (columns["status"] != "ok")
    if not failed.any():
        return "<h2>Failures</h2>\n<p>No analysis ended in a failure of the bridge or an error.</p>"
    messages = columns.get("message", np.full(failed.size, ""))
    rows = [
        [columns["bridge"][i], columns["record"][i], columns["failure_mode"][i],
         _cell(columns["failure_time"][i], 1.0), columns["status"][i], messages[i] or "-"]
        for i in np.flatnonzero(failed)
    ]  # fmt: skip
    headers = ["bridge", "record", "failure", "at [s]", "status", "message"]
    return f"<h2>Failures</h2>\n{_table(headers, rows, text_columns=(0, 1, 2, 4, 5))}"


RECORD_COLUMNS = (
    ("source", "source"), ("file units", "file_units"), ("dt [s]", "time_step"),
    ("duration [s]", "duration"), ("PGA [g]", "pga_g"), ("PGV [m/s]", "pgv"),
    ("earthquake", "earthquake"), ("year", "year"), ("M", "magnitude"), ("station", "station"),
    ("R_rup [km]", "distance_rrup_km"), ("T_p [s]", "pulse_period_s"),
    ("pulse PI", "pulse_indicator"),
)  # fmt: skip
"""The columns of the table of input records: heading, attribute of ``/records/<id>``. T_p is
the period of the record's velocity pulse, "-" without one, and PI Shahi & Baker's indicator
(> 0 for a pulse; `motions.pulse_identification`)."""


def _records_table(group: Any) -> str:
    """The records the study read, as read: where from, units, sampling, peaks and, for recorded
    motions, their provenance (columns that no record has are left out; scaled copies of a
    record, an intensity study's, are one row: their source's)."""
    rows, seen = [], set()
    for name in group:
        attrs = group[name].attrs
        source = str(attrs.get("source", ""))
        if source in seen:
            continue
        seen.add(source)
        scaled = "+" in name  # a stripe's scaled copy: its peaks are the level's, not the record's
        rows.append({key: attrs.get(key) for _, key in RECORD_COLUMNS}
                    | {"id": name.split("+")[0]}
                    | ({"pga_g": None, "pgv": None} if scaled else {}))  # fmt: skip
    shown = [(head, key) for head, key in RECORD_COLUMNS if any(r[key] is not None for r in rows)]
    table = [
        [row["id"], *(_record_cell(row[key]) for _, key in shown)]
        for row in rows[:MAX_ROWS]
    ]  # fmt: skip
    more = f'<p class="note">{len(rows) - MAX_ROWS} more records in the file.</p>' if (
        len(rows) > MAX_ROWS) else ""  # fmt: skip
    texts = (0, *(i + 1 for i, (_, key) in enumerate(shown) if key in TEXT_RECORD_KEYS))
    return "<h2>Input records</h2>\n" + _table(["record", *(h for h, _ in shown)], table,
                                                 text_columns=texts) + more  # fmt: skip


TEXT_RECORD_KEYS = {"source", "file_units", "earthquake", "station"}


def _record_cell(value: Any) -> str:
    """An attribute of a record as a cell: numbers to 3 digits, "-" where absent or NaN."""
    if isinstance(value, float):
        return _number(value) if np.isfinite(value) else "-"
    return "-" if value is None else str(value)


def _record_sets(attributes: dict[str, Any], sources: dict[str, str]) -> str:
    """The EN 1998-1 §3.2.3.1.2 check of each generated record set the study read, from the
    set's manifest (found from the record sources, relative to the study file)."""
    study_folder = Path(str(attributes.get("study_file", "."))).parent
    folders = dict.fromkeys((study_folder / source).parent for source in sources.values() if source)
    parts = []
    for folder in folders:
        try:
            manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
            parts.append(_compliance(folder.name, manifest))
        except (OSError, ValueError, KeyError, TypeError):  # not a generated set, or unreadable
            continue
    if not parts:
        return ""
    return "<h2>Record sets: EN 1998-1 §3.2.3.1.2</h2>\n" + "\n".join(parts)


def _compliance(name: str, manifest: dict[str, Any]) -> str:
    target, check, verdict = manifest["target"], manifest["compliance"], manifest["check"]
    low, high = verdict["band_s"]
    surface = target["surface_pga_m_s2"]
    dg = target.get("ground_displacement_m")  # sets made before it was recorded lack it

    def motion(r: dict[str, Any]) -> list[str]:
        if dg is None or "pgd_m" not in r:
            return ["-", "-", "-"]
        return [f"{100 * r['pgv_m_s']:.1f}", f"{100 * r['pgd_m']:.1f}", f"{r['pgd_m'] / dg:.2f}"]

    rows = [
        [r["name"], f"{r['pga_m_s2'] / surface:.4f}", f"{r['min_ratio']:.3f}",
         f"{r['max_ratio']:.3f}", *motion(r), f"{r['d5_95_s']:.1f}"]
        for r in manifest["records"]
    ]  # fmt: skip
    rows.append(["mean", "", f"{manifest['mean']['min_ratio']:.3f}",
                 f"{manifest['mean']['max_ratio']:.3f}", "", "", "", ""])  # fmt: skip
    headers = ["record", "PGA/(a_g·S)", "spectrum/target, min", "max", "PGV [cm/s]", "PGD [cm]",
               "PGD/d_g", "D5–95 [s]"]  # fmt: skip
    displacement = "" if dg is None else (
        f"<p>EN 1998-1 §3.2.2.4 design ground displacement d<sub>g</sub> = 0.025·a<sub>g</sub>·S·"
        f"T<sub>C</sub>·T<sub>D</sub> = {100 * dg:.1f} cm; PGD is the peak of the doubly "
        "integrated record, from rest.</p>")  # fmt: skip

    def said(ok: bool | None) -> str:
        return "unknown" if ok is None else ("yes" if ok else '<span class="bad">NO</span>')

    checks = [
        ("(4)a at least 3 records", check["count_ok"]),
        ("(4)b mean zero-period value ≥ a<sub>g</sub>·S", check["zero_period_ok"]),
        (f"(4)c mean ≥ 90 % of the target over {low:g}–{high:g} s", check["mean_ok"]),
        ("(3) stationary part ≥ 10 s (not required of recorded motions, §3.2.3.1.3)",
         check["stationary_ok"]),
    ]  # fmt: skip
    if check.get("tolerance") is not None:  # scaled records have none
        checks.append((f"every record within ±{check['tolerance']:.0%} of the target (the set's "
                       "tolerance, rockbridge)", check["records_ok"]))  # fmt: skip
    items = "".join(f"<li>{label}: {said(ok)}</li>" for label, ok in checks)
    overall = "compliant" if check["compliant"] else '<span class="bad">NOT compliant</span>'
    return (
        f"<h3>{_text(name)}: EN 1998-1 type {_text(target['spectrum_type'])}, ground "
        f"{_text(target['ground_type'])}, a<sub>g</sub>·S = {surface:.4g} m/s²</h3>\n"
        + _table(headers, rows, text_columns=(0,))
        + f"\n{displacement}<ul>{items}</ul>\n<p>Overall: {overall}.</p>"
    )


def _warnings(attributes: dict[str, Any]) -> str:
    warnings = json.loads(attributes.get("warnings", "[]"))
    if not warnings:
        return ""
    items = "".join(f"<li>{_text(w)}</li>" for w in warnings)
    return f"<h2>Warnings</h2>\n<ul>{items}</ul>"


def _table(headers: Sequence[str], rows: Iterable[Sequence[Any]], text_columns=()) -> str:
    def cell(tag: str, index: int, value: Any) -> str:
        kind = ' class="text"' if index in text_columns else ""
        return f"<{tag}{kind}>{_text(value)}</{tag}>"

    head = "".join(cell("th", i, h) for i, h in enumerate(headers))
    body = "".join(
        "<tr>" + "".join(cell("td", i, v) for i, v in enumerate(row)) + "</tr>" for row in rows
    )
    table = f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
    return f'<div class="scroll">{table}</div>'


def _cell(value: Any, scale: float) -> str:
    if isinstance(value, (float, np.floating)):
        return "-" if not np.isfinite(value) else f"{_rounded(float(value)) * scale:.4g}"
    if isinstance(value, (int, np.integer)):
        return "-" if value < 0 else str(int(value))
    return str(value)


def _rounded(value: float) -> float:
    return 0.0 if abs(value) < ROUND_OFF else value


def _number(value: float | None) -> str:
    return "-" if value is None else f"{value:.3g}"


def _text(value: Any) -> str:
    return html.escape(str(value))


def _plain(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value

"""The report's sections on its inputs: the records the study read, as read, and the EN 1998-1
compliance of the generated record sets among them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..motions.intensity import MEASURES
from ..records.set_files import read_manifest
from .markup import MAX_ROWS, escaped, number, table_html

RECORD_COLUMNS = (
    ("source", "source"), ("file units", "file_units"), ("dt [s]", "time_step"),
    ("duration [s]", "duration"), (MEASURES["pga_g"].label, "pga_g"),
    (MEASURES["pgv"].label, "pgv"),
    ("earthquake", "earthquake"), ("year", "year"), ("M", "magnitude"), ("station", "station"),
    ("R_rup [km]", "distance_rrup_km"), ("T_p [s]", "pulse_period_s"),
    ("pulse PI", "pulse_indicator"),
)  # fmt: skip
"""The columns of the table of input records: heading, attribute of ``/records/<id>``. T_p is
the period of the record's velocity pulse, "-" without one, and PI Shahi & Baker's indicator
(> 0 for a pulse; `motions.pulse_identification`)."""


def records_table(group: Any) -> str:
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
    return "<h2>Input records</h2>\n" + table_html(["record", *(h for h, _ in shown)], table,
                                                 text_columns=texts) + more  # fmt: skip


TEXT_RECORD_KEYS = {"source", "file_units", "earthquake", "station"}


def _record_cell(value: Any) -> str:
    """An attribute of a record as a cell: numbers to 3 digits, "-" where absent or NaN."""
    if isinstance(value, float):
        return number(value) if np.isfinite(value) else "-"
    return "-" if value is None else str(value)


def record_sets(attributes: dict[str, Any], sources: dict[str, str]) -> str:
    """The EN 1998-1 §3.2.3.1.2 check of each generated record set the study read, from the
    set's manifest (found from the record sources, relative to the study file)."""
    study_folder = Path(str(attributes.get("study_file", "."))).parent
    folders = dict.fromkeys((study_folder / source).parent for source in sources.values() if source)
    parts = []
    for folder in folders:
        try:
            parts.append(_compliance(folder.name, read_manifest(folder)))
        except (InputError, KeyError, TypeError):  # not a generated set, or unreadable
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
        f"<h3>{escaped(name)}: EN 1998-1 type {escaped(target['spectrum_type'])}, ground "
        f"{escaped(target['ground_type'])}, a<sub>g</sub>·S = {surface:.4g} m/s²</h3>\n"
        + table_html(headers, rows, text_columns=(0,))
        + f"\n{displacement}<ul>{items}</ul>\n<p>Overall: {overall}.</p>"
    )

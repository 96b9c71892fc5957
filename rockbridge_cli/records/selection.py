"""A record set selected from a pool of recorded motions and scaled to an EN 1998-1 spectrum
(`select_record_set`): the pool's spectra computed once, the choice and its factors
(`motions.selection`), the raise EN 1998-1 §3.2.3.1.2(4)b–c asks, the check on the dense period
grid (`motions.spectral_fit.dense_periods`), and the set written as `sets.generate_record_set`
writes one (record files, a manifest any study reads with ``records: {set: ...}``), with its
compliance table (`compliance_text`, also in ``compliance.txt``)."""

from __future__ import annotations

import hashlib
import json
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..motions import baseline, ec8, selection, spectra, spectral_fit
from ..paths import replace_folder, writable
from .files import Record, write_record
from .manifest import compliance_entries, motion_entries, round_floats
from .pool import Candidate, FemaSource, PoolFolder, read_pool
from .selection_files import build_manifest, record_header
from .set_files import COMPLIANCE, MANIFEST, holds_a_set, output_folder
from .summary import RecordSummary
from .target import TargetDefinition, UserSpectrum


@dataclass(frozen=True)
class SelectionRequest:
    """What to select, in SI units (`config.selection.SelectionConfig.request`).

    Attributes
    ----------
    fema, folders
        the pool's sources.
    target
        the EN 1998-1 target.
    periods
        the period range [s].
    period_count
        log-spaced periods of the selection over it [-].
    count, max_per_earthquake, max_per_recording
        the set's size and caps [-].
    bounds
        lowest and highest scale factor [-].
    dispersion_weight
        w of `motions.selection` [-].
    gravity
        for values in g [m/s²].
    config
        the config as the manifest stores it.
    spectrum
        a spectrum of the user's that replaces Se(T) over the periods (the fit and (4)c); None:
        EN 1998-1's.
    mean_ratio
        the share of the target the raise brings the mean to, >= 0.9 [-].
    """

    fema: tuple[FemaSource, ...]
    folders: tuple[PoolFolder, ...]
    target: TargetDefinition
    periods: tuple[float, float]
    period_count: int
    count: int
    max_per_earthquake: int
    max_per_recording: int
    bounds: tuple[float, float]
    dispersion_weight: float
    gravity: float
    config: dict[str, Any]
    spectrum: UserSpectrum | None = None
    mean_ratio: float = selection.MEAN_RATIO

    def goal(self, periods: np.ndarray) -> np.ndarray:
        """The target at the periods: the user's spectrum, or Se [m/s²]."""
        if self.spectrum is not None:
            return self.spectrum.evaluate(periods)
        return self.target.evaluate(periods)


@dataclass(frozen=True)
class Check:
    """One row of the compliance table: what is checked, its value, what is required, whether
    it holds."""

    label: str
    value: str
    required: str
    ok: bool


@dataclass(frozen=True)
class SelectionReport:
    """The outcome of `select_record_set`.

    Attributes
    ----------
    folder
        where the set was written.
    chosen
        the chosen candidates, in the pool's order.
    factors
        their scale factors, raised [-].
    multiplier
        the common raise of EN 1998-1 (4)b–c (`motions.selection.code_multiplier`), 1 if none [-].
    compliance
        EN 1998-1 §3.2.3.1.2(4) on the dense grid.
    lowest_period
        where the mean spectrum is lowest against the target, on the dense grid [s].
    checks
        the compliance table's rows.
    choice
        the objective's value and parts (`motions.selection.Selection`).
    pool_size, usable
        candidates read, and those usable over the period range [-].
    dense_periods
        periods of the dense grid [-].
    selection_time, wall_time
        time to compute the pool's spectra and choose; to read, choose and write [s].
    selection_cpu
        the process's CPU time to compute the pool's spectra and choose [s] (the first run
        after an install includes compiling the spectra kernel).
    """

    folder: Path
    chosen: tuple[Candidate, ...]
    factors: tuple[float, ...]
    multiplier: float
    compliance: ec8.ComplianceReport
    lowest_period: float
    checks: tuple[Check, ...]
    choice: selection.Selection
    pool_size: int
    usable: int
    dense_periods: int
    selection_time: float
    wall_time: float
    selection_cpu: float = 0.0


def select_record_set(
    request: SelectionRequest, folder: str | Path, config_name: str = "", source: str | Path = "",
    overwrite: bool = False,
) -> SelectionReport:  # fmt: skip
    """Select and scale a record set from the pool, check it and write it (module docstring).

    ``source`` (the config file) names what a refusal refuses; ``config_name`` goes in the
    manifest; ``overwrite`` lets the set replace a record set in ``folder``.

    Raises
    ------
    InputError
        ``folder`` holds files that are not a record set's, a set without ``overwrite``, or
        is a folder of the pool; a candidate cannot be read; the pool cannot meet a rule
        (which, and by how much).
    """
    started = time.perf_counter()
    folder = _check_folder(writable(folder, folder=True), request.folders, overwrite)
    pool = read_pool(request.fema, request.folders)
    usable = [c for c in pool if not c.lowest_usable_frequency > 1.0 / request.periods[1]]
    timer, cpu = time.perf_counter(), time.process_time()
    grid = np.geomspace(*request.periods, request.period_count)
    damping = request.target.damping
    computed = np.array([spectra.compute_psa(c.record.acceleration, c.record.time_step, grid,
                                             damping) for c in usable])  # fmt: skip
    log_target = np.log(request.goal(grid))
    choice = _choose(request, usable, np.log(computed), log_target, source or "pool")
    selection_time, selection_cpu = time.perf_counter() - timer, time.process_time() - cpu
    chosen = tuple(usable[i] for i in choice.indices)
    dense = spectral_fit.dense_periods(request.periods, damping)
    goal = request.goal(dense)
    unscaled = np.array([spectra.compute_psa(c.record.acceleration, c.record.time_step, dense,
                                             damping) for c in chosen])  # fmt: skip
    peaks = np.array([c.record.peak_acceleration for c in chosen])
    factors = np.array(choice.factors)
    multiplier = selection.code_multiplier(unscaled, goal, peaks, request.target.surface_pga,
                                           factors, request.mean_ratio)  # fmt: skip
    factors = factors * multiplier
    _check_bounds(request, chosen, factors, multiplier, source or "pool")
    compliance = ec8.check_compliance(factors[:, None] * unscaled, goal, factors * peaks,
                                      request.target.surface_pga)  # fmt: skip
    records = [_scaled(c, f) for c, f in zip(chosen, factors, strict=True)]
    lowest = float(dense[np.argmin((factors[:, None] * unscaled).mean(axis=0) / goal)])
    checks = _checks(request, chosen, factors, compliance, lowest)
    report = SelectionReport(folder, chosen, tuple(float(f) for f in factors), multiplier,
                             compliance, lowest, tuple(checks), choice, len(pool), len(usable),
                             dense.size, selection_time, 0.0, selection_cpu)  # fmt: skip
    summaries = [_summary(r, dense, goal, f * s) for r, f, s in zip(records, factors, unscaled,
                                                                   strict=True)]  # fmt: skip
    _write(request, report, records, summaries, config_name)
    return SelectionReport(**{**report.__dict__, "wall_time": time.perf_counter() - started})


def _check_folder(folder: Path, read: tuple[PoolFolder, ...], overwrite: bool) -> Path:
    """The output folder, once it is neither a folder of the pool nor holds one, and is new,
    empty or a record set ``overwrite`` lets the new one replace (`set_files.output_folder`)."""
    for source in read:
        if folder.resolve() == source.path.resolve() or folder.resolve() in source.path.resolve(
        ).parents:  # fmt: skip
            raise InputError(folder, [("", f"would replace the pool's folder {source.path}: "
                                       "give another output folder")])  # fmt: skip
    return output_folder(folder, overwrite)


def _choose(request, usable, log_spectra, log_target, source) -> selection.Selection:
    """`motions.selection.select_records` on the usable candidates; a pool whose caps admit too
    few is refused with the rule."""
    caps = [("max_per_earthquake", np.array([c.earthquake for c in usable]),
             request.max_per_earthquake),
            ("max_per_recording", np.array([c.recording for c in usable]),
             request.max_per_recording)]  # fmt: skip
    try:
        return selection.select_records(log_spectra, log_target, request.count, request.bounds,
                                        [(label, cap) for _, label, cap in caps],
                                        request.dispersion_weight)  # fmt: skip
    except selection.PoolTooSmall as short:
        rule, _, cap = caps[int(short.rule.split()[-1])]
        earthquakes = len({c.earthquake for c in usable})
        why = (f"{request.count} records at most {cap} per {rule.split('_')[-1]}: the pool's "
               f"{len(usable)} usable candidates ({earthquakes} earthquakes) admit "
               f"{short.available}, short by {request.count - short.available}")  # fmt: skip
        raise InputError(source, [(f"rules.{rule}", why)]) from None


def _check_bounds(request, chosen, factors, multiplier, source) -> None:
    """Refuse a set whose raise takes a factor past the highest bound, saying by how much."""
    high = request.bounds[1]
    worst = int(np.argmax(factors))
    if factors[worst] <= high * (1.0 + 2 * selection.RAISE_MARGIN):
        return
    why = (f"EN 1998-1 §3.2.3.1.2(4)b-c need the chosen set raised x{multiplier:.4g}, which "
           f"takes {chosen[worst].record.name}'s factor to {factors[worst]:.4g}, above the "
           f"highest {high:g} by {factors[worst] - high:.3g}")  # fmt: skip
    raise InputError(source, [("rules.scale_factor", why)])


def _scaled(candidate: Candidate, factor: float) -> Record:
    """The record scaled, its factor (times any the source applied) in its metadata."""
    record = candidate.record
    meta = {**record.metadata, "earthquake_key": candidate.earthquake,
            "recording": candidate.recording, "source": record.source,
            "scale_factor": factor * record.metadata.get("scale_factor", 1.0)}  # fmt: skip
    return Record(record.name, record.time_step, factor * record.acceleration, "select-records",
                  meta)  # fmt: skip


def _checks(request: SelectionRequest, chosen, factors, compliance, argmin) -> list[Check]:
    """The rows of the compliance table."""
    g, (low, high) = request.gravity, request.periods
    per_quake = max([c.earthquake for c in chosen].count(c.earthquake) for c in chosen)
    per_recording = max([c.recording for c in chosen].count(c.recording) for c in chosen)
    bounds = request.bounds
    return [
        Check("(4)a records", f"{compliance.count}", ">= 3 (>= 7 to use means, §4.3.3.4.3)",
              compliance.count_ok),
        Check("(4)b mean PGA [g]", f"{compliance.mean_zero_period / g:.4f}",
              f">= a_g*S = {compliance.surface_pga / g:.4f}", compliance.zero_period_ok),
        Check(f"(4)c mean/target, min over {low:g}-{high:g} s",
              f"{compliance.mean_min_ratio:.4f} at {argmin:.3f} s",
              ">= 0.9" + (f" (aim {request.mean_ratio:g})" if request.mean_ratio > 0.9 else ""),
              compliance.mean_ok),
        Check("records per earthquake, most", f"{per_quake}", f"<= {request.max_per_earthquake}",
              per_quake <= request.max_per_earthquake),
        Check("components per recording, most", f"{per_recording}",
              f"<= {request.max_per_recording}", per_recording <= request.max_per_recording),
        Check("scale factors", f"{factors.min():.4g}-{factors.max():.4g}",
              f"{bounds[0]:g}-{bounds[1]:g}",
              bool(bounds[0] * (1 - 1e-9) <= factors.min() and factors.max() <= bounds[1] * (
                  1 + 2 * selection.RAISE_MARGIN))),
    ]  # fmt: skip


def _summary(record: Record, dense, goal, scaled_spectrum) -> RecordSummary:
    """A scaled record's fit on the dense grid, peaks and durations, as a manifest gives them."""
    ratios = scaled_spectrum / goal
    velocity, displacement = baseline.compute_final_motion(record.acceleration, record.time_step)
    motion = baseline.integrate_motion(record.acceleration, record.time_step)
    return RecordSummary(
        record.name, f"{record.name}.txt", record.peak_acceleration, float(ratios.min()),
        float(ratios.max()), velocity, displacement, float(np.max(np.abs(motion[0]))),
        float(np.max(np.abs(motion[1]))),
        baseline.compute_significant_duration(record.acceleration, record.time_step), 0, 0,
        spectral_fit.SpectralFit(dense, ratios, np.zeros(dense.size, bool)),
        float(record.metadata["scale_factor"]),
    )  # fmt: skip


def _write(request, report, records, summaries, config_name) -> None:
    """The record files, the manifest and the compliance table, staged beside the folder and
    swapped in whole."""
    folder = report.folder
    staging = folder.with_name(f".{folder.name}.partial-{os.getpid()}")
    staging.mkdir()
    for index, record in enumerate(records):
        write_record(staging / f"{record.name}.txt", record,
                     record_header(request, index, record))  # fmt: skip
    manifest = build_manifest(request, config_name, report, records, [
        motion_entries(s, request.gravity) for s in summaries], compliance_entries(
        report.compliance))  # fmt: skip
    manifest = round_floats(manifest)
    for entry in manifest["records"]:  # a study verifies them (`set_files.check_set_file`)
        entry["sha256"] = hashlib.sha256((staging / entry["file"]).read_bytes()).hexdigest()
    (staging / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")
    (staging / COMPLIANCE).write_text(compliance_text(request, report) + "\n", encoding="utf-8")
    replace_folder(staging, folder, keep=holds_a_set)


def compliance_text(request: SelectionRequest, report: SelectionReport) -> str:
    """The chosen records and the compliance table, as text (no times: the same config gives
    the same text)."""
    g, (low, high) = request.gravity, request.periods
    lines = [
        f"Selected {len(report.chosen)} of {report.usable} usable candidates ({report.pool_size} "
        f"in the pool) to EN 1998-1 type {request.target.spectrum_type}, ground "
        f"{request.target.ground_type}, a_g = {request.target.design_acceleration / g:.4g} g, "
        f"over {low:g}-{high:g} s"
        + ("" if request.spectrum is None else f", Se replaced by {request.spectrum.source}"),
        f"  objective {report.choice.objective:.5f} = mean-log misfit "
        f"{report.choice.misfit:.5f} + {request.dispersion_weight:g} x dispersion "
        f"{report.choice.dispersion:.5f}; common raise x{report.multiplier:.4f}",
        f"  {'record':<8} {'earthquake':<24} {'station':<26} {'M':>4} {'Rrup[km]':>8} "
        f"{'factor':>7} {'PGA[g]':>7} {'min':>6} {'max':>6}",
    ]
    c = report.compliance
    for index, (candidate, factor) in enumerate(zip(report.chosen, report.factors, strict=True)):
        meta = candidate.record.metadata
        lines.append(
            f"  {candidate.record.name:<8} {candidate.earthquake[:24]:<24} "
            f"{str(meta.get('station', '-'))[:26]:<26} {meta.get('magnitude', '-'):>4} "
            f"{meta.get('distance_rrup_km', '-'):>8} {factor:7.4f} "
            f"{factor * candidate.record.peak_acceleration / g:7.4f} "
            f"{c.record_min_ratio[index]:6.3f} {c.record_max_ratio[index]:6.3f}"
        )
    lines += [
        f"Compliance, on the dense grid ({report.dense_periods} periods over {low:g}-{high:g} s):",
        f"  {'check':<36} {'value':<22} {'required':<40} verdict",
        *(f"  {c.label:<36} {c.value:<22} {c.required:<40} {'pass' if c.ok else 'FAIL'}"
          for c in report.checks),
        "  (§3.2.3.1.3: records consistent with the site's earthquakes - magnitude, distance, "
        "source - is the designer's to judge; the table above gives them)",
        f"  overall: {'compliant' if all(c.ok for c in report.checks) else 'NOT compliant'}",
    ]  # fmt: skip
    return "\n".join(lines)

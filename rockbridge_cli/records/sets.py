"""Record sets: artificial accelerograms matched to an EN 1998-1 spectrum (`generate_record_set`),
with vertical components matched to its vertical spectrum if asked for, or recorded seeds
matched or scaled to it, with the manifest that describes them, the compliance
check of EN 1998-1 §3.2.3.1.2, the fit on a dense period grid (`spectral_fit`) and, for matched
seeds, what the matching changed of each seed."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import re
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config.record_sets import RecordSetConfig
from ..config.records import FemaSet
from ..motions import baseline, ec8, matching, seeds, spectra, spectral_fit
from ..paths import replace_folder, writable
from .fema import read_fema_set
from .files import PROVENANCE, Record, read_record, write_record
from .manifest import add_verticals, build_manifest, checks_dense, record_header, round_floats
from .set_files import MANIFEST, holds_a_set, output_folder
from .summary import RecordSummary, SeedChange
from .target import TargetDefinition, resolve_target

GROUND_DISPLACEMENT_AIM = 2.0
"""The peak ground displacement a matched record should stay within, as a multiple of EN 1998-1's
d_g (§3.2.2.4): rockbridge's aim, not a rule of the code; the compliance report states it. The
least-displacement baseline correction (`baseline.BaselineCorrection`) keeps the bundled sets
at 0.9–1.9 d_g."""

SEED_GROUND_GROWTH = 1.25
"""A matched seed's PGD may reach this multiple of the seed's linearly scaled to the target PGA,
or `GROUND_DISPLACEMENT_AIM` d_g where that is larger; the same for its PGV with v_g
(`TargetDefinition.ground_velocity`) [-]."""


@dataclass(frozen=True)
class RecordSetReport:
    """The outcome of `generate_record_set`.

    Attributes
    ----------
    folder
        where the set was written.
    records
        one summary per record.
    compliance
        the EN 1998-1 §3.2.3.1.2 check over the band.
    band
        the checked periods' range [s].
    check_periods
        number of checked periods [-].
    wall_time
        time taken to generate and write the set [s].
    ground_displacement
        EN 1998-1's design ground displacement d_g of the target [m].
    dense_periods
        periods of the dense grid over the band [-].
    dense_tolerance
        whether the config's tolerance is checked on the dense grid (matched seeds) rather than
        at the check periods (artificial records, which the generator matches there).
    vertical
        the same for the records' vertical components, matched to the vertical spectrum; None
        without.
    """

    folder: Path
    records: tuple[RecordSummary, ...]
    compliance: ec8.ComplianceReport
    band: tuple[float, float]
    check_periods: int
    wall_time: float
    ground_displacement: float
    dense_periods: int = 0
    dense_tolerance: bool = False
    vertical: RecordSetReport | None = None


def generate_record_set(
    config: RecordSetConfig, folder: str | Path, config_name: str = "", overwrite: bool = False
) -> RecordSetReport:
    """Generate a matched record set and write it: one rockbridge file per record + manifest.

    Artificial record i uses ``numpy.random.default_rng`` seeded with child i of
    ``numpy.random.SeedSequence(config.seed)``, so the same config gives the same bytes with the
    same numpy and scipy (other releases move the last printed digit of some samples); its
    vertical component (``config.vertical``) child count + i, matched by the same generator to
    the vertical spectrum (`TargetDefinition.vertical_component`). A
    recorded seed is matched with its phases, envelope, ground motion and durations kept
    (`seeds.match_seed`), first resampled if its time step cannot resolve the band.

    Parameters
    ----------
    config
        the record-set config.
    folder
        output folder: new, empty, or with ``overwrite`` a record set, which the new set
        replaces whole (it is written beside it and swapped in, so that a reader never finds a
        mix of the two; `set_files.output_folder`).
    config_name
        name of the config (e.g. its file stem), stored in the manifest.
    overwrite
        whether a record set in ``folder`` may be replaced.

    Raises
    ------
    InputError
        A seed cannot be read, or ``folder`` holds files that are not a record set's, or a
        set without ``overwrite``.
    """
    started = time.perf_counter()
    folder = output_folder(writable(folder, folder=True), overwrite)  # refused before the work
    target = resolve_target(config)
    settings = match_settings(config, target)
    made = _matched_seeds(config, target, settings) if config.seeds is not None else _synthesised(
        config, target, settings)  # fmt: skip
    records = [record for record, _, _ in made]
    check = np.geomspace(*config.band, config.check_periods)
    summaries, compliance = _summarise(made, check, target, config)
    vertical = target.vertical_component() if config.vertical else None
    if vertical is not None:
        uprights = _synthesised(config, vertical, settings)
        vertical_summaries, vertical_compliance = _summarise(uprights, check, vertical, config)
    staging = folder.with_name(f".{folder.name}.partial-{os.getpid()}")
    staging.mkdir()
    written = [(target, records)] + ([(vertical, [r for r, _, _ in uprights])] if vertical else [])
    for aim, motions in written:
        for index, record in enumerate(motions):
            header = record_header(config, aim, index, record)
            write_record(staging / f"{record.name}.txt", record, header)
    manifest = build_manifest(config, config_name, target, records, summaries, compliance)
    if vertical is not None:
        add_verticals(manifest, config, vertical, vertical_summaries, vertical_compliance)
    manifest = round_floats(manifest)
    for entry in manifest["records"]:  # a study verifies them (`set_files.check_set_file`)
        for item in [entry] + ([entry["vertical"]] if "vertical" in entry else []):
            item["sha256"] = hashlib.sha256((staging / item["file"]).read_bytes()).hexdigest()
    (staging / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")
    replace_folder(staging, folder, keep=holds_a_set)
    report = RecordSetReport(
        folder,
        tuple(summaries),
        compliance,
        config.band,
        config.check_periods,
        time.perf_counter() - started,
        target.ground_displacement,
        spectral_fit.dense_periods(config.band, target.damping).size,
        checks_dense(config),
    )
    if vertical is None:
        return report
    upright = dataclasses.replace(report, records=tuple(vertical_summaries),
                                  compliance=vertical_compliance)  # fmt: skip
    return dataclasses.replace(report, vertical=upright)


def match_settings(config: RecordSetConfig, target: TargetDefinition) -> matching.MatchSettings:
    """How closely and how hard the records of a config are matched."""
    return matching.MatchSettings(
        tolerance=config.tolerance,
        max_iterations=config.max_iterations,
        max_attempts=config.attempts,
        damping=target.damping,
        # A seed's worst misfit jumps about under the duration rows while its RMS misfit still
        # falls: it runs its iterations out (FEMA P695 FF11a: 0.952–1.094 after 25, where the
        # artificial records' patience of 6 left it at 0.784–1.155).
        **({"patience": config.max_iterations} if checks_dense(config) else {}),
    )


Made = tuple[Record, matching.MatchedRecord, "SeedChange | None"]
"""A record of the set, how its matching went, and what it changed of its seed."""


def _synthesised(config, target, settings) -> list[Made]:
    """``config.count`` artificial records from random phases: the horizontal ones, or for a
    vertical ``target`` their vertical components (``<name>-V``, children count … 2·count − 1
    of the seed sequence, so that the horizontal records stay as they are without them)."""
    assert config.count and config.time_step and config.envelope and config.seed is not None
    periods = matching.compute_matching_periods(config.band, config.check_periods, config.time_step)
    envelope = matching.Envelope(
        config.envelope.rise,
        config.envelope.stationary,
        config.envelope.decay,
        config.envelope.end_level,
    )
    goal = target.evaluate(periods, extrapolate=True)
    width = max(2, len(str(config.count)))
    made: list[Made] = []
    children = np.random.SeedSequence(config.seed).spawn(2 * config.count)
    offset, suffix = (config.count, "-V") if target.vertical else (0, "")
    for index, child in enumerate(children[offset : offset + config.count]):
        matched = matching.generate_matched_record(
            periods, goal, target.surface_pga, config.time_step, envelope,
            np.random.default_rng(child), settings, band=config.band,
        )  # fmt: skip
        name = f"{config.name_prefix}{index + 1:0{width}d}{suffix}"
        made.append((Record(name, config.time_step, matched.acceleration, "generate-records"),
                     matched, None))  # fmt: skip
    return made


def _matched_seeds(config, target, settings) -> list[Made]:
    """One record per seed (EN 1998-1 §3.2.3.1.3): matched at the seed's own time step, or one
    that resolves the band (`seeds.resample_for_band`); scaled without changing its shape
    (`ec8.scale_factors`); or as read (``adjust: none``)."""
    found = _read_seeds(config)
    factors = _scale_factors(config, target, found) if config.adjust.startswith("scale") else None
    made: list[Made] = []
    for index, seed in enumerate(found):
        metadata = dict(seed.metadata)
        if config.adjust == "match":
            samples, step = seeds.resample_for_band(seed.acceleration, seed.time_step,
                                                    config.band[0])  # fmt: skip
            resampled = None if step == seed.time_step else (seed.time_step, step)
            if resampled:
                metadata["resampled_from_s"] = seed.time_step
            matched = seeds.match_seed(
                lambda periods: target.evaluate(periods, extrapolate=True), config.band,
                target.surface_pga, samples, step, settings, config.check_periods)  # fmt: skip
            change = compare_with_seed(matched, samples, target, resampled)
        else:
            factor = 1.0 if factors is None else float(factors[index])
            metadata["scale_factor"] = factor * metadata.get("scale_factor", 1.0)
            matched = matching.MatchedRecord(factor * seed.acceleration, seed.time_step,
                                             0, 0, float("nan"))  # fmt: skip
            change = None
        made.append((Record(seed.name, matched.time_step, matched.acceleration,
                            "generate-records", metadata), matched, change))  # fmt: skip
    return made


def compare_with_seed(
    matched: matching.MatchedRecord,
    seed: np.ndarray,
    target: TargetDefinition,
    resampled: tuple[float, float] | None = None,
) -> SeedChange:
    """The matched record's traits beside those of its seed [m/s²] (at the matched record's
    time step) scaled to the target PGA, and the bounds of its PGV and PGD."""
    scaled = seed * (target.surface_pga / np.max(np.abs(seed)))
    before = seeds.MotionTraits.of(scaled, matched.time_step)
    return SeedChange(
        seeds.MotionTraits.of(matched.acceleration, matched.time_step),
        before,
        max(SEED_GROUND_GROWTH * before.pgv, GROUND_DISPLACEMENT_AIM * target.ground_velocity),
        max(SEED_GROUND_GROWTH * before.pgd,
            GROUND_DISPLACEMENT_AIM * target.ground_displacement),
        resampled,
    )  # fmt: skip


def _read_seeds(config: RecordSetConfig) -> list[Record]:
    """The seeds as read, named as the set will name them, with their provenance as metadata.

    Raises
    ------
    InputError
        A seed cannot be read.
    """
    if isinstance(config.seeds, FemaSet):
        fema = config.seeds
        return [
            Record(r.name, r.time_step, r.acceleration, r.source,
                   {key: r.metadata[key] for key in PROVENANCE if key in r.metadata})
            for r in read_fema_set(fema.name, tuple(fema.components), fema.normalize,
                                   None if fema.records is None else tuple(fema.records))
        ]  # fmt: skip
    else:
        assert config.seeds is not None
        return [
            Record(entry.id or re.sub(r"[^A-Za-z0-9_.+-]", "_", Path(entry.path).stem),
                   record.time_step, record.acceleration, record.source,
                   {"seed_file": Path(entry.path).name})
            for entry in config.seeds
            for record in [read_record(entry.path, units=entry.units, time_step=entry.time_step)]
        ]  # fmt: skip


def _scale_factors(config, target, found: list[Record]) -> np.ndarray:
    """The factors of the seeds, at the check periods of the band."""
    check = np.geomspace(config.band[0], config.band[1], config.check_periods)
    computed = np.array(
        [spectra.compute_psa(s.acceleration, s.time_step, check, target.damping) for s in found]
    )
    peaks = np.array([s.peak_acceleration for s in found])
    return ec8.scale_factors(computed, target.evaluate(check), peaks, target.surface_pga,
                             individual=config.adjust == "scale")  # fmt: skip


def _summarise(made: list[Made], check, target, config):
    """Per-record statistics, the EN 1998-1 check and the config's per-record tolerance: at the
    check periods, or for matched seeds on the dense grid (`_checks_dense`)."""
    records = [record for record, _, _ in made]
    goal = target.evaluate(check)
    computed = np.array(
        [spectra.compute_psa(r.acceleration, r.time_step, check, target.damping) for r in records]
    )
    compliance = ec8.check_compliance(
        computed,
        goal,
        np.array([r.peak_acceleration for r in records]),
        target.surface_pga,
        config.envelope.stationary if config.envelope else None,  # not for recorded motions
        config.tolerance if config.adjust == "match" else None,  # scaling keeps their shapes
    )
    fits = [spectral_fit.measure_fit(r.acceleration, r.time_step, target.evaluate, config.band,
                                     target.damping) for r in records]  # fmt: skip
    if checks_dense(config):
        compliance = dataclasses.replace(
            compliance,
            record_min_ratio=tuple(fit.min_ratio for fit in fits),
            record_max_ratio=tuple(fit.max_ratio for fit in fits),
        )
    summaries = []
    for (record, matched, change), low, high, fit in zip(
        made, compliance.record_min_ratio, compliance.record_max_ratio, fits, strict=True
    ):
        velocity, displacement = baseline.compute_final_motion(
            record.acceleration, record.time_step
        )
        motion = baseline.integrate_motion(record.acceleration, record.time_step)
        summaries.append(
            RecordSummary(
                record.name,
                f"{record.name}.txt",
                record.peak_acceleration,
                low,
                high,
                velocity,
                displacement,
                float(np.max(np.abs(motion[0]))),
                float(np.max(np.abs(motion[1]))),
                baseline.compute_significant_duration(record.acceleration, record.time_step),
                matched.attempts,
                matched.iterations,
                fit,
                None if config.adjust == "match" else record.metadata.get("scale_factor"),
                change,
            )
        )
    return summaries, compliance

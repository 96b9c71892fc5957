"""Record sets: artificial accelerograms matched to an EN 1998-1 spectrum (`generate_record_set`),
or recorded seeds matched or scaled to it, with the manifest that describes them, the compliance
check of EN 1998-1 §3.2.3.1.2, the fit on a dense period grid (`spectral_fit`) and, for matched
seeds, what the matching changed of each seed."""

from __future__ import annotations

import dataclasses
import json
import platform
import re
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy

from .. import __version__
from ..config.records import FemaSet, RecordSetConfig
from ..errors import InputError
from ..motions import baseline, ec8, matching, seeds, spectra, spectral_fit
from ..paths import writable
from .fema import read_fema_set
from .files import MANIFEST, PROVENANCE, Record, read_manifest, read_record, write_record

GROUND_DISPLACEMENT_AIM = 2.0
"""The peak ground displacement a matched record should stay within, as a multiple of EN 1998-1's
d_g (§3.2.2.4): rockbridge's aim, not a rule of the code; the compliance report states it. The
least-displacement baseline correction (`baseline.BaselineCorrection`) keeps the bundled sets
at 0.9–1.9 d_g."""

SEED_GROUND_GROWTH = 1.25
"""A matched seed's PGD may reach this multiple of the seed's linearly scaled to the target PGA,
or `GROUND_DISPLACEMENT_AIM` d_g where that is larger; the same for its PGV with v_g
(`TargetDefinition.ground_velocity`) [-]."""

SEED_CHANGE = 0.25
"""The report flags a matched seed whose D5–95, D5–75 or PGV changed by more than this share of
the seed's (the PGV of the seed scaled to the target PGA), or whose Arias time moved by more
than this share of its D5–95 [-]."""


@dataclass(frozen=True)
class SeedChange:
    """What matching did to a seed: the matched record's traits beside the seed's, the seed
    linearly scaled to the target PGA.

    Attributes
    ----------
    record, seed
        their PGV, PGD, D5–95, D5–75 and Arias time (`seeds.MotionTraits`).
    pgv_bound, pgd_bound
        the largest PGV [m/s] and PGD [m] the matched record may have (`SEED_GROUND_GROWTH`).
    resampled
        the seed's own time step and the one it was resampled to, to resolve the band [s]; None
        where it was matched at its own.
    """

    record: seeds.MotionTraits
    seed: seeds.MotionTraits
    pgv_bound: float
    pgd_bound: float
    resampled: tuple[float, float] | None

    @property
    def ground_ok(self) -> bool:
        """PGV and PGD within their bounds."""
        return self.record.pgv <= self.pgv_bound and self.record.pgd <= self.pgd_bound

    @property
    def flags(self) -> tuple[str, ...]:
        """The traits that changed by more than `SEED_CHANGE`."""
        new, old = self.record, self.seed
        changes = {
            "PGV": new.pgv / old.pgv - 1.0,
            "D5-95": new.d5_95 / old.d5_95 - 1.0,
            "D5-75": new.d5_75 / old.d5_75 - 1.0,
            "Arias time": (new.arias_time - old.arias_time) / old.d5_95,
        }
        return tuple(name for name, change in changes.items() if abs(change) > SEED_CHANGE)


@dataclass(frozen=True)
class RecordSummary:
    """How one generated record turned out.

    Attributes
    ----------
    name, file
        record name and file name in the set's folder.
    peak_acceleration
        PGA [m/s²].
    min_ratio, max_ratio
        min and max over the check periods of computed / target spectrum [-].
    final_velocity, final_displacement
        ground velocity [m/s] and displacement [m] at the end of the record.
    peak_velocity, peak_displacement
        largest |ground velocity| [m/s] and |displacement| [m] over the record.
    significant_duration
        D5–95 [s].
    attempts, iterations
        phase sets tried and matching iterations of the kept one [-].
    scale_factor
        the factor of a seed scaled rather than matched (`ec8.scale_factors`) [-], else None.
    fit
        the ratio to the target on the dense grid, every local extreme refined
        (`spectral_fit.measure_fit`).
    seed_change
        what the matching changed of a matched seed, else None.
    """

    name: str
    file: str
    peak_acceleration: float
    min_ratio: float
    max_ratio: float
    final_velocity: float
    final_displacement: float
    peak_velocity: float
    peak_displacement: float
    significant_duration: float
    attempts: int
    iterations: int
    fit: spectral_fit.SpectralFit
    scale_factor: float | None = None
    seed_change: SeedChange | None = None


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


@dataclass(frozen=True)
class TargetDefinition:
    """The resolved target of a record set, in SI units.

    Attributes
    ----------
    spectrum_type, ground_type, damping
        as in the config.
    design_acceleration
        a_g [m/s²].
    surface_pga
        a_g·S, the records' PGA [m/s²].
    """

    spectrum_type: int
    ground_type: str
    damping: float
    design_acceleration: float
    surface_pga: float

    @property
    def ground_displacement(self) -> float:
        """EN 1998-1's design ground displacement d_g [m] (`ec8.design_ground_displacement`)."""
        return ec8.design_ground_displacement(
            self.spectrum_type, self.ground_type, self.design_acceleration
        )

    @property
    def ground_velocity(self) -> float:
        """v_g = 2π·d_g/T_D [m/s]: EN 1998-1 gives no design ground velocity; this one stands to
        d_g as the spectrum's pseudo-velocity to its displacement at T_D, where its constant
        velocity and constant displacement branches meet (0.64 m/s for type 1, ground C,
        a_g = 0.6 g)."""
        corner = ec8.get_spectrum_shape(self.spectrum_type, self.ground_type).corner_d
        return 2.0 * np.pi * self.ground_displacement / corner

    def evaluate(self, periods: np.ndarray, extrapolate: bool = False) -> np.ndarray:
        """Se at the given periods [m/s²]."""
        return ec8.compute_elastic_spectrum(
            periods,
            self.spectrum_type,
            self.ground_type,
            design_acceleration=self.design_acceleration,
            damping=self.damping,
            extrapolate=extrapolate,
        )


def resolve_target(config: RecordSetConfig) -> TargetDefinition:
    """a_g and a_g·S of a config in m/s², whichever of ``ag_g`` and ``pga_g`` it gives."""
    target = config.target
    soil = ec8.get_spectrum_shape(target.spectrum_type, target.ground_type).soil_factor
    if target.ag_g is not None:
        design = target.ag_g * config.gravity
    else:
        assert target.pga_g is not None  # the config gives exactly one of the two
        design = target.pga_g * config.gravity / soil
    return TargetDefinition(
        target.spectrum_type, target.ground_type, target.damping, design, design * soil
    )


def generate_record_set(
    config: RecordSetConfig, folder: str | Path, config_name: str = ""
) -> RecordSetReport:
    """Generate a matched record set and write it: one rockbridge file per record + manifest.

    Artificial record i uses ``numpy.random.default_rng`` seeded with child i of
    ``numpy.random.SeedSequence(config.seed)``, so the same config gives the same bytes. A
    recorded seed is matched with its phases, envelope, ground motion and durations kept
    (`seeds.match_seed`), first resampled if its time step cannot resolve the band.

    Parameters
    ----------
    config
        the record-set config.
    folder
        output folder (created if needed; files of the same names are replaced).
    config_name
        name of the config (e.g. its file stem), stored in the manifest.

    Raises
    ------
    InputError
        A seed cannot be read.
    """
    started = time.perf_counter()
    folder = writable(folder, folder=True)
    target = resolve_target(config)
    settings = match_settings(config, target)
    made = _matched_seeds(config, target, settings) if config.seeds is not None else _synthesised(
        config, target, settings)  # fmt: skip
    records = [record for record, _, _ in made]
    check = np.geomspace(*config.band, config.check_periods)
    summaries, compliance = _summarise(made, check, target, config)
    for index, record in enumerate(records):
        header = _record_header(config, target, index, record)
        write_record(folder / f"{record.name}.txt", record, header)
    manifest = _round_floats(
        _build_manifest(config, config_name, target, records, summaries, compliance)
    )
    (folder / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")
    return RecordSetReport(
        folder,
        tuple(summaries),
        compliance,
        config.band,
        config.check_periods,
        time.perf_counter() - started,
        target.ground_displacement,
        spectral_fit.dense_periods(config.band, target.damping).size,
        _checks_dense(config),
    )


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
        **({"patience": config.max_iterations} if _checks_dense(config) else {}),
    )


Made = tuple[Record, matching.MatchedRecord, "SeedChange | None"]
"""A record of the set, how its matching went, and what it changed of its seed."""


def _checks_dense(config: RecordSetConfig) -> bool:
    """Whether the set's tolerance is checked on the dense grid: for matched seeds, which
    `seeds.match_seed` matches there; artificial records keep the check periods they were
    matched at, so that the bundled sets' manifests stay as they were made."""
    return config.seeds is not None and config.adjust == "match"


def _synthesised(config, target, settings) -> list[Made]:
    """``config.count`` artificial records from random phases."""
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
    for index, child in enumerate(np.random.SeedSequence(config.seed).spawn(config.count)):
        matched = matching.generate_matched_record(
            periods, goal, target.surface_pga, config.time_step, envelope,
            np.random.default_rng(child), settings, band=config.band,
        )  # fmt: skip
        name = f"{config.name_prefix}{index + 1:0{width}d}"
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
    if _checks_dense(config):
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


def _record_header(
    config: RecordSetConfig, target: TargetDefinition, index: int, record: Record
) -> dict:
    pga = target.surface_pga if config.adjust == "match" else record.peak_acceleration
    return {
        "pga": pga,
        "pga_g": pga / config.gravity,
        **({"seed": config.seed} if config.seeds is None else record.metadata),
        "record_index": index,
        "target": f"{config.target.code} type {target.spectrum_type} ground {target.ground_type}"
        f" a_g={target.design_acceleration / config.gravity:g}g"
        f" damping={target.damping:g}",
        "generator": f"rockbridge {__version__}",
    }


def _build_manifest(config, config_name, target, records, summaries, compliance) -> dict[str, Any]:
    shape = ec8.get_spectrum_shape(target.spectrum_type, target.ground_type)
    return {
        "format": "rockbridge-record-set 1",
        "generator": f"rockbridge {__version__}",
        # The last printed digit of the samples depends on these (FFT and linear algebra).
        "environment": {
            "python": platform.python_version(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
        },
        "config_name": config_name,
        "config": config.model_dump(mode="json", by_alias=True),
        "target": {
            "code": config.target.code,
            "spectrum_type": target.spectrum_type,
            "ground_type": target.ground_type,
            "damping": target.damping,
            "soil_factor": shape.soil_factor,
            "corner_periods_s": [shape.corner_b, shape.corner_c, shape.corner_d],
            "design_acceleration_m_s2": target.design_acceleration,
            "surface_pga_m_s2": target.surface_pga,
            "ground_displacement_m": target.ground_displacement,
            "gravity_m_s2": config.gravity,
        },
        "check": {
            "band_s": list(config.band),
            "periods": config.check_periods,
            **(_dense_check(config, target) if config.seeds is not None else {}),
        },
        "seed": config.seed,
        "records": [
            {
                "name": s.name,
                "file": s.file,
                "record_index": index,
                "pga_m_s2": s.peak_acceleration,
                "pga_g": s.peak_acceleration / config.gravity,
                "min_ratio": s.min_ratio,
                "max_ratio": s.max_ratio,
                "final_velocity_m_s": s.final_velocity,
                "final_displacement_m": s.final_displacement,
                "pgv_m_s": s.peak_velocity,
                "pgd_m": s.peak_displacement,
                "d5_95_s": s.significant_duration,
                "stationary_duration_s": config.envelope.stationary if config.envelope else None,
                **(records[index].metadata if config.seeds is not None else {}),
                **(_seed_entries(s) if config.seeds is not None else {}),
                "attempts": s.attempts,
                "iterations": s.iterations,
            }
            for index, s in enumerate(summaries)
        ],
        "mean": {"min_ratio": compliance.mean_min_ratio, "max_ratio": compliance.mean_max_ratio},
        "compliance": {
            "count": compliance.count,
            "count_ok": compliance.count_ok,
            "mean_zero_period_m_s2": compliance.mean_zero_period,
            "zero_period_ok": compliance.zero_period_ok,
            "mean_ok": compliance.mean_ok,
            "stationary_ok": compliance.stationary_ok,
            "tolerance": compliance.tolerance,
            "records_ok": compliance.records_ok,
            "compliant": compliance.compliant,
        },
    }


def _dense_check(config: RecordSetConfig, target: TargetDefinition) -> dict[str, Any]:
    """How the manifest of a set of seeds states the dense grid."""
    return {
        "dense_periods": spectral_fit.dense_periods(config.band, target.damping).size,
        "dense_step_ln_period": spectral_fit.STEP * target.damping,
        "dense_extremes_refined_to_ln_period": spectral_fit.PRECISION,
        "tolerance_checked_on": "dense" if _checks_dense(config) else "check periods",
    }


def _seed_entries(summary: RecordSummary) -> dict[str, Any]:
    """A seed record's dense fit and, matched, what the matching changed of its seed."""
    fit = summary.fit
    entries: dict[str, Any] = {
        "dense_min_ratio": fit.min_ratio,
        "dense_min_period_s": fit.min_period,
        "dense_max_ratio": fit.max_ratio,
        "dense_max_period_s": fit.max_period,
    }
    change = summary.seed_change
    if change is not None:
        entries["matched"] = _traits(change.record)
        entries["seed_scaled_to_pga"] = _traits(change.seed)
        entries["pgv_bound_m_s"] = change.pgv_bound
        entries["pgd_bound_m"] = change.pgd_bound
        entries["ground_ok"] = change.ground_ok
        entries["changed_over_25_percent"] = list(change.flags)
    return entries


def _traits(traits: seeds.MotionTraits) -> dict[str, float]:
    return {"pgv_m_s": traits.pgv, "pgd_m": traits.pgd, "d5_95_s": traits.d5_95,
            "d5_75_s": traits.d5_75, "arias_time_s": traits.arias_time}  # fmt: skip


def _round_floats(value: Any) -> Any:
    """Floats to 10 significant digits, recursively: a readable, stable manifest."""
    if isinstance(value, float):
        return float(f"{value:.10g}")
    if isinstance(value, dict):
        return {key: _round_floats(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_round_floats(item) for item in value]
    return value


def read_set_target(folder: str | Path) -> TargetDefinition:
    """The target spectrum stored in a record set's manifest (SI units).

    Raises
    ------
    InputError
        The manifest is missing or corrupt, or lacks the target.
    """
    manifest = read_manifest(folder)
    target = manifest.get("target")
    keys = (
        "spectrum_type",
        "ground_type",
        "damping",
        "design_acceleration_m_s2",
        "surface_pga_m_s2",
    )
    if not isinstance(target, dict) or any(key not in target for key in keys):
        raise InputError(Path(folder) / MANIFEST, [("target", "missing or incomplete")])
    return TargetDefinition(*(target[key] for key in keys))

"""Record sets: artificial accelerograms matched to an EN 1998-1 spectrum (`generate_record_set`),
with the manifest that describes them and the compliance check of EN 1998-1 §3.2.3.1.2."""

from __future__ import annotations

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
from ..motions import baseline, ec8, matching, spectra
from ..paths import writable
from .fema import read_fema_set
from .files import MANIFEST, PROVENANCE, Record, read_manifest, read_record, write_record

GROUND_DISPLACEMENT_AIM = 2.0
"""The peak ground displacement a matched record should stay within, as a multiple of EN 1998-1's
d_g (§3.2.2.4): rockbridge's aim, not a rule of the code; the compliance report states it. The
least-displacement baseline correction (`baseline.BaselineCorrection`) keeps the bundled sets
at 0.9–1.9 d_g."""


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
    scale_factor: float | None = None


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
    """

    folder: Path
    records: tuple[RecordSummary, ...]
    compliance: ec8.ComplianceReport
    band: tuple[float, float]
    check_periods: int
    wall_time: float
    ground_displacement: float


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
    recorded seed is matched with its phases and envelope kept (`matching.match_seed`).

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
        A seed cannot be read, or its time step is too coarse for the band.
    """
    started = time.perf_counter()
    folder = writable(folder, folder=True)
    target = resolve_target(config)
    settings = matching.MatchSettings(
        tolerance=config.tolerance,
        max_iterations=config.max_iterations,
        max_attempts=config.attempts,
        damping=target.damping,
    )
    made = _matched_seeds(config, target, settings) if config.seeds is not None else _synthesised(
        config, target, settings)  # fmt: skip
    records = [record for record, _ in made]
    check = np.geomspace(*config.band, config.check_periods)
    summaries, compliance = _summarise(records, [m for _, m in made], check, target, config)
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
    )


def _synthesised(config, target, settings) -> list[tuple[Record, matching.MatchedRecord]]:
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
    made = []
    for index, child in enumerate(np.random.SeedSequence(config.seed).spawn(config.count)):
        matched = matching.generate_matched_record(
            periods, goal, target.surface_pga, config.time_step, envelope,
            np.random.default_rng(child), settings, band=config.band,
        )  # fmt: skip
        name = f"{config.name_prefix}{index + 1:0{width}d}"
        made.append((Record(name, config.time_step, matched.acceleration, "generate-records"),
                     matched))  # fmt: skip
    return made


def _matched_seeds(config, target, settings) -> list[tuple[Record, matching.MatchedRecord]]:
    """One record per seed at the seed's own time step (EN 1998-1 §3.2.3.1.3): matched, scaled
    without changing its shape (`ec8.scale_factors`), or as read (``adjust: none``)."""
    seeds = _read_seeds(config)
    factors = _scale_factors(config, target, seeds) if config.adjust.startswith("scale") else None
    made = []
    for index, seed in enumerate(seeds):
        metadata = dict(seed.metadata)
        if config.adjust == "match":
            periods = matching.compute_matching_periods(config.band, config.check_periods,
                                                        seed.time_step)  # fmt: skip
            matched = matching.match_seed(
                periods, target.evaluate(periods, extrapolate=True), target.surface_pga,
                seed.acceleration, seed.time_step, settings, config.band)  # fmt: skip
        else:
            factor = 1.0 if factors is None else float(factors[index])
            metadata["scale_factor"] = factor * metadata.get("scale_factor", 1.0)
            matched = matching.MatchedRecord(factor * seed.acceleration, seed.time_step,
                                             0, 0, float("nan"))  # fmt: skip
        made.append((Record(seed.name, seed.time_step, matched.acceleration, "generate-records",
                            metadata), matched))  # fmt: skip
    return made


def _read_seeds(config: RecordSetConfig) -> list[Record]:
    """The seeds as read, named as the set will name them, with their provenance as metadata;
    to be matched, each must resolve the band (at least 5 time steps in its shortest period).

    Raises
    ------
    InputError
        A seed cannot be read, or is too coarse for the band.
    """
    if isinstance(config.seeds, FemaSet):
        fema = config.seeds
        seeds = [
            Record(r.name, r.time_step, r.acceleration, r.source,
                   {key: r.metadata[key] for key in PROVENANCE if key in r.metadata})
            for r in read_fema_set(fema.name, tuple(fema.components), fema.normalize,
                                   None if fema.records is None else tuple(fema.records))
        ]  # fmt: skip
        where = [f"seeds: {seed.name}" for seed in seeds]
    else:
        assert config.seeds is not None
        seeds = [
            Record(entry.id or re.sub(r"[^A-Za-z0-9_.+-]", "_", Path(entry.path).stem),
                   record.time_step, record.acceleration, record.source,
                   {"seed_file": Path(entry.path).name})
            for entry in config.seeds
            for record in [read_record(entry.path, units=entry.units, time_step=entry.time_step)]
        ]  # fmt: skip
        where = [f"seeds.{index}.path" for index in range(len(seeds))]
    for seed, field in zip(seeds, where, strict=True):
        if config.adjust == "match" and config.band[0] < 5.0 * seed.time_step - 1e-12:
            raise InputError(seed.source, [(field, f"time step {seed.time_step:g} s is too "
                                            f"coarse for the band from {config.band[0]:g} s: at "
                                            "least 5 steps per period are needed")])  # fmt: skip
    return seeds


def _scale_factors(config, target, seeds: list[Record]) -> np.ndarray:
    """The factors of the seeds, at the check periods of the band."""
    check = np.geomspace(config.band[0], config.band[1], config.check_periods)
    computed = np.array(
        [spectra.compute_psa(s.acceleration, s.time_step, check, target.damping) for s in seeds]
    )
    peaks = np.array([s.peak_acceleration for s in seeds])
    return ec8.scale_factors(computed, target.evaluate(check), peaks, target.surface_pga,
                             individual=config.adjust == "scale")  # fmt: skip


def _summarise(records, matches, check, target, config):
    """Per-record statistics, the EN 1998-1 check and the config's per-record tolerance, at the
    check periods."""
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
    summaries = []
    for record, matched, low, high in zip(
        records, matches, compliance.record_min_ratio, compliance.record_max_ratio, strict=True
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
                record.metadata.get("scale_factor"),
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
        "check": {"band_s": list(config.band), "periods": config.check_periods},
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

"""What a record set writes about itself: each record file's header and the set's manifest
(the config, the target, the check, each record's fit, peaks and provenance, the compliance)."""

from __future__ import annotations

import platform
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy

from .. import __version__
from ..motions import ec8, spectral_fit
from .files import Record
from .target import TargetDefinition

if TYPE_CHECKING:
    from ..config.record_sets import RecordSetConfig
    from ..motions import seeds  # scipy.signal: 1-2 s to import, which select-records needs not
    from .summary import RecordSummary


def record_header(
    config: RecordSetConfig, target: TargetDefinition, index: int, record: Record
) -> dict:
    pga = target.surface_pga if config.adjust == "match" else record.peak_acceleration
    return {
        "pga": pga,
        "pga_g": pga / config.gravity,
        **({"seed": config.seed} if config.seeds is None else record.metadata),
        "record_index": index,
        "target": f"{config.target.code} {'vertical ' if target.vertical else ''}type "
        f"{target.spectrum_type} ground {target.ground_type}"
        f" a_g={target.design_acceleration / config.gravity:g}g"
        + (f" a_vg={target.surface_pga / config.gravity:g}g" if target.vertical else "")
        + f" damping={target.damping:g}",
        "generator": f"rockbridge {__version__}",
    }


def build_manifest(config, config_name, target, records, summaries, compliance) -> dict[str, Any]:
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
        # a set without vertical components keeps the manifest it had before they existed
        "config": config.model_dump(
            mode="json", by_alias=True, exclude=None if config.vertical else {"vertical"}
        ),  # fmt: skip
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
                **motion_entries(s, config.gravity),
                "stationary_duration_s": config.envelope.stationary if config.envelope else None,
                **(records[index].metadata if config.seeds is not None else {}),
                **(_seed_entries(s) if config.seeds is not None else {}),
                "attempts": s.attempts,
                "iterations": s.iterations,
            }
            for index, s in enumerate(summaries)
        ],
        "mean": {"min_ratio": compliance.mean_min_ratio, "max_ratio": compliance.mean_max_ratio},
        "compliance": compliance_entries(compliance),
    }


def add_verticals(manifest: dict[str, Any], config, target, summaries, compliance) -> None:
    """Add the vertical components to a manifest: each record's (its entry ``vertical``, the
    companion's file and how it fits), the vertical target (EN 1998-1 §3.2.2.3) and their
    EN 1998-1 §3.2.3.1.2 check (``vertical_compliance``)."""
    ratio, *corners = ec8.VERTICAL_SHAPES[target.spectrum_type]
    manifest["vertical_target"] = {
        "code": config.target.code,
        "clause": "EN 1998-1 3.2.2.3, vertical elastic response spectrum",
        "spectrum_type": target.spectrum_type,
        "damping": target.damping,
        "avg_over_ag": ratio,
        "corner_periods_s": corners,
        "design_acceleration_m_s2": target.design_acceleration,
        "vertical_pga_m_s2": target.surface_pga,
    }
    for entry, s in zip(manifest["records"], summaries, strict=True):
        entry["vertical"] = {"file": s.file, **motion_entries(s, config.gravity),
                             "attempts": s.attempts, "iterations": s.iterations}  # fmt: skip
    manifest["vertical_mean"] = {
        "min_ratio": compliance.mean_min_ratio,
        "max_ratio": compliance.mean_max_ratio,
    }
    manifest["vertical_compliance"] = compliance_entries(compliance)


def motion_entries(s: RecordSummary, gravity: float) -> dict[str, float]:
    """A record's peaks, fit to its target, final motion and duration, as a manifest gives
    them."""
    return {
        "pga_m_s2": s.peak_acceleration,
        "pga_g": s.peak_acceleration / gravity,
        "min_ratio": s.min_ratio,
        "max_ratio": s.max_ratio,
        "final_velocity_m_s": s.final_velocity,
        "final_displacement_m": s.final_displacement,
        "pgv_m_s": s.peak_velocity,
        "pgd_m": s.peak_displacement,
        "d5_95_s": s.significant_duration,
    }


def compliance_entries(compliance: ec8.ComplianceReport) -> dict[str, Any]:
    """The EN 1998-1 §3.2.3.1.2 check of a set, as a manifest gives it."""
    return {
        "count": compliance.count,
        "count_ok": compliance.count_ok,
        "mean_zero_period_m_s2": compliance.mean_zero_period,
        "zero_period_ok": compliance.zero_period_ok,
        "mean_ok": compliance.mean_ok,
        "stationary_ok": compliance.stationary_ok,
        "tolerance": compliance.tolerance,
        "records_ok": compliance.records_ok,
        "compliant": compliance.compliant,
    }


def _dense_check(config: RecordSetConfig, target: TargetDefinition) -> dict[str, Any]:
    """How the manifest of a set of seeds states the dense grid."""
    return {
        "dense_periods": spectral_fit.dense_periods(config.band, target.damping).size,
        "dense_step_ln_period": spectral_fit.STEP * target.damping,
        "dense_extremes_refined_to_ln_period": spectral_fit.PRECISION,
        "tolerance_checked_on": "dense" if checks_dense(config) else "check periods",
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


def round_floats(value: Any) -> Any:
    """Floats to 10 significant digits, recursively: a readable, stable manifest."""
    if isinstance(value, float):
        return float(f"{value:.10g}")
    if isinstance(value, dict):
        return {key: round_floats(item) for key, item in value.items()}
    if isinstance(value, list):
        return [round_floats(item) for item in value]
    return value


def checks_dense(config: RecordSetConfig) -> bool:
    """Whether the set's tolerance is checked on the dense grid: for matched seeds, which
    `seeds.match_seed` matches there; artificial records keep the check periods they were
    matched at, so that the bundled sets' manifests stay as they were made."""
    return config.seeds is not None and config.adjust == "match"

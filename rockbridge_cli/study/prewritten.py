"""The description of a run's results file, written while the run goes on and copied in at its
end.

The description of a study of many records (a spectrum's thousand pulses) is thousands of HDF5
attributes: writing them took 2.9 s of every end of such a run, a stop's included, for 1000
records (about 24 attributes each). So once the workers have computed its numerics (`describe`),
a thread of the parent writes it into a file of its own beside the output while the parent goes
on sending batches (the workers never wait for it; they use no HDF5); the end then copies it in
as one HDF5 object copy (H5Ocopy, as a merge copies a part's, about a tenth of the time), once
the thread is done, and writes it as before only where it could not be written early (a
one-worker run, whose numerics are computed at its end; a run stopped first; a failure, met
again at the end).
"""

from __future__ import annotations

import os
import threading
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
    early into ``.<output>.<pid>.description.tmp`` beside the output, in a thread (`write`), and
    put into the results file at the end (`into`); `remove` deletes it (a killed run's is
    removed with its other temporary files by the next run).

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
        self._thread: threading.Thread | None = None

    def write(self, computed: Numerics) -> None:
        """Start writing the description with the numerics the workers ``computed`` into the
        side file, in a thread; a failure leaves no side file (the end writes the description,
        and meets the failure there)."""
        self._thread = threading.Thread(target=self._early, args=(computed,), daemon=True,
                                        name="rockbridge-description")  # fmt: skip
        self._thread.start()

    def into(self, file: h5py.File, computed: Numerics | None) -> None:
        """Put the description into the results ``file``: copied from the side file where it was
        written (waiting for the thread that writes it), else written with the numerics
        ``computed`` (None: computed here)."""
        self._join()
        if not self.written:
            self._write(file, computed)
            return
        with h5py.File(self.path, "r") as source:
            copy_description(file, source, skip=())

    def remove(self) -> None:
        """Delete the side file, if any, once the thread that writes it is done."""
        self._join()
        self.path.unlink(missing_ok=True)
        self.written = False

    def _early(self, computed: Numerics) -> None:
        try:
            with h5py.File(self.path, "w") as file:
                self._write(file, computed)
        except Exception:  # met again where the results file is written
            self.path.unlink(missing_ok=True)
            return
        self.written = True

    def _join(self) -> None:
        if self._thread is not None:
            self._thread.join()
            self._thread = None

    def _write(self, file: h5py.File, computed: Numerics | None) -> None:
        description = describe(self.study, self.bridges, computed)
        write_description(file, description, self.created, self.shard)

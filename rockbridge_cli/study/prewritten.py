"""The description of a run's results file, written while the run goes on and copied in at its
end.

The description of a study of many records (a spectrum's thousand pulses) is thousands of HDF5
attributes: writing them took 2.9 s of every end of such a run, a stop's included, for 1000
records (about 24 attributes each). So once the workers have computed its numerics (`describe`),
the parent hands the description to a worker of the local pool, which writes it into a file of
its own beside the output (`write_side`) as it would run a batch; the end then copies it in as
one HDF5 object copy (H5Ocopy, as a merge copies a part's, about a tenth of the time), and
writes it as before where it was not written early (a one-worker run, whose numerics are
computed at its end; a run stopped before; a failure, met again at the end; a Dask cluster,
whose workers may not see the output's folder). The parent itself does not write it while the
analyses run: a thread of its own writing HDF5 (which holds the GIL) halved how fast it sent
batches.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py

from ..results.description import Description
from ..results.writing import copy_description, write_description
from .describe import Numerics, describe

if TYPE_CHECKING:
    from ..config.study import Study
    from ..core.bridge import Bridge


class Prewritten:
    """The description of a run's results file (`results.writing.write_description`), written
    early into ``.<output>.<pid>.description.tmp`` beside the output by a worker (`write`), and
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
        self._written: Callable[..., Any] | None = None

    def write(self, computed: Numerics, call: Callable[..., Callable[..., Any]]) -> None:
        """Have a worker write the description with the numerics the workers ``computed`` into
        the side file: ``call`` is the executor's (`executors.interface.Call`)."""
        description = describe(self.study, self.bridges, computed)
        self._written = call(write_side, self.path, description, self.created, self.shard)

    @property
    def written(self) -> bool:
        """Whether a worker has written the side file (it is never waited for, nor written in
        this process: a run stopped first writes the description at its end)."""
        if self._written is None:
            return False
        try:
            return bool(self._written(wait=False))
        except Exception:  # the worker's failure: met again where the results file is written
            return False

    def into(self, file: h5py.File, computed: Numerics | None) -> None:
        """Put the description into the results ``file``: copied from the side file where a
        worker wrote it, else written with the numerics ``computed`` (None: computed here)."""
        if not self.written:
            description = describe(self.study, self.bridges, computed)
            write_description(file, description, self.created, self.shard)
            return
        with h5py.File(self.path, "r") as source:
            copy_description(file, source, skip=())

    def remove(self) -> None:
        """Delete the side file, if any (once the workers have ended: none writes it then)."""
        self.path.unlink(missing_ok=True)
        self._written = None


def write_side(
    path: Path, description: Description, created: str, shard: tuple[int, int] | None
) -> bool:
    """Write a description into a file of its own at ``path`` (on a worker); False, and no
    file, where it could not be written."""
    try:
        with h5py.File(path, "w") as file:
            write_description(file, description, created, shard)
    except Exception:  # a full disk, a removed folder: met again at the end
        path.unlink(missing_ok=True)
        return False
    return True

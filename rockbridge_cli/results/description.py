"""The study's description as a results file stores it, one plain value: the root's attributes,
a group per record with its samples, a group per bridge. The study layer computes it
(`study.describe`); the writer writes it as it is (`writing.write_description`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np


@dataclass(frozen=True)
class Attributes:
    """A group's attributes and the units of those that have one (its ``units`` attribute, in
    this order; None: the group has no ``units`` attribute)."""

    values: dict[str, Any]
    units: dict[str, str] | None = None


class Samples(NamedTuple):
    """A dataset of a record's group: ``acceleration`` (as analyzed), ``base_acceleration`` (as
    read, of a record scaled by its group's ``scale``), or their vertical components. Samples of
    one ``key`` are one dataset (HDF5 hard links), however many records hold them."""

    name: str
    key: str
    values: np.ndarray


class RecordGroup(NamedTuple):
    """The group of a record, named by its id. Records of one ``key`` (one content) are one group:
    the first writes it, the others are hard links to it."""

    id: str
    key: tuple[str, str]
    attributes: Attributes
    samples: tuple[Samples, ...]


@dataclass(frozen=True)
class Description:
    """What the results rest on.

    Attributes
    ----------
    root : the study and its inputs (root attributes, after the format and versions the writer
        adds)
    records : a group per record, in the study's order
    bridges : bridge id → its group's attributes, in the study's order
    """

    root: dict[str, Any]
    records: tuple[RecordGroup, ...]
    bridges: dict[str, Attributes]

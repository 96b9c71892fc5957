"""What a process keeps per bridge is bounded in bytes, whatever the number of bridges.

Expected values: the definition of the cache (the least recently used value goes first once the
values pass the budget) and the size of a bridge's tables from their shape, 2 modes × 2560
intervals × 14 quantities × 4 coefficients × 8 bytes = 2.29 MB (`core.tables`).
"""

from __future__ import annotations

import numpy as np
from conftest import studied_bridge, with_

from rockbridge_cli.core import analysis
from rockbridge_cli.core.analysis import TABLE_BYTES, analyze
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.memo import BoundedCache
from rockbridge_cli.core.tables import tabulated


def test_the_least_recently_used_value_goes_first():
    built = []

    def build(key: str) -> bytes:
        built.append(key)
        return bytes(10)

    cache = BoundedCache(build, max_bytes=25, size=len)
    for key in ("a", "b", "a", "c"):  # c passes 25 bytes: b, used least recently, goes
        cache(key)
    assert built == ["a", "b", "c"] and cache.bytes == 20 and len(cache) == 2
    cache("a")
    cache("b")  # built again
    assert built == ["a", "b", "c", "b"]
    alone = BoundedCache(lambda key: bytes(40), max_bytes=25, size=len)
    assert len(alone("x")) == 40 and alone.bytes == 40  # the value just built is kept


def test_a_sweep_of_many_bridges_keeps_its_tables_within_the_budget():
    """60 bridges (the studied h̄ = 1.25 bridge at 60 gaps) under a one-second record: the tables
    kept stay within `TABLE_BYTES` (14 bridges'), none in `tables.tabulated`'s own cache."""
    analysis._TABLES.clear()
    tabulated.cache_clear()
    ground = 2.0 * np.sin(2.0 * np.pi * np.arange(0.0, 1.0, 0.01))
    base = studied_bridge(1.25)
    for gap in np.linspace(0.06, 0.24, 60):
        analyze(Bridge(with_(base, u_jo=float(gap))), ground, 0.01, "fast")
    one = 2 * 2560 * 14 * 4 * 8
    assert analysis._TABLES.bytes <= TABLE_BYTES < analysis._TABLES.bytes + one
    assert len(analysis._TABLES) == TABLE_BYTES // one == 14
    assert tabulated.cache_info().currsize == 0

"""Properties that must hold for every input, checked on inputs hypothesis draws: the IDA rule on
monotonic curves, the deterministic shard split, and the packed form of a result (issue 30)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from rockbridge_cli.assessment.ida import Lattice, Outcome, walk
from rockbridge_cli.core.bridge import Bridge
from rockbridge_cli.core.geometry import single_block
from rockbridge_cli.results.packing import AnalysisResult, Chunk, Packed
from rockbridge_cli.study.grid import BridgeCase, Grid, RecordCase

SETTINGS = settings(max_examples=60, deadline=None)


@SETTINGS
@given(
    start=st.floats(0.01, 1.0),
    step=st.floats(0.01, 1.0),
    scans=st.integers(1, 30),
    tolerance=st.floats(0.005, 0.2),
    thresholds=st.lists(st.floats(0.0, 40.0), min_size=1, max_size=3),
    ending=st.booleans(),
)
def test_the_ida_rule_brackets_a_monotonic_threshold(
    start, step, scans, tolerance, thresholds, ending
):
    """A curve that reaches state i at every level from x_i on: the rule, run round by round as
    a study runs it, reports as capacity the first lattice level at or above x_i, with the level
    below it under x_i and within ``tolerance`` of the capacity (or the lattice's resolution, the
    rule's definition); a threshold above the last scan level is not reached; one at or below
    ``start`` is censored there (below = −1). With ``ending``, state 0 is a failure that ends
    the analysis: the curve ends at its capacity, and a state not reached there is unreachable
    (no capacity, whatever its threshold)."""
    depth = max(0, math.ceil(math.log2(step / (tolerance * start))))
    lattice = Lattice(start, step, depth, scans * 2**depth + 1)
    states = tuple(f"s{i}" for i in range(len(thresholds)))
    done: dict[int, Outcome] = {}

    for _ in range(10_000):  # rounds: run what the rule wants, until it wants nothing
        found = walk(lattice, tolerance, states, done.get)
        if not found.wanted:
            break
        for n in found.wanted:
            level = lattice.level(n)
            hit = frozenset(s for s, x in zip(states, thresholds, strict=True) if level >= x)
            done[n] = Outcome(hit, "s0" if ending and "s0" in hit else "")
    top = lattice.level(lattice.count - 1)
    end = found.capacities["s0"][1] if ending else None
    assert found.end == end
    for state, threshold in zip(states, thresholds, strict=True):
        below, n = found.capacities[state]
        if end is not None and threshold > lattice.level(end):
            assert n is None and found.unreachable(state)
            continue
        if threshold > top:
            assert n is None
            continue
        assert n is not None
        capacity = lattice.level(n)
        assert capacity >= threshold
        if below < 0:
            assert threshold <= start and n == 0
        else:
            assert lattice.level(below) < threshold
            assert capacity - lattice.level(below) <= max(tolerance * capacity, step / 2**depth)
            assert n - below >= 1


def grid_of(costs: list[int]) -> Grid:
    """A grid of one bridge and records of the given numbers of samples (the cost of a cell)."""
    bridge = BridgeCase("b", Bridge(single_block(1.0, 10.0, 2500.0, 9.81)))
    records = tuple(
        RecordCase(f"r{i}", np.zeros(c), 0.01, "", f"r{i}", math.nan, 1.0)
        for i, c in enumerate(costs)
    )
    return Grid((bridge,), records, "fast", {}, (), "hash")


@SETTINGS
@given(costs=st.lists(st.integers(2, 5000), min_size=1, max_size=60), count=st.integers(1, 9))
def test_shards_partition_the_grid_and_balance_its_cost(costs, count):
    """Every cell in exactly one shard, in the order of the results, and the shards' costs within
    the largest single cell's cost of each other (greedy largest-first balancing)."""
    grid = grid_of(costs)
    shards = [grid.shard(index, count) for index in range(count)]
    cells = [cell for shard in shards for cell in shard]
    assert sorted(c.index for c in cells) == [c.index for c in grid.cells]
    assert all(shard == sorted(shard) for shard in shards)
    loads = [sum(grid.cost(c) for c in shard) for shard in shards]
    assert max(loads) - min(loads) <= max(costs)


texts = st.text(st.characters(blacklist_categories=("Cs",)), max_size=30)


@SETTINGS
@given(
    message=texts,
    numbers=st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=3, max_size=3),
    samples=st.lists(st.floats(allow_nan=False, width=64), min_size=0, max_size=50),
    events=st.integers(0, 20),
)
def test_a_packed_result_unpacks_to_what_was_packed(message, numbers, samples, events):
    """The packed form keeps every value: texts (a NUL becomes U+FFFD, which HDF5 strings can
    hold), numbers bit for bit, counts as integers, events and histories (shuffled and deflated
    as HDF5 stores them) exactly."""
    result = AnalysisResult.failed("bridge-1", "record+0.5g", message, wall_time=numbers[0])
    result.values.update(u_deck_max=numbers[1], dcr_backfill=numbers[2], n_impacts=events)
    result.time = np.arange(len(samples), dtype=float)
    result.histories = {"theta1": np.array(samples, dtype=float)} if samples else {}
    result.events = {name: np.arange(events, dtype=float) for name in result.events}
    result.events["kind"] = np.array(["impact"] * events)
    packed = Packed(*result.pack())
    values = packed.values
    assert values["message"] == message.replace("\0", "\ufffd")
    for name, number in (("wall_time_s", numbers[0]), ("u_deck_max", numbers[1]),
                         ("dcr_backfill", numbers[2])):  # fmt: skip
        assert np.array_equal(values[name], number, equal_nan=True)
    assert values["n_impacts"] == events and isinstance(values["n_impacts"], int)
    assert np.array_equal(packed.event_rows["time"], np.arange(events, dtype=float))
    chunks = packed.chunks
    if samples:
        assert np.array_equal(chunks["theta1"].samples(), np.array(samples))
        assert np.array_equal(chunks["time"].samples(), result.time)
    else:
        assert chunks == {}


@SETTINGS
@given(samples=st.lists(st.floats(width=64, allow_nan=True), min_size=1, max_size=200))
def test_a_chunk_is_hdf5s_shuffle_and_deflate(samples):
    """`Chunk.of` then `samples` is the identity, bit for bit (NaN payloads included)."""
    values = np.array(samples, dtype=float)
    back = Chunk.of(values).samples()
    assert back.tobytes() == values.tobytes()

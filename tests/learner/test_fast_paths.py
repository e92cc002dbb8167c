"""The faster paths (BENCHMARKS.md, "The learner") give the simple paths' answers.

A leaf's grasp options and object ids are read as arrays (``DescriptionMatrix.labels``)
instead of description by description; a partition works on each column's distinct
values instead of its entries, and partitions of nodes below the root are memoised per
matrix (``node_splits``). Each is checked here against the simple path on random
libraries perturbed from the shipped one.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from executive.defaults import EXAMPLE_LIBRARY
from learner.choosing.criteria import criterion
from learner.choosing.gain import partition_columns
from learner.choosing.leaf import grasp_options, object_ids
from learner.choosing.matrix import NODE_SPLITS_KEPT, DescriptionMatrix, RowLabels
from learner.choosing.node import Context, Node
from learner.choosing.scoring import _failure_share
from learner.costs import ModelMoveCost
from learner.decision_tree import grow
from learner.description import ObjectDescription
from learner.library.format import read_library_json
from learner.library.synthetic import synthetic_library
from learner.position import Position
from tests.learner.fixtures import hero
from tests.learner.reference_paths import entry_partition, simple_failure_share, simple_grasp_options

KNOWLEDGE = hero()
SHIPPED = read_library_json(EXAMPLE_LIBRARY)
START = Position(60.0, 0.0)


@st.composite
def libraries(draw) -> list[ObjectDescription]:
    """A perturbed library, some ids repeated (one object described twice)."""
    library = synthetic_library(KNOWLEDGE, draw(st.integers(3, 60)), draw(st.integers(0, 10_000)), base=SHIPPED)
    twice = draw(st.lists(st.integers(0, len(library) - 1), max_size=3))
    for i in twice:
        library.append(ObjectDescription(library[i].object_id, library[-1].grasp, library[i].grasp_position,
                                         library[i].observations, library[i].appearance))
    return library


@st.composite
def nodes(draw, n: int) -> Node:
    rows = sorted(draw(st.sets(st.integers(0, n - 1), min_size=1)))
    return Node(tuple(rows), tuple(draw(st.lists(st.booleans(), min_size=len(rows), max_size=len(rows)))))


@settings(max_examples=60, deadline=None)
@given(st.data())
def test_leaf_options_and_ids_as_arrays_equal_the_row_by_row_reading(data) -> None:
    library = data.draw(libraries())
    ctx = Context(DescriptionMatrix(library, KNOWLEDGE), criterion("cs-id3"), ModelMoveCost(KNOWLEDGE.move))
    node = data.draw(nodes(len(library)))
    assert grasp_options(node, START, ctx) == simple_grasp_options(node, START, ctx)
    genuine = [r for r, c in zip(node.rows, node.carried) if not c] or list(node.rows)
    assert object_ids(node, ctx) == tuple(sorted({library[r].object_id for r in genuine}))


@settings(max_examples=40, deadline=None)
@given(libraries(), st.integers(1, 5))
def test_labels_grown_by_appending_equal_labels_built_at_once(library, k) -> None:
    k = min(k, len(library) - 1)
    grown = DescriptionMatrix(library[:-k], KNOWLEDGE)
    grown.labels  # made before the append, extended after it
    grown = grown.extended_to(library)
    fresh = RowLabels.of(library)
    assert grown.labels.object_id.tolist() == fresh.object_id.tolist() == [d.object_id for d in library]
    assert [grown.labels.positions[i] for i in grown.labels.grasp_position.tolist()] == [
        d.grasp_position for d in library]


@settings(max_examples=40, deadline=None)
@given(st.data())
def test_a_memoised_node_partition_equals_one_worked_out_afresh(data) -> None:
    library = data.draw(libraries())
    matrix = DescriptionMatrix(library, KNOWLEDGE)
    node = data.draw(nodes(len(library)))
    columns = np.arange(len(matrix.tests))
    first = partition_columns(node.rows, matrix, columns)
    again = partition_columns(node.rows, matrix, columns)
    afresh = partition_columns(node.rows, DescriptionMatrix(library, KNOWLEDGE), columns)
    assert again is first or len(node.rows) == len(library)  # the whole library: the root's memo
    for found in (again, afresh):
        assert found.ranges == first.ranges
        for field in ("unknown", "gains", "n_ranges", "mass"):
            assert np.array_equal(getattr(found, field), getattr(first, field))


@settings(max_examples=25, deadline=None)
@given(libraries())
def test_a_tree_grown_again_on_the_memos_is_the_same_tree(library) -> None:
    matrix = DescriptionMatrix(library, KNOWLEDGE)
    ctx = Context(matrix, criterion("cs-id3"), ModelMoveCost(KNOWLEDGE.move))
    first = grow(Node.root(len(library)), START, ctx)
    assert grow(Node.root(len(library)), START, ctx) == first
    fresh = Context(DescriptionMatrix(library, KNOWLEDGE), criterion("cs-id3"), ModelMoveCost(KNOWLEDGE.move))
    assert grow(Node.root(len(library)), START, fresh) == first


def same_split(a, b) -> bool:
    return (a.ranges == b.ranges and all(np.array_equal(getattr(a, f), getattr(b, f))
                                         for f in ("unknown", "gains", "n_ranges", "mass")))


@pytest.mark.slow
@settings(max_examples=80, deadline=None)
@given(st.data())
def test_a_partition_over_distinct_values_equals_the_one_over_entries(data) -> None:
    library = data.draw(libraries())
    matrix = DescriptionMatrix(library, KNOWLEDGE)
    node = data.draw(nodes(len(library)))
    columns = np.array(sorted(data.draw(st.sets(st.integers(0, len(matrix.tests) - 1), min_size=1))))
    assert same_split(partition_columns(node.rows, matrix, columns), entry_partition(node.rows, matrix, columns))
    everyone = tuple(range(len(library)))
    assert same_split(partition_columns(everyone, matrix, columns), entry_partition(everyone, matrix, columns))


@settings(max_examples=30, deadline=None)
@given(libraries(), st.integers(1, 5), st.data())
def test_a_partition_after_appending_equals_the_one_over_entries(library, k, data) -> None:
    k = min(k, len(library) - 1)
    matrix = DescriptionMatrix(library[:-k], KNOWLEDGE)
    matrix.known  # made before the append, updated by it
    grown = matrix.extended_to(library)
    node = data.draw(nodes(len(library)))
    columns = np.arange(len(grown.tests))
    assert same_split(partition_columns(node.rows, grown, columns), entry_partition(node.rows, grown, columns))


def test_the_node_memo_keeps_the_latest_partitions_only() -> None:
    matrix = DescriptionMatrix(SHIPPED, KNOWLEDGE)
    found = partition_columns((0, 1, 2), matrix, np.arange(len(matrix.tests)))
    for i in range(NODE_SPLITS_KEPT + 10):
        matrix.remember_node_split(i.to_bytes(4, "little"), found)
    assert len(matrix.node_splits) == NODE_SPLITS_KEPT
    assert min(int.from_bytes(k, "little") for k in matrix.node_splits) == 10  # the oldest dropped first


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(st.data())
def test_a_grasps_failure_share_over_arrays_equals_the_row_by_row_sum(data) -> None:
    library = data.draw(libraries())
    matrix = DescriptionMatrix(library, KNOWLEDGE)
    node = data.draw(nodes(len(library)))
    if data.draw(st.booleans()):  # a node below a fork some rows lacked: weights 1/k
        node = Node(node.rows, node.carried, tuple(data.draw(st.sampled_from((1.0, 0.5, 1 / 3)))
                                                   for _ in node.rows))
    rows = np.asarray(node.rows, dtype=np.int64)
    for test in (t for t in matrix.tests if t.is_grasp):
        assert _failure_share(node.weight_array(), rows, matrix, test) == pytest.approx(simple_failure_share(node, matrix, test),
                                                                          rel=1e-12, abs=1e-15)

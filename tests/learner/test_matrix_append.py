"""Appending learned descriptions to the matrix gives the matrix built from scratch,
and leaves the matrix it grew from as it was."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.appearance import Appearance
from learner.choosing.matrix import DescriptionMatrix
from learner.description import Descriptions, ObjectDescription, Observation
from tests.learner.fixtures import ANY, P, desc, four_objects, hero

KNOWLEDGE = hero()
# A small menu so that ties, shared columns and "*" positions happen often.
MENU = [("Width-Degree-1°", P(24, 0)), ("Width-Degree-1°", P(24, 90)), ("Height", P(6, ANY)),
        ("Height", P(6, 0)), ("Top-Hole?", P(6, ANY)), ("Front-Hole?", P(6, 0))]
VALUES = {"Width-Degree-1°": [8.0, 9.0, 18.0, 30.0], "Height": [3.5, 6.0, 9.0], "Top-Hole?": [0.0, 1.0],
          "Front-Hole?": [0.0, 1.0]}


@st.composite
def descriptions(draw: st.DrawFn) -> ObjectDescription:
    chosen = draw(st.sets(st.sampled_from(range(len(MENU))), min_size=1, max_size=4))
    observations = tuple(sorted(Observation(MENU[i][0], MENU[i][1], draw(st.sampled_from(VALUES[MENU[i][0]])))
                                for i in chosen))
    look = draw(st.none() | st.builds(Appearance, st.booleans(), st.sampled_from([20.0, 40.0]),
                                      st.sampled_from([1.0, 2.0])))
    return ObjectDescription(f"d{draw(st.integers(0, 10**6))}", draw(st.sampled_from(["Front-Wrap", "Top-Pinch"])),
                             draw(st.sampled_from([P(6, ANY), P(ANY, ANY), P(6, 0)])), observations, look)


def assert_same(a: DescriptionMatrix, b: DescriptionMatrix) -> None:
    assert a.descriptions == b.descriptions
    assert a.tests == b.tests and a.classes == b.classes and a.column == b.column
    assert np.array_equal(a.values, b.values, equal_nan=True)
    assert np.array_equal(a.class_of, b.class_of)
    assert np.array_equal(a.order, b.order)
    assert np.array_equal(a.sorted_values, b.sorted_values, equal_nan=True)
    assert np.array_equal(a.appearance_axes, b.appearance_axes, equal_nan=True)
    for name in ("errors", "binary", "is_grasp", "span_lo", "span_hi"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(st.lists(descriptions(), min_size=1, max_size=12), st.lists(st.lists(descriptions(), max_size=3), max_size=6),
       st.booleans())
def test_appending_equals_building_from_scratch(first: list[ObjectDescription],
                                                learned: list[list[ObjectDescription]], grasps: bool) -> None:
    matrix = DescriptionMatrix(first, KNOWLEDGE, grasps)
    so_far = list(first)
    for batch in learned:
        before = (matrix.values.copy(), matrix.order.copy(), len(matrix.descriptions))
        grown = matrix.appended(batch)
        so_far += batch
        assert_same(grown, DescriptionMatrix(so_far, KNOWLEDGE, grasps))
        # the matrix it grew from is unchanged (a decision under way keeps using it)
        assert np.array_equal(matrix.values, before[0], equal_nan=True) and len(matrix.descriptions) == before[2]
        assert np.array_equal(matrix.order, before[1])
        matrix = grown


def test_two_matrices_grown_from_one_do_not_share_rows() -> None:
    base = DescriptionMatrix(four_objects(), KNOWLEDGE)
    cup = desc("cup2", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8.5))
    box = desc("box2", "Front-Pinch", ("Width-Degree-1°", P(24, 0), 17))
    one, other = base.appended([cup]), base.appended([box])
    width = base.column[next(t for t in base.tests if t.feature == "Width-Degree-1°")]
    assert one.values[4, width] == 8.5
    assert other.values[4, width] == 17
    assert_same(one, DescriptionMatrix([*four_objects(), cup], KNOWLEDGE))
    assert_same(other, DescriptionMatrix([*four_objects(), box], KNOWLEDGE))


def test_a_learned_row_sorts_after_equal_values_and_before_larger_ones() -> None:
    # Width-Degree-1°(24,0): cup 8, box 18, tumbler 9, closed 30; a new 9 goes after the tumbler
    grown = DescriptionMatrix(four_objects(), KNOWLEDGE).appended(
        [desc("t2", "Top-Pinch", ("Width-Degree-1°", P(24, 0), 9))])
    column = grown.column[next(t for t in grown.tests if t.feature == "Width-Degree-1°")]
    assert grown.order[column].tolist() == [0, 2, 4, 1, 3]
    assert grown.sorted_values[column].tolist() == [8, 9, 9, 18, 30]


def test_a_new_grasp_or_column_builds_the_matrix_anew_and_still_equal() -> None:
    base = DescriptionMatrix(four_objects()[:2], KNOWLEDGE)
    new = [desc("t", "Top-Pinch", ("Width-Degree-1°", P(24, 90), 9))]
    grown = base.appended(new)
    assert_same(grown, DescriptionMatrix([*four_objects()[:2], *new], KNOWLEDGE))
    assert len(grown.classes) == 3


def test_the_executive_appends_what_was_learned_instead_of_rebuilding(tmp_path, monkeypatch) -> None:  # noqa: ANN001
    import behaviours.services as services
    from learner.service import LocalLearner

    built: list[int] = []

    def counted(descriptions, knowledge):  # noqa: ANN001, ANN202
        built.append(len(descriptions))
        return DescriptionMatrix(descriptions, knowledge)

    monkeypatch.setattr(services, "DescriptionMatrix", counted)
    with LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects()) as learner:
        library = services.LibraryMatrix(learner, KNOWLEDGE)
        first = library.current()
        cup = desc("cup", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8.5), ("Height", P(6, ANY), 3.5))
        learner.learn(cup)
        grown = library.current()
        assert built == [4]  # built once, for the first library; the learned cup was appended
        assert library.current() is grown  # nothing changed: the same matrix
        assert len(first.descriptions) == 4
        assert_same(grown, DescriptionMatrix(learner.library().descriptions, KNOWLEDGE))


def test_descriptions_grow_in_place_without_changing_a_view_handed_out() -> None:
    cup, box, tumbler, closed = four_objects()
    first = Descriptions([cup, box])
    longer = first.plus([tumbler])  # extends the shared list in place
    other = first.plus([closed])  # first is no longer the longest view: copied
    assert first == (cup, box) and len(first) == 2 and list(first) == [cup, box]
    assert longer == (cup, box, tumbler) and other == [cup, box, closed]
    assert longer.extends(first) and other.extends(first) and not other.extends(longer)
    assert longer[-1] is tumbler and longer[1:] == (box, tumbler) and first[-1] is box
    with pytest.raises(IndexError):
        first[2]  # noqa: B018 - the shared list has a third entry, this view does not


def test_a_matrix_grows_to_a_learner_snapshot_sharing_its_list(tmp_path) -> None:  # noqa: ANN001
    from learner.service import LocalLearner

    with LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects()) as learner:
        matrix = DescriptionMatrix(learner.library().descriptions, KNOWLEDGE)
        learner.learn(desc("cup", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8.5)))
        grown = matrix.extended_to(learner.library().descriptions)
        assert grown is not None and grown.descriptions is learner.library().descriptions
        assert_same(grown, DescriptionMatrix(tuple(learner.library().descriptions), KNOWLEDGE))
        assert matrix.extended_to(four_objects()[1:]) is None  # not a growth of this library


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(st.lists(descriptions(), max_size=12), st.booleans())
def test_the_bulk_fill_equals_each_row_built_alone(library: list[ObjectDescription], grasps: bool) -> None:
    # the simple path: each description's row on its own (value_at per column), as appending does
    matrix = DescriptionMatrix(library, KNOWLEDGE, grasps)
    alone = np.array([matrix._row(d) for d in library]).reshape(len(library), len(matrix.tests))  # noqa: SLF001
    assert np.array_equal(matrix.values, alone, equal_nan=True)
    for i, d in enumerate(library):
        for j, t in enumerate(matrix.tests):
            if not t.is_grasp:
                v = d.value_at(t.feature, t.position)
                assert (np.isnan(matrix.values[i, j]) if v is None else matrix.values[i, j] == v)


def known_bytes(matrix: DescriptionMatrix) -> dict[str, tuple[str, bytes] | int]:
    """Every field of the matrix's known values, bit for bit (dtype and bytes: -0.0 is not 0.0)."""
    known = matrix.known
    out: dict[str, tuple[str, bytes] | int] = {"rows_covered": known.rows_covered}
    for name in ("rows", "cell", "value_column", "value_first", "value_last", "root_counts"):
        array = getattr(known, name)
        out[name] = (str(array.dtype) + str(array.shape), np.ascontiguousarray(array).tobytes())
    return out


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(st.lists(descriptions(), min_size=1, max_size=12), st.lists(st.lists(descriptions(), max_size=3), max_size=6))
def test_known_values_updated_by_appends_equal_a_fresh_build_bit_for_bit(
        first: list[ObjectDescription], batches: list[list[ObjectDescription]]) -> None:
    from learner.choosing.gain import partition_columns  # noqa: PLC0415

    matrix = DescriptionMatrix(first, KNOWLEDGE)
    matrix.known  # read before every append, so each append updates it rather than builds it
    for batch in batches:
        matrix = matrix.appended(batch)
        fresh = DescriptionMatrix(matrix.descriptions, KNOWLEDGE)
        assert known_bytes(matrix) == known_bytes(fresh)
        if matrix.tests == fresh.tests:
            columns = np.arange(len(matrix.tests))
            everyone = tuple(range(len(matrix.descriptions)))
            a, b = partition_columns(everyone, matrix, columns), partition_columns(everyone, fresh, columns)
            assert a.ranges == b.ranges and np.array_equal(a.gains, b.gains, equal_nan=True)


def test_a_new_distinct_value_and_a_negative_zero_take_their_places() -> None:
    """By hand: Height(6,0) holds 3.5 and 9 (rows 0, 1); appending 6 (a new value between
    them) and -0.0 (a new smallest value) renumbers 9 and counts each value's classes."""
    height = ("Height", P(6, 0))
    library = [desc("a", "Front-Wrap", (*height, 3.5)), desc("b", "Top-Pinch", (*height, 9.0))]
    matrix = DescriptionMatrix(library, KNOWLEDGE, grasps_as_features=False)
    matrix.known
    grown = matrix.appended([desc("c", "Top-Pinch", (*height, 6.0)), desc("d", "Front-Wrap", (*height, -0.0))])
    known = grown.known
    assert known.value_first.tolist() == [0.0, 3.5, 6.0, 9.0] and np.signbit(known.value_first[0])
    assert known.rows.tolist() == [3, 0, 2, 1]
    assert known.root_counts.tolist() == [[1, 0], [1, 0], [0, 1], [0, 1]]
    assert known_bytes(grown) == known_bytes(DescriptionMatrix(grown.descriptions, KNOWLEDGE, grasps_as_features=False))

"""The library as a matrix: one row per description, one column per test.

Choosing a test scores every feature-position against every description at the node;
doing that description by description in Python costs far more than the robot can wait
for (the benchmark's 1,000 descriptions x 100 tests). Building the matrix once per
library turns each choice into a few array operations.

A robot learns one object at a time into a library of up to 100,000 descriptions, so a
learned description is *appended* (:meth:`DescriptionMatrix.appended`): its row is
written into spare capacity shared with the matrix it grew from, and each column's
sort order takes the new rows by binary search when a choice first needs it. Nothing
is re-read or rebuilt, and the result equals the matrix built from scratch.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from learner.appearance import AXIS_TOLERANCE_IN, Appearance
from learner.choosing.partition import Split
from learner.description import Descriptions, ObjectDescription, Observation
from learner.knowledge import Knowledge
from learner.position import Position


NODE_SPLITS_KEPT = 256
"""Partitions of nodes below the root a matrix keeps: a few sessions' paths, each a
handful of nodes; every entry is small (ranges and per-column counts)."""


@dataclass(frozen=True)
class RowLabels:
    """Per row: the description's object id (a fixed-width string array, which numpy
    sorts as Python sorts ``str``) and its grasp position (an index into ``positions``)."""

    object_id: np.ndarray
    grasp_position: np.ndarray
    positions: tuple[Position, ...]

    @staticmethod
    def of(descriptions: Sequence[ObjectDescription], prefix: RowLabels | None = None) -> RowLabels:
        """The labels of ``descriptions``, reusing ``prefix``'s for the rows it covers
        when they are the first ones (a matrix grown by appending)."""
        done = 0 if prefix is None or len(prefix.object_id) > len(descriptions) else len(prefix.object_id)
        positions = list(prefix.positions) if done else []
        index = {p: i for i, p in enumerate(positions)}
        new = [descriptions[i] for i in range(done, len(descriptions))]
        at = np.array([index.setdefault(d.grasp_position, len(index)) for d in new], dtype=np.int32)
        positions.extend(list(index)[len(positions):])
        ids = np.array([d.object_id for d in new], dtype=str)
        if done:
            ids = np.concatenate([prefix.object_id, ids]) if len(ids) else prefix.object_id
            at = np.concatenate([prefix.grasp_position, at])
        return RowLabels(ids, at, tuple(positions))


@dataclass(frozen=True, order=True)
class Test:
    """A feature (or a grasp, when ``is_grasp``) at a position as the library records it."""

    feature: str
    position: Position
    procedure: str
    is_grasp: bool = False

    def __str__(self) -> str:
        return f"{self.feature}{self.position}"


class DescriptionMatrix:
    """Values of every test for every description (NaN: missing), and their classes.

    A grasp test's value is 1 for descriptions of that grasp at a compatible position
    and 0 for the rest: grasps are binary features known for every labelled object.
    """

    def __init__(self, descriptions: Sequence[ObjectDescription], knowledge: Knowledge,
                 grasps_as_features: bool = True) -> None:
        self.descriptions = descriptions if isinstance(descriptions, Descriptions) else Descriptions(descriptions)
        self.knowledge = knowledge
        grasps = _Distinct(self.descriptions)
        self.classes = tuple(sorted({d.grasp for d in grasps.firsts}))
        class_index = {c: i for i, c in enumerate(self.classes)}
        self.class_of = np.array([class_index[d.grasp] for d in grasps.firsts], dtype=np.int64)[grasps.of]
        observed = _Observed(self.descriptions)
        self.tests = tuple(self._sense_tests(observed)
                           + (self._grasp_tests(grasps.firsts) if grasps_as_features else []))
        self.column = {t: j for j, t in enumerate(self.tests)}
        self.values = self._fill(observed, grasps)
        specs = [None if t.is_grasp else knowledge.feature(t.feature) for t in self.tests]
        self.errors = np.array([0.0 if f is None else f.error for f in specs])
        # grasps are binary features known for everyone: never an "unknown" subset
        self.binary = np.array([f is None or f.binary for f in specs], dtype=bool)
        self.is_grasp = np.array([t.is_grasp for t in self.tests], dtype=bool)
        self.span_lo = np.array([0.0 if f is None else f.span[0] for f in specs])
        self.span_hi = np.array([1.0 if f is None else f.span[1] for f in specs])
        self.grasps_as_features = grasps_as_features
        # each column's rows sorted by value (NaN last), once: a node's sorted values are
        # then a filter of this order instead of a sort per choice
        values_by_test = np.ascontiguousarray(self.values.T)
        self._order = np.argsort(values_by_test, axis=1, kind="stable")
        self._sorted_values = np.take_along_axis(values_by_test, self._order, axis=1)
        self._sorted_rows = len(self.descriptions)  # rows the two arrays above cover
        self.class_of = self.class_of.astype(np.int32)
        # each description's appearance as equivalent-ellipse axes (NaN: not recorded), so
        # ruling candidates out by what the camera saw is two comparisons per row
        axes = [_axes(d) for d in self.descriptions]
        self.appearance_axes = np.array(axes, dtype=float).reshape(len(self.descriptions), 2)
        self._rows: _Rows | None = None  # spare capacity, made by the first append
        self._known: KnownValues | None = None  # made when first read
        self.root_splits: dict[bytes, Split] = {}
        """``learner.choosing.gain.partition_columns`` of all rows, by the columns asked (bytes):
        every object's session starts at the root, so it is worked out once per matrix."""
        self.node_splits: dict[bytes, Split] = {}
        """The same below the root, by a digest of the node's rows and the columns, the
        latest :data:`NODE_SPLITS_KEPT`: objects of one kind walk the same first nodes
        (at 100,000 descriptions they hold tens of thousands of rows each)."""
        self._labels: RowLabels | None = None  # made when first read

    @property
    def order(self) -> np.ndarray:
        """Each column's rows by value, NaN last, ties by row (a stable argsort)."""
        self._merge_appended()
        return self._order

    @property
    def sorted_values(self) -> np.ndarray:
        """Each column's values in :attr:`order`."""
        self._merge_appended()
        return self._sorted_values

    @property
    def known(self) -> KnownValues:
        """Each column's known values in :attr:`order`, without the missing ones."""
        n = len(self.descriptions)
        if self._known is not None and self._known.rows_covered < n:
            # a grown matrix: the parent's entries take the new rows' (no sort, no recount)
            self._known = self._known.appended(self.values[self._known.rows_covered:n], self.class_of, n)
        if self._known is None or self._known.rows_covered != n:
            self._merge_appended()
            present = ~np.isnan(self._sorted_values)
            rows = self._order[present].astype(np.int32)  # half the bytes a node's filter reads
            per_column = present.sum(axis=1)
            column = np.repeat(np.arange(len(self.tests), dtype=np.int32), per_column)
            self._known = KnownValues.of(rows, self._sorted_values[present], column, self.class_of[rows],
                                         self._sorted_rows, len(self.classes))
        return self._known

    @property
    def labels(self) -> RowLabels:
        """Each row's object id and grasp position as arrays, so a leaf's grasps and ids
        are read for tens of thousands of rows at once. A grown matrix extends its
        parent's labels by the new rows only."""
        n = len(self.descriptions)
        if self._labels is None or len(self._labels.object_id) != n:
            self._labels = RowLabels.of(self.descriptions, self._labels)
        return self._labels

    def remember_node_split(self, key: bytes, split: Split) -> None:
        """Keep a node's partition (``learner.choosing.gain``), dropping the oldest past
        :data:`NODE_SPLITS_KEPT`."""
        if len(self.node_splits) >= NODE_SPLITS_KEPT:  # pop, not del: two sessions may drop the same one
            self.node_splits.pop(next(iter(self.node_splits), b""), None)
        self.node_splits[key] = split

    def appended(self, new: Sequence[ObjectDescription]) -> DescriptionMatrix:
        """This matrix with ``new`` descriptions added as its last rows; ``self`` is left
        as it was (a decision under way keeps its matrix). See :meth:`extended_to`."""
        grown = self.extended_to(self.descriptions.plus(new))
        assert grown is not None  # the descriptions extend ours by construction
        return grown

    def extended_to(self, descriptions: Sequence[ObjectDescription]) -> DescriptionMatrix | None:
        """The matrix of ``descriptions`` grown from this one, when they are this
        matrix's descriptions followed by new ones (a library only grows); else None.

        The cost is that of the new rows, not of the library: each row is written into
        capacity shared with ``self`` (doubled when full, so a copy every doubling), and
        the columns' sort orders take the rows when first read. Only a description that
        needs a column or a grasp class the matrix lacks (a feature at a position no
        description had, a new grasp) makes it build the matrix anew, as it must: every
        row then gains a value in the new column.
        """
        if not isinstance(descriptions, Descriptions):
            descriptions = Descriptions(descriptions)
        if not descriptions.extends(self.descriptions):
            return None
        n, k = len(self.descriptions), len(descriptions) - len(self.descriptions)
        if k == 0:
            return self
        new = descriptions[n:]
        if not self._fits(new):
            return DescriptionMatrix(descriptions, self.knowledge, self.grasps_as_features)
        rows = self._rows
        if rows is None or rows.used != n or rows.capacity < n + k:
            rows = _Rows.grown(self.values, self.class_of, self.appearance_axes, n + k)
        rows.values[n:n + k] = [self._row(d) for d in new]
        rows.class_of[n:n + k] = [self.classes.index(d.grasp) for d in new]
        rows.axes[n:n + k] = [_axes(d) for d in new]
        rows.used = n + k
        grown = object.__new__(DescriptionMatrix)
        grown.__dict__.update(self.__dict__)
        grown.descriptions = descriptions
        grown.values, grown.class_of, grown.appearance_axes = rows.values[:n + k], rows.class_of[:n + k], rows.axes[:n + k]
        grown._rows = rows
        # the known values are immutable: the grown matrix updates them when first read;
        # every memoised partition counted fewer rows than the grown matrix has
        grown.root_splits, grown.node_splits = {}, {}
        self._rows = None  # the capacity now belongs to the grown matrix
        return grown

    def _fits(self, new: Sequence[ObjectDescription]) -> bool:
        """Whether ``new`` needs no column and no class the matrix lacks."""
        classes = set(self.classes)
        for d in new:
            if d.grasp not in classes:
                return False
            grasp = self._grasp_test_of(d) if self.grasps_as_features else None
            needed = [*self._sense_tests_of(d), *([] if grasp is None else [grasp])]
            if any(t not in self.column for t in needed):
                return False
        return True

    def _row(self, d: ObjectDescription) -> np.ndarray:
        """One description's values, as :meth:`_fill` gives them (for a matrix that has
        every column the description needs)."""
        row = np.full(len(self.tests), np.nan)
        for j, t in enumerate(self.tests):
            if t.is_grasp:
                row[j] = _grasp_value(d, t)
        for j, v in self._sense_values(d):
            row[j] = v
        return row

    def _merge_appended(self) -> None:
        """Take the rows appended since the sort orders were made into them: per column,
        the new rows sorted among themselves, then placed by binary search after any
        equal value (their rows come last, as a stable argsort would put them); the
        old entries fill the other slots in one masked copy."""
        n, done = len(self.descriptions), self._sorted_rows
        if done == n:
            return
        new_values = self.values[done:n].T  # (tests, new rows)
        new_order = np.argsort(new_values, axis=1, kind="stable")
        new_sorted = np.take_along_axis(new_values, new_order, axis=1)
        at = np.array([np.searchsorted(self._sorted_values[j], new_sorted[j], side="right")
                       for j in range(len(self.tests))], dtype=np.int64).reshape(new_values.shape)
        is_new = np.zeros((len(self.tests), n), dtype=bool)
        np.put_along_axis(is_new, at + np.arange(n - done), True, axis=1)  # slots ascend along each column
        order = np.empty(is_new.shape, dtype=self._order.dtype)
        order[~is_new], order[is_new] = self._order.ravel(), (new_order + done).ravel()
        sorted_values = np.empty(is_new.shape)
        sorted_values[~is_new], sorted_values[is_new] = self._sorted_values.ravel(), new_sorted.ravel()
        self._order, self._sorted_values, self._sorted_rows = order, sorted_values, n

    def unlike(self, appearance: Appearance, tolerance_in: float = AXIS_TOLERANCE_IN) -> np.ndarray:
        """Rows whose recorded appearance disagrees with ``appearance`` (an axis off by more
        than ``tolerance_in``); a description without one is never unlike anything."""
        seen = np.array(appearance.axes_in)
        off = np.abs(self.appearance_axes - seen) > tolerance_in + 1e-9  # NaN compares False
        return off.any(axis=1)

    def _sense_tests(self, observed: _Observed) -> list[Test]:
        return sorted({Test(o.feature, o.position, self.knowledge.procedure_for(o.feature).name)
                       for o in observed.distinct if self.knowledge.has_feature(o.feature)})

    def _grasp_tests(self, descriptions: Sequence[ObjectDescription]) -> list[Test]:
        return sorted({t for d in descriptions if (t := self._grasp_test_of(d)) is not None})

    def _sense_tests_of(self, d: ObjectDescription) -> list[Test]:
        """The sensing columns ``d`` has values for (features the knowledge knows)."""
        return [Test(o.feature, o.position, self.knowledge.procedure_for(o.feature).name)
                for o in d.observations if self.knowledge.has_feature(o.feature)]

    def _grasp_test_of(self, d: ObjectDescription) -> Test | None:
        """The grasp column ``d`` makes, when its grasp can be tried as a feature."""
        if self.knowledge.has_grasp(d.grasp) and self.knowledge.grasp(d.grasp).verifiable:
            return Test(d.grasp, d.grasp_position, d.grasp, is_grasp=True)
        return None

    def _fill(self, observed: _Observed, grasps: _Distinct) -> np.ndarray:
        """Every row's values at once, equal to :meth:`_row` of each description.

        Per row this is :meth:`_sense_values` (each column takes the most specific
        observation covering it, the first of equals), but worked out once per distinct
        observation and grasp (a library of 100,000 descriptions holds about 12,000
        distinct observations and a few dozen grasps), then spread over the rows and
        resolved with array operations.
        """
        values = np.full((len(self.descriptions), len(self.tests)), np.nan)
        self._exact: dict[tuple[str, object], int] = {}
        self._general: dict[str, list[int]] = defaultdict(list)  # columns at positions holding "*"
        grasp_columns = []
        for j, t in enumerate(self.tests):
            if t.is_grasp:
                grasp_columns.append(j)
            else:
                self._exact[(t.feature, t.position)] = j
                self._general[t.feature].append(j)
        if grasp_columns:
            per_grasp = np.array([[_grasp_value(d, self.tests[j]) for j in grasp_columns] for d in grasps.firsts])
            values[:, grasp_columns] = per_grasp.reshape(len(grasps.firsts), len(grasp_columns))[grasps.of]
        covered = [self._covered_by(o) for o in observed.distinct]
        counts = np.array([len(c) for c in covered], dtype=np.int64)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]]) if len(counts) else counts
        cover_column = np.array([j for c in covered for j, _ in c], dtype=np.int64)
        cover_specificity = np.array([s for c in covered for _, s in c], dtype=np.int64)
        distinct_value = np.array([o.value for o in observed.distinct], dtype=float)
        # one entry per (observation of a row, column it covers), in the rows' order
        per = counts[observed.flat] if len(observed.flat) else np.zeros(0, dtype=np.int64)
        source = np.repeat(np.arange(len(observed.flat)), per)
        within = np.arange(len(source)) - np.repeat(np.cumsum(per) - per, per)
        cover = first[observed.flat[source]] + within
        row, column = observed.row[source], cover_column[cover]
        specificity, value = cover_specificity[cover], distinct_value[observed.flat[source]]
        # per (row, column): the most specific entry, the first of equals (a stable sort)
        order = np.argsort((row * len(self.tests) + column) * 3 + (2 - specificity), kind="stable")
        row, column, value = row[order], column[order], value[order]
        lead = np.ones(len(row), dtype=bool)
        lead[1:] = (row[1:] != row[:-1]) | (column[1:] != column[:-1])
        values[row[lead], column[lead]] = value[lead]
        return values

    def _covered_by(self, o: Observation) -> list[tuple[int, int]]:
        """``(column, specificity)`` of each sensing column ``o``'s value holds at: its
        own position's column when concrete, every column it covers when it has ``*``."""
        if o.position.distance_in is not None and o.position.orientation_deg is not None:
            j = self._exact.get((o.feature, o.position))
            return [] if j is None else [(j, 2)]
        return [(j, specificity(o.position)) for j in self._general.get(o.feature, [])
                if o.position.covers(self.tests[j].position)]

    def _sense_values(self, d: ObjectDescription) -> list[tuple[int, float]]:
        """``(column, value)`` of each sensing test ``d`` has a value for."""
        if all(o.position.distance_in is not None and o.position.orientation_deg is not None
               for o in d.observations):
            # concrete values cover only their own column: a direct look-up
            return [(j, o.value) for o in d.observations
                    if (j := self._exact.get((o.feature, o.position))) is not None]
        out = []
        for j in {j for o in d.observations for j in self._general.get(o.feature, [])}:
            v = d.value_at(self.tests[j].feature, self.tests[j].position)
            if v is not None:
                out.append((j, v))
        return out


@dataclass(frozen=True)
class KnownValues:
    """The known values of every column, column after column, each column's sorted as
    in :attr:`DescriptionMatrix.order` (ties by row), kept as what a choice reads: each
    entry's row, and its distinct (column, value) with its row's class as one ``cell``
    (``value * classes + class``).

    Most descriptions lack most features, and the known ones repeat a few values (at
    100,000 synthetic descriptions 4.3 million entries hold 17,148 distinct
    (column, value) pairs), so a partition works on the distinct values, each with its
    count per class (``learner.choosing.gain.partition_columns``).
    """

    rows: np.ndarray
    rows_covered: int  # the matrix rows these were made from
    cell: np.ndarray
    value_column: np.ndarray  # per distinct value: its column
    value_first: np.ndarray  # the value as its first entry holds it
    value_last: np.ndarray  # and as its last does (the same number; -0.0 and 0.0 are one value)
    root_counts: np.ndarray  # (values, classes): every row's count

    @staticmethod
    def of(rows: np.ndarray, values: np.ndarray, column: np.ndarray, class_of: np.ndarray, rows_covered: int,
           classes: int) -> KnownValues:
        """The known entries (sorted as above) with their distinct values counted per class."""
        new_value = np.ones(len(values), dtype=bool)
        new_value[1:] = (column[1:] != column[:-1]) | (values[1:] != values[:-1])
        value_of = np.cumsum(new_value, dtype=np.int64) - 1
        first = np.flatnonzero(new_value)
        last = np.append(first[1:] - 1, len(values) - 1) if len(first) else first
        cell = value_of * classes + class_of
        root_counts = np.bincount(cell, minlength=len(first) * classes).reshape(len(first), classes).astype(float)
        return KnownValues(rows, rows_covered, cell, column[first], values[first], values[last], root_counts)


    def appended(self, new_values: np.ndarray, class_of: np.ndarray, rows_covered: int) -> KnownValues:
        """These entries with the known values of rows ``self.rows_covered`` on (``new_values``,
        one row each) inserted where a fresh :meth:`of` would put them: each after the
        last entry of its (column, value), a value not seen before as a new distinct value
        in its place, every later value's cells renumbered and the root's class counts
        extended instead of recounted. The cost is a few passes over the entries' arrays,
        not a sort of them."""
        classes = self.root_counts.shape[1]
        row, column = np.nonzero(~np.isnan(new_values))
        if len(row) == 0:
            return KnownValues(self.rows, rows_covered, self.cell, self.value_column, self.value_first,
                               self.value_last, self.root_counts)
        value = new_values[row, column]
        row = (row + self.rows_covered).astype(np.int32)
        order = np.lexsort((row, value, column))  # as a fresh build sorts: column, value, row
        row, column, value = row[order], column[order].astype(self.value_column.dtype), value[order]
        klass = class_of[row].astype(self.cell.dtype)
        # each entry's place among the distinct values: its column's run, then its value there
        column_start = np.searchsorted(self.value_column, column, side="left")
        column_end = np.searchsorted(self.value_column, column, side="right")
        at = np.empty(len(row), dtype=np.int64)
        for c in np.unique(column):  # a description holds a few dozen columns
            mine = column == c
            lo, hi = column_start[mine][0], column_end[mine][0]
            at[mine] = lo + np.searchsorted(self.value_first[lo:hi], value[mine], side="left")
        exists = at < len(self.value_first)
        exists[exists] = (self.value_column[at[exists]] == column[exists]) & (self.value_first[at[exists]] == value[exists])
        # the new distinct values, in order, each inserted before the old value ``at``
        fresh = ~exists
        lead = fresh.copy()
        lead[1:] &= (column[1:] != column[:-1]) | (value[1:] != value[:-1]) | ~fresh[:-1]
        new_at = at[lead]
        rank = np.cumsum(lead) - 1  # per entry: its new distinct value's rank (for the fresh ones)
        final = at + np.searchsorted(new_at, at, side="right")
        final[fresh] = new_at[rank[fresh]] + rank[fresh]
        # where each entry goes among the old entries: after its value's last, or where
        # its new value begins (the first entry of the old value it precedes)
        value_end = np.searchsorted(self.cell, (at + exists) * classes, side="left")
        old_final = np.arange(len(self.value_first)) + np.searchsorted(new_at, np.arange(len(self.value_first)), side="right")
        # a value seen before (the usual case) renumbers nothing: the old cells stand
        old_cell = self.cell + classes * (old_final - np.arange(len(old_final)))[self.cell // classes] if len(new_at) else self.cell
        cell = np.insert(old_cell, value_end, final * classes + klass)
        rows = np.insert(self.rows, value_end, row)
        value_column = np.insert(self.value_column, new_at, column[lead])
        value_first = np.insert(self.value_first, new_at, value[lead])
        value_last = np.insert(self.value_last, new_at, value[lead])
        last_of = np.flatnonzero(np.append((column[1:] != column[:-1]) | (value[1:] != value[:-1]), True))
        value_last[final[last_of]] = value[last_of]  # the value as the last entry of each holds it
        root_counts = np.zeros((len(value_first), classes))
        root_counts[old_final] = self.root_counts
        np.add.at(root_counts, (final, klass), 1.0)
        return KnownValues(rows, rows_covered, cell, value_column, value_first, value_last, root_counts)


class _Distinct:
    """The descriptions with distinct (grasp, grasp position), as the first description
    of each, and which of them each description has (``of``): the grasp columns and
    classes are then worked out once per distinct grasp, not once per row."""

    def __init__(self, descriptions: Sequence[ObjectDescription]) -> None:
        index: dict[tuple[str, int], int] = {}
        self.firsts: list[ObjectDescription] = []
        of = []
        for d in descriptions:
            key = (d.grasp, id(d.grasp_position))  # positions are shared objects: compare by identity
            i = index.get(key)
            if i is None:
                i = index[key] = len(self.firsts)
                self.firsts.append(d)
            of.append(i)
        self.of = np.array(of, dtype=np.int64)


class _Observed:
    """Every row's observations as indices into the distinct ones: ``distinct`` (one
    Observation per distinct feature, position and value), ``flat`` (each row's in
    order, rows one after another) and ``row`` (whose each entry of ``flat`` is).

    Equal positions are usually one shared object (the library readers share them),
    so identity stands in for equality; two equal positions that are separate objects
    only make two entries of ``distinct`` that cover the same columns.
    """

    def __init__(self, descriptions: Sequence[ObjectDescription]) -> None:
        self._by_value: dict[tuple[str, int, float], int] = {}
        self._by_id: dict[int, int] = {}  # the objects stay alive (the rows hold them): ids stay theirs
        self.distinct: list[Observation] = []
        flat: list[int] = []
        lengths: list[int] = []
        seen = self._by_id.get
        for d in descriptions:
            lengths.append(len(d.observations))
            found = [*map(seen, map(id, d.observations))]  # a stored library shares its observations
            flat.extend(found if None not in found else map(self._index, d.observations))
        self.flat = np.array(flat, dtype=np.int64)
        self.row = np.repeat(np.arange(len(lengths), dtype=np.int64), lengths)

    def _index(self, o: Observation) -> int:
        i = self._by_value.get(key := (o.feature, id(o.position), o.value))
        if i is None:
            i = self._by_value[key] = len(self.distinct)
            self.distinct.append(o)
        self._by_id[id(o)] = i
        return i


def specificity(position: Position) -> int:
    """How many slots are concrete: a value recorded there beats one with more ``*``."""
    return (position.distance_in is not None) + (position.orientation_deg is not None)


def _grasp_value(d: ObjectDescription, t: Test) -> float:
    """A grasp column's value: 1 for a description of that grasp at a compatible position."""
    return 1.0 if d.grasp == t.feature and d.grasp_position.compatible(t.position) else 0.0


def _axes(d: ObjectDescription) -> tuple[float, float]:
    return d.appearance.axes_in if d.appearance is not None else (np.nan, np.nan)


class _Rows:
    """Row arrays with spare capacity, shared by a matrix and the one appended to it:
    each matrix views its own prefix, so writing rows past it changes no matrix already
    handed out. Only the matrix whose length is ``used`` may write past it."""

    def __init__(self, values: np.ndarray, class_of: np.ndarray, axes: np.ndarray, used: int) -> None:
        self.values, self.class_of, self.axes, self.used = values, class_of, axes, used

    @property
    def capacity(self) -> int:
        return len(self.values)

    @classmethod
    def grown(cls, values: np.ndarray, class_of: np.ndarray, axes: np.ndarray, needed: int) -> _Rows:
        """Fresh arrays holding the given rows and room for at least ``needed`` rows."""
        n = len(values)
        capacity = max(needed, 2 * n, 16)
        out = cls(np.full((capacity, values.shape[1]), np.nan), np.zeros(capacity, dtype=np.int32),
                  np.full((capacity, 2), np.nan), n)
        out.values[:n], out.class_of[:n], out.axes[:n] = values, class_of, axes
        return out

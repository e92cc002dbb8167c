"""Object descriptions: what CSL learns (docs/method.md §2).

``{object-id, grasp(position), [(feature(position), value), ...]}`` — incomplete on
purpose: a feature is recorded only where it was needed to tell this object from
others, so "missing" is the normal case, not an error.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import overload

from learner.appearance import Appearance
from learner.position import Position


@dataclass(frozen=True, order=True, slots=True)
class Observation:
    """``feature(position) = value``, e.g. ``Width-Degree-1°(26,0) = 16``."""

    feature: str
    position: Position
    value: float

    def __str__(self) -> str:
        return f"({self.feature}{self.position}, {_num(self.value)})"


@dataclass(frozen=True, slots=True)
class ObjectDescription:
    """One object's grasp and the features measured on it, with the appearance the
    overhead camera saw it with (None: not recorded, as in libraries of format version 1;
    such a description is never ruled out by appearance)."""

    object_id: str
    grasp: str
    grasp_position: Position
    observations: tuple[Observation, ...] = ()
    appearance: Appearance | None = None

    def value_at(self, feature: str, position: Position) -> float | None:
        """The value of ``feature`` valid at ``position``, or None when it is missing.

        A value recorded at a generalised position covers the concrete one; with several
        candidates the most specific (fewest ``*``) wins.
        """
        best: Observation | None = None
        for obs in self.observations:
            if obs.feature == feature and obs.position.covers(position):
                if best is None or _specificity(obs.position) > _specificity(best.position):
                    best = obs
        return None if best is None else best.value

    def with_observations(self, extra: Iterable[Observation]) -> ObjectDescription:
        """A copy with ``extra`` added; a new value at an existing (feature, position) wins."""
        merged = {(o.feature, o.position): o for o in self.observations}
        for obs in extra:
            merged[(obs.feature, obs.position)] = obs
        return ObjectDescription(self.object_id, self.grasp, self.grasp_position, in_order(merged.values()),
                                 self.appearance)

    def __str__(self) -> str:
        obs = ", ".join(str(o) for o in self.observations)
        return f"{{{self.object_id}, {self.grasp}{self.grasp_position}, [{obs}]}}"


def in_order(observations: Iterable[Observation]) -> tuple[Observation, ...]:
    """``tuple(sorted(observations))``, sorted on plain tuple keys: the same order (a
    position's key is equal exactly when the positions are), compared in C, which is
    what keeps loading a 100,000-description library fast."""
    return tuple(sorted(observations, key=_order_key))


def _order_key(o: Observation) -> tuple[str, tuple[bool, float, bool, float], float]:
    return (o.feature, o.position.order_key(), o.value)


def _specificity(position: Position) -> int:
    return (position.distance_in is not None) + (position.orientation_deg is not None)


def _num(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else f"{value:g}"


class Descriptions(Sequence[ObjectDescription]):
    """An append-only run of descriptions, where adding one costs the same at 100 and at
    100,000 entries.

    A library only grows, and every snapshot and every matrix holds all of it: copying a
    100,000-entry tuple for each learned object would make learning cost grow with the
    library. So each value is a view of a prefix of one shared list. :meth:`plus` on
    the longest view extends the list in place, which changes no view already handed
    out (each stops at its own length); on any other view it copies that prefix first.
    Seen from outside a value never changes, like a tuple, and compares equal to a
    tuple or list with the same entries. Views of one list are extended by one thread
    at a time (the learner's lock, or the executive's single tick thread).
    """

    __slots__ = ("_items", "_n")

    def __init__(self, items: Iterable[ObjectDescription] = ()) -> None:
        self._items = list(items)
        self._n = len(self._items)

    def plus(self, new: Iterable[ObjectDescription]) -> Descriptions:
        """These descriptions followed by ``new``."""
        out = object.__new__(Descriptions)
        if len(self._items) == self._n:  # nobody appended past this view: extend in place
            self._items.extend(new)
            out._items = self._items
        else:
            out._items = [*self._items[:self._n], *new]
        out._n = len(out._items)
        return out

    def extends(self, other: Sequence[ObjectDescription]) -> bool:
        """Whether ``other`` is a prefix of these descriptions (at once when ``other``
        is a view of the same list)."""
        if isinstance(other, Descriptions) and other._items is self._items:
            return other._n <= self._n
        return len(other) <= self._n and all(a == b for a, b in zip(self, other))

    def __len__(self) -> int:
        return self._n

    @overload
    def __getitem__(self, index: int) -> ObjectDescription: ...

    @overload
    def __getitem__(self, index: slice) -> tuple[ObjectDescription, ...]: ...

    def __getitem__(self, index: int | slice) -> ObjectDescription | tuple[ObjectDescription, ...]:
        if isinstance(index, slice):
            return tuple(self._items[i] for i in range(self._n)[index])
        return self._items[range(self._n)[index]]  # IndexError beyond this view

    def __iter__(self) -> Iterator[ObjectDescription]:
        return itertools.islice(self._items, self._n)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, (Descriptions, tuple, list)):
            return NotImplemented
        return len(other) == self._n and (
            (isinstance(other, Descriptions) and other._items is self._items)
            or all(a == b for a, b in zip(self, other)))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Descriptions({list(self)!r})"


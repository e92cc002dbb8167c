"""Object descriptions: what CSL learns (docs/method.md §2).

``{object-id, grasp(position), [(feature(position), value), ...]}`` — incomplete on
purpose: a feature is recorded only where it was needed to tell this object from
others, so "missing" is the normal case, not an error.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

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

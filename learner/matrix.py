"""The library as a matrix: one row per description, one column per test.

Choosing a test scores every feature-position against every description at the node;
doing that description by description in Python costs far more than the robot can wait
for (the benchmark's 1,000 descriptions x 100 tests). Building the matrix once per
library turns each choice into a few array operations.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from learner.appearance import AXIS_TOLERANCE_IN, Appearance
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.position import Position


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
        self.descriptions = tuple(descriptions)
        self.knowledge = knowledge
        self.classes = tuple(sorted({d.grasp for d in self.descriptions}))
        class_index = {c: i for i, c in enumerate(self.classes)}
        self.class_of = np.array([class_index[d.grasp] for d in self.descriptions], dtype=np.int64)
        self.tests = tuple(self._sense_tests() + (self._grasp_tests() if grasps_as_features else []))
        self.column = {t: j for j, t in enumerate(self.tests)}
        self.values = self._fill()
        specs = [None if t.is_grasp else knowledge.feature(t.feature) for t in self.tests]
        self.errors = np.array([0.0 if f is None else f.error for f in specs])
        # grasps are binary features known for everyone: never an "unknown" subset
        self.binary = np.array([f is None or f.binary for f in specs], dtype=bool)
        self.is_grasp = np.array([t.is_grasp for t in self.tests], dtype=bool)
        self.span_lo = np.array([0.0 if f is None else f.span[0] for f in specs])
        self.span_hi = np.array([1.0 if f is None else f.span[1] for f in specs])
        # each column's rows sorted by value (NaN last), once: a node's sorted values are
        # then a filter of this order instead of a sort per choice
        self.values_by_test = np.ascontiguousarray(self.values.T)
        self.order = np.argsort(self.values_by_test, axis=1, kind="stable")
        self.sorted_values = np.take_along_axis(self.values_by_test, self.order, axis=1)
        self.class_of = self.class_of.astype(np.int32)
        # each description's appearance as equivalent-ellipse axes (NaN: not recorded), so
        # ruling candidates out by what the camera saw is two comparisons per row
        axes = [d.appearance.axes_in if d.appearance is not None else (np.nan, np.nan) for d in self.descriptions]
        self.appearance_axes = np.array(axes, dtype=float).reshape(len(self.descriptions), 2)

    def unlike(self, appearance: Appearance, tolerance_in: float = AXIS_TOLERANCE_IN) -> np.ndarray:
        """Rows whose recorded appearance disagrees with ``appearance`` (an axis off by more
        than ``tolerance_in``); a description without one is never unlike anything."""
        seen = np.array(appearance.axes_in)
        off = np.abs(self.appearance_axes - seen) > tolerance_in + 1e-9  # NaN compares False
        return off.any(axis=1)

    def _sense_tests(self) -> list[Test]:
        tests = {
            Test(o.feature, o.position, self.knowledge.procedure_for(o.feature).name)
            for d in self.descriptions for o in d.observations if self.knowledge.has_feature(o.feature)
        }
        return sorted(tests)

    def _grasp_tests(self) -> list[Test]:
        tests = {
            Test(d.grasp, d.grasp_position, d.grasp, is_grasp=True)
            for d in self.descriptions
            if self.knowledge.has_grasp(d.grasp) and self.knowledge.grasp(d.grasp).verifiable
        }
        return sorted(tests)

    def _fill(self) -> np.ndarray:
        values = np.full((len(self.descriptions), len(self.tests)), np.nan)
        exact: dict[tuple[str, object], int] = {}
        general: dict[str, list[int]] = defaultdict(list)  # columns at positions holding "*"
        for j, t in enumerate(self.tests):
            if t.is_grasp:
                values[:, j] = [1.0 if d.grasp == t.feature and d.grasp_position.compatible(t.position) else 0.0
                                for d in self.descriptions]
            else:
                exact[(t.feature, t.position)] = j
                general[t.feature].append(j)
        for i, d in enumerate(self.descriptions):
            if all(o.position.distance_in is not None and o.position.orientation_deg is not None
                   for o in d.observations):
                # concrete values cover only their own column: a direct look-up
                for o in d.observations:
                    j = exact.get((o.feature, o.position))
                    if j is not None:
                        values[i, j] = o.value
                continue
            for j in {j for o in d.observations for j in general.get(o.feature, [])}:
                v = d.value_at(self.tests[j].feature, self.tests[j].position)
                if v is not None:
                    values[i, j] = v
        return values

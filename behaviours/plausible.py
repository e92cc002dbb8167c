"""A sensed value is checked against what a value of its feature can be.

The driver's values are its word: a sonar reporting in centimetres, or a sensor stuck
far off, yields numbers the learner would match to a branch (or call unreliable and
then follow the nearest one). Two checks need no truth about the object:

- the feature's ``span`` in the robot profile (what the feature can take at all);
- the values the library holds for the feature: an object unlike every description can
  be new, but one more than :data:`LIBRARY_MARGIN_ERRORS` times the feature's expected
  error beyond the whole range the library holds is not an object, it is a fault.

``Plausible?`` stands after the sensing, before ``FollowBranch``::

    measure
      ApplyTest or re-approach
      Plausible?       every value within its span and near the library's range
      FollowBranch

A value that fails is ``implausible``: an event, and the test is unusable here
(``RecognitionSession.unusable``), as a test the driver refused: it is reselected, and
the value is never matched to a branch. The run's closing lines count them
(``executive.exit_status``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

from py_trees.common import Status

from behaviours.base import CslBehaviour
from behaviours.events import Event
from learner.choosing.matrix import DescriptionMatrix
from learner.description import ObjectDescription
from learner.knowledge import FeatureSpec, Knowledge

LIBRARY_MARGIN_ERRORS = 20.0
"""k: how many of a feature's expected errors beyond the range the library holds a value
may lie before it is implausible. Chosen so that the shipped worlds' test objects, which
are not in the training library, are never flagged in ``csl demo`` nor in the paper's
experiment (tests/behaviours/test_plausible.py pins the margin it leaves), while a
length sensed in centimetres of an object longer than the library's longest is."""


def library_ranges(descriptions: Iterable[ObjectDescription]) -> dict[str, tuple[float, float]]:
    """Each feature's lowest and highest value over every description's observations."""
    ranges: dict[str, tuple[float, float]] = {}
    for description in descriptions:
        for seen in description.observations:
            lo, hi = ranges.get(seen.feature, (seen.value, seen.value))
            ranges[seen.feature] = (min(lo, seen.value), max(hi, seen.value))
    return ranges


def implausibility(value: float, spec: FeatureSpec, held: tuple[float, float] | None) -> str | None:
    """Why ``value`` of the feature ``spec`` is implausible, given the range ``held``
    by the library (None: it holds none); None when it is plausible."""
    if not math.isfinite(value):
        return f"{value} is not a finite number"
    lo, hi = spec.span
    if not lo <= value <= hi:
        return f"outside the feature's span [{lo:g}, {hi:g}] {spec.unit}"
    if held is None or spec.binary or spec.error <= 0:
        return None
    margin = LIBRARY_MARGIN_ERRORS * spec.error
    if not held[0] - margin <= value <= held[1] + margin:
        return (f"more than {LIBRARY_MARGIN_ERRORS:g} x its error ({spec.error:g} {spec.unit}) beyond every "
                f"library description ({held[0]:g} to {held[1]:g} {spec.unit})")
    return None


def implausible_values(values: Mapping[str, float | None], knowledge: Knowledge,
                       ranges: Mapping[str, tuple[float, float]]) -> dict[str, str]:
    """The features of ``values`` whose value is implausible, each with why (a feature
    the profile does not know is implausible too; a missing value is not: no echo is
    the unreliable value the learner handles)."""
    out: dict[str, str] = {}
    for feature, value in values.items():
        if value is None:
            continue
        try:
            spec = knowledge.feature(feature)
        except KeyError:
            out[feature] = "not a feature of the robot profile"
            continue
        why = implausibility(float(value), spec, ranges.get(feature))
        if why is not None:
            out[feature] = why
    return out


class LibraryRanges:
    """:func:`library_ranges` of the library a behaviour reads, made again only when the
    library changed (a new matrix object): a check per sensing must not walk every
    description each time."""

    def __init__(self) -> None:
        self._cached: tuple[DescriptionMatrix, dict[str, tuple[float, float]]] | None = None

    def of(self, matrix: DescriptionMatrix) -> dict[str, tuple[float, float]]:
        """The ranges of ``matrix``'s descriptions (its identity is the key)."""
        if self._cached is None or self._cached[0] is not matrix:
            self._cached = (matrix, library_ranges(matrix.descriptions))
        return self._cached[1]


def values_checked(behaviour: CslBehaviour, ranges: LibraryRanges, test: str,
                   values: Mapping[str, float | None]) -> dict[str, str]:
    """:func:`implausible_values` of what ``behaviour`` sensed for ``test``, each noted as
    an ``implausible`` event; the features that failed, with why (empty: all plausible)."""
    bad = implausible_values(values, behaviour.services.knowledge, ranges.of(behaviour.services.library.current()))
    for feature, why in bad.items():
        behaviour.note(Event.IMPLAUSIBLE, test=test, feature=feature, value=values[feature], why=why)
    return bad


class Plausible(CslBehaviour):
    """Condition ``Plausible?``: every value the step's sensing yielded is plausible
    (module docstring); else ``implausible`` events, the test unusable here, and it
    fails, so the step ends and the next one reselects."""

    def __init__(self, robot: str, name: str = "Plausible?") -> None:
        super().__init__(name, robot)
        self._ranges = LibraryRanges()

    def update(self) -> Status:
        step = self.step
        test = step.test
        if test is None or test.test.is_grasp or not step.values:
            self.feedback_message = "nothing sensed"
            return Status.SUCCESS
        bad = values_checked(self, self._ranges, str(test.test), step.values)
        if not bad:
            self.feedback_message = "plausible"
            return Status.SUCCESS
        self.obj.session.unusable(test)
        self.feedback_message = f"implausible: {', '.join(bad)}"
        return Status.FAILURE

"""The execution stage as a state machine the executive steps through (docs/method.md §5).

A :class:`RecognitionSession` grows only the path the object at hand needs, one test
at a time, from where the robot stands. The executive asks :meth:`decide` what to do,
carries it out on the robot, and reports back; each control strategy of the paper is one
method, so the behaviour tree can show each recovery as its own branch:

- ``observe``: a measured value follows the branch it matches, or is *unreliable*;
- ``decide`` after an unreliable value: *reselection*, the next-best test at the node;
- ``backtrack``: invalidate the parent's value and choose a different test there;
- ``follow_nearest``: the last resort, the branch nearest the measured value;
- an ``AmbiguousLeaf`` decision: try its grasps as binary features;
- ``grasp_failed``: drop the failed grasp's descriptions and rebuild from here, or, after
  side effects, restore them all and start over.

What the overhead camera saw of the object (its :class:`Appearance`) is a feature measured
before the session starts, at no cost: descriptions recorded with a different appearance
are not candidates at the root (unless that would leave none: an unseen object, and the
appearance is ignored, ``appearance_ignored``).
"""

from __future__ import annotations

import logging
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from learner.appearance import AXIS_TOLERANCE_IN, Appearance
from learner.choosing.criteria import Criterion
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf, grasp_options, leaf_at, object_ids
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.node import Context, Node, ScoredTest, measured_value, split, target_for
from learner.choosing.partition import match, nearest
from learner.choosing.selection import rank
from learner.costs import MoveCostEstimator, sensing_cost
from learner.description import ObjectDescription, Observation
from learner.knowledge import Knowledge
from learner.position import Position

log = logging.getLogger(__name__)
RANKED_TOLD = 5
"""The best tests told on the log (DEBUG) each time a test is chosen."""


@dataclass(frozen=True)
class Exhausted:
    """No reliable test is left at this node (or N alternatives were tried): backtrack."""

    tried: int


Decision = ScoredTest | GraspLeaf | AmbiguousLeaf | Exhausted


@dataclass(frozen=True)
class Matched:
    """The measured value follows branch ``branch`` (range ``range``)."""

    branch: int
    range: tuple[float, float]
    value: float


@dataclass(frozen=True)
class Unreliable:
    """The value fell between or outside the branches (None: the sonar dropped out)."""

    value: float | None


@dataclass
class _Frame:
    """One node on the path: its descriptions, the test chosen there and what was tried."""

    node: Node
    position: Position
    test: ScoredTest | None = None
    value: float | None = None
    tried: set[Test] = field(default_factory=set)
    unreliable: list[tuple[ScoredTest, float]] = field(default_factory=list)  # for nearest neighbour
    nearest_used: bool = False  # nearest neighbour is followed once per node, never in a loop
    awaiting_reselection: bool = False  # the latest value here was not trusted (or none could be had)
    guessed: bool = False  # reached by following nearest neighbour: a guess, not a measurement


class RecognitionSession:
    """The run-time tree for one object, grown one decision at a time."""

    def __init__(
        self,
        matrix: DescriptionMatrix,
        criterion: Criterion,
        estimator: MoveCostEstimator,
        start: Position,
        *,
        max_alternatives: int = 3,
        orientation_free: bool = False,
        seed: int = 0,
        appearance: Appearance | None = None,
        use_appearance: bool = True,
        appearance_tolerance_in: float = AXIS_TOLERANCE_IN,
    ) -> None:
        """Start recognizing one object from ``start``; ``matrix`` is the library, built
        once and shared by every object until the library changes.

        ``orientation_free``: the object has no orientation (a round footprint), so its
        values hold from every side and are recorded at ``(d,*)``, as training does.
        ``seed``: for the choices the criterion leaves to chance (ties of a cost-blind one).
        ``appearance``: what the overhead camera saw of the object; with ``use_appearance``
        descriptions whose recorded appearance differs by more than
        ``appearance_tolerance_in`` on an axis are ruled out for free. It is kept either
        way, for the description learned from this object.
        """
        if not matrix.descriptions:
            raise ValueError("the library holds no object descriptions to recognize with")
        if max_alternatives < 1:
            raise ValueError(f"max_alternatives must be at least 1, got {max_alternatives}")
        self.matrix = matrix
        self.ctx = Context(matrix, criterion, estimator, np.random.default_rng(seed))
        self.orientation_free = orientation_free
        self.max_alternatives = max_alternatives
        self.appearance = appearance
        self.use_appearance = use_appearance
        self.appearance_tolerance_in = appearance_tolerance_in
        self.appearance_ignored = False  # every candidate was unlike the object: appearance not used
        self._changes = 0  # bumped by every change that can alter decide()'s answer
        self._decided: tuple[int, Decision] | None = None
        self._position = start
        self.measurements: dict[tuple[str, Position], float] = {}
        self.dropped_grasps: set[str] = set()
        self.pushes: Counter[str] = Counter()  # pushes per grasp on this object
        self.wrong_predictions: list[str] = []
        self.unreliable_count = 0  # values not trusted on this object (since it last changed)
        self._frames = [_Frame(self._root_node(), start)]

    @classmethod
    def for_library(cls, library: Sequence[ObjectDescription], knowledge: Knowledge, criterion: Criterion,
                    estimator: MoveCostEstimator, start: Position, *, grasps_as_features: bool = True,
                    max_alternatives: int = 3, appearance: Appearance | None = None) -> RecognitionSession:
        """A session over a library not yet built into a matrix."""
        return cls(DescriptionMatrix(library, knowledge, grasps_as_features), criterion, estimator, start,
                   max_alternatives=max_alternatives, appearance=appearance)

    # -- where we are -------------------------------------------------------------
    @property
    def position(self) -> Position:
        """Where the robot stands relative to the object (moves and measurements update it)."""
        return self._position

    @position.setter
    def position(self, where: Position) -> None:
        if where != self._position:
            self._position = where
            self._changed()

    def _changed(self) -> None:
        self._changes += 1

    @property
    def depth(self) -> int:
        """Tests followed so far on the current path."""
        return len(self._frames) - 1

    @property
    def path(self) -> list[tuple[ScoredTest, float]]:
        """The tests taken and the values that chose their branches."""
        return [(f.test, f.value) for f in self._frames[:-1] if f.test is not None and f.value is not None]

    @property
    def candidates(self) -> tuple[str, ...]:
        """Ids of the descriptions still consistent with what was measured."""
        return object_ids(self._frames[-1].node, self.ctx)

    # -- choosing -------------------------------------------------------------------
    def decide(self) -> Decision:
        """What to do next at the current node: a test, a grasp, grasps to try, or backtrack.

        Several behaviours ask within one step; the answer is kept until something changes.
        """
        if self._decided is None or self._decided[0] != self._changes:
            self._decided = (self._changes, self._decide())
        return self._decided[1]

    def _decide(self) -> Decision:
        frame = self._frames[-1]
        leaf = leaf_at(frame.node, self.position, self.ctx)
        if leaf is not None:
            return self._unless_guessed(leaf)
        on_path = frozenset(f.test.test for f in self._frames[:-1] if f.test is not None)
        if len(frame.tried) >= self.max_alternatives:
            return Exhausted(len(frame.tried))
        ranked = rank(frame.node, self.position, self.ctx, self.measurements, on_path | frame.tried)
        if ranked and log.isEnabledFor(logging.DEBUG):
            log.debug("%d tests ranked at %s among %d descriptions (%s): %s", len(ranked), self.position,
                      len(frame.node.rows), self.ctx.criterion.name, "; ".join(_told(t) for t in ranked[:RANKED_TOLD]))
        if ranked:
            frame.test = ranked[0]
            return ranked[0]
        if frame.tried:
            return Exhausted(len(frame.tried))
        return AmbiguousLeaf(tuple(grasp_options(frame.node, self.position, self.ctx)),
                             object_ids(frame.node, self.ctx))

    def _unless_guessed(self, leaf: GraspLeaf) -> GraspLeaf | AmbiguousLeaf:
        """A leaf whose grasp the finger sensor cannot confirm (No-Grab) does not leave
        the object when what led to it is a guess: the branch *nearest* a value that
        matched none (the rows beside it are as likely), or descriptions the camera
        rules out (``appearance_ignored``: the object looks like none of the candidates
        left, so the leaf is only its nearest relative). The grasps of the node the guess
        was made at (the root, for the appearance) become an ambiguous leaf instead,
        No-Grab last; each that fails is dropped and the tree rebuilt, so the object is
        left only when no confirmable grasp remains.

        Leaving is the one act nothing corrects (the robot never learns it was wrong, and
        the object stays on the floor: the walk rollout prices it at 1.5 h), while a
        wrong confirmable grasp costs its move and time and is dropped.
        """
        if self.ctx.knowledge.grasp(leaf.grasp).verifiable:
            return leaf
        guess = next((i for i, f in enumerate(self._frames) if f.guessed), None)
        if guess is not None:
            node = self._frames[guess - 1].node  # where the value matched no branch
        elif self.appearance_ignored:
            node = self._frames[0].node
        else:
            return leaf
        options = grasp_options(node, self.position, self.ctx)
        if not any(self.ctx.knowledge.grasp(o.grasp).verifiable for o in options):
            return leaf  # nothing left that could hold it
        return AmbiguousLeaf(tuple(options), object_ids(node, self.ctx))

    # -- measuring ------------------------------------------------------------------
    def observe(self, test: ScoredTest, values: Mapping[str, float | None], at: Position) -> Matched | Unreliable:
        """Record a sensing procedure's values measured at ``at`` and follow ``test``'s branch.

        Every feature the procedure yielded is kept (one procedure, several features, one
        cost); an unreliable value marks the test tried at this node.
        """
        self.position = at
        self.record(values, at)
        value = values.get(test.test.feature)
        if value is None:
            value = measured_value(test.test, self.measurements)
        return self._follow(test, value)

    def grasp_as_feature(self, test: ScoredTest, success: bool, at: Position) -> Matched | Unreliable:
        """A grasp tried as a binary feature: success ends recognition, failure follows
        the 'failure' branch (the grasp had no side effects)."""
        self.position = at
        if not success:
            self.wrong_predictions.append(test.test.feature)
            self.dropped_grasps.add(test.test.feature)  # stays ruled out if the tree is rebuilt
        return self._follow(test, 1.0 if success else 0.0)

    def _follow(self, test: ScoredTest, value: float | None) -> Matched | Unreliable:
        self._changed()
        frame = self._frames[-1]
        frame.test = test
        frame.value = value
        idx = None if value is None else match(value, test.ranges, test.error)
        if idx is None:
            frame.tried.add(test.test)
            frame.awaiting_reselection = True
            self.unreliable_count += 1
            if value is not None:
                frame.unreliable.append((test, value))
                # the distrusted value must not come back for free as another test of the
                # same feature (a round object's (6,*) width answers (6,0) and (6,90) alike)
                frame.tried.update(t for t in self.matrix.tests if t.feature == test.test.feature
                                   and measured_value(t, self.measurements) == value)
            return Unreliable(value)
        return self._push(frame, test, idx, value)

    def unusable(self, test: ScoredTest) -> None:
        """``test`` cannot be applied from here (no path to its position, the driver
        refused it): it counts as tried at this node and another is reselected, but no
        value is recorded and nearest neighbour has nothing to be near to."""
        self._changed()
        frame = self._frames[-1]
        frame.test, frame.value = test, None
        frame.tried.add(test.test)
        frame.awaiting_reselection = True

    @property
    def awaiting_reselection(self) -> bool:
        """True when the current node's latest value was not trusted (or none could be
        had): the next test here is a reselection, not a fresh best choice."""
        return self._frames[-1].awaiting_reselection

    @property
    def can_follow_nearest(self) -> bool:
        """True when a value measured at this node was unreliable and nearest neighbour
        has not been followed from here yet."""
        frame = self._frames[-1]
        return bool(frame.unreliable) and not frame.nearest_used

    def classification_failure(self) -> AmbiguousLeaf:
        """Nothing reliable is left to test here: offer the node's grasps, to be tried
        as binary features (docs/method.md §5, ambiguous leaf)."""
        frame = self._frames[-1]
        return AmbiguousLeaf(tuple(grasp_options(frame.node, self.position, self.ctx)),
                             object_ids(frame.node, self.ctx))

    def follow_nearest(self) -> Matched:
        """Follow the branch nearest the node's latest unreliable value (docs/method.md §5,
        the last resort)."""
        frame = self._frames[-1]
        if not frame.unreliable:
            raise ValueError("nearest neighbour needs an unreliable value measured at the current node")
        test, value = frame.unreliable[-1]
        frame.nearest_used = True
        return self._push(frame, test, nearest(value, test.ranges), value, guessed=True)

    def _push(self, frame: _Frame, test: ScoredTest, idx: int, value: float, guessed: bool = False) -> Matched:
        self._changed()
        frame.test, frame.value = test, value
        frame.awaiting_reselection = False
        child = split(frame.node, test, self.matrix)[idx]
        self._frames.append(_Frame(child, self.position, guessed=guessed))
        return Matched(idx, test.ranges[idx], value)

    def backtrack(self) -> bool:
        """Invalidate the parent's measured value and make it choose a different test.

        Returns False at the root, where there is nothing left to undo.
        """
        if len(self._frames) == 1:
            return False
        self._changed()
        self._frames.pop()
        parent = self._frames[-1]
        if parent.test is not None:
            parent.tried.add(parent.test.test)
            for key in [k for k in self.measurements
                        if k[0] == parent.test.test.feature and parent.test.test.position.overlaps(k[1])]:
                del self.measurements[key]
        parent.test, parent.value = None, None
        parent.awaiting_reselection = False  # the parent chooses afresh
        return True

    # -- grasping -------------------------------------------------------------------
    def grasp_failed(self, grasp: str, *, side_effects: bool, changed: bool = False,
                     position: Position | None = None, appearance: Appearance | None = None) -> None:
        """A grasp at a leaf failed; rebuild the tree from the current position.

        Without side effects the object is not of that grasp's class: drop its
        descriptions, keep what was measured. With side effects (docs/method.md §5.4) we
        tell apart the two cases the camera distinguishes: *pushed* is the same object,
        moved; the push may be why this grasp failed, so its descriptions are restored,
        but grasps that failed cleanly before stay ruled out and every value measured
        relative to the object still holds; a grasp that pushes the object a second time
        is dropped (pushing it across the floor again teaches nothing). *Changed*
        (knocked over) is in effect a new object: all descriptions are restored and all
        sensing is void; ``appearance`` is what the camera sees of it now (None when it
        could not look), so the new object is narrowed, and later learned, by its own
        footprint and never by the one it had before (docs/method.md §5.8).
        """
        self._changed()
        if position is not None:
            self.position = position
        if not side_effects:  # a clean failure says the prediction was wrong; a push or a fall does not
            self.wrong_predictions.append(grasp)
        if side_effects and changed:
            self.unreliable_count = 0  # a new object as far as sensing goes
            self.wrong_predictions.clear()  # and as far as lessons go: those were about the object before it fell
            self.appearance = appearance  # it no longer looks as the camera saw it first
            self.dropped_grasps.clear()
            self.measurements.clear()
            self.pushes.clear()
        elif side_effects:
            self.pushes[grasp] += 1
            if self.pushes[grasp] >= 2:
                self.dropped_grasps.add(grasp)
            else:
                self.dropped_grasps.discard(grasp)
        else:
            self.dropped_grasps.add(grasp)
        self._frames = [_Frame(self._root_node(), self.position)]

    def _root_node(self) -> Node:
        dropped_classes = [c for c, grasp in enumerate(self.matrix.classes) if grasp in self.dropped_grasps]
        dropped = np.flatnonzero(np.isin(self.matrix.class_of, dropped_classes)).tolist()
        node = Node.root(len(self.matrix.descriptions), dropped)
        if not node.rows:
            raise ValueError("every grasp in the library has failed on this object")
        unlike = self.unlike_rows()
        narrowed = Node.root(len(self.matrix.descriptions), sorted({*dropped, *unlike}))
        self.appearance_ignored = bool(unlike) and not narrowed.rows
        return node if self.appearance_ignored else narrowed

    def unlike_rows(self) -> list[int]:
        """Descriptions the camera's appearance of this object rules out (none when the
        appearance is unknown or not used)."""
        if self.appearance is None or not self.use_appearance:
            return []
        return [int(i) for i in np.flatnonzero(self.matrix.unlike(self.appearance, self.appearance_tolerance_in))]

    # -- learning -------------------------------------------------------------------
    def discriminating_test(self, wrong_grasp: str, exclude: frozenset[Test] = frozenset()) -> ScoredTest | None:
        """The cheapest sensing test the wrongly predicted grasp's descriptions have and
        this object lacks (and not in ``exclude``): measuring it may let the next tree
        tell the two apart."""
        best: ScoredTest | None = None
        for test in self.matrix.tests:
            if test.is_grasp or test in exclude or measured_value(test, self.measurements) is not None:
                continue
            known = ~np.isnan(self.matrix.values[:, self.matrix.column[test]])
            if not any(k and d.grasp == wrong_grasp for k, d in zip(known, self.matrix.descriptions)):
                continue
            target = target_for(test, self.position, self.ctx)
            move = sensing_cost(self.ctx.estimator, self.position, target)
            if not np.isfinite(move):
                continue  # no usable reading from there (no path, or the sound meets a neighbour)
            sense = self.ctx.knowledge.procedure_for(test.feature).time_s
            if best is None or move + sense < best.cost:
                best = ScoredTest(test, target, 0.0, move, sense, 0.0, (), self.ctx.knowledge.feature(test.feature).error)
        return best

    def told_apart(self, wrong_grasp: str) -> bool:
        """True when something already measured separates this object from every
        description of the wrongly predicted grasp."""
        for test in self.matrix.tests:
            if not test.is_grasp and measured_value(test, self.measurements) is not None:
                error = self.ctx.knowledge.feature(test.feature).error
                if self.discriminates(ScoredTest(test, self.position, 0.0, 0.0, 0.0, 0.0, (), error), wrong_grasp):
                    return True
        return False

    def discriminates(self, test: ScoredTest, wrong_grasp: str) -> bool:
        """True when this object's measured value for ``test`` lies outside every value
        the wrongly predicted grasp's descriptions have there (widened by the error)."""
        value = measured_value(test.test, self.measurements)
        if value is None:
            return False
        column = self.matrix.values[:, self.matrix.column[test.test]]
        theirs = [v for v, d in zip(column, self.matrix.descriptions) if d.grasp == wrong_grasp and not np.isnan(v)]
        return bool(theirs) and all(abs(value - v) > test.error + 1e-9 for v in theirs)

    def record(self, values: Mapping[str, float | None], at: Position) -> None:
        """Keep the values a procedure yielded at ``at`` (every feature it yields)."""
        self._changed()
        where = Position(at.distance_in, None) if self.orientation_free else at
        for feature, value in values.items():
            if value is not None:
                self.measurements[(feature, where)] = float(value)

    def description(self, object_id: str, grasp: str, grasp_position: Position) -> ObjectDescription:
        """The new object description to save after a successful grasp (docs/method.md §5.3)."""
        observations = tuple(sorted(Observation(f, p, v) for (f, p), v in self.measurements.items()))
        return ObjectDescription(object_id, grasp, grasp_position, observations, self.appearance)


def _told(test: ScoredTest) -> str:
    """A ranked test as the log tells it: score, gain and cost (move + sense)."""
    return (f"{test.test} score {test.score:.4g}, gain {test.gain:.4g}, cost {test.cost:.1f} s "
            f"(move {test.move_cost:.1f} + sense {test.sense_cost:.1f})")

"""The limit: the expected cost of the best adaptive policy, and of the learner's own.

How far is a test-choice rule from the best any policy could do? :func:`optimal_cost`
answers exactly, by dynamic programming, for libraries small enough to search (the
shipped 14 descriptions in seconds); :func:`policy_cost` walks the learner's greedy
:class:`~learner.runtime.RecognitionSession` under the same accounting, so the two are
comparable and ``optimal_cost <= policy_cost`` for every criterion.

The accounting (docs/optimum.md), shared by both: a policy is charged until the object's
own grasp is executed.

- The object is one of the library's descriptions, each with probability ``1/n``;
  sensing is noise-free.
- A test costs the move from where the robot stands to the test's position (the
  estimator's ``sensing_move_cost`` for a sensing test where it has one, as the learner's
  ``rank`` prices it: ``inf`` where a reading there would not be the object's alone)
  plus the procedure's ``time_s``. A procedure yields all its features: once
  it ran at a position, a test of any of its features at a position covering that one
  is free (``node.measured_value``) and is made where the robot stands.
- Concrete positions only: a ``*`` slot of a test's position may be filled by any value
  the library uses for that slot within the procedure's range, or the way the learner
  fills it (``node.target_for``: where the robot is).
- Tests split the candidate descriptions exactly as the learner does (``gain``'s
  chain-merged ranges, ``node.split``); a test already on the path is not repeated.
- A description's value for a test is its value in the learner's matrix column. One
  that lacks it is carried down every branch (docs/method.md §3.2); as the object at
  hand its outcome is unknown, so it follows each branch with probability ``1/k``. The
  walk forks there (and a fork's value stays the object's value for the rest of the
  walk); the search carries each candidate's probability, which is why its state holds
  weights, not only a set of rows.
- Executing the object's own grasp ends recognition and is not counted. Executing a
  wrong grasp is a failed attempt: the move to the grasp plus its ``feature_cost_s``
  (time plus side-effect penalty); then its descriptions are dropped, what was measured
  is kept, and recognition goes on. A grasp tried as a binary feature is the same
  act: paid only when it fails. A grasp the finger sensor cannot confirm (No-Grab:
  "executing" it means moving on) teaches nothing when wrong, so the search never tries
  it blind, and a walk that executes it wrongly has left the object behind (``missed``).
- The learner executes a grasp at its own leaf (``leaf_at``: the deciding, i.e. not
  carried, descriptions share one grasp; every description, carried ones included, for
  a ``leaf_every_row`` criterion) or, where nothing splits, the first of an
  ambiguous leaf's options; after a failure the session rebuilds from its root
  (``RecognitionSession.grasp_failed``). The optimal policy may execute any (confirmable)
  grasp at any point, and stops only when every candidate left shares one grasp.

The state of the search is what the future depends on: the candidate rows, their
probabilities, the robot's position, which still-useful tests are free, and which were
already taken. Only tests that can still split a subset of the rows matter, so the memo
key keeps just those; everything else is the same state. The search is
``learner.choosing.exact``'s, which ``cs-id3-failure-exact`` also runs at a session's
nodes (``learner.choosing.exact_choice``).
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from learner.choosing.criteria import DEFAULT_CRITERION, Criterion, criterion
from learner.choosing.exact import ExactSearch, forget_nodes
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Context, ScoredTest, measured_value
from learner.choosing.rollout_walk import shared_decisions
from learner.costs import MoveCostEstimator
from learner.position import Position
from learner.runtime import Decision, Matched, RecognitionSession, Unreliable

# -- the optimum ------------------------------------------------------------------------
def optimal_cost(matrix: DescriptionMatrix, estimator: MoveCostEstimator, start: Position) -> float:
    """Expected seconds of tests of the optimal adaptive policy from ``start`` (see the
    module's accounting). Exact; exponential in the worst case, so for small libraries."""
    if not matrix.descriptions:
        raise ValueError("the library holds no object descriptions")
    if start.distance_in is None or start.orientation_deg is None:
        raise ValueError(f"the start position must be concrete, got {start}")
    search = ExactSearch(matrix, estimator, Context(matrix, criterion(DEFAULT_CRITERION), estimator))
    n = len(matrix.descriptions)
    return search.expected(search.node_id(tuple(range(n))), (1.0 / n,) * n, search.place(start), 0, 0)


# -- the learner's own policy, walked ---------------------------------------------------
@dataclass(frozen=True)
class Outcome:
    """One description as the object at hand: the expected seconds until its own grasp
    is executed (failed grasps included), and the probability that the first grasp the
    walk executed was already its own (below 1 where a carried description reached
    another grasp's leaf, or a missing value sent the walk down several branches)."""

    object_id: str
    cost_s: float
    right: float
    missed: float = 0.0  # probability it was left behind by a wrong unverifiable grasp (No-Grab)


@dataclass(frozen=True)
class PolicyWalk:
    """The learner's greedy policy walked for every description of the library."""

    criterion: str
    outcomes: tuple[Outcome, ...]

    @property
    def expected_cost(self) -> float:
        """Mean over the descriptions (the uniform prior)."""
        return sum(o.cost_s for o in self.outcomes) / len(self.outcomes)

    @property
    def right(self) -> float:
        """Share of the descriptions whose first executed grasp was their own."""
        return sum(o.right for o in self.outcomes) / len(self.outcomes)

    @property
    def missed(self) -> float:
        """Share of the descriptions left behind, never grasped (see :class:`Outcome`)."""
        return sum(o.missed for o in self.outcomes) / len(self.outcomes)


def policy_walk(matrix: DescriptionMatrix, criterion: Criterion, estimator: MoveCostEstimator, start: Position,
                *, seed: int = 0) -> PolicyWalk:
    """Drive a :class:`RecognitionSession` per description with its noise-free values
    (the module's accounting) until it executes the description's own grasp."""
    if not matrix.descriptions:
        raise ValueError("the library holds no object descriptions")
    outcomes = []
    with shared_decisions():  # every session starts from the same root: decide each node once
        for row, description in enumerate(matrix.descriptions):
            session = RecognitionSession(matrix, criterion, estimator, start, seed=seed)
            outcomes.append(Outcome(description.object_id, *_walk(session, row)))
    return PolicyWalk(criterion.name, tuple(outcomes))


def policy_cost(matrix: DescriptionMatrix, criterion: Criterion, estimator: MoveCostEstimator, start: Position,
                *, seed: int = 0) -> float:
    """Expected seconds of the learner's greedy policy (see :func:`policy_walk`)."""
    return policy_walk(matrix, criterion, estimator, start, seed=seed).expected_cost


@dataclass(frozen=True)
class DecisionTimes:
    """CPU seconds of the decisions of the walks (:func:`decision_times`): each session's
    first, and every later one (forks included)."""

    first: tuple[float, ...]
    later: tuple[float, ...]


class _Clock(list[float]):
    """The decision times of one walk, shared by its forks (a copy would lose theirs)."""

    def __deepcopy__(self, memo: dict[int, object]) -> _Clock:
        return self


class _TimedSession(RecognitionSession):
    """A session that records the CPU time of every decision it works out."""

    clock: _Clock

    def _decide(self) -> Decision:
        began = time.process_time()
        try:
            return super()._decide()
        finally:
            self.clock.append(time.process_time() - began)


def decision_times(matrix: DescriptionMatrix, criterion: Criterion, estimator: MoveCostEstimator, start: Position,
                   *, seed: int = 0, cold: bool = False) -> DecisionTimes:
    """The CPU time of every decision of :func:`policy_walk`'s walks, each description's
    session deciding for itself (no decision shared between them, as a robot's session
    for one object decides alone): what a criterion costs a robot per decision, and at
    the first decision of a session, where a search shared by its later ones is paid.
    The sessions over one matrix share the exact search's nodes (``exact.NodeTable``), as
    a robot's do while its library is unchanged; ``cold``: each session as the first over
    the library, those nodes forgotten before it."""
    first: list[float] = []
    later: list[float] = []
    for row in range(len(matrix.descriptions)):
        if cold:
            forget_nodes(matrix)
        session = _TimedSession(matrix, criterion, estimator, start, seed=seed)
        session.clock = _Clock()
        _walk(session, row)
        first.extend(session.clock[:1])
        later.extend(session.clock[1:])
    return DecisionTimes(tuple(first), tuple(later))


def _walk(session: RecognitionSession, row: int, *, first: bool = True,
          forked: Mapping[int, float] = MappingProxyType({})) -> tuple[float, float, float]:
    """(expected cost, probability the first grasp executed is the object's own, and that
    the object is left behind) from the session's current node; ``first``: no grasp was
    executed yet on this path;
    ``forked``: the value each fork on this path gave a column the object lacks."""
    matrix = session.matrix
    truth = matrix.descriptions[row]
    spent = 0.0
    while True:
        decision = session.decide()
        if isinstance(decision, AmbiguousLeaf):
            decision = decision.options[0]  # tried in the learner's order, cheapest first
        if isinstance(decision, GraspLeaf):
            if decision.grasp == truth.grasp:
                return spent, float(first), 0.0
            # a wrong grasp: its execution is a failed attempt, then the session rebuilds
            # from the root without that grasp's descriptions, keeping what was measured
            if not matrix.knowledge.grasp(decision.grasp).verifiable:
                return spent, 0.0, 1.0  # "executing" No-Grab is moving on: the robot never learns
            spent += decision.move_cost + matrix.knowledge.grasp(decision.grasp).feature_cost_s
            if all(d.grasp in session.dropped_grasps or d.grasp == decision.grasp for d in matrix.descriptions):
                # the object's own grasp was ruled out by name (tried as a feature at a
                # position its description does not record): this learner stops here
                return spent, 0.0, 1.0
            session.grasp_failed(decision.grasp, side_effects=False, position=decision.position)
            first = False
            continue
        if not isinstance(decision, ScoredTest):
            raise RuntimeError(f"noise-free walk of {truth.object_id} reached {decision!r}")
        column = matrix.column[decision.test]
        if not decision.test.is_grasp or matrix.values[row, column] != 1.0:
            spent += decision.cost  # a grasp that holds is the object's own: not counted
        value = float(matrix.values[row, column])
        if math.isnan(value):
            # settled by the fork that first tested it: a re-use after a failed grasp
            # follows the same branch, not a new fork
            value = forked.get(column, math.nan)
        if decision.test.is_grasp:
            result = session.grasp_as_feature(decision, value == 1.0, decision.target)
        elif math.isnan(value):  # unknown for this object: each branch equally likely
            forks = []
            for lo, hi in decision.ranges:
                # the library and the criterion are shared, not copied: a copied criterion's
                # bound formula compares unequal, and every decision of the fork would miss
                # the walk's shared decisions (rollout_walk.shared_decisions)
                fork = copy.deepcopy(session, {id(matrix): matrix, id(session.ctx.criterion): session.ctx.criterion})
                _observe(fork, decision, (lo + hi) / 2, truth_row=row)
                forks.append(_walk(fork, row, first=first, forked={**forked, column: (lo + hi) / 2}))
            return (spent + sum(c for c, _, _ in forks) / len(forks), sum(r for _, r, _ in forks) / len(forks),
                    sum(m for _, _, m in forks) / len(forks))
        else:
            result = _observe(session, decision, value, truth_row=row)
            if isinstance(result, Unreliable) and column in forked:
                # a fork's value re-used after a failed grasp, that no branch of the
                # rebuilt tree holds (their descriptions were dropped): the nearest
                # branch, the session's last resort, at no further cost
                result = session.follow_nearest()
        if not isinstance(result, Matched):
            raise RuntimeError(f"noise-free walk of {truth.object_id}: {decision.test} gave {result!r}")


def _observe(session: RecognitionSession, test: ScoredTest, value: float, *, truth_row: int) -> object:
    """Report ``value`` for ``test``: a paid test reports every feature its procedure
    yields at the target (NaN where the description lacks one: it is measured, its value
    unknown); a free re-use reports just the tested feature, where the robot stands."""
    if measured_value(test.test, session.measurements) is not None:
        return session.observe(test, {test.test.feature: value}, test.target)
    truth = session.matrix.descriptions[truth_row]
    procedure = session.matrix.knowledge.procedure_for(test.test.feature)
    values: dict[str, float | None] = {}
    for f in procedure.features:
        known = truth.value_at(f.name, test.target)
        values[f.name] = math.nan if known is None else known
    values[test.test.feature] = value
    return session.observe(test, values, test.target)


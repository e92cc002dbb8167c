"""The limit: the expected cost of the best adaptive policy, and of the learner's own.

How far is a test-choice rule from the best any policy could do? :func:`optimal_cost`
answers exactly, by dynamic programming, for libraries small enough to search (the
shipped 14 descriptions in seconds); :func:`policy_cost` walks the learner's greedy
:class:`~learner.runtime.RecognitionSession` under the same accounting, so the two are
comparable and ``optimal_cost <= policy_cost`` for every criterion.

The accounting (docs/optimum.md), shared by both:

- The object is one of the library's descriptions, each with probability ``1/n``;
  sensing is noise-free.
- A test costs the move from where the robot stands to the test's position (the
  estimator) plus the procedure's ``time_s``, or, for a grasp tried as a binary feature,
  the grasp's ``feature_cost_s``. A procedure yields all its features: once it ran at a
  position, a test of any of its features at a position covering that one is free
  (``selection.measured_value``) and is made where the robot stands.
- Concrete positions only: a ``*`` slot of a test's position may be filled by any value
  the library uses for that slot within the procedure's range, or the way the learner
  fills it (``selection.target_for``: where the robot is).
- Tests split the candidate descriptions exactly as the learner does (``gain``'s
  chain-merged ranges, ``selection.split``); a test already on the path is not repeated.
- A description's value for a test is its value in the learner's matrix column. One
  that lacks it is carried down every branch (the learner's rule, docs/method.md §3.2);
  as the object at hand its outcome is unknown, so it follows each branch with equal
  probability ``1/k``. The walk forks there; the search carries each candidate's
  probability, which is why its state holds weights, not only a set of rows.
- Recognition stops, at no further cost, at the learner's own leaf (``leaf_at``: the
  deciding descriptions share one grasp; the grasp itself is not counted) or where no
  test splits the node (an ambiguous leaf). A grasp that succeeds as a feature is a leaf.

The state of the search is what the future depends on: the node (rows and which are
carried), the candidates' probabilities, the robot's position, which still-useful tests
are free, and which were already taken. Only tests that can still split a subset of
the node matter, so the memo key keeps just those; everything else is the same state.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from learner.costs import MoveCostEstimator
from learner.criteria import DEFAULT_CRITERION, Criterion, criterion
from learner.decision_tree import AmbiguousLeaf, GraspLeaf
from learner.gain import partition_columns
from learner.matrix import DescriptionMatrix
from learner.position import Position
from learner.runtime import Matched, RecognitionSession
from learner.selection import Context, Node, ScoredTest, leaf_classes, measured_value, split, target_for

_EPS = 1e-9


# -- the optimum ------------------------------------------------------------------------
def optimal_cost(matrix: DescriptionMatrix, estimator: MoveCostEstimator, start: Position) -> float:
    """Expected seconds of tests of the optimal adaptive policy from ``start`` (see the
    module's accounting). Exact; exponential in the worst case, so for small libraries."""
    if not matrix.descriptions:
        raise ValueError("the library holds no object descriptions")
    if start.distance_in is None or start.orientation_deg is None:
        raise ValueError(f"the start position must be concrete, got {start}")
    search = _Search(matrix, estimator)
    n = len(matrix.descriptions)
    return search.expected(search.node_id(Node.root(n)), (1.0 / n,) * n, search.place(start), 0, 0, math.inf)


@dataclass(frozen=True)
class _Branching:
    """A test's split of a node: its children (ids) and, per child, each row's share of
    the row's probability (1 for a row with the value, ``1/k`` for a carried one)."""

    column: int
    children: tuple[int, ...]
    shares: tuple[tuple[float, ...], ...]


@dataclass(frozen=True)
class _NodeFacts:
    """What the search needs of a node, worked out once: whether it is a leaf, its
    splitting tests, and (bitmask) every test that could split some subset of it."""

    leaf: bool
    branchings: tuple[_Branching, ...]
    splitting: int
    useful: int


class _Search:
    """Branch and bound over (node, probabilities, position, free tests, taken tests).

    Nodes, positions and test sets are small integers (ids and bitmasks over the matrix's
    columns) so that states hash fast. ``expected`` takes a budget: it returns the exact
    expected cost when that is below the budget, else a lower bound at least the budget
    (the caller has something better); both are memoised. Actions are tried in the order
    of a lower bound of their total (their cost plus, per branch, the cheapest next
    test), and an action stops being expanded as soon as its bound reaches the best.
    """

    def __init__(self, matrix: DescriptionMatrix, estimator: MoveCostEstimator) -> None:
        self.matrix = matrix
        self.estimator = estimator
        self.ctx = Context(matrix, criterion(DEFAULT_CRITERION), estimator)  # target_for reads only knowledge
        k = matrix.knowledge
        tests = matrix.tests
        self.price = [k.grasp(t.procedure).feature_cost_s if t.is_grasp else k.procedure_for(t.feature).time_s
                      for t in tests]
        self.reach = [k.grasp(t.procedure).range_in if t.is_grasp else k.procedure_for(t.feature).range_in
                      for t in tests]
        places = [o.position for d in matrix.descriptions for o in d.observations]
        places += [d.grasp_position for d in matrix.descriptions]
        self.distances = sorted({p.distance_in for p in places if p.distance_in is not None})
        self.orientations = sorted({p.orientation_deg for p in places if p.orientation_deg is not None})
        self.memo: dict[tuple[object, ...], tuple[float, bool]] = {}
        self.facts: list[_NodeFacts] = []
        self._node_ids: dict[Node, int] = {}
        self.positions: list[Position] = []
        self._position_ids: dict[Position, int] = {}
        self._moves: dict[tuple[int, int], float] = {}
        self._targets: dict[tuple[int, int], tuple[int, ...]] = {}
        self._made_free: dict[tuple[str, str, int], int] = {}
        self._cheapest: dict[tuple[int, int], float] = {}

    # -- ids ------------------------------------------------------------------------
    def place(self, position: Position) -> int:
        if position not in self._position_ids:
            self._position_ids[position] = len(self.positions)
            self.positions.append(position)
        return self._position_ids[position]

    def node_id(self, node: Node) -> int:
        if node not in self._node_ids:
            self._node_ids[node] = len(self.facts)
            self.facts.append(_NodeFacts(True, (), 0, 0))  # placeholder: working out the facts adds the children
            self.facts[self._node_ids[node]] = self._facts(node)
        return self._node_ids[node]

    # -- the recursion ----------------------------------------------------------------
    def expected(self, node: int, weights: tuple[float, ...], at: int, free: int, taken: int, budget: float) -> float:
        facts = self.facts[node]
        if facts.leaf or not facts.branchings:
            return 0.0  # the learner's leaf, or an ambiguous one: recognition stops here
        key = (node, tuple(round(w, 12) for w in weights), at, free & facts.useful, taken & facts.useful)
        known = self.memo.get(key)
        if known is not None and (known[1] or known[0] >= budget):
            return known[0]
        actions = []
        for cost, b, target, now_free in self._actions(facts, at, free, taken):
            masses = [sum(w * s for w, s in zip(weights, shares)) for shares in b.shares]
            bounds = [self._bound(child, target, now_free) for child in b.children]
            actions.append((cost + sum(m * x for m, x in zip(masses, bounds)), cost, b, target, now_free,
                            masses, bounds))
        actions.sort(key=lambda a: a[0])
        best = math.inf
        for bound, cost, b, target, now_free, masses, bounds in actions:
            limit = min(best, budget)
            if bound >= limit - _EPS:
                break  # sorted: no later action can do better
            total, rest = cost, bound - cost
            for child, shares, mass, child_bound in zip(b.children, b.shares, masses, bounds):
                rest -= mass * child_bound
                child_weights = tuple(w * s / mass for w, s in zip(weights, shares) if s > 0)
                total += mass * self.expected(child, child_weights, target, now_free, taken | (1 << b.column),
                                              (limit - total - rest) / mass + _EPS)
                if total + rest >= limit - _EPS:
                    break
            else:
                best = min(best, total)
        if best < budget:
            self.memo[key] = (best, True)
            return best
        lower = max(budget, known[0] if known is not None else 0.0)
        self.memo[key] = (lower, False)
        return lower

    def _actions(self, facts: _NodeFacts, at: int, free: int,
                 taken: int) -> Iterator[tuple[float, _Branching, int, int]]:
        """Every (cost, split, where the robot ends, free tests after) from ``at``."""
        for b in facts.branchings:
            c = b.column
            if taken >> c & 1:
                continue
            test = self.matrix.tests[c]
            if free >> c & 1:  # re-used where the robot stands; the session records it there too
                yield 0.0, b, at, free | self._frees(test.feature, "feature", at)
                continue
            for target in self._targets_for(c, at):
                move = self._move(at, target)
                if math.isfinite(move):
                    now_free = free if test.is_grasp else free | self._frees(test.procedure, "procedure", target)
                    yield move + self.price[c], b, target, now_free

    def _bound(self, node: int, at: int, free: int) -> float:
        """A lower bound of a node's expected cost: 0 at a leaf or with a free split,
        else the cheapest paid test from ``at``."""
        facts = self.facts[node]
        if facts.leaf or not facts.branchings or free & facts.splitting:
            return 0.0
        key = (node, at)
        if key not in self._cheapest:
            self._cheapest[key] = min(
                (self._move(at, t) + self.price[b.column] for b in facts.branchings
                 for t in self._targets_for(b.column, at)), default=0.0)
        return self._cheapest[key]

    # -- facts, worked out once -------------------------------------------------------
    def _facts(self, node: Node) -> _NodeFacts:
        matrix = self.matrix
        if len(leaf_classes(node, matrix)) == 1:
            return _NodeFacts(True, (), 0, 0)
        values = matrix.values[list(node.rows)]
        known = ~np.isnan(values)
        high = np.where(known, values, -np.inf).max(axis=0)
        low = np.where(known, values, np.inf).min(axis=0)
        useful_columns = np.flatnonzero(known.any(axis=0) & (high - low > matrix.errors + _EPS))
        branchings: list[_Branching] = []
        if len(useful_columns):
            found = partition_columns(node.rows, matrix, useful_columns)
            for j, c in enumerate(useful_columns.tolist()):
                ranges = tuple(found.ranges[j])
                if len(ranges) < 2:
                    continue
                probe = ScoredTest(matrix.tests[c], Position(0.0, 0.0), 0.0, 0.0, 0.0, 0.0, ranges,
                                   float(matrix.errors[c]))
                children = split(node, probe, matrix)
                shares = tuple(tuple((1.0 if known[i, c] else 1.0 / len(ranges)) if r in child.rows else 0.0
                                     for i, r in enumerate(node.rows)) for child in children)
                branchings.append(_Branching(c, tuple(self.node_id(child) for child in children), shares))
        return _NodeFacts(False, tuple(branchings), _mask(b.column for b in branchings), _mask(useful_columns))

    def _frees(self, name: str, kind: str, at: int) -> int:
        """The columns a measurement makes free: every feature of ``procedure`` ``name``
        measured at ``at``, or just ``feature`` ``name`` (``selection.measured_value``)."""
        key = (name, kind, at)
        if key not in self._made_free:
            where = self.positions[at]
            self._made_free[key] = _mask(
                c for c, t in enumerate(self.matrix.tests)
                if not t.is_grasp and (t.procedure if kind == "procedure" else t.feature) == name
                and (t.position.covers(where) or where.covers(t.position)))
        return self._made_free[key]

    def _targets_for(self, column: int, at: int) -> tuple[int, ...]:
        """Where a test can be made: its own slots, or for a ``*`` every in-range value the
        library uses plus the learner's own fill from ``at``."""
        key = (column, at)
        if key not in self._targets:
            test = self.matrix.tests[column]
            lo, hi = self.reach[column]
            own = target_for(test, self.positions[at], self.ctx)
            distances = ([test.position.distance_in] if test.position.distance_in is not None
                         else [d for d in self.distances if lo - _EPS <= d <= hi + _EPS] + [own.distance_in])
            orientations = ([test.position.orientation_deg] if test.position.orientation_deg is not None
                            else self.orientations + [own.orientation_deg])
            self._targets[key] = tuple(self.place(p) for p in sorted({Position(d, o) for d in distances
                                                                     for o in orientations}))
        return self._targets[key]

    def _move(self, start: int, goal: int) -> float:
        key = (start, goal)
        if key not in self._moves:
            self._moves[key] = self.estimator.move_cost(self.positions[start], self.positions[goal])
        return self._moves[key]


def _mask(columns: Iterable[int]) -> int:
    bits = 0
    for c in columns:
        bits |= 1 << int(c)
    return bits


# -- the learner's own policy, walked ---------------------------------------------------
@dataclass(frozen=True)
class Outcome:
    """One description as the object at hand: the expected seconds of tests until the
    walk stopped, and the probability it stopped at a leaf of this description's grasp
    (below 1 only where a missing value sent the walk down several branches)."""

    object_id: str
    cost_s: float
    right: float


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
        """Share of the descriptions recognised with their own grasp."""
        return sum(o.right for o in self.outcomes) / len(self.outcomes)


def policy_walk(matrix: DescriptionMatrix, criterion: Criterion, estimator: MoveCostEstimator, start: Position,
                *, seed: int = 0) -> PolicyWalk:
    """Drive a :class:`RecognitionSession` per description with its noise-free values
    (the module's accounting) until it reaches a leaf."""
    if not matrix.descriptions:
        raise ValueError("the library holds no object descriptions")
    outcomes = []
    for row, description in enumerate(matrix.descriptions):
        session = RecognitionSession(matrix, criterion, estimator, start, seed=seed)
        cost, right = _walk(session, row)
        outcomes.append(Outcome(description.object_id, cost, right))
    return PolicyWalk(criterion.name, tuple(outcomes))


def policy_cost(matrix: DescriptionMatrix, criterion: Criterion, estimator: MoveCostEstimator, start: Position,
                *, seed: int = 0) -> float:
    """Expected seconds of tests of the learner's greedy policy (see :func:`policy_walk`)."""
    return policy_walk(matrix, criterion, estimator, start, seed=seed).expected_cost


def _walk(session: RecognitionSession, row: int) -> tuple[float, float]:
    """(expected cost, probability of the right grasp) from the session's current node."""
    matrix = session.matrix
    truth = matrix.descriptions[row]
    spent = 0.0
    while True:
        decision = session.decide()
        if isinstance(decision, GraspLeaf):
            return spent, float(decision.grasp == truth.grasp)
        if isinstance(decision, AmbiguousLeaf):
            return spent, 0.0
        if not isinstance(decision, ScoredTest):
            raise RuntimeError(f"noise-free walk of {truth.object_id} reached {decision!r}")
        spent += decision.cost
        value = float(matrix.values[row, matrix.column[decision.test]])
        if decision.test.is_grasp:
            result = session.grasp_as_feature(decision, value == 1.0, decision.target)
        elif math.isnan(value):  # unknown for this object: each branch equally likely
            forks = []
            for lo, hi in decision.ranges:
                fork = copy.deepcopy(session, {id(matrix): matrix})
                _observe(fork, decision, (lo + hi) / 2, truth_row=row)
                forks.append(_walk(fork, row))
            return (spent + sum(c for c, _ in forks) / len(forks), sum(r for _, r in forks) / len(forks))
        else:
            result = _observe(session, decision, value, truth_row=row)
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


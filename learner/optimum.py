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
key keeps just those; everything else is the same state.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from learner.choosing.criteria import DEFAULT_CRITERION, Criterion, criterion
from learner.choosing.gain import partition_columns
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf, grasp_options
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import (Context, Node, ScoredTest, measured_value, procedure_cost, procedure_range, split,
                                   target_for)
from learner.choosing.rollout_walk import shared_decisions
from learner.costs import MoveCostEstimator, sensing_cost
from learner.position import Position
from learner.runtime import Matched, RecognitionSession, Unreliable

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
    """What the search needs of a node, worked out once: the grasps of its candidates
    (any may be executed; one alone settles the node), its splitting tests, and
    (bitmask) every test that could split some subset of it."""

    grasps: tuple[str, ...]
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
    test or blind grasp), and an action stops being expanded as soon as its bound
    reaches the best. The rows' probabilities say all the search needs of the learner's
    carried marks, so its nodes keep none (fewer distinct states).
    """

    def __init__(self, matrix: DescriptionMatrix, estimator: MoveCostEstimator) -> None:
        self.matrix = matrix
        self.estimator = estimator
        self.knowledge = matrix.knowledge
        self.ctx = Context(matrix, criterion(DEFAULT_CRITERION), estimator)  # target_for reads only knowledge
        self.price = [procedure_cost(t, matrix.knowledge) for t in matrix.tests]
        self.reach = [procedure_range(t, matrix.knowledge) for t in matrix.tests]
        places = [o.position for d in matrix.descriptions for o in d.observations]
        places += [d.grasp_position for d in matrix.descriptions]
        self.distances = sorted({p.distance_in for p in places if p.distance_in is not None})
        self.orientations = sorted({p.orientation_deg for p in places if p.orientation_deg is not None})
        self.memo: dict[tuple[object, ...], tuple[float, bool]] = {}
        self.facts: list[_NodeFacts] = []
        self.nodes: list[Node] = []
        self._node_ids: dict[Node, int] = {}
        self._grasp_places: dict[tuple[int, int, str], int] = {}
        self._without: dict[tuple[int, str], tuple[int, tuple[bool, ...]]] = {}
        self.positions: list[Position] = []
        self._position_ids: dict[Position, int] = {}
        self._moves: dict[tuple[int, int, bool], float] = {}
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
            self.nodes.append(node)
            self.facts.append(_NodeFacts((), (), 0, 0))  # placeholder: working out the facts adds the children
            self.facts[self._node_ids[node]] = self._facts(node)
        return self._node_ids[node]

    # -- the recursion ----------------------------------------------------------------
    def expected(self, node: int, weights: tuple[float, ...], at: int, free: int, taken: int, budget: float) -> float:
        facts = self.facts[node]
        if len(facts.grasps) < 2:
            return 0.0  # every candidate left has one grasp: executing it holds the object
        key = (node, tuple(round(w, 12) for w in weights), at, free & facts.useful, taken & facts.useful)
        known = self.memo.get(key)
        if known is not None and (known[1] or known[0] >= budget):
            return known[0]
        actions = []
        for cost, children, target, now_free, now_taken in self._actions(node, weights, at, free, taken):
            bounds = [self._bound(child, child_weights, target, now_free) for child, _, child_weights in children]
            actions.append((cost + sum(m * x for (_, m, _), x in zip(children, bounds)), cost, children, bounds,
                            target, now_free, now_taken))
        if not actions:
            return 0.0  # nothing splits and no grasp may be tried blind: a last guess ends it
        actions.sort(key=lambda a: a[0])
        best = math.inf
        for bound, cost, children, bounds, target, now_free, now_taken in actions:
            limit = min(best, budget)
            if bound >= limit - _EPS:
                break  # sorted: no later action can do better
            total, rest = cost, bound - cost
            for (child, mass, child_weights), child_bound in zip(children, bounds):
                rest -= mass * child_bound
                total += mass * self.expected(child, child_weights, target, now_free, now_taken,
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

    def _actions(self, node: int, weights: tuple[float, ...], at: int, free: int,
                 taken: int) -> Iterator[tuple[float, list[tuple[int, float, tuple[float, ...]]], int, int, int]]:
        """Every action from ``at``: (its expected cost now, its children as (node,
        probability, their rows' probabilities), where the robot ends, free tests after,
        tests taken after). A test is paid whatever comes of it; a grasp only when it
        is wrong (the right one ends recognition, not counted), and then, as a failed
        attempt, its move and ``feature_cost_s``: time plus side-effect penalty."""
        facts = self.facts[node]
        for b in facts.branchings:
            c = b.column
            if taken >> c & 1:
                continue
            children = []
            for child, shares in zip(b.children, b.shares):
                mass = sum(w * s for w, s in zip(weights, shares))
                if mass > _EPS:
                    children.append((child, mass, tuple(w * s / mass for w, s in zip(weights, shares) if s > 0)))
            now_taken = taken | (1 << c)
            test = self.matrix.tests[c]
            if free >> c & 1:  # re-used where the robot stands; the session records it there too
                yield 0.0, children, at, free | self._frees(test.feature, "feature", at), now_taken
                continue
            # a grasp tried as a feature is paid only when it fails: when it holds, it is
            # the object's own grasp executed, which is not counted
            # (its branches are 0 and 1, in that order)
            paid = sum(w * s for w, s in zip(weights, b.shares[0])) if test.is_grasp else 1.0
            for target in self._targets_for(c, at):
                move = self._move(at, target, sensing=not test.is_grasp)
                if math.isfinite(move):
                    now_free = free if test.is_grasp else free | self._frees(test.procedure, "procedure", target)
                    yield paid * (move + self.price[c]), children, target, now_free, now_taken
        for grasp in facts.grasps:
            if not self.knowledge.grasp(grasp).verifiable:
                continue  # "executing" it means moving on: the robot would never learn it was wrong
            rest, keep = self._dropped(node, grasp)
            wrong = sum(w for w, k in zip(weights, keep) if k)
            target = self._grasp_place(node, at, grasp)
            move = self._move(at, target)
            if math.isfinite(move):
                yield (wrong * (move + self.knowledge.grasp(grasp).feature_cost_s),
                       [(rest, wrong, tuple(w / wrong for w, k in zip(weights, keep) if k))], target, free, taken)

    def _dropped(self, node: int, grasp: str) -> tuple[int, tuple[bool, ...]]:
        """The node left when ``grasp`` failed (its descriptions dropped) and which of
        this node's rows it keeps."""
        key = (node, grasp)
        if key not in self._without:
            rows = self.nodes[node].rows
            keep = tuple(self.matrix.descriptions[r].grasp != grasp for r in rows)
            rest = tuple(r for r, k in zip(rows, keep) if k)
            self._without[key] = (self.node_id(Node(rest, (False,) * len(rest))), keep)
        return self._without[key]

    def _grasp_place(self, node: int, at: int, grasp: str) -> int:
        """Where the learner would execute ``grasp`` from ``at`` (``grasp_options``: the
        cheapest of the positions its descriptions at this node record)."""
        key = (node, at, grasp)
        if key not in self._grasp_places:
            options = grasp_options(self.nodes[node], self.positions[at], self.ctx)
            self._grasp_places[key] = self.place(next(o.position for o in options if o.grasp == grasp))
        return self._grasp_places[key]

    def _bound(self, node: int, weights: tuple[float, ...], at: int, free: int) -> float:
        """A lower bound of a node's expected cost: 0 when it is settled or a free test
        splits it, else the cheaper of the cheapest paid test from ``at`` and the
        cheapest grasp's expected failure."""
        facts = self.facts[node]
        if len(facts.grasps) < 2 or free & facts.splitting:
            return 0.0
        key = (node, at)
        if key not in self._cheapest:
            self._cheapest[key] = min(
                (self._move(at, t, sensing=True) + self.price[b.column] for b in facts.branchings
                 if not self.matrix.tests[b.column].is_grasp for t in self._targets_for(b.column, at)),
                default=math.inf)
        # a grasp tried as a feature is paid only when it fails: its failure share of the
        # node's weights, as _actions prices it (in full it would overstate the bound and
        # prune the best action)
        failing = min((sum(w * s for w, s in zip(weights, b.shares[0])) * (self._move(at, t) + self.price[b.column])
                       for b in facts.branchings if self.matrix.tests[b.column].is_grasp
                       for t in self._targets_for(b.column, at)), default=math.inf)
        grasping = min((sum(w for w, k in zip(weights, self._dropped(node, g)[1]) if k)
                        * (self._move(at, self._grasp_place(node, at, g)) + self.knowledge.grasp(g).feature_cost_s)
                        for g in facts.grasps if self.knowledge.grasp(g).verifiable), default=math.inf)
        cheapest = min(self._cheapest[key], failing, grasping)
        return cheapest if math.isfinite(cheapest) else 0.0  # no action at all: a last guess, free

    # -- facts, worked out once -------------------------------------------------------
    def _facts(self, node: Node) -> _NodeFacts:
        matrix = self.matrix
        grasps = tuple(sorted({matrix.descriptions[r].grasp for r in node.rows}))
        if len(grasps) < 2:
            return _NodeFacts(grasps, (), 0, 0)
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
                # the search keeps no carried marks: the rows' probabilities say all it needs
                children = [Node(child.rows, (False,) * len(child.rows)) for child in split(node, probe, matrix)]
                shares = tuple(tuple((1.0 if known[i, c] else 1.0 / len(ranges)) if r in child.rows else 0.0
                                     for i, r in enumerate(node.rows)) for child in children)
                branchings.append(_Branching(c, tuple(self.node_id(child) for child in children), shares))
        return _NodeFacts(grasps, tuple(branchings), _mask(b.column for b in branchings), _mask(useful_columns))

    def _frees(self, name: str, kind: str, at: int) -> int:
        """The columns a measurement makes free: every feature of ``procedure`` ``name``
        measured at ``at``, or just ``feature`` ``name`` (``node.measured_value``)."""
        key = (name, kind, at)
        if key not in self._made_free:
            where = self.positions[at]
            self._made_free[key] = _mask(
                c for c, t in enumerate(self.matrix.tests)
                if not t.is_grasp and (t.procedure if kind == "procedure" else t.feature) == name
                and t.position.overlaps(where))
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

    def _move(self, start: int, goal: int, sensing: bool = False) -> float:
        """The move, to sense at ``goal`` (``sensing``: priced as ``rank`` prices a sensing
        test) or to grasp there."""
        key = (start, goal, sensing)
        if key not in self._moves:
            here, there = self.positions[start], self.positions[goal]
            self._moves[key] = (sensing_cost(self.estimator, here, there) if sensing
                                else self.estimator.move_cost(here, there))
        return self._moves[key]


def _mask(columns: Iterable[int]) -> int:
    bits = 0
    for c in columns:
        bits |= 1 << int(c)
    return bits


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


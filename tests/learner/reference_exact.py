"""The exact search as it was before it shared its nodes between searches and priced a
node's bound from per-position tables (issue 32): kept, unchanged but for this note, as
the reference that tests/learner/test_exact_fast.py compares the faster search with
(the same optimum, the same best action, the same prices and order of the candidates).
Not used by the product.
"""
from __future__ import annotations

import math
from bisect import bisect_right
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.node import Context, Measurements, ScoredTest, measured_value, procedure_cost, \
    procedure_range, target_for
from learner.choosing.partition import partition
from learner.costs import MoveCostEstimator, sensing_cost
from learner.position import Position

_EPS = 1e-9
Weights = tuple[float, ...]
Rows = tuple[int, ...]


@dataclass(frozen=True)
class _Branching:
    """A test's split of a node: its children (ids) and, per child, its rows (their index
    in the node) with each one's share of the row's probability (1 for a row with the
    value, ``1/k`` for one lacking it)."""

    column: int
    children: tuple[int, ...]
    members: tuple[tuple[tuple[int, float], ...], ...]  # per child, (index in the node, share) of its rows


@dataclass(frozen=True)
class _NodeFacts:
    """What the search needs of a node to bound it, worked out with a few array
    operations: the grasps of its rows (any may be executed; one alone settles the
    node) and each row's, which tests split it (bitmask, and the columns), and which
    could split some subset of it (bitmask). Its branchings
    (:meth:`ExactSearch.branchings`) are worked out only when the node is expanded."""

    grasps: tuple[str, ...]
    splitting: int
    useful: int
    columns: tuple[int, ...] = ()
    grasp_of: tuple[int, ...] = ()  # per row, the index of its grasp in ``grasps``


class ExactSearch:
    """Branch and bound over (node, probabilities, position, free tests, taken tests)
    for one matrix and one move-cost estimator whose costs do not change while it lives.

    :meth:`expected` takes a budget: it returns the exact expected cost when that is below
    the budget, else a lower bound at least the budget (the caller has something better);
    both are memoised. Actions are tried in the order of a lower bound of their total
    (their cost plus, per branch, the cheapest next test or blind grasp), and an action
    stops being expanded as soon as its bound reaches the best. The rows' probabilities
    say all the search needs of the learner's carried marks, so its nodes keep none.
    """

    def __init__(self, matrix: DescriptionMatrix, estimator: MoveCostEstimator, ctx: Context) -> None:
        """``ctx``: the matrix's context, for where the learner fills a ``*`` slot and
        places a grasp (it reads the knowledge only, not the criterion)."""
        self.matrix = matrix
        self.estimator = estimator
        self.knowledge = matrix.knowledge
        self.ctx = ctx
        self.price = [procedure_cost(t, matrix.knowledge) for t in matrix.tests]
        self.reach = [procedure_range(t, matrix.knowledge) for t in matrix.tests]
        self.is_grasp = [t.is_grasp for t in matrix.tests]
        self.errors = matrix.errors.tolist()
        # the slot values the library uses: every test's position and every grasp position
        places = [t.position for t in matrix.tests] + list(matrix.labels.positions)
        self.distances = sorted({p.distance_in for p in places if p.distance_in is not None})
        self.orientations = sorted({p.orientation_deg for p in places if p.orientation_deg is not None})
        self.verifiable = {g: matrix.knowledge.grasp(g).verifiable for g in matrix.classes}
        self.failure_s = {g: matrix.knowledge.grasp(g).feature_cost_s for g in matrix.classes}
        self.memo: dict[tuple[object, ...], tuple[float, bool]] = {}
        self.choices: dict[tuple[object, ...], tuple[int, int]] = {}  # a solved state's best action: (its bit, target)
        self.rows: list[Rows] = []
        self._facts: list[_NodeFacts | None] = []
        self._branchings: dict[int, tuple[_Branching, ...]] = {}
        self._node_ids: dict[Rows, int] = {}
        self._grasp_places: dict[tuple[object, int, str], int] = {}
        self._recorded: dict[tuple[int, str], tuple[Position, ...]] = {}
        self._column_from: dict[tuple[int, int], float] = {}
        self._offered: dict[tuple[int, int], tuple[tuple[float, int], ...]] = {}
        self._without: dict[tuple[int, str], tuple[int, tuple[bool, ...]]] = {}
        self.positions: list[Position] = []
        self._position_ids: dict[Position, int] = {}
        self._moves: dict[tuple[int, int, bool], float] = {}
        self._targets: dict[tuple[int, int], tuple[int, ...]] = {}
        self._made_free: dict[tuple[str, str, int], int] = {}
        self._cheapest: dict[tuple[int, int], tuple[float, list[float]]] = {}

    # -- ids ------------------------------------------------------------------------
    def place(self, position: Position) -> int:
        """The id of a concrete position."""
        if position not in self._position_ids:
            self._position_ids[position] = len(self.positions)
            self.positions.append(position)
        return self._position_ids[position]

    def node_id(self, rows: Rows) -> int:
        """The id of the node holding ``rows`` (its facts are worked out when first needed)."""
        known = self._node_ids.get(rows)
        if known is None:
            known = self._node_ids[rows] = len(self.rows)
            self.rows.append(rows)
            self._facts.append(None)
        return known

    def facts(self, node: int) -> _NodeFacts:
        found = self._facts[node]
        if found is None:
            found = self._facts[node] = self._work_out(self.rows[node])
        return found

    def free_mask(self, measurements: Measurements) -> int:
        """The sensing tests a session's ``measurements`` make free."""
        return _mask(c for c, t in enumerate(self.matrix.tests)
                     if not t.is_grasp and measured_value(t, measurements) is not None)

    def taken_mask(self, tests: Iterable[Test]) -> int:
        """The columns of ``tests`` (taken on the path, or tried at the node)."""
        return _mask(self.matrix.column[t] for t in tests if t in self.matrix.column)

    # -- the recursion ----------------------------------------------------------------
    def expected(self, node: int, weights: Weights, at: int, free: int, taken: int, budget: float = math.inf) -> float:
        """The least expected cost from this state, exact when below ``budget`` (else a
        lower bound at least the budget)."""
        facts = self.facts(node)
        if len(facts.grasps) < 2:
            return 0.0  # every candidate left has one grasp: executing it holds the object
        key = (node, tuple(round(w, 12) for w in weights), at, free & facts.useful, taken & facts.useful)
        known = self.memo.get(key)
        if known is not None and (known[1] or known[0] >= budget):
            return known[0]
        actions = []
        # an action that alone costs the budget is left out: bounding its children would not save it
        found, some = self.actions(node, weights, at, free, taken, budget)
        for cost, children, target, now_free, now_taken in found:
            bound, bounds = cost, []
            for child, mass, child_weights in children:
                bounds.append(self._bound(child, child_weights, target, now_free))
                bound += mass * bounds[-1]
                if bound >= budget - _EPS:
                    break  # it cannot come in under the budget: no need to bound the rest
            else:
                actions.append((bound, cost, children, bounds, target, now_free, now_taken))
        if not some:
            return 0.0  # nothing splits and no grasp may be tried blind: a last guess ends it
        actions.sort(key=lambda a: a[0])
        best, chosen = math.inf, (0, at)
        for bound, cost, children, bounds, target, now_free, now_taken in actions:
            limit = min(best, budget)
            if bound >= limit - _EPS:
                break  # sorted: no later action can do better
            total = self.below(cost, children, bounds, target, now_free, now_taken, limit)
            if total < best:
                best, chosen = total, (now_taken & ~taken, target)
        if best < budget:
            self.memo[key] = (best, True)
            self.choices[key] = chosen
            return best
        lower = max(budget, known[0] if known is not None else 0.0)
        self.memo[key] = (lower, False)
        return lower

    def solved(self, node: int, weights: Weights, at: int, free: int, taken: int) -> tuple[float, int, int] | None:
        """A state the search has solved exactly: (its least expected cost, the column of
        its best action, -1 for a blind grasp, and where that action is made); None
        when it was not searched to the end."""
        facts = self.facts(node)
        key = (node, tuple(round(w, 12) for w in weights), at, free & facts.useful, taken & facts.useful)
        known, chosen = self.memo.get(key), self.choices.get(key)
        if known is None or not known[1] or chosen is None:
            return None
        return known[0], chosen[0].bit_length() - 1, chosen[1]

    def below(self, cost: float, children: Sequence[tuple[int, float, Weights]], bounds: Sequence[float], target: int,
              free: int, taken: int, limit: float = math.inf) -> float:
        """An action's total: ``cost`` plus, per child, its probability times its least
        expected cost, the children searched within what is left of ``limit`` (at least
        ``limit`` when the action cannot do better)."""
        total, rest = cost, sum(m * x for (_, m, _), x in zip(children, bounds))
        for (child, mass, child_weights), child_bound in zip(children, bounds):
            rest -= mass * child_bound
            total += mass * self.expected(child, child_weights, target, free, taken,
                                          (limit - total - rest) / mass + _EPS)
            if total + rest >= limit - _EPS:
                return max(total + rest, limit)
        return total

    def actions(self, node: int, weights: Weights, at: int, free: int, taken: int,
                budget: float = math.inf) -> tuple[list[tuple[float, list[tuple[int, float, Weights]], int, int, int]],
                                                   bool]:
        """Every action from ``at`` that costs less than ``budget`` by itself, and whether
        there is any action at all: (its expected cost now, its children as (node,
        probability, their rows' probabilities), where the robot ends, free tests after,
        tests taken after). A test is paid whatever comes of it; a grasp only when it
        is wrong (the right one ends recognition, not counted), and then, as a failed
        attempt, its move and ``feature_cost_s``: time plus side-effect penalty."""
        facts = self.facts(node)
        found: list[tuple[float, list[tuple[int, float, Weights]], int, int, int]] = []
        some = False
        limit = budget - _EPS
        for b in self.branchings(node):
            c = b.column
            if taken >> c & 1:
                continue
            some = True
            if free >> c & 1:  # re-used where the robot stands; the session records it there too
                found.append((0.0, self._children(b, weights), at, free | self._frees(c, "feature", at),
                              taken | (1 << c)))
                continue
            grasp = self.is_grasp[c]
            paid = sum(weights[i] for i, _ in b.members[0]) if grasp else 1.0
            children = None
            for base, target in self._offers(c, at):
                cost = paid * base
                if cost >= limit:
                    break  # the offers are cheapest first
                if children is None:
                    children = self._children(b, weights)
                now_free = free if grasp else free | self._frees(c, "procedure", target)
                found.append((cost, children, target, now_free, taken | (1 << c)))
        for grasp in facts.grasps:
            if not self.verifiable[grasp]:
                continue  # "executing" it means moving on: the robot would never learn it was wrong
            rest, keep = self._dropped(node, grasp)
            wrong = sum(w for w, k in zip(weights, keep) if k)
            target = self._grasp_place(node, at, grasp)
            move = self._move(at, target)
            if math.isfinite(move):
                some = True
                cost = wrong * (move + self.failure_s[grasp])
                if cost < limit:
                    found.append((cost, [(rest, wrong, tuple(w / wrong for w, k in zip(weights, keep) if k))],
                                  target, free, taken))
        return found, some

    def test_action(self, node: int, weights: Weights, b: _Branching, at: int, target: int, free: int, taken: int,
                    children: list[tuple[int, float, Weights]] | None = None
                    ) -> tuple[float, list[tuple[int, float, Weights]], int, int, int] | None:
        """A paid test made at ``target`` (None when no move gets there): a grasp tried as
        a feature is paid only when it fails (when it holds, the object's own grasp was
        executed); its branches are 0 and 1, in that order."""
        c = b.column
        grasp = self.is_grasp[c]
        move = self._move(at, target, sensing=not grasp)
        if not math.isfinite(move):
            return None
        paid = sum(weights[i] for i, _ in b.members[0]) if grasp else 1.0
        now_free = free if grasp else free | self._frees(c, "procedure", target)
        if children is None:
            children = self._children(b, weights)
        return paid * (move + self.price[c]), children, target, now_free, taken | (1 << c)

    def branching(self, node: int, column: int) -> _Branching | None:
        """``column``'s split of the node, None when it does not split it."""
        return next((b for b in self.branchings(node) if b.column == column), None)

    def _children(self, b: _Branching, weights: Weights) -> list[tuple[int, float, Weights]]:
        children = []
        for child, members in zip(b.children, b.members):
            raw = [weights[i] * s for i, s in members]
            mass = sum(raw)
            if mass > _EPS:
                children.append((child, mass, tuple(x / mass for x in raw)))
        return children

    def bounds_of(self, children: Sequence[tuple[int, float, Weights]], target: int, free: int,
                  taken: int) -> list[float]:
        """A lower bound of each child's expected cost: what the memo knows of its state
        (exact, or a bound at least some budget) where it was searched, else :meth:`_bound`."""
        out = []
        for child, _, child_weights in children:
            facts = self.facts(child)
            if len(facts.grasps) < 2:
                out.append(0.0)
                continue
            known = self.memo.get((child, tuple(round(w, 12) for w in child_weights), target, free & facts.useful,
                                   taken & facts.useful))
            if known is not None:
                out.append(known[0])
            else:
                out.append(self._bound(child, child_weights, target, free))
        return out

    def _dropped(self, node: int, grasp: str) -> tuple[int, tuple[bool, ...]]:
        """The node left when ``grasp`` failed (its rows dropped) and which of this
        node's rows it keeps."""
        key = (node, grasp)
        if key not in self._without:
            rows = self.rows[node]
            classes = self.matrix.classes
            keep = tuple(classes[self.matrix.class_of[r]] != grasp for r in rows)
            self._without[key] = (self.node_id(tuple(r for r, k in zip(rows, keep) if k)), keep)
        return self._without[key]

    def _grasp_place(self, node: int, at: int, grasp: str) -> int:
        """Where the learner would execute ``grasp`` from ``at`` (``grasp_options``: the
        cheapest of the positions its descriptions at this node record)."""
        key = (node, at, grasp)
        if key in self._grasp_places:
            return self._grasp_places[key]
        recorded = self._recorded.get((node, grasp))
        if recorded is None:
            labels = self.matrix.labels
            recorded = self._recorded[node, grasp] = tuple(sorted(
                {labels.positions[labels.grasp_position[r]] for r in self.rows[node]
                 if self.matrix.classes[self.matrix.class_of[r]] == grasp}))
        chosen = self._grasp_places.get((recorded, at, grasp))
        if chosen is None:
            here = self.positions[at]
            places = recorded
            best, least = here, math.inf
            for position in places:  # grasp_options' choice: the first of the cheapest, in order
                target = target_for(Test(grasp, position, grasp, is_grasp=True), here, self.ctx)
                move = self.estimator.move_cost(here, target)
                if move < least:
                    best, least = target, move
            chosen = self._grasp_places[recorded, at, grasp] = self.place(best)
        self._grasp_places[key] = chosen
        return chosen

    def _bound(self, node: int, weights: Weights, at: int, free: int) -> float:
        """A lower bound of a node's expected cost: 0 when it is settled or a free test
        splits it, else the cheapest of: the cheapest paid sensing test from ``at``, and
        per confirmable grasp, the probability that it fails times the cheapest way to
        try it (blind, or as a binary feature: a grasp test fails at least for every row
        of another grasp). A grasp is paid only when it fails, as the actions price it (in
        full it would overstate the bound and prune the best action)."""
        facts = self.facts(node)
        if len(facts.grasps) < 2 or free & facts.splitting:
            return 0.0
        key = (node, at)
        priced = self._cheapest.get(key)
        if priced is None:
            priced = self._cheapest[key] = self._priced_from(node, at)
        least, per_grasp = priced
        held = [0.0] * len(per_grasp)
        for g, w in zip(facts.grasp_of, weights):
            held[g] += w
        for h, cost in zip(held, per_grasp):
            least = min(least, (1.0 - h) * cost)
        return least if math.isfinite(least) else 0.0  # no action at all: a last guess, free

    def _priced_from(self, node: int, at: int) -> tuple[float, list[float]]:
        """What a node's actions cost from ``at`` before their probabilities: the cheapest
        paid sensing test, and per grasp of the node the cheapest try of it when it fails
        (``inf`` for one the finger sensor cannot confirm)."""
        facts = self.facts(node)
        sensing = min((self._sensing_from(c, at) for c in facts.columns if not self.is_grasp[c]), default=math.inf)
        per_grasp = []
        for g in facts.grasps:
            if not self.verifiable[g]:
                per_grasp.append(math.inf)
                continue
            tries = [self._move(at, self._grasp_place(node, at, g)) + self.failure_s[g]]
            tries += [self._move(at, t) + self.price[c] for c in facts.columns
                      if self.is_grasp[c] and self.matrix.tests[c].feature == g for t in self._targets_for(c, at)]
            per_grasp.append(min(tries))
        return sensing, per_grasp

    # -- facts, worked out once per node -------------------------------------------------
    def _work_out(self, rows: Rows) -> _NodeFacts:
        matrix = self.matrix
        grasps = tuple(sorted({matrix.classes[c] for c in matrix.class_of[list(rows)].tolist()}))
        if len(grasps) < 2:
            return _NodeFacts(grasps, 0, 0)
        values = matrix.values[list(rows)]
        known = ~np.isnan(values)
        high = np.where(known, values, -np.inf).max(axis=0)
        low = np.where(known, values, np.inf).min(axis=0)
        useful = np.flatnonzero(known.any(axis=0) & (high - low > matrix.errors + _EPS))
        # chain-merged ranges (partition, as gain.partition_columns): a new range wherever
        # two sorted known values are more than the error apart (NaN sorts last, never apart)
        ordered = np.sort(values[:, useful], axis=0)
        n_ranges = 1 + (np.diff(ordered, axis=0) > matrix.errors[useful] + _EPS).sum(axis=0)
        columns = useful[n_ranges >= 2].tolist()
        grasp_of = tuple(grasps.index(matrix.classes[c]) for c in matrix.class_of[list(rows)].tolist())
        return _NodeFacts(grasps, _mask(columns), _mask(useful.tolist()), tuple(columns), grasp_of)

    def branchings(self, node: int) -> tuple[_Branching, ...]:
        """Each splitting test's children and shares (``node.split``: a value within two
        ranges goes to the first; a row lacking the value goes down every branch)."""
        found = self._branchings.get(node)
        if found is not None:
            return found
        rows, columns = self.rows[node], list(self.facts(node).columns)
        out = []
        for c, values in zip(columns, self.matrix.values[list(rows)][:, columns].T.tolist()):
            ranges = partition([v for v in values if v == v], self.errors[c])
            k = len(ranges)
            lows = [lo - _EPS for lo, _ in ranges]
            # each known value lies in one range (they were made from these values): the
            # last range starting at or below it; -1: lacking, down every branch
            branch = [bisect_right(lows, v) - 1 if v == v else -1 for v in values]
            members: list[list[tuple[int, float]]] = [[] for _ in range(k)]
            for i, j in enumerate(branch):
                if j < 0:
                    for m in members:
                        m.append((i, 1.0 / k))
                else:
                    members[j].append((i, 1.0))
            children = tuple(self.node_id(tuple(rows[i] for i, _ in m)) for m in members)
            out.append(_Branching(c, children, tuple(tuple(m) for m in members)))
        found = self._branchings[node] = tuple(out)
        return found

    def _offers(self, column: int, at: int) -> tuple[tuple[float, int], ...]:
        """Where test ``column`` can be made from ``at``, cheapest first: (move plus the
        procedure's time or the grasp's ``feature_cost_s``, target), unreachable ones left out."""
        key = (column, at)
        found = self._offered.get(key)
        if found is None:
            grasp = self.is_grasp[column]
            priced = ((self._move(at, t, sensing=not grasp) + self.price[column], t)
                      for t in self._targets_for(column, at))
            found = self._offered[key] = tuple(sorted(o for o in priced if math.isfinite(o[0])))
        return found

    def _sensing_from(self, column: int, at: int) -> float:
        """The cheapest way to make sensing test ``column`` from ``at``: move and time."""
        key = (column, at)
        found = self._column_from.get(key)
        if found is None:
            found = self._column_from[key] = min(self._move(at, t, sensing=True) + self.price[column]
                                                 for t in self._targets_for(column, at))
        return found

    def _frees(self, column: int, kind: str, at: int) -> int:
        """The columns a measurement makes free: every feature of ``column``'s procedure
        measured at ``at`` (``kind`` "procedure"), or just its feature (``node.measured_value``)."""
        test = self.matrix.tests[column]
        name = test.procedure if kind == "procedure" else test.feature
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


def session_action(search: ExactSearch, node: int, weights: Weights, test: ScoredTest, at: int, free: int,
                   taken: int) -> tuple[float, list[tuple[int, float, Weights]], int, int, int] | None:
    """``test`` as a session would take it at the search's ``node`` (from ``at``, to its
    ``target``), as the search's action: (its expected cost now, its children, where the
    robot ends, free and taken tests after); None when it splits nothing or cannot be
    reached."""
    column = search.matrix.column[test.test]
    b = search.branching(node, column)
    if b is None:
        return None
    if test.cost <= 0 and not test.test.is_grasp:  # a value already measured, re-used where the robot stands
        return 0.0, search._children(b, weights), at, free | search._frees(column, "feature", at), taken | (1 << column)
    return search.test_action(node, weights, b, at, search.place(test.target), free, taken)


def priced_all(search: ExactSearch, node: int, weights: Weights, tests: Sequence[ScoredTest], at: int, free: int,
               taken: int) -> list[tuple[float, bool]]:
    """Each of ``tests`` priced as a session would take it: what it costs plus, per
    branch, the least expected cost below it, and whether that price is exact. Branch
    and bound, as the search's own node: the tests are searched in the order of their
    lower bounds, and one that cannot beat the least total found is searched no further
    (its price is then a lower bound, at least that least; ``inf`` for a test that
    splits nothing here). The least price is exact."""
    prices = [(math.inf, False)] * len(tests)
    bounded = []
    for i, test in enumerate(tests):
        action = session_action(search, node, weights, test, at, free, taken)
        if action is not None:
            cost, children, target, now_free, now_taken = action
            bounds = search.bounds_of(children, target, now_free, now_taken)
            bounded.append((cost + sum(m * x for (_, m, _), x in zip(children, bounds)), i, action, bounds))
    bounded.sort(key=lambda a: (a[0], a[1]))
    best = math.inf
    for bound, i, (cost, children, target, now_free, now_taken), bounds in bounded:
        if bound >= best - _EPS:
            prices[i] = (max(bound, best), False)
            continue
        price = search.below(cost, children, bounds, target, now_free, now_taken, best)
        prices[i] = (price, price < best)
        best = min(best, price)
    return prices


def _mask(columns: Iterable[int]) -> int:
    bits = 0
    for c in columns:
        bits |= 1 << int(c)
    return bits

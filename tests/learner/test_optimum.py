"""The exact optimum against hand-worked libraries, and never above the learner's policy."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from experiments.ablations import MEASURED, criterion
from learner.choosing.matrix import DescriptionMatrix
from learner.costs import ModelMoveCost
from learner.description import ObjectDescription, Observation
from learner.knowledge import FeatureSpec, GraspingProcedure, Knowledge, MoveModel, SensingProcedure
from learner.optimum import PolicyWalk, optimal_cost, policy_cost, policy_walk
from learner.position import Position
from tests.learner.fixtures import ANY, P

PER_INCH = MoveModel(seconds_per_inch=2.0, seconds_per_degree=0.0, overhead_s=0.0)


def knowledge(move: MoveModel = PER_INCH) -> Knowledge:
    """Scan: 40 s at 6 in, yields H and D. Sweep: 10 s from 6 to 30 in, yields W.
    Grasps A and B: 60 s + 30 s penalty (90 s as features or when they fail); C, 60 s,
    cannot be confirmed by the finger sensor, so it is never a feature."""
    return Knowledge(
        sensing=(SensingProcedure("Scan", 40.0, (6.0, 6.0), (FeatureSpec("H", 0.5, "in", False, (0.0, 20.0)),
                                                               FeatureSpec("D", 0.5, "in", False, (0.0, 20.0)))),
                 SensingProcedure("Sweep", 10.0, (6.0, 30.0), (FeatureSpec("W", 1.0, "deg", False, (0.0, 90.0)),))),
        grasping=(GraspingProcedure("A", 60.0, (6.0, 6.0), 30.0, True),
                  GraspingProcedure("B", 60.0, (6.0, 6.0), 30.0, True),
                  GraspingProcedure("C", 60.0, (6.0, 999.0), 0.0, False)),
        move=move)


def d(oid: str, grasp: str, *obs: tuple[str, Position, float], at: Position = P(6, 0)) -> ObjectDescription:
    return ObjectDescription(oid, grasp, at, tuple(sorted(Observation(f, p, v) for f, p, v in obs)))


def matrix(library: list[ObjectDescription], grasps: bool = True, move: MoveModel = PER_INCH) -> DescriptionMatrix:
    return DescriptionMatrix(library, knowledge(move), grasps)


EST = ModelMoveCost(PER_INCH)


def test_grasps_as_features_worked_by_hand() -> None:
    # From (20,0): W(20,0) costs 10 and splits {a,b} | {c}; H(6,0) costs 14 in * 2 + 40 =
    # 68; grasp A or B tried as a feature 28 + 90 = 118, paid whatever comes of it. A grasp
    # executed costs nothing when it is the object's own and, when it fails, its move plus
    # time and penalty: A or B 28 + 90.
    #   W first: 10 + 2/3 * (1/2 * 118) (execute A from (20,0))    = 49.333
    #   A first: 2/3 * 118; H first: 68 at least; C (unconfirmable) is never tried blind
    lib = [d("a", "A", ("W", P(20, 0), 10), ("H", P(6, 0), 3)),
           d("b", "B", ("W", P(20, 0), 10), ("H", P(6, 0), 5)),
           d("c", "C", ("W", P(20, 0), 30), ("H", P(6, 0), 5))]
    m = matrix(lib)
    assert optimal_cost(m, EST, P(20, 0)) == pytest.approx(10 + 2 / 3 * 59)
    # I^2/C takes the cheap sweep first, then the Scan (68 s, not the 118 s grasp test),
    # which ends a and b at their own leaves: 10 + 2/3 * 68
    walk = policy_walk(m, criterion("cs-id3"), EST, P(20, 0))
    assert walk.expected_cost == pytest.approx(10 + 2 / 3 * 68)
    assert walk.right == 1.0


class BeamBlockedAt:
    """The model's moves, but a reading at ``blocked`` would meet a neighbour: the
    planner's estimator prices sensing there ``inf`` (behaviours.bridge.PlannerMoveCost)."""

    def __init__(self, blocked: Position) -> None:
        self.blocked = blocked

    def move_cost(self, start: Position, goal: Position) -> float:
        return EST.move_cost(start, goal)

    def sensing_move_cost(self, start: Position, goal: Position) -> float:
        return math.inf if goal == self.blocked else EST.move_cost(start, goal)


def test_a_test_whose_reading_a_neighbour_spoils_is_not_used_by_the_optimum() -> None:
    # The library of the test above, the sweep's only position (20,0) blocked. Left: H at
    # (6,0), 28 + 40 = 68, splits {a} | {b,c}; for {b,c} at (6,0) B tried as a feature, or
    # executed, fails for c only: 1/2 * 90 = 45. 68 + 2/3 * 45 = 98. Starting with a grasp
    # costs more: A first 2/3 * (28 + 90) = 78.67, then {b,c} 2/3 * 45: 108.67; B first
    # 78.67, then a | c by H (40): 105.33. (With the sweep: 10 + 2/3 * 59 = 49.33.)
    lib = [d("a", "A", ("W", P(20, 0), 10), ("H", P(6, 0), 3)),
           d("b", "B", ("W", P(20, 0), 10), ("H", P(6, 0), 5)),
           d("c", "C", ("W", P(20, 0), 30), ("H", P(6, 0), 5))]
    assert optimal_cost(matrix(lib), BeamBlockedAt(P(20, 0)), P(20, 0)) == pytest.approx(68 + 2 / 3 * 45)


def test_a_missing_value_spreads_its_description_over_the_branches() -> None:
    # c lacks H, b lacks W: each is carried down every branch of that test and, as the
    # object at hand, follows each branch with probability 1/2. From (6,0), no grasps as
    # features; every grasp position is (6,0). A failed A or B costs 90 s, C 60 s (+ move).
    # C, like No-Grab, cannot be confirmed: "executing" it means moving on, so it is never
    # tried blind, only when every candidate left is C's.
    #   execute B first: wrong for a and c, 1/2 * 90 = 45; then {a, c}: W (20,0), 14 in * 2
    #     + 10 = 38, tells them apart (A blind: 1/2 * 90)        45 + 1/2 * 38 = 64
    #   execute A first: 3/4 * 90 = 67.5 already; H first (40 s): H=3 -> {a, e, c*} (5/8) needs W (38) and a
    #     grasp from (20,0) to part e and c (3/5 * 1/3 * 118), H=5 -> {b, c*} (3/8) B,
    #     1/3 * 90:                        40 + 5/8 * (38 + 23.6) + 3/8 * 30 = 89.75
    #   W first (38 s): W=10 -> {a, b*} (3/8), A from (20,0) wrong for b: 1/3 * 118;
    #     W=30 -> {e, c, b*} (5/8), B wrong for c: 2/5 * 118   = 38 + 14.75 + 29.5 = 82.25
    lib = [d("a", "A", ("H", P(6, 0), 3), ("W", P(20, 0), 10)),
           d("e", "B", ("H", P(6, 0), 3), ("W", P(20, 0), 30)),
           d("b", "B", ("H", P(6, 0), 5)),
           d("c", "C", ("W", P(20, 0), 30))]
    m = matrix(lib, grasps=False)
    assert optimal_cost(m, EST, P(6, 0)) == pytest.approx(45 + 1 / 2 * 38)
    # I^2/C takes the 38 s sweep first (2 s cheaper); the walk follows it object by object,
    # each until its own grasp is executed:
    #   a: W=10, leaf A: 38.  e: W=30, H (28 + 40 = 68) = 3, leaf B: 106.
    #   c: W=30, then H lacks a value: H=3 reaches leaf B, H=5 the ambiguous {b*, c*},
    #     whose first option is B (verifiable first); either way B fails (90 s), the
    #     session restarts without B, the measured W=30 (free) separates c from a: 196.
    #   b lacks W: W=30 goes as e's, H=5, the ambiguous {b*, c*} tries B: 106; W=10
    #     reaches leaf A at (6,0), 28 + 90, restart without A, W (the fork's 10) splits
    #     nothing left, the Scan H(6,0), 40 s, finds b: 38 + 118 + 40 = 196; b costs 151.
    walk = policy_walk(m, criterion("cs-id3"), EST, P(6, 0))
    costs = {o.object_id: o.cost_s for o in walk.outcomes}
    assert costs == pytest.approx({"a": 38, "e": 106, "b": (106 + 196) / 2, "c": 196})
    assert walk.expected_cost == pytest.approx((38 + 106 + 151 + 196) / 4)
    # the first grasp executed: c never starts with its own, b half the time
    assert {o.object_id: o.right for o in walk.outcomes} == {"a": 1.0, "e": 1.0, "b": 0.5, "c": 0.0}


def test_a_procedure_yields_all_its_features_for_one_cost() -> None:
    # H splits {a,b} | {c} and D {a} | {b,c}: one Scan (40 s, no move) measures both, the
    # second test is free, so every object costs 40 s, not 40 + 2/3 * 40. (Executing A or
    # B blind costs more: 2/3 of 90 s before the move to (6,0).)
    lib = [d("a", "A", ("H", P(6, ANY), 3), ("D", P(6, ANY), 1)),
           d("b", "B", ("H", P(6, ANY), 3), ("D", P(6, ANY), 9)),
           d("c", "C", ("H", P(6, ANY), 5), ("D", P(6, ANY), 9))]
    m = matrix(lib, grasps=False)
    assert optimal_cost(m, EST, P(6, 90)) == pytest.approx(40)
    # from (20,90) the Scan is made at (6,90), where the robot's bearing already is: 28 s
    assert optimal_cost(m, EST, P(20, 90)) == pytest.approx(28 + 40)


def test_the_optimum_is_zero_when_the_library_is_already_a_leaf() -> None:
    lib = [d("a", "A", ("H", P(6, 0), 3)), d("b", "A", ("H", P(6, 0), 9))]
    assert optimal_cost(matrix(lib), EST, P(40, 0)) == 0.0
    assert policy_cost(matrix(lib), criterion("cs-id3"), EST, P(40, 0)) == 0.0


def test_a_start_with_a_star_slot_is_refused() -> None:
    with pytest.raises(ValueError, match="concrete"):
        optimal_cost(matrix([d("a", "A", ("H", P(6, 0), 3))]), EST, P(6, None))


# -- never above the learner's own policy ----------------------------------------------
SLOTS = {"H": [P(6, 0), P(6, 90), P(6, ANY)], "D": [P(6, 0), P(6, ANY)],
         "W": [P(20, 0), P(12, 90), P(20, ANY), P(ANY, 90)]}
CONCRETE = {f: [p for p in ps if p.distance_in is not None and p.orientation_deg is not None]
            for f, ps in SLOTS.items()}


@st.composite
def libraries(draw: st.DrawFn, slots: dict[str, list[Position]]) -> list[ObjectDescription]:
    """3-5 descriptions, each with 1-4 values from a few coarse levels (so they collide,
    chain and go missing as learned ones do)."""
    n = draw(st.integers(3, 5))
    grasp_places = [P(6, 0), P(6, 90)] if slots is CONCRETE else [P(6, 0), P(6, ANY)]
    out = []
    for i in range(n):
        tests = draw(st.lists(st.sampled_from([(f, p) for f, ps in slots.items() for p in ps]),
                              min_size=1, max_size=4, unique=True))
        obs = [(f, p, float(draw(st.sampled_from([1, 3, 5, 9] if f != "W" else [10, 12, 30, 50]))))
               for f, p in tests]
        out.append(d(f"o{i}", draw(st.sampled_from("ABC")), *obs, at=draw(st.sampled_from(grasp_places))))
    return out


STARTS = [P(6, 0), P(16, 90), P(40, 180), P(24, 270)]


def _assert_bounded(best: float, walk: PolicyWalk, name: str) -> None:
    """The optimum is below the walk, unless the walk left an object behind: a wrong C
    (unverifiable, like No-Grab) ends its walk unseen, a cost the search never takes."""
    if walk.missed == 0:
        assert best <= walk.expected_cost + 1e-9, name
    else:
        assert 0 < walk.missed <= 1 and all(o.right == 0 for o in walk.outcomes if o.missed == 1), name
SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.slow
@SETTINGS
@given(libraries(SLOTS), st.sampled_from(STARTS), st.booleans())
def test_the_optimum_is_never_above_a_cost_sensitive_policy(library: list[ObjectDescription], start: Position,
                                                             grasps: bool) -> None:
    """Every criterion that fills a ``*`` slot where the robot stands takes, at each step,
    an action the search also considers, so its walk can only cost more. (Every one the
    experiments measure, the ablations too: their traits are the learner's.)"""
    move = MoveModel(2.0, 0.1, 0.0)
    m, est = matrix(library, grasps, move), ModelMoveCost(move)
    best = optimal_cost(m, est, start)
    for name, spec in MEASURED.items():
        if not spec.cost_blind_choices:
            _assert_bounded(best, policy_walk(m, criterion(name), est, start), name)


@pytest.mark.slow
@SETTINGS
@given(libraries(CONCRETE), st.sampled_from(STARTS), st.booleans(), st.integers(0, 3))
def test_the_optimum_is_never_above_any_policy_on_concrete_positions(library: list[ObjectDescription],
                                                                     start: Position, grasps: bool, seed: int) -> None:
    """With no ``*`` slot, even a cost-blind criterion's random choices stay among the
    search's actions."""
    move = MoveModel(2.0, 0.1, 0.0)
    m, est = matrix(library, grasps, move), ModelMoveCost(move)
    best = optimal_cost(m, est, start)
    for name in MEASURED:
        _assert_bounded(best, policy_walk(m, criterion(name), est, start, seed=seed), name)


@pytest.mark.slow
@SETTINGS
@given(libraries(SLOTS), st.sampled_from(STARTS), st.booleans(), st.integers(0, 3))
def test_the_optimum_is_never_above_a_random_fill_when_any_move_costs_the_same(
        library: list[ObjectDescription], start: Position, grasps: bool, seed: int) -> None:
    """A cost-blind criterion fills ``*`` at random, off the search's positions. When every
    move costs the same 15 s, staying where the robot stands is never dearer than a random
    place and frees at least the same tests, so the bound holds for it too."""
    move = MoveModel(0.0, 0.0, 15.0)
    m, est = matrix(library, grasps, move), ModelMoveCost(move)
    best = optimal_cost(m, est, start)
    for name in MEASURED:
        _assert_bounded(best, policy_walk(m, criterion(name), est, start, seed=seed), name)

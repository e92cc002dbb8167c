"""The estimate mode's cheaper distance fields (issue 32) price every move as before.

Fields are kept per coarse block, without copies on the map's grid, searched on a graph
made symmetric once and at first only as far as :data:`FIELD_REACH_IN`: none of it may
change a price. Compared with the estimator as it was (tests/planner/reference_move_cost.py)
on the simulated lab's own vision map, over moves between the positions around its
objects the learner prices and any points of the floor, blocked, outside or far apart.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from hero_driver.sim_driver import SimulatedHero
from planner import CostEstimator, Navigator, Pose
from planner.grid_search import GridGraph, descend
from planner.move_cost import FIELD_COARSENING, FIELD_REACH_IN, FIELDS_KEPT
from tests.planner.drawing import Canvas
from tests.planner.reference_move_cost import ReferenceCostEstimator, reference_descend
from tests.planner.sim import navigator


@pytest.fixture(scope="module")
def lab() -> Navigator:
    nav = navigator()
    nav.observe(SimulatedHero(seed=1).camera().result())
    return nav


@pytest.fixture(scope="module")
def both(lab: Navigator) -> tuple[CostEstimator, ReferenceCostEstimator]:
    """One of each for the whole module: their caches fill and evict as pricing goes on."""
    return (CostEstimator(lab.vision_map, lab.robot.motion, cache_size=4),
            ReferenceCostEstimator(lab.vision_map, lab.robot.motion))


def _pose(nav: Navigator, draw: st.DrawFn) -> Pose:
    """A learner position around one of the lab's objects, or any point on or off the floor."""
    if draw(st.booleans()):
        region = draw(st.sampled_from(nav.scene.regions))
        return nav.pose_for(region, draw(st.floats(0.0, 130.0)), draw(st.floats(0.0, 359.9)))
    x_min, x_max, y_min, y_max = nav.vision_map.bounds
    return Pose(draw(st.floats(x_min - 10.0, x_max + 10.0)), draw(st.floats(y_min - 10.0, y_max + 10.0)),
                draw(st.floats(0.0, 359.9)))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.data())
def test_every_move_is_priced_as_before(lab, both, data) -> None:
    fast, reference = both
    start = _pose(lab, data.draw)
    for _ in range(4):  # a start prices several goals, as the learner's do
        goal = _pose(lab, data.draw)
        assert fast.estimate(start, goal) == reference.estimate(start, goal)


def test_the_moves_of_a_learner_around_each_object_are_priced_as_before(lab) -> None:
    fast = CostEstimator(lab.vision_map, lab.robot.motion)
    reference = ReferenceCostEstimator(lab.vision_map, lab.robot.motion)
    rng = np.random.default_rng(0)
    costs = []
    for region in lab.scene.regions:
        positions = [lab.pose_for(region, float(d), float(o))
                     for d, o in zip(rng.choice([6, 16, 24, 40, 60, 100], 12), rng.uniform(0, 360, 12))]
        priced = [(s, g) for s in positions for g in positions]
        costs += [fast.estimate(s, g) for s, g in priced]
        assert costs[-len(priced):] == [reference.estimate(s, g) for s, g in priced]
    # what the comparison covered: moves beyond the first field's reach, and moves that cannot be made
    assert any(c.possible and c.length_in > FIELD_REACH_IN for c in costs)
    assert any(not c.possible for c in costs)


def _open() -> tuple[CostEstimator, Pose]:
    """An estimator on an empty drawn room (240 x 180 in, 0.8 in cells), keeping two
    fields, and a start near its left wall."""
    nav = navigator()
    nav.observe(Canvas().robot(20.0, 40.0, 0.0).image())
    return CostEstimator(nav.vision_map, nav.robot.motion, cache_size=2), Pose(20.0, 40.0, 0.0)


def test_starts_in_one_block_share_a_field_and_the_cache_keeps_its_bound() -> None:
    estimator, start = _open()
    step = estimator.map.image.inches_per_pixel
    cell = estimator.map.cell_of(start.x_in, start.y_in)
    # the other cell of the start's block (blocks are FIELD_COARSENING cells wide)
    mate = cell[1] + 1 if cell[1] % FIELD_COARSENING == 0 else cell[1] - 1
    neighbour = Pose(start.x_in + (mate - cell[1]) * step, start.y_in, 0.0)
    goal = Pose(60.0, 40.0, 0.0)
    estimator.estimate(start, goal)
    estimator.estimate(neighbour, goal)
    assert estimator.fields_computed == 1
    # two fields kept (cache_size=2): a third start's field evicts the first's
    for x in (40.0, 50.0):
        estimator.estimate(Pose(x, 40.0, 0.0), goal)
    assert estimator.fields_computed == 3
    estimator.estimate(start, goal)
    assert estimator.fields_computed == 4
    assert FIELDS_KEPT >= 8  # at least what the estimator kept before


def test_a_goal_beyond_the_first_fields_reach_gets_the_whole_field() -> None:
    estimator, start = _open()
    near, far = Pose(start.x_in + 30.0, start.y_in, 0.0), Pose(start.x_in + FIELD_REACH_IN + 20.0, start.y_in, 0.0)
    assert estimator.map.is_free(far.x_in, far.y_in)
    estimator.estimate(start, near)
    assert estimator.fields_computed == 1
    priced = estimator.estimate(start, far)
    assert estimator.fields_computed == 2 and priced.possible
    # straight across an open floor: the length is the straight line's (the field's 8-connected
    # distance, scaled, is below it), so the far goal is priced, not cut off at the reach
    assert priced.length_in == pytest.approx(FIELD_REACH_IN + 20.0)
    estimator.estimate(start, near)  # within reach: the first field still answers
    assert estimator.fields_computed == 2


def test_a_limited_search_finds_the_whole_searchs_distances_within_its_limit() -> None:
    free = np.ones((40, 60), bool)
    free[5:35, 30] = False  # a wall the short way round leaves
    graph = GridGraph(free)
    whole, limited = graph.distances_from((20, 10)), graph.distances_from((20, 10), 25.0)
    assert limited[20, 20] == whole[20, 20] == 10.0  # ten straight steps, by hand
    inside = whole <= 25.0
    assert np.array_equal(limited[inside], whole[inside])  # to the last bit
    assert np.isinf(limited[~inside]).all()
    # straight across, 25 steps, the wall is in the way: round its end, farther than the limit
    assert 25.0 < whole[20, 35] < math.inf and math.isinf(limited[20, 35])


def test_the_descent_follows_the_same_cells_as_before() -> None:
    # random walls on a small grid, every reachable goal from a few starts: the same path,
    # cell for cell, as the descent that indexed numpy's scalars (ties go to the first
    # lowest neighbour, row by row, in both)
    rng = np.random.default_rng(1)
    free = rng.random((30, 40)) > 0.25
    graph = GridGraph(free)
    for start in [tuple(int(v) for v in cell) for cell in np.argwhere(free)[::97]]:
        field = graph.distances_from(start)
        goals = [tuple(int(v) for v in cell) for cell in np.argwhere(np.isfinite(field))[::7]]
        assert goals and all(descend(field, g) == reference_descend(field, g) for g in goals)

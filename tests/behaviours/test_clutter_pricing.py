"""``PlannerMoveCost.sensing_move_cost`` (behaviours.bridge): a blocked beam priced up front.

Geometry (as tests/behaviours/test_clutter.py): the object is the 4 x 4 in square at
(100, 50), axis +x. Sensing from (24, 0) puts the sonar at x = 100 + 2 + 24 = 126, the
corridor spanning x 98..126, y 48..52: a neighbour at (115, 50) sits in it. From
(24, 180) the sonar stands at x = 74 and the corridor spans x 74..102: the same
neighbour is behind the robot. The fake navigator charges 2 s per inch between poses
at the position's distance from the centroid: from (60, 0) (pose x 160) to (24, 0)
(x 124) is 36 in, 72 s; to (24, 180) (x 76) 84 in, 168 s.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from behaviours.bridge import PlannerMoveCost
from learner.costs import sensing_cost
from tests.behaviours.conftest import REGION, FakeNavigator, P, region

START = P(60, 0)


def _priced(*regions, beam_check: bool = True, of=REGION) -> PlannerMoveCost:  # noqa: ANN001, ANN202
    return PlannerMoveCost(FakeNavigator(latest=regions), of, beam_check=beam_check)


def test_a_sensing_position_whose_beam_meets_a_neighbour_is_priced_inf() -> None:
    estimator = _priced(REGION, region(115.0, 50.0))
    assert estimator.sensing_move_cost(START, P(24, 0)) == math.inf
    assert sensing_cost(estimator, START, P(24, 0)) == math.inf
    # a grasp from the same pose makes no sound: priced as a move
    assert estimator.move_cost(START, P(24, 0)) == pytest.approx(72.0)
    # the neighbour is behind the robot from the other side
    assert estimator.sensing_move_cost(START, P(24, 180)) == pytest.approx(168.0)


def test_a_neighbour_well_beside_the_beam_or_the_object_seen_anew_costs_nothing_extra() -> None:
    beside = _priced(REGION, region(115.0, 60.0))  # near edge y = 58: 6 in from the corridor
    assert beside.sensing_move_cost(START, P(24, 0)) == pytest.approx(72.0)
    itself = _priced(region(100.4, 50.3))  # within pushed_in (1 in) of the centroid
    assert itself.sensing_move_cost(START, P(24, 0)) == pytest.approx(72.0)


def test_a_cluster_is_never_sensed_and_the_check_off_prices_as_before() -> None:
    cluster = dataclasses.replace(REGION, cluster=True)
    assert _priced(cluster, of=cluster).sensing_move_cost(START, P(24, 180)) == math.inf
    off = _priced(REGION, region(115.0, 50.0), beam_check=False)
    assert off.sensing_move_cost(START, P(24, 0)) == pytest.approx(72.0)


def test_retarget_forgets_what_was_blocked() -> None:
    estimator = _priced(REGION, region(115.0, 50.0))
    assert estimator.sensing_move_cost(START, P(24, 0)) == math.inf
    estimator.retarget(region(100.0, 20.0))  # pushed 30 in away: the neighbour is off its beam
    assert estimator.sensing_move_cost(START, P(24, 0)) == pytest.approx(72.0)

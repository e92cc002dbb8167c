"""Routing on a roadmap: entry and exit by visibility, A* over the graph."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.roadmap import Roadmap


def ring() -> Roadmap:
    """Four milestones round a wall on x = 0 (from y = -20 to 5): two ways round it,
    the one over the top shorter."""
    points = np.array([(-3.0, 6.0), (3.0, 6.0), (-3.0, -21.0), (3.0, -21.0)])
    return Roadmap(points, [[1], [0], [3], [2]])


def clear_of_wall(p, q) -> bool:
    """True unless the segment crosses x = 0 between y = -20 and 5."""
    if (p[0] < 0) == (q[0] < 0):
        return True
    t = -p[0] / (q[0] - p[0])
    return not -20 <= p[1] + t * (q[1] - p[1]) <= 5


def test_route_takes_the_shorter_way_round():
    route = ring().route((-4.0, 0.0), (4.0, 0.0), clear_of_wall)
    assert route == [(-4.0, 0.0), (-3.0, 6.0), (3.0, 6.0), (4.0, 0.0)]
    assert all(clear_of_wall(p, q) for p, q in zip(route, route[1:]))


def test_route_uses_the_long_way_when_the_short_one_is_cut():
    roadmap = ring()
    roadmap.neighbours[0], roadmap.neighbours[1] = [], []
    route = roadmap.route((-4.0, 0.0), (4.0, 0.0), clear_of_wall)
    assert route[1:3] == [(-3.0, -21.0), (3.0, -21.0)]
    assert sum(math.dist(p, q) for p, q in zip(route, route[1:])) == pytest.approx(
        math.dist((-4, 0), (-3, -21)) + 6 + math.dist((3, -21), (4, 0)))


def test_no_route_when_start_sees_no_milestone_or_the_graph_is_cut():
    assert ring().route((-4.0, 0.0), (4.0, 0.0), lambda p, q: False) is None
    roadmap = ring()
    roadmap.neighbours[:] = [[], [], [], []]
    assert roadmap.route((-4.0, 0.0), (4.0, 0.0), clear_of_wall) is None
    assert Roadmap(np.zeros((0, 2)), []).route((0.0, 0.0), (1.0, 1.0), clear_of_wall) is None

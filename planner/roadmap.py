"""A probabilistic roadmap of the free space, grown by OMPL once per map, searched here.

The map stays the same while the robot drives about and the learner asks for many
paths on it, so the roadmap is grown once (OMPL's PRM, to a fixed number of
milestones, single-threaded) and every query then only connects its start and goal to
nearby milestones and searches the graph. The search is done here, not by
``PRM.solve``: that grows the roadmap in one thread while a second one polls for a
solution, which made queries slow (tens of milliseconds while it grew) and their
answers depend on thread timing. Searching a fixed graph is fast and deterministic.
"""

from __future__ import annotations

import heapq
import math
import time
from collections.abc import Callable

import numpy as np
from ompl import base as ob
from ompl import geometric as og

Point = tuple[float, float]

# How many of the nearest milestones a query's start and goal try to connect to.
CONNECT_NEIGHBOURS = 12


class Roadmap:
    """Milestones (world inches) and the straight, collision-free edges between them."""

    def __init__(self, points: np.ndarray, neighbours: list[list[int]]) -> None:
        self.points = points
        self.neighbours = neighbours

    @classmethod
    def grow(cls, setup: og.SimpleSetup, milestones: int, max_s: float) -> Roadmap:
        """Grow a PRM roadmap to ``milestones`` (or for ``max_s`` seconds at most) with
        ``setup``'s space and validity checker, and copy it out."""
        planner = og.PRM(setup.getSpaceInformation())
        setup.setPlanner(planner)
        setup.setup()
        give_up = time.perf_counter() + max_s
        planner.growRoadmapPtc(ob.PlannerTerminationCondition(
            lambda: planner.milestoneCount() >= milestones or time.perf_counter() > give_up))
        data = ob.PlannerData(setup.getSpaceInformation())
        planner.getPlannerData(data)
        count = data.numVertices()
        points = np.array([(data.getVertex(i).getState()[0], data.getVertex(i).getState()[1])
                           for i in range(count)], dtype=float).reshape(-1, 2)
        neighbours = [list(data.getEdges(i)) for i in range(count)]
        return cls(points, neighbours)

    def __len__(self) -> int:
        return len(self.points)

    def pruned(self, free: Callable[[np.ndarray], np.ndarray], step: float) -> Roadmap:
        """The milestones and edges still clear on a new map (``free`` tells, for an Nx2
        array of points, which lie in free space), edges sampled every ``step`` inches.

        A map that changed a little (an object gone, a few edge cells flickering in the
        camera's noise) keeps almost all of its roadmap this way, for a fraction of the
        cost of growing one.
        """
        keep = free(self.points) if len(self.points) else np.zeros(0, bool)
        pairs = sorted({(min(i, j), max(i, j)) for i, ns in enumerate(self.neighbours) for j in ns
                        if i != j and keep[i] and keep[j]})
        clear: list[tuple[int, int]] = []
        if pairs:
            ends = np.array(pairs)
            a, b = self.points[ends[:, 0]], self.points[ends[:, 1]]
            counts = np.maximum(2, np.ceil(np.linalg.norm(b - a, axis=1) / step).astype(int) + 1)
            edge = np.repeat(np.arange(len(pairs)), counts)  # each edge sampled by its own length
            first = np.repeat(np.cumsum(counts) - counts, counts)
            t = (np.arange(len(edge)) - first) / (counts[edge] - 1)
            points = a[edge] + t[:, None] * (b - a)[edge]
            blocked = np.zeros(len(pairs), dtype=bool)
            np.logical_or.at(blocked, edge, ~free(points))
            clear = [p for p, bad in zip(pairs, blocked) if not bad]
        index = {old: new for new, old in enumerate(np.flatnonzero(keep))}
        neighbours: list[list[int]] = [[] for _ in index]
        for i, j in clear:
            neighbours[index[i]].append(index[j])
            neighbours[index[j]].append(index[i])
        return Roadmap(self.points[keep], neighbours)

    def route(self, start: Point, goal: Point, sees: Callable[[Point, Point], bool]) -> list[Point] | None:
        """The shortest roadmap route from ``start`` to ``goal``, or None.

        ``sees(p, q)`` says whether the straight segment is clear; start and goal are
        joined to those of their nearest milestones they see. A* over the graph with
        Euclidean edge lengths (and the straight-line heuristic) finds the route.
        """
        if len(self.points) == 0:
            return None
        entries = self._visible(start, sees)
        exits = {i: math.dist(self.points[i], goal) for i in self._visible(goal, sees)}
        if not entries or not exits:
            return None
        goal_node = -1
        best = {i: math.dist(start, self.points[i]) for i in entries}
        parent: dict[int, int | None] = {i: None for i in entries}
        queue = [(d + math.dist(self.points[i], goal), d, i) for i, d in best.items()]
        heapq.heapify(queue)
        while queue:
            _, dist, node = heapq.heappop(queue)
            if node == goal_node:
                break
            if dist > best.get(node, math.inf):
                continue
            if node in exits:
                total = dist + exits[node]
                if total < best.get(goal_node, math.inf):
                    best[goal_node], parent[goal_node] = total, node
                    heapq.heappush(queue, (total, total, goal_node))
            here = self.points[node]
            for nxt in self.neighbours[node]:
                candidate = dist + math.dist(here, self.points[nxt])
                if candidate < best.get(nxt, math.inf):
                    best[nxt], parent[nxt] = candidate, node
                    heapq.heappush(queue, (candidate + math.dist(self.points[nxt], goal), candidate, nxt))
        if goal_node not in parent:
            return None
        nodes = []
        node = parent[goal_node]
        while node is not None:
            nodes.append(node)
            node = parent[node]
        return [start] + [tuple(map(float, self.points[i])) for i in reversed(nodes)] + [goal]

    def _visible(self, point: Point, sees: Callable[[Point, Point], bool]) -> list[int]:
        distances = np.hypot(self.points[:, 0] - point[0], self.points[:, 1] - point[1])
        nearest = np.argsort(distances)[:CONNECT_NEIGHBOURS]
        return [int(i) for i in nearest if sees(point, tuple(self.points[i]))]

"""The first path query on a new map, which grows its roadmap: before and after the byte
grid validity checker, side by side in this process.

    python bench/bench_planner_first_query.py [--repeat 7] [--seed 0]

Each run makes a fresh ``PathPlanner`` on the lab's vision map (the simulator's camera,
seed ``--seed``) and times its first query that needs a detour: growing the PRM
roadmap (400 milestones, OMPL calling the Python validity checker for every state)
and answering on it. "Before" installs the checker as it was (the planner holding the numpy
grid, indexed with ``min`` clamps; kept below verbatim as the reference); "after" is
``planner.paths``' own. Both
must grow the same roadmap and return the same path. Runs alternate; medians.

Then, on the same map: how many roadmaps a ``Navigator`` grows while the same world is
seen again (once per map).
"""

from __future__ import annotations

import argparse
import datetime
import platform
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import planner.paths as paths  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402
from planner import Navigator, PathPlanner, PlanResult, Pose  # noqa: E402
from planner.roadmap import Roadmap  # noqa: E402
from planner.vision_map import VisionMap  # noqa: E402
from robot_profile import load_profile  # noqa: E402


def reference_checker(vision_map: VisionMap, holder: list[np.ndarray]) -> Callable[[Any], bool]:
    """The checker before, verbatim: the numpy grid, clamped with ``min`` (same answers)."""
    image = vision_map.image
    x0, y1, inv = image.origin_x_in, image.origin_y_in, 1.0 / image.inches_per_pixel
    last_row, last_col = vision_map.free.shape[0] - 1, vision_map.free.shape[1] - 1

    def is_valid(state: Any) -> bool:
        col = min(int((state[0] - x0) * inv), last_col)
        row = min(int((y1 - state[1]) * inv), last_row)
        return bool(holder[0][row, col])

    return is_valid


def numpy_cells(grid: np.ndarray) -> np.ndarray:
    """Before, the planner held the numpy grid itself."""
    return grid


def detour(vision_map: VisionMap, seed: int) -> tuple[Pose, Pose]:
    """A start and goal in one free component with no straight line between them."""
    rng = np.random.default_rng(seed)
    free = np.argwhere(vision_map.free_strict)
    while True:
        a, b = free[rng.integers(len(free))], free[rng.integers(len(free))]
        pa, pb = vision_map.image.to_world(a[0], a[1])[0], vision_map.image.to_world(b[0], b[1])[0]
        start, goal = Pose(float(pa[0]), float(pa[1]), 0.0), Pose(float(pb[0]), float(pb[1]), 0.0)
        if not vision_map.segment_is_free((start.x_in, start.y_in), (goal.x_in, goal.y_in)):
            plan = PathPlanner(vision_map, roadmap_milestones=1).plan(start, goal)
            if plan.found:
                return start, goal


def first_query(vision_map: VisionMap, start: Pose, goal: Pose) -> tuple[float, PlanResult, Roadmap]:
    planner = PathPlanner(vision_map)
    began = time.perf_counter()
    plan = planner.plan(start, goal)
    elapsed = time.perf_counter() - began
    assert planner.roadmap is not None and plan.planner == paths.ROADMAP, plan
    return elapsed, plan, planner.roadmap


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    hero = SimulatedHero(seed=args.seed)
    navigator = Navigator(load_profile().robot)
    navigator.observe(hero.camera().result())
    vision_map = navigator.vision_map
    start, goal = detour(vision_map, args.seed)

    ours = paths._validity_checker, paths._cells
    times: dict[str, list[float]] = {"before": [], "after": []}
    answers: dict[str, tuple[PlanResult, Roadmap]] = {}
    for _ in range(args.repeat):
        for name, (checker, cells) in (("before", (reference_checker, numpy_cells)), ("after", ours)):
            paths._validity_checker, paths._cells = checker, cells
            try:
                elapsed, plan, roadmap = first_query(vision_map, start, goal)
            finally:
                paths._validity_checker, paths._cells = ours
            times[name].append(elapsed)
            answers[name] = (plan, roadmap)
    (plan_a, map_a), (plan_b, map_b) = answers["before"], answers["after"]
    same = (plan_a == plan_b and np.array_equal(map_a.points, map_b.points) and map_a.neighbours == map_b.neighbours)
    before, after = statistics.median(times["before"]) * 1e3, statistics.median(times["after"]) * 1e3

    grown = []
    original = Roadmap.grow.__func__

    def counting(cls, setup, milestones, max_s):  # noqa: ANN001, ANN202
        grown.append(1)
        return original(cls, setup, milestones, max_s)

    Roadmap.grow = classmethod(counting)
    try:
        nav = Navigator(load_profile().robot)
        for _ in range(3):  # the same world seen three times (the robot is not an obstacle)
            nav.observe(hero.camera().result())
            nav.plan(start, goal)
    finally:
        Roadmap.grow = classmethod(original)

    print(f"{datetime.date.today()} {platform.machine()} python {platform.python_version()}, lab seed {args.seed}, "
          f"repeat {args.repeat}, {len(map_b)} milestones")
    print("| first query on a new map (grows the roadmap) | median | ratio | same roadmap and path |")
    print("|---|---:|---:|---|")
    print(f"| validity checker before (numpy grid, `min` clamps) | {before:.0f} ms | 1.00 | |")
    print(f"| validity checker now (byte grid) | {after:.0f} ms | **{before / after:.2f}x** | "
          f"{'yes' if same else 'NO'} |")
    print(f"roadmaps a Navigator grew for 3 looks at one world, each followed by the same detour query: "
          f"{len(grown)}")


if __name__ == "__main__":
    main()

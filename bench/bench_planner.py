"""Planner benchmarks on the simulator's default lab, side by side in one run.

    python bench/bench_planner.py [--queries 200] [--moves 60] [--seed 0]

1. Plan time: the default planner (straight line when clear, else PRM on the map's
   kept roadmap, RRT-Connect as fallback; with simplification) between random free,
   mutually reachable base positions on the lab's vision map; plans are not cached.
   The first query that needs OMPL grows the roadmap and is reported on its own.
2. Path length: each plan's length against the true shortest path on the same
   inflated grid (8-connected Dijkstra, √2 diagonals). An any-angle path may beat the
   grid path, so ratios below 1 are expected.
3. Move-cost error: the robot drives to learner positions (6/16/24 in, 0/90/180/270°
   of random objects) in the simulated lab; the estimate mode's and the exact mode's
   prices are compared with the simulator's move durations.

Prints a Markdown table of medians (and 90th percentiles) with the machine and date;
BENCHMARKS.md keeps the figures of record.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import sys
import time
from importlib.metadata import version
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from camera_model.image import CameraImage  # noqa: E402
from hero_driver.interface import Pose as DriverPose  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402
from planner import Navigator, PathPlanner, Pose  # noqa: E402
from planner.grid_search import distance_field  # noqa: E402
from planner.move_cost import arrived  # noqa: E402
from planner.paths import STRAIGHT  # noqa: E402
from robot_profile import load_profile  # noqa: E402



def overhead(hero: SimulatedHero) -> CameraImage:
    return hero.camera().result()


def percentile(values: list[float], q: float) -> float:
    return float(np.percentile(values, q)) if values else float("nan")


def bench_plans(queries: int, seed: int) -> dict[str, list[float]]:
    """Plan times (ms) and length ratios against the grid's shortest path."""
    navigator = Navigator(load_profile().robot)
    navigator.observe(overhead(SimulatedHero(seed=seed)))
    vision_map = navigator.vision_map
    planner = PathPlanner(vision_map, cache_size=1)
    rng = np.random.default_rng(seed)
    free = np.argwhere(vision_map.free)
    times, ratios, detour_times, detour_ratios, first = [], [], [], [], []
    while len(times) < queries:
        a, b = free[rng.integers(len(free))], free[rng.integers(len(free))]
        start_xy, goal_xy = vision_map.image.to_world(a[0], a[1])[0], vision_map.image.to_world(b[0], b[1])[0]
        grid_in = distance_field(vision_map.free, (int(a[0]), int(a[1])))[b[0], b[1]] * vision_map.image.inches_per_pixel
        if not np.isfinite(grid_in) or grid_in < 1.0:
            continue
        start = Pose(float(start_xy[0]), float(start_xy[1]), float(rng.uniform(0, 360)))
        goal = Pose(float(goal_xy[0]), float(goal_xy[1]), float(rng.uniform(0, 360)))
        began = time.perf_counter()
        result = planner.plan(start, goal)
        elapsed_ms = (time.perf_counter() - began) * 1000
        if not result.found:
            raise RuntimeError(f"no path between reachable cells: {start} -> {goal}: {result.reason}")
        ratios.append(result.length_in / grid_in)
        if result.planner == STRAIGHT:
            times.append(elapsed_ms)
            continue
        detour_ratios.append(result.length_in / grid_in)
        if not first:
            first.append(elapsed_ms)  # grows the roadmap: once per map
            continue
        times.append(elapsed_ms)
        detour_times.append(elapsed_ms)
    return {"times": times, "ratios": ratios, "detour_times": detour_times, "detour_ratios": detour_ratios,
            "first": first}


def bench_move_costs(moves: int, seed: int) -> dict[str, list[float]]:
    """Relative errors of the estimate and exact prices against simulated durations."""
    hero = SimulatedHero(seed=seed)
    navigator = Navigator(load_profile().robot)
    regions = navigator.observe(overhead(hero)).regions
    rng = np.random.default_rng(seed)
    estimate_errors, exact_errors, first_ms, further_ms = [], [], [], []
    attempts = 0
    while len(exact_errors) < moves and attempts < 10 * moves:
        attempts += 1
        region = regions[rng.integers(len(regions))]
        distance = float(rng.choice([6.0, 16.0, 24.0]))
        orientation = float(rng.choice([0.0, 90.0, 180.0, 270.0]))
        state = hero.state().pose
        start = Pose(state.x_in, state.y_in, state.heading_deg)
        goal = navigator.pose_for(region, distance, orientation)
        plan = navigator.plan(start, goal)
        if not plan.found or arrived(start, goal):
            continue
        began = time.perf_counter()
        estimate = navigator.move_cost(start, goal)
        first_ms.append((time.perf_counter() - began) * 1000)
        # The learner prices every candidate position from the same start.
        candidates = [navigator.pose_for(r, d, o) for r in regions for d in (6.0, 16.0, 24.0)
                      for o in (0.0, 90.0, 180.0, 270.0)]
        began = time.perf_counter()
        for candidate in candidates:
            navigator.move_cost(start, candidate)
        further_ms.append((time.perf_counter() - began) * 1000 / len(candidates))
        exact = navigator.move_cost(start, goal, exact=True)
        waypoints = [DriverPose(w.x_in, w.y_in, w.heading_deg) for w in plan.path]
        actual = hero.move(waypoints, face=region.centroid).result().duration_s
        estimate_errors.append(abs(estimate.seconds - actual) / actual)
        exact_errors.append(abs(exact.seconds - actual) / actual)
        navigator.observe(overhead(hero))
    return {"estimate": estimate_errors, "exact": exact_errors, "first_ms": first_ms, "further_ms": further_ms}


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as handle:
            cpu = next(line.split(":", 1)[1].strip() for line in handle if line.startswith("model name"))
    except (OSError, StopIteration):
        pass  # not Linux: keep the platform module's name for the processor
    return (f"{cpu} ({os.cpu_count()} CPUs), Python {platform.python_version()}, OMPL {version('ompl')}, "
            f"OpenCV {version('opencv-python-headless')}, {platform.system()}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--queries", type=int, default=200)
    parser.add_argument("--moves", type=int, default=60)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    plans = bench_plans(args.queries, args.seed)
    costs = bench_move_costs(args.moves, args.seed)
    rows = [
        ("plan time, all queries (ms)", plans["times"], "< 20"),
        ("plan time, queries needing OMPL (ms)", plans["detour_times"], "< 20"),
        ("first OMPL query on a new map, grows the roadmap (ms)", plans["first"], "—"),
        ("path length / grid shortest, all", plans["ratios"], "≤ 1.10"),
        ("path length / grid shortest, OMPL", plans["detour_ratios"], "≤ 1.10"),
        ("move-cost estimate error vs simulator", costs["estimate"], "< 0.15"),
        ("move-cost exact error vs simulator", costs["exact"], "—"),
        ("estimate, first candidate from a new pose (ms)", costs["first_ms"], "—"),
        ("estimate, each further candidate (ms)", costs["further_ms"], "—"),
    ]
    print(f"date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    print(f"machine: {machine()}")
    print(f"command: python bench/bench_planner.py --queries {args.queries} --moves {args.moves} --seed {args.seed}")
    print()
    print("| measure | n | median | p90 | target |")
    print("|---|---:|---:|---:|---|")
    for name, values, target in rows:
        print(f"| {name} | {len(values)} | {statistics.median(values):.3f} | {percentile(values, 90):.3f} | {target} |")


if __name__ == "__main__":
    main()

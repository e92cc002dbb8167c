"""Simulator speed: simulated robot seconds per wall-clock second for a typical object
episode (camera, move to 24 in, H-Sweep-1°, move to 6 in, H-Scan-0.3 and D-Scan-0.3,
grasp, camera, release) on each object of the default lab, with default noise.

Run: ``/work/venv/bin/python bench/bench_sim.py [--rounds N]``; prints the median
speed-up over real time (the target is at least 500x). Figures of record are in BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from hero_driver.interface import DriverError  # noqa: E402
from hero_driver.sim.probe import approach_pose  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402


def episode(hero: SimulatedHero, index: int) -> tuple[float, float]:
    """One object's episode; returns (simulated seconds, wall seconds)."""
    sim = hero.world
    target = hero.truth()[index]
    face = (target.x_in, target.y_in)
    start_clock, start_wall = hero.state().clock_s, time.perf_counter()
    steps = [
        lambda: hero.camera(),
        lambda: hero.move([approach_pose(sim, index, 24.0, 180.0)], face=face),
        lambda: hero.sense("H-Sweep-1°"),
        lambda: hero.move([approach_pose(sim, index, 6.0, 180.0)], face=face),
        lambda: hero.sense("H-Scan-0.3"),
        lambda: hero.sense("D-Scan-0.3"),
        lambda: hero.grasp(target.grasps[0].procedure),
        lambda: hero.camera(),
        lambda: hero.release(),
    ]
    for step in steps:
        error = step().exception()
        if error is not None and not isinstance(error, DriverError):
            raise error
    return hero.state().clock_s - start_clock, time.perf_counter() - start_wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=20, help="lab resets (each runs every object)")
    args = parser.parse_args()
    hero = SimulatedHero(seed=0)
    ratios, sim_total, wall_total = [], 0.0, 0.0
    for r in range(args.rounds):
        hero.reset(seed=r).result()
        for index in range(len(hero.truth())):
            sim_s, wall_s = episode(hero, index)
            ratios.append(sim_s / wall_s)
            sim_total, wall_total = sim_total + sim_s, wall_total + wall_s
    print(f"episodes: {len(ratios)}  simulated: {sim_total:.0f} s  wall: {wall_total:.3f} s")
    print(f"median speed-up: {statistics.median(ratios):.0f}x real time "
          f"(min {min(ratios):.0f}x, max {max(ratios):.0f}x)")


if __name__ == "__main__":
    main()

"""Exploration alone: how long the robot takes to map a home from its own scans, and what it leaves.

Each run is one onboard episode of the whole executive on the in-process simulator,
stopped when the exploration branch ends (its ``mapped`` event: no frontier worth a trip
is left, or the bound on views was spent). Measured against the simulator's truth:

- views (scans read by the exploration, the looks between legs included) and the
  exploration's robot minutes (the ``mapped`` event's seconds), and why it ended;
- the map, as ``experiments.onboard_truth.map_accuracy`` reads it (``bench_onboard.py``
  and the onboard study do the same): IoU of occupied cells, surface IoU, the share of
  the home's free floor known free; and the largest localisation error over the scans
  (``experiments.onboard_truth.localisation``), which the map's accuracy turns on;
- the objects the exploration left a candidate for: a true object with a candidate
  within ``reporting.report.FOUND_WITHIN_IN`` of its centre (the study's "found"
  reads the records of handled objects; exploration alone has none, and an object
  with no candidate after the exploration is one the robot will not approach); and the
  false candidates, near no object (each would cost the executive an approach).

``--trace`` prints each exploration choice (robot, frontier size, its middle and the
viewing pose), to see which frontiers are chased and how often.

    python bench/bench_exploration.py [--homes apartment,apartment-2] [--presets clean,paper]
                                      [--seeds 2] [--jobs 1] [--trace]
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from executive.defaults import EXAMPLE_LIBRARY  # noqa: E402
from executive.executive import ONBOARD, Executive  # noqa: E402
from experiments.conditions import noise_config  # noqa: E402
from experiments.onboard_truth import TruthAtScans, localisation  # noqa: E402
from experiments.study_onboard import built_map_accuracy, explore_until_mapped  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from mapping import ExplorationGoal, ExplorationSettings, OccupancyGrid  # noqa: E402
from mapping.candidates import Candidate  # noqa: E402
from mapping.exploration import MoveCost  # noqa: E402
from planner.geometry import Pose  # noqa: E402
from learner.service.local import LocalLearner  # noqa: E402
from reporting.report import FOUND_WITHIN_IN  # noqa: E402
from robot_profile import load_profile  # noqa: E402
from home_args import add_home_arguments, home_presets  # noqa: E402

@dataclass(frozen=True)
class Explored:
    world: str
    preset: str
    seed: int
    views: int
    explore_min: float
    reason: str
    iou: float
    surface_iou: float
    coverage: float
    located_max_in: float
    present: int
    with_candidate: int
    false_candidates: int
    wall_s: float
    trace: tuple[str, ...]


def explore(world: str, preset: str, seed: int, trace: bool = False) -> Explored:
    """One explore-only episode, measured (the module docstring); ``trace``: note each
    exploration choice (the executive's perception asks ``exploration_goals``, wrapped here)."""
    import executive.onboard as onboard
    import mapping.exploration

    profile = load_profile()
    hero = TruthAtScans("bench", world=world, seed=seed, profile=profile, noise=noise_config(preset))
    spec, catalogue, start = hero.world.spec, hero.world.catalogue, hero.world.pose
    lines: list[str] = []
    if trace:
        chosen = mapping.exploration.exploration_goals

        def traced(grid: OccupancyGrid, robot: Pose, candidates: Sequence[Candidate], cost: MoveCost,
                   settings: ExplorationSettings) -> list[ExplorationGoal]:
            goals = chosen(grid, robot, candidates, cost, settings)
            first = (f"size {goals[0].frontier.size} middle ({goals[0].target_x_in:.0f}, {goals[0].target_y_in:.0f}) "
                     f"view ({goals[0].pose.x_in:.0f}, {goals[0].pose.y_in:.0f}) cost {goals[0].cost_s:.0f} s"
                     if goals else "none")
            lines.append(f"robot ({robot.x_in:.0f}, {robot.y_in:.0f}) goals {len(goals)}: {first}")
            return goals
        onboard.exploration_goals = traced  # type: ignore[assignment]
    with tempfile.TemporaryDirectory(prefix="csl-explore-") as tmp:
        learner = LocalLearner(Path(tmp) / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
        executive = Executive(hero, learner, profile=profile, perception=ONBOARD)
        began = time.perf_counter()
        events = explore_until_mapped(executive, learner)
        wall_s = time.perf_counter() - began
    mapped = next(e for e in events if e["event"] == "mapped")
    perception = executive.perception
    assert perception is not None and perception.grid is not None
    grid = perception.grid
    accuracy = built_map_accuracy(grid, spec, catalogue, (start.x_in, start.y_in))
    located = localisation(perception.poses, hero.true_at)
    candidates = perception.finder.candidates(grid)
    objects = hero.truth()
    covered = sum(1 for o in objects
                  if any(math.hypot(c.x_in - o.x_in, c.y_in - o.y_in) <= FOUND_WITHIN_IN for c in candidates))
    false = sum(1 for c in candidates
                if all(math.hypot(c.x_in - o.x_in, c.y_in - o.y_in) > FOUND_WITHIN_IN for o in objects))
    hero.close()
    return Explored(world, preset, seed, int(mapped["views"]), float(mapped["seconds"]) / 60.0, str(mapped["reason"]),
                    accuracy.iou, accuracy.surface_iou, accuracy.coverage,
                    max(located.corrected.position_in) if located is not None else math.nan, len(objects), covered,
                    false, wall_s, tuple(lines))


def _run(job: tuple[str, str, int, bool]) -> Explored:
    return explore(*job)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_home_arguments(parser, presets="clean,paper")
    parser.add_argument("--trace", action="store_true", help="print each exploration choice")
    args = parser.parse_args(argv)
    presets = home_presets(args, "bench_exploration")
    if presets is None:
        return 2
    jobs = [(w, p, s, args.trace) for w in args.homes.split(",") for p in presets for s in range(args.seeds)]
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        done = list(pool.map(_run, jobs))
    print("| home | preset | seed | views | exploration min | ended | IoU | surface IoU | free floor known "
          "| localisation max in | objects with a candidate | false candidates | wall s |")
    print("|---|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for e in done:
        print(f"| {e.world} | {e.preset} | {e.seed} | {e.views} | {e.explore_min:.1f} | {e.reason} | {e.iou:.3f} "
              f"| {e.surface_iou:.3f} | {e.coverage:.3f} | {e.located_max_in:.1f} | {e.with_candidate}/{e.present} "
              f"| {e.false_candidates} | {e.wall_s:.0f} |")
    for e in done:
        if e.trace:
            print(f"\n{e.world} {e.preset} {e.seed}:")
            print("\n".join(e.trace))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

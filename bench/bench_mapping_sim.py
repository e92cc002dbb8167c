"""The mapping stack on the simulated apartments: map accuracy and localisation error.

The robot drives a survey route through every room of a home (planned on the home's
true occupancy, so the route is the same for every noise preset: what is measured is
the mapping, not the exploration), stopping every ``--step`` inches to take a lidar
scan (the driver's ``scan`` verb, ray cast in pymunk from the true pose, stamped with
the drifting odometry's). Each scan goes to ``mapping.ScanMatcher``, which corrects the
pose, and to ``mapping.OccupancyGrid`` at the corrected pose. The robot is driven in a
closed loop as a real one would be: each waypoint is turned into the odometry's frame
by the latest correction before it is sent.

Reported per home and noise preset:

- localisation error (corrected pose against the simulator's true pose): final, mean,
  max, in inches and degrees; beside it the raw odometry's;
- map accuracy against the true scan-plane map (walls, furniture, table legs, objects),
  two ways: ``IoU`` of occupied cells as they are (the robot never sees the inside of a
  wall or its far side, so a perfect robot scores below 1), and ``surface IoU``: the
  true cells a robot can see (occupied cells beside a free cell) against the built ones,
  each counted as matched when the other grid has an occupied cell within one cell;
- the share of the truly free floor the grid knows to be free (coverage);
- wall time per scan (matching and integrating).

Then the goals for the map, checked per home, one line each and a non-zero exit
when one is missed: under ``clean`` (exact odometry) the matcher's largest error is
within :data:`CLEAN_TOLERANCE_IN` of the odometry's on every seed (it must not move a
pose the odometry had right), and under ``paper`` the median surface IoU is at least
:data:`experiments.study_onboard.GOAL_SURFACE_IOU`. The measures are
``experiments.onboard_truth``'s, as ``csl experiment onboard`` takes them.

Writes ``map-<home>-<preset>-<seed>.png`` (the built map beside the truth, the survey route on it:
``reporting.built_map``, as ``csl demo --perception onboard`` draws its map.png) under ``--out``.

    python bench/bench_mapping_sim.py [--homes apartment,apartment-2] [--presets clean,paper,harsh]
                                      [--seeds 3] [--step 24] [--resolution 2] [--out /tmp/csl-mapping]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from scipy import ndimage

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.onboard import planar_scan  # noqa: E402
from experiments.onboard_truth import Localisation, MapAccuracy, localisation, map_accuracy  # noqa: E402
from experiments.study_onboard import GOAL_SURFACE_IOU  # noqa: E402
from hero_driver.interface import Pose  # noqa: E402
from hero_driver.sim.catalogue import profile_and_catalogue  # noqa: E402
from hero_driver.sim.noise import NOISE_PRESETS  # noqa: E402
from hero_driver.sim.truth_map import TruthMap, truth_map  # noqa: E402
from hero_driver.sim.world import SimWorld  # noqa: E402
from hero_driver.sim.worldfile import WorldSpec, load_world  # noqa: E402
from mapping import OccupancyGrid, ScanMatcher  # noqa: E402
from planner.geometry import Pose as PlannerPose  # noqa: E402
from reporting.built_map import plot_built_map  # noqa: E402

MARGIN_IN = 4.0  # clearance kept beyond the base's radius on the survey route
CLEAN_TOLERANCE_IN = 0.25  # under clean, the matcher's largest error beyond the exact odometry's


@dataclass(frozen=True)
class Outcome:
    """One survey: where the robot thought it was against the truth, the map it built,
    and the matching's and integrating's wall time per scan."""

    located: Localisation
    map: MapAccuracy
    ms_per_scan: float


def survey_route(home: WorldSpec, truth: TruthMap, start: tuple[float, float], radius_in: float,
                 step_in: float) -> list[tuple[float, float]]:
    """Waypoints every ``step_in`` along shortest grid paths (8-connected, on the true
    footprint map inflated by the base) from the start through every room's most open
    point, nearest room first; the route the robot drives in every preset."""
    blocked = ndimage.binary_dilation(truth.occupied, iterations=math.ceil((radius_in + MARGIN_IN) / truth.resolution_in))
    clearance = ndimage.distance_transform_edt(~blocked)
    goals = []
    for room in home.home.rooms:
        drawn = np.zeros(blocked.shape, dtype=np.uint8)  # the room on the grid: (col, row) of each corner
        corners = [((x - truth.x0_in) / truth.resolution_in - 0.5, (y - truth.y0_in) / truth.resolution_in - 0.5)
                   for x, y in room.outline]
        cv2.fillPoly(drawn, [np.round(np.asarray(corners)).astype(np.int32)], 1)
        inside = drawn.astype(bool) & ~blocked
        if inside.any():
            best = np.unravel_index(np.argmax(np.where(inside, clearance, -1.0)), blocked.shape)
            goals.append((int(best[0]), int(best[1])))
    here = truth.cell_of(*start)
    route: list[tuple[float, float]] = []
    while goals:
        paths = {g: _path(blocked, here, g) for g in goals}
        reachable = {g: p for g, p in paths.items() if p}
        if not reachable:
            break
        goal = min(reachable, key=lambda g: len(reachable[g]))
        path = reachable[goal]
        every = max(1, round(step_in / truth.resolution_in))
        route += [truth.centre(*cell) for cell in path[every::every]] + [truth.centre(*goal)]
        here = goal
        goals.remove(goal)
    return route


def _path(blocked: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> list[tuple[int, int]]:
    """Breadth-first 8-connected path of free cells (start first); empty when none."""
    rows, cols = blocked.shape
    came: dict[tuple[int, int], tuple[int, int] | None] = {start: None}
    queue = deque([start])
    while queue:
        cell = queue.popleft()
        if cell == goal:
            out = []
            at: tuple[int, int] | None = cell
            while at is not None:
                out.append(at)
                at = came[at]
            return out[::-1]
        r, c = cell
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                n = (r + dr, c + dc)
                if (dr or dc) and 0 <= n[0] < rows and 0 <= n[1] < cols and not blocked[n] and n not in came:
                    came[n] = cell
                    queue.append(n)
    return []


def to_odometry(target: tuple[float, float], corrected: PlannerPose, reported: Pose) -> Pose:
    """A world point in the odometry's frame, by the latest correction (the transform
    taking the corrected pose to the reported one)."""
    turn = math.radians(reported.heading_deg - corrected.heading_deg)
    dx, dy = target[0] - corrected.x_in, target[1] - corrected.y_in
    x = reported.x_in + dx * math.cos(turn) - dy * math.sin(turn)
    y = reported.y_in + dx * math.sin(turn) + dy * math.cos(turn)
    return Pose(x, y, reported.heading_deg)


def run(home_name: str, preset: str, seed: int, step_in: float, resolution_in: float,
        out: Path | None) -> Outcome:
    profile, catalogue = profile_and_catalogue(None)
    home = load_world(home_name, catalogue)
    truth = truth_map(home, catalogue, resolution_in, objects=True)
    footprint = truth_map(home, catalogue, resolution_in, layer="footprint", objects=True)
    sim = SimWorld(home, seed, profile, NOISE_PRESETS[preset])
    x0, y0, x1, y1 = truth.extent
    grid, matcher = OccupancyGrid(x0, y0, x1, y1, resolution_in), ScanMatcher()
    start = sim.pose
    route = survey_route(home, footprint, (start.x_in, start.y_in), profile.robot.geometry.base_radius_in, step_in)
    poses: list[tuple[float, PlannerPose, PlannerPose]] = []  # (clock, reported, corrected) of each scan
    true_at: dict[float, PlannerPose] = {}
    took: list[float] = []

    def look() -> tuple[PlannerPose, Pose]:
        scan = sim.scan()
        began = time.perf_counter()
        seen = planar_scan(scan)
        correction = matcher.update(seen)
        grid.integrate(seen, correction.pose)
        took.append(time.perf_counter() - began)
        reported = PlannerPose(scan.pose.x_in, scan.pose.y_in, scan.pose.heading_deg)
        poses.append((scan.clock_s, reported, correction.pose))
        true_at[scan.clock_s] = PlannerPose(sim.pose.x_in, sim.pose.y_in, sim.pose.heading_deg)
        return correction.pose, scan.pose

    corrected, reported = look()
    for target in route:
        sim.move([to_odometry(target, corrected, reported)], None)
        corrected, reported = look()
    located = localisation(poses, true_at)
    assert located is not None  # every scan's truth was noted
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        plot_built_map(out / f"map-{home_name}-{preset}-{seed}.png", grid, truth,
                       route=[(c.x_in, c.y_in) for _, _, c in poses],
                       title=f"{home_name} under {preset}, seed {seed}: the map from {len(poses)} scans")
    return Outcome(located, map_accuracy(grid, truth, footprint, (start.x_in, start.y_in)),
                   1000 * statistics.median(took))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--homes", default="apartment,apartment-2")
    parser.add_argument("--presets", default="clean,paper,harsh")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--step", type=float, default=24.0, help="inches between scans (default 24)")
    parser.add_argument("--resolution", type=float, default=2.0, help="inches per cell (default 2)")
    parser.add_argument("--out", type=Path, default=None, help="folder for the map PNGs (default: none)")
    args = parser.parse_args(argv)
    print("| home | preset | seeds | final in (odometry) | mean in | max in | final deg | IoU | surface IoU | "
          "free floor known | ms/scan |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    goals: list[tuple[bool, str]] = []
    for home in args.homes.split(","):
        for preset in args.presets.split(","):
            runs = [run(home, preset, seed, args.step, args.resolution, args.out) for seed in range(args.seeds)]

            def med(measure: Callable[[Outcome], float]) -> float:
                return statistics.median(measure(r) for r in runs)
            print(f"| {home} | {preset} | {len(runs)} | {med(lambda r: r.located.corrected.final_in):.1f} "
                  f"({med(lambda r: r.located.odometry.final_in):.1f}) | "
                  f"{med(lambda r: r.located.corrected.mean_in):.1f} | "
                  f"{med(lambda r: r.located.corrected.max_in):.1f} | "
                  f"{med(lambda r: r.located.corrected.final_deg):.2f} | {med(lambda r: r.map.iou):.2f} | "
                  f"{med(lambda r: r.map.surface_iou):.2f} | {med(lambda r: r.map.coverage):.0%} | "
                  f"{med(lambda r: r.ms_per_scan):.1f} |", flush=True)
            if preset == "clean":
                beyond = max(r.located.corrected.max_in - r.located.odometry.max_in for r in runs)
                goals.append((beyond <= CLEAN_TOLERANCE_IN,
                              f"{home} clean: the matcher's largest error is {beyond:.2f} in beyond the exact "
                              f"odometry's (at most {CLEAN_TOLERANCE_IN} in)"))
            if preset == "paper":
                surface = med(lambda r: r.map.surface_iou)
                goals.append((surface >= GOAL_SURFACE_IOU,
                              f"{home} paper: surface IoU {surface:.3f} (at least {GOAL_SURFACE_IOU})"))
    return report_goals(goals)


def report_goals(goals: list[tuple[bool, str]]) -> int:
    """Print one line per goal, met or MISSED; the exit status: 0 when every one was met."""
    print()
    for met, line in goals:
        print(f"goal {'met' if met else 'MISSED'}: {line}")
    return 0 if all(met for met, _ in goals) else 1


if __name__ == "__main__":
    raise SystemExit(main())

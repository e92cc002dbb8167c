"""How well an object's outline from scans gives its training orientations (mapping/outline.py).

    python bench/bench_outline.py [--trials 24] [--sigmas 0.25,0.5] [--scans 1,8] [--views 1,2,3,4,6]

Each catalogue-sized object stands alone in a 120 in room (tests/mapping/synthetic.py's
ray caster; a 360-beam range finder, 1° apart, 10 % of the beams lost, Gaussian range
noise sigma in inches). The survey's views (``--views`` evenly round it at 24 in, facing
it, the first on its +x side) each scan it ``--scans`` times; the object's yaw is drawn
uniformly, one seed per trial. Reported per (object, sigma, scans, views): the worst and
RMS error of the outline's face orientations against the true ones (boxes), the share
of outlines with every face seen (complete), the share called round, and the share
refused (ValueError: too few returns). ``--trials`` trials each.
"""

from __future__ import annotations

import argparse
import datetime
import math
import platform
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from learner.training.stage import face_normals  # noqa: E402
from mapping.outline import outline, survey_plan  # noqa: E402
from mapping.scan import PlanarScan  # noqa: E402
from tests.mapping.synthetic import Lidar, circle, rect, scene, square_room  # noqa: E402

CENTRE = (60.0, 60.0)
OBJECTS = {  # name: (kind, length, width) — catalogue footprints
    "box 9 x 4": ("rect", 9.0, 4.0),
    "box 11 x 9": ("rect", 11.0, 9.0),
    "box 5 x 4": ("rect", 5.0, 4.0),
    "box 2 x 2": ("rect", 2.0, 2.0),
    "can 2.6": ("disc", 1.3, 0.0),
    "can 3.5": ("disc", 1.75, 0.0),
}


def trial(kind: str, a: float, b: float, sigma: float, scans: int, views: int, seed: int) -> tuple[float, bool, bool]:
    """(worst face error in degrees or NaN, complete, round); raises ValueError if refused."""
    rng = np.random.default_rng(seed)
    yaw = float(rng.uniform(0.0, 360.0))
    shape = rect(*CENTRE, a, b, yaw) if kind == "rect" else circle(*CENTRE, a, sides=90)
    world = scene([tuple(w) for w in square_room(120.0)], shape)
    lidar = Lidar(sigma_in=sigma, dropout=0.1)
    taken = []
    for pose in survey_plan(CENTRE, views=views):
        for _ in range(scans):
            ranges = lidar.scan(world, (pose.x_in, pose.y_in, math.radians(pose.heading_deg)), rng)
            taken.append((PlanarScan(lidar.angles_rad, ranges, pose.x_in, pose.y_in, pose.heading_deg, 0.0,
                                     lidar.max_range_in), pose))
    found = outline(taken, CENTRE, sigma)
    error = math.nan
    if kind == "rect" and not found.round:
        truths = [(yaw + 90.0 * k) % 360.0 for k in range(4)]
        error = max(min(abs((n - t + 180.0) % 360.0 - 180.0) for t in truths) for n, _ in face_normals(found.polygon))
    return error, found.complete, found.round


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=24)
    parser.add_argument("--sigmas", default="0.25,0.5")
    parser.add_argument("--scans", default="1,8")
    parser.add_argument("--views", default="1,2,3,4,6")
    args = parser.parse_args()
    sigmas = [float(s) for s in args.sigmas.split(",")]
    scans_list = [int(s) for s in args.scans.split(",")]
    views_list = [int(v) for v in args.views.split(",")]
    print(f"date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}")
    print(f"command: python bench/bench_outline.py --trials {args.trials} --sigmas {args.sigmas} "
          f"--scans {args.scans} --views {args.views}")
    print()
    print("| object | sigma in | scans / view | views | worst ° | RMS ° | complete | round | refused |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, (kind, a, b) in OBJECTS.items():
        for sigma in sigmas:
            for scans in scans_list:
                for views in views_list:
                    errors, complete, round_, refused = [], 0, 0, 0
                    for seed in range(args.trials):
                        try:
                            error, whole, is_round = trial(kind, a, b, sigma, scans, views, seed)
                        except ValueError:
                            refused += 1
                            continue
                        complete += whole
                        round_ += is_round
                        if not math.isnan(error):
                            errors.append(error)
                    worst = f"{max(errors):.1f}" if errors else "—"
                    rms = f"{math.sqrt(np.mean(np.square(errors))):.2f}" if errors else "—"
                    n = args.trials
                    print(f"| {name} | {sigma:g} | {scans} | {views} | {worst} | {rms} | {complete / n:.0%} | "
                          f"{round_ / n:.0%} | {refused / n:.0%} |")


if __name__ == "__main__":
    main()

"""Vision when the room changed after calibration: each scene-change preset of the
simulator's realistic camera read through a calibration made on the plain room.

The camera is calibrated on the shipped lab through the plain ``realistic`` preset
(tests/planner/vision_truth.py's ``lab_camera``: the objects and the robot on the floor
and painted out of the empty floor). Then the lab at several poses (each object shifted
up to 6 in and turned; the robot parked elsewhere each time) is photographed through
each preset (``realistic`` itself, then ``realistic-lamp``, ``-shadow``, ``-floor``,
``-exposure``: docs/camera.md, "When the room changes") and looked at. A look either
gives regions, or stops with the scene-change line (:class:`planner.scene_check.SceneChanged`).

Columns: poses stopped by the scene-change check, objects found (a region within 6 in)
of those on the poses read, phantom regions (regions near no object) per pose read, and
the localisation error of the objects found (mean and max, inches); then the check's
two measures on the first pose (share of the floor unlike the calibration's, regions).

    python bench/bench_scene_change.py [--poses 4]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hero_driver.sim.camera import PRESETS  # noqa: E402
from planner.scene_check import SceneChanged  # noqa: E402
from planner.segmentation import segment  # noqa: E402
from planner.vision import look  # noqa: E402
from tests.planner.vision_truth import MATCH_IN, lab_at, lab_camera, overhead  # noqa: E402

REALISTIC = tuple(p for p in PRESETS if p.startswith("realistic"))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=4, help="lab poses per preset (default 4)")
    args = parser.parse_args()
    camera = lab_camera()
    print("| preset | stopped | found | phantoms / pose | loc mean in | loc max in | unlike floor | regions |")
    print("|---|---|---|---|---|---|---|---|")
    for preset in REALISTIC:
        stopped, found, objects, phantoms, errors = 0, 0, 0, 0, []
        first = None
        for pose in range(args.poses):
            sim = lab_at(pose)
            image = overhead(sim, preset)
            if first is None:
                flat = camera.calibration.rectify(image.pixels)
                first = segment(flat, camera.empty_floor, check=False).scene
            try:
                scene = look(image, camera)
            except SceneChanged:
                stopped += 1
                continue
            near = set()
            for obj in sim.physics.objects:
                objects += 1
                dist = [math.hypot(r.centroid[0] - obj.x_in, r.centroid[1] - obj.y_in) for r in scene.regions]
                if dist and min(dist) < MATCH_IN:
                    found += 1
                    errors.append(min(dist))
                    near.add(dist.index(min(dist)))
            phantoms += sum(1 for i, r in enumerate(scene.regions) if i not in near and all(
                math.hypot(r.centroid[0] - o.x_in, r.centroid[1] - o.y_in) >= MATCH_IN for o in sim.physics.objects))
        read = args.poses - stopped
        loc = f"{statistics.mean(errors):.2f} | {max(errors):.2f}" if errors else "– | –"
        print(f"| {preset} | {stopped}/{args.poses} | {found}/{objects} | "
              f"{f'{phantoms / read:.1f}' if read else '–'} | {loc} | "
              f"{100 * first.unlike_share:.1f} % | {first.regions} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Vision error by camera preset: how far from the truth vision puts each lab object.

The built-in lab's 7 test objects at several poses (each shifted up to 6 in and turned
by 37° per pose; the robot parked elsewhere each time, once right at an object), each
pose photographed through every camera preset and looked at. ``simple`` is read by its
grey bands; ``realistic`` through a calibration made from the first pose's image (the
marker board, the objects left on the floor and painted out of the empty floor). The
measurement is tests/planner/vision_truth.py's, shared with the test that bounds it.

Columns: localisation error (region centroid to object centre, inches), orientation
error (major axis modulo the footprint's symmetry, degrees; objects of 25 pixels or
more: smaller ones show no usable axis), the largest change of one object's pixel count
between poses (the side-effect check calls > 0.25 "changed"), measured area over true
area, and vision time per image.

    python bench/bench_vision.py [--poses 8]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hero_driver.sim.catalogue import profile_and_catalogue  # noqa: E402
from planner.vision import look  # noqa: E402
from tests.planner.vision_truth import Seen, lab_at, lab_camera, overhead, pixel_spread, seen  # noqa: E402

PRESETS = ("simple", "realistic")
AXIS_MIN_PIXELS = 25


def true_area(entry_id: str) -> float:
    fp = profile_and_catalogue()[1][entry_id].footprint
    return math.pi * fp.radius_in ** 2 if fp.shape == "circle" else fp.length_in * fp.width_in


def row(preset: str, results: list[Seen], ipp: float, seconds: list[float]) -> str:
    found = [s for s in results if s.found]
    loc = [s.location_error_in for s in found]
    ori = [s.orientation_error_deg for s in found
           if s.orientation_error_deg is not None and s.pixel_count >= AXIS_MIN_PIXELS]
    area = [s.pixel_count * ipp * ipp / true_area(s.entry_id) for s in found]
    spread = pixel_spread(results)
    return (f"| {preset} | {len(found)}/{len(results)} | {statistics.mean(loc):.2f} | "
            f"{sorted(loc)[int(0.95 * (len(loc) - 1))]:.2f} | {max(loc):.2f} | {statistics.mean(ori):.1f} | "
            f"{max(ori):.1f} | {max(spread.values()):.2f} | {min(area):.2f}–{max(area):.2f} | "
            f"{1000 * statistics.median(seconds):.0f} |")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=8, help="lab poses per preset (default 8)")
    args = parser.parse_args()
    camera = lab_camera()
    print(f"calibration: {camera.calibration.markers_seen} markers, reprojection error "
          f"{camera.calibration.error_in:.2f} in RMS")
    print("| preset | found | loc mean in | loc p95 in | loc max in | orient mean ° | orient max ° | "
          "max pixel-count change | area / true | ms / image |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for preset in PRESETS:
        results: list[Seen] = []
        seconds: list[float] = []
        ipp = 0.0
        for pose in range(args.poses):
            sim = lab_at(pose)
            image = overhead(sim, preset)
            start = time.perf_counter()
            scene = look(image, camera if preset == "realistic" else None)
            seconds.append(time.perf_counter() - start)
            ipp = scene.image.inches_per_pixel
            results.extend(seen(sim, preset, pose, camera))
        print(row(preset, results, ipp, seconds))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

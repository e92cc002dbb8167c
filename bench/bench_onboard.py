"""Onboard episodes: the robot without a ceiling camera, measured against the simulator's truth.

Each episode is the whole executive (``Executive(..., perception="onboard")``) on the
in-process simulator: the exploration branch maps the home from the robot's own scans,
then every candidate found is handled by CSL as in the lab. Measured per episode:

- objects present; found: true objects with an object record whose first region's
  centroid lies within ``reporting.report.FOUND_WITHIN_IN`` of the object's centre
  (``found_truth``: the record is matched to the truth nearest it, ``reporting.report.match_truth``, as every report of
  the project does); handled right: found objects whose record the report judges
  correct (``reporting.report.rows``); false: records matching no object (nearer than
  the tolerance to none) or a second record of an object already found;
- robot time: exploration (the ``mapped`` event's seconds), the objects' (moving,
  sensing, grasping of every record), and minutes per object two ways: the objects'
  time per object found, and everything (exploration included) per object present;
- the map: the built occupancy grid, resampled to the truth's cells, against
  ``hero_driver.sim.truth_map`` at the start (objects included): IoU of occupied cells
  as they are and the surface IoU, the same code as ``bench/bench_mapping_sim.py``;
- localisation: each scan's corrected pose (``executive.perception.poses``) against the
  simulator's true pose when the scan was taken (keyed by the scan's clock): final,
  median and largest error over the episode (inches), and the raw odometry's largest.

Beside them the ceiling-camera lab (world ``lab``, ``perception="ceiling"``, the same
library, params, preset and seeds) gives the baseline's minutes per object, and the
table shows the onboard minutes per object as a multiple of it.

Issue 35's goals, checked for each home under ``paper`` (one line each; a missed one
exits non-zero): found >= 95 % of present, handled right >= 95 % of found, robot time
per object present (exploration included) <= 1.5x the lab's, surface IoU >= 0.9.

``--explore-only`` stops each onboard episode when the home is mapped (no objects
handled, no lab baseline, no object goals): map and localisation only, much faster.

    python bench/bench_onboard.py [--homes apartment,apartment-2] [--presets paper]
                                  [--seeds 2] [--jobs 1] [--explore-only] [--leg-in 60]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from bench_mapping_sim import report_goals  # noqa: E402
from home_args import add_home_arguments, home_presets  # noqa: E402

from experiments.runner import run_all  # noqa: E402
from experiments.study import perform  # noqa: E402
from experiments.study_onboard import HEADERS, LAB, OnboardJob, goals, pooled, table_row  # noqa: E402
from experiments.table import markdown_table  # noqa: E402
from experiments.worker import install_worker  # noqa: E402
from robot_profile import load_profile  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_home_arguments(parser, presets="paper")
    parser.add_argument("--explore-only", action="store_true",
                        help="end each onboard episode when the home is mapped: map and localisation only")
    parser.add_argument("--leg-in", type=float, default=None,
                        help="override OnboardSettings.leg_in for the run (a probe; default: as shipped)")
    args = parser.parse_args(argv)
    presets = home_presets(args, "bench_onboard")
    if presets is None:
        return 2
    homes = args.homes.split(",")
    seeds = range(args.seeds)
    jobs = [OnboardJob(w, p, s, explore_only=args.explore_only, leg_in=args.leg_in)
            for w in homes + ([] if args.explore_only else [LAB]) for p in presets for s in seeds]
    done = run_all(jobs, perform, workers=args.jobs, group=lambda job: job.world, initializer=install_worker,
                   initargs=({}, load_profile()))
    rows = pooled(done, homes, presets)
    print("\n".join(markdown_table(HEADERS, (table_row(r) for r in rows))))
    print()
    print("\n".join(markdown_table(("world", "preset", "seed", "wall s"),
                                   ((j.world, j.preset, str(j.seed), f"{e.wall_s:.0f}") for j, e in done.items()))))
    return report_goals([(g.met, g.text) for g in goals(rows, objects=not args.explore_only)])


if __name__ == "__main__":
    raise SystemExit(main())

"""Robot time by evaluation function: CSL's I^2/C against cost-blind ID3 (and I/C, EG2).

The paper: cost-sensitive trees were at least 30% cheaper than standard (cost-blind)
ones, and execution took about 12 minutes per object with over 80% success. Here: the
built-in lab's 7 unseen test objects, the shipped library (trained in the simulator on
Table 3), default noise, the same seeds for every criterion, side by side.

    python bench/bench_criteria.py [--seeds 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY  # noqa: E402
from executive.executive import Executive  # noqa: E402
from reporting.report import Truth, rows  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402
from experiments.ablations import MEASURED, criterion  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.service.local import LocalLearner  # noqa: E402


def episode(name: str, seed: int) -> list:  # noqa: ANN001
    hero = SimulatedHero("bench", world="lab", seed=seed)
    start = hero.truth()
    learner = LocalLearner(Path(tempfile.mkdtemp()) / "lib.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    ex = Executive(hero, learner, criterion=criterion(name))
    result = ex.run()
    ex.shutdown()
    now = hero.truth()
    truths = [Truth(n.entry_id, tuple(g.procedure for g in n.grasps), s.x_in, s.y_in) for s, n in zip(start, now)]
    return rows(result.objects, truths)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5)
    args = ap.parse_args()
    results = {c: [r for s in range(args.seeds) for r in episode(c, s)] for c in MEASURED}
    base = statistics.mean(r.robot_s for r in results["id3"])
    print(f"lab, 7 test objects x {args.seeds} seeds per criterion")
    print("| criterion | robot min / object (mean) | median | sensing s | moving s | correct | vs id3 |")
    print("|---|---|---|---|---|---|---|")
    for c, rs in results.items():
        mean = statistics.mean(r.robot_s for r in rs)
        ok = sum(bool(r.correct) for r in rs)
        print(f"| {c} | {mean / 60:.1f} | {statistics.median(r.robot_s for r in rs) / 60:.1f} | "
              f"{statistics.mean(r.sensing_s for r in rs):.0f} | {statistics.mean(r.moving_s for r in rs):.0f} | "
              f"{ok}/{len(rs)} ({100 * ok / len(rs):.0f}%) | {mean / base:.2f} |")


if __name__ == "__main__":
    main()

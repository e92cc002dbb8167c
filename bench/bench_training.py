"""Training speed on the Table 3 objects: each distinct phase-2 tree grown once and only as
far as predictions walk it, each description kept until it changes
(``learner/training/trees.py``), against the method as written, which rebuilds the
descriptions and grows a whole tree for every prediction of Table 6
(``train(reuse=False)``), side by side in this process.

Two workloads: the learner alone, replaying the shipped measurements
(``hero_driver/profiles/hero2000-measurements.json``), and the whole ``csl train --sim``
path (camera objects once, then every measurement from the simulator; the new path also
keeps one noise-free world per object, the old one builds a world per measurement,
``SimulatorSource(reuse=...)``). Runs alternate
between the two paths; figures are medians. Both paths must learn the same library.

Last, ``csl demo``'s library (``csl_cli/demo_library.py``): trained (``--retrain``)
against reused from the content-hash cache, in a temporary folder.

    python bench/bench_training.py [--repeat 7]
"""

from __future__ import annotations

import argparse
import datetime
import platform
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from csl_cli.demo_library import trained_library  # noqa: E402
from executive.training_sources import SimulatorSource, camera_objects  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.training.inputs import read_objects, read_replay  # noqa: E402
from learner.training.stage import TrainingResult, train  # noqa: E402
from robot_profile import load_profile  # noqa: E402

PROFILES = ROOT / "hero_driver" / "profiles"


def _timed(run: Callable[[bool], TrainingResult], repeat: int) -> tuple[dict[bool, list[float]], dict[bool, TrainingResult]]:
    times: dict[bool, list[float]] = {False: [], True: []}
    results: dict[bool, TrainingResult] = {}
    for _ in range(repeat):
        for reuse in (False, True):
            start = time.perf_counter()
            results[reuse] = run(reuse)
            times[reuse].append(time.perf_counter() - start)
    return times, results


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs of each path per workload (default 7)")
    args = ap.parse_args()
    profile = load_profile()
    knowledge = profile.knowledge()
    estimator = ModelMoveCost(knowledge.move)

    objects = read_objects(PROFILES / "hero2000-measurements-objects.json")
    replay = read_replay(PROFILES / "hero2000-measurements.json")
    seen = camera_objects("training", profile)

    def replayed(reuse: bool) -> TrainingResult:
        return train(objects, knowledge, replay, estimator, reuse=reuse)

    def simulated(reuse: bool) -> TrainingResult:
        source = SimulatorSource(profile=profile, axis_offsets_deg=seen.axis_offsets_deg, reuse=reuse)
        return train(seen.objects, knowledge, source, estimator, reuse=reuse)

    print(f"{datetime.date.today()} {platform.machine()} python {platform.python_version()}, repeat {args.repeat}")
    print("| Table 3 training | as written: every description and whole tree rebuilt | each distinct tree once, as far as walked | ratio | trees grown | same library |")
    print("|---|---:|---:|---:|---:|---|")
    for name, run in (("learner alone (replayed measurements)", replayed), ("csl train --sim (simulator)", simulated)):
        times, results = _timed(run, args.repeat)
        old, new = statistics.median(times[False]), statistics.median(times[True])
        same = results[False].descriptions == results[True].descriptions
        log = results[True].log
        print(f"| {name} | {old:.2f} s | {new:.2f} s | **{old / new:.2f}x** | "
              f"{log.trees_grown} of {log.trees_asked} | {'yes' if same else 'NO'} |")

    with tempfile.TemporaryDirectory() as folder:
        times = {True: [], False: []}
        libraries = {}
        for _ in range(args.repeat):
            for retrain in (True, False):
                start = time.perf_counter()
                libraries[retrain] = trained_library(knowledge, profile, "lab", 0, retrain=retrain,
                                                     folder=Path(folder), say=lambda _: None)
                times[retrain].append(time.perf_counter() - start)
        old, new = statistics.median(times[True]), statistics.median(times[False])
        same = libraries[True].descriptions == libraries[False].descriptions and libraries[False].reused
        print(f"| csl demo's library: trained (--retrain) vs reused (cache hit) | {old:.2f} s | {new * 1e3:.0f} ms | "
              f"**{old / new:.0f}x** | | {'yes' if same else 'NO'} |")


if __name__ == "__main__":
    main()

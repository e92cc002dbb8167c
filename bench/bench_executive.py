"""Executive speed: computation per object, tick overhead, episode wall time.

- computation per object: wall seconds spent in the learner and planner while handling
  one object (the ledger's ``computing_s``), over the lab's 7 test objects and several
  seeds. The paper needed about 20 s per object.
- tick overhead: one tick of the full tree while the robot is busy (a move in flight:
  the tick walks down to MoveTo and finds its future not done), against a bare py_trees
  tree of one running behaviour, side by side.
- episode wall time: the whole lab episode with the in-process simulator.

    python bench/bench_executive.py [--seeds 3] [--ticks 20000]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import sys
import tempfile
import time
from concurrent.futures import Future
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import py_trees  # noqa: E402

from behaviours.records import reset_blackboard  # noqa: E402
from executive.defaults import EXAMPLE_LIBRARY  # noqa: E402
from executive.executive import Executive  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.service.local import LocalLearner  # noqa: E402


class BusyHero(SimulatedHero):
    """The simulator, except that moves never finish: the robot is always on its way."""

    def move(self, waypoints, face=None):  # noqa: ANN001, ANN201
        return Future()


def learner() -> LocalLearner:
    return LocalLearner(Path(tempfile.mkdtemp()) / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))


def episode(seed: int):  # noqa: ANN201
    ex = Executive(SimulatedHero("bench", world="lab", seed=seed), learner())
    result = ex.run()
    ex.shutdown()
    return result


def tick_overhead(n: int) -> tuple[float, float]:
    ex = Executive(BusyHero("busy", world="lab", seed=0), learner())
    reset_blackboard(ex.services.driver.robot)  # driving the tree by hand for the measurement
    for _ in range(50):  # locate, choose the first test, start the move
        ex.tree.tick()
    start = time.perf_counter()
    for _ in range(n):
        ex.tree.tick()
    full = (time.perf_counter() - start) / n
    bare = py_trees.composites.Sequence("bare", memory=True, children=[py_trees.behaviours.Running("busy")])
    tree = py_trees.trees.BehaviourTree(bare)
    start = time.perf_counter()
    for _ in range(n):
        tree.tick()
    return full, (time.perf_counter() - start) / n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--ticks", type=int, default=20000)
    args = ap.parse_args()
    computing, walls, ticks = [], [], []
    for seed in range(args.seeds):
        result = episode(seed)
        computing += [o.ledger.computing_s for o in result.objects]
        walls.append(result.wall_s)
        ticks.append(result.ticks)
    full, bare = tick_overhead(args.ticks)
    med = statistics.median
    print(f"machine: {platform.machine()} python {platform.python_version()}, {args.seeds} lab episodes "
          f"(7 objects each)")
    print("| measure | median |")
    print("|---|---|")
    print(f"| computation per object (learner + planner) | {med(computing) * 1e3:.0f} ms "
          f"(p90 {sorted(computing)[int(0.9 * len(computing))] * 1e3:.0f} ms; paper ~20 s) |")
    print(f"| tick while the robot is busy (full tree) | {full * 1e6:.1f} µs |")
    print(f"| tick of a bare one-behaviour py_trees tree | {bare * 1e6:.1f} µs ({full / bare:.1f}x) |")
    print(f"| lab episode wall time (in-process simulator) | {med(walls):.2f} s, {med(ticks):.0f} ticks |")


if __name__ == "__main__":
    main()

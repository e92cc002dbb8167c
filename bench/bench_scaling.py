"""Scaling: how the learner's costs grow with the library, from 100 to 100,000 descriptions.

Libraries are synthetic (learner/library/synthetic.py): each description is one of the shipped
library's, perturbed within its features' errors, so the structure (which features at
which positions, what is missing, the few grasps) stays the robot's. Per size, medians of:

- building the ``DescriptionMatrix`` (once per library change);
- one test choice at the root (``rank`` on ``Node.root``, the criterion, ``ModelMoveCost``),
  each in a session's own context: the first, worked out (the matrix's memo of the
  root's partition and the exact search's nodes cleared each time), and a repeated one
  (the matrix's memos kept: what every object after the first pays);
- one object's whole run-time tree: a ``RecognitionSession`` driven noise-free with a
  description's own values until it executes that description's grasp (a value the
  description lacks takes the first branch; a wrong grasp is dropped and the session
  goes on), for a few descriptions chosen at random as the object: "alone", each as
  if the first of its kind (the matrix's memo of nodes below the root cleared before
  it, and the exact search's nodes forgotten), and "in a run", one after another as a
  robot meets them (a node an earlier object reached is memoised);
- loading the library from JSON (``read_library_json``; the row layout, version 2, and
  the columnar one, version 3) and from a SQLite store (``LibraryStore.descriptions``);
- peak memory (tracemalloc) of loading the JSON, building the matrix and one choice,
  measured in a separate pass because tracing slows everything it traces.

The first row is the shipped library itself, every description as the object. The
curve's shape is the slope of a least-squares line through log(time) against
log(descriptions) over the synthetic sizes, and over the sizes from 3,000 up (where
fixed per-call overheads no longer dominate).

    python bench/bench_scaling.py [--max 100000] [--objects 5] [--seed 0] [--cpu] [--criterion NAME]

``--criterion`` (default: the executive's, ``cs-id3-failure``) measures another rule on the
same libraries and objects: the cost of a slower but cheaper rule is read off here.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import statistics
import sys
import tempfile
import time
import tracemalloc
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from experiments.ablations import MEASURED, criterion  # noqa: E402
from learner.choosing.criteria import DEFAULT_CRITERION, Criterion  # noqa: E402
from learner.choosing.exact import forget_nodes  # noqa: E402
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.choosing.node import Context, Node, ScoredTest, measured_value  # noqa: E402
from learner.choosing.selection import rank  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.description import ObjectDescription  # noqa: E402
from learner.library.format import read_library_json, write_library_json  # noqa: E402
from learner.library.store import LibraryStore  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner.position import Position  # noqa: E402
from learner.runtime import Exhausted, Matched, RecognitionSession, Unreliable  # noqa: E402

SIZES = (100, 300, 1_000, 3_000, 10_000, 30_000, 100_000)
START = Position(60.0, 0.0)  # as bench_learner.py: the robot starts away from the object
MAX_DECISIONS = 200  # a walk longer than this is a bug in the walk, not a slow learner


@dataclass(frozen=True)
class Repeats:
    """How many times each measure runs at a size: fewer at the large ones, where one
    run already takes long enough for a stable median."""

    build: int
    choice: int
    load: int


def repeats_for(n: int) -> Repeats:
    if n <= 1_000:
        return Repeats(build=7, choice=31, load=7)
    if n <= 10_000:
        return Repeats(build=5, choice=15, load=5)
    if n <= 30_000:
        return Repeats(build=3, choice=7, load=3)
    return Repeats(build=3, choice=5, load=3)


@dataclass(frozen=True)
class Row:
    """One size's medians (seconds, bytes)."""

    label: str
    n: int
    tests: int
    build_s: float
    first_choice_s: float
    choice_s: float
    object_alone_s: float
    object_s: float
    decisions: float
    load_s: float
    load_columnar_s: float
    store_s: float
    peak_bytes: int


CLOCK: Callable[[], float] = time.perf_counter  # or time.process_time, with --cpu


def median_time(fn: Callable[[], object], repeat: int) -> float:
    out = []
    for _ in range(repeat):
        began = CLOCK()
        fn()
        out.append(CLOCK() - began)
    return statistics.median(out)


def report_values(session: RecognitionSession, test: ScoredTest, value: float,
                  truth: ObjectDescription) -> Matched | Unreliable:
    """Report a test's value the way the driver does: a paid procedure yields all its
    features at the target (the description's values; None where it lacks one), a free
    re-use of a measured value just that one."""
    if measured_value(test.test, session.measurements) is not None:
        return session.observe(test, {test.test.feature: value}, test.target)
    procedure = session.matrix.knowledge.procedure_for(test.test.feature)
    values: dict[str, float | None] = {f.name: truth.value_at(f.name, test.target) for f in procedure.features}
    values[test.test.feature] = value
    return session.observe(test, values, test.target)


def recognise(matrix: DescriptionMatrix, crit: Criterion, estimator: ModelMoveCost, row: int) -> int:
    """Drive one session noise-free with description ``row`` as the object until its own
    grasp is executed; returns how many decisions that took."""
    truth = matrix.descriptions[row]
    session = RecognitionSession(matrix, crit, estimator, START)
    for decisions in range(1, MAX_DECISIONS + 1):
        decision = session.decide()
        if isinstance(decision, AmbiguousLeaf):
            decision = decision.options[0]  # the learner's order, cheapest first
        if isinstance(decision, GraspLeaf):
            if decision.grasp == truth.grasp or not matrix.knowledge.grasp(decision.grasp).verifiable:
                return decisions  # held, or (a wrong No-Grab) left behind: either way the object is done
            if all(d.grasp in session.dropped_grasps or d.grasp == decision.grasp for d in matrix.descriptions):
                return decisions  # no description of another grasp is left to fall back on
            session.grasp_failed(decision.grasp, side_effects=False, position=decision.position)
            continue
        if isinstance(decision, Exhausted):
            if not session.backtrack():
                return decisions
            continue
        value = float(matrix.values[row, matrix.column[decision.test]])
        if decision.test.is_grasp:
            session.grasp_as_feature(decision, value == 1.0, decision.target)
            continue
        if math.isnan(value):
            value = sum(decision.ranges[0]) / 2  # unknown for this object: take the first branch
        if not isinstance(report_values(session, decision, value, truth), Matched):
            session.follow_nearest()
    raise RuntimeError(f"the walk of {truth.object_id} took more than {MAX_DECISIONS} decisions")


def measure(label: str, library: list[ObjectDescription], knowledge, crit: Criterion,  # noqa: ANN001
            estimator: ModelMoveCost, objects: Sequence[int], folder: Path) -> Row:
    reps = repeats_for(len(library))
    build = median_time(lambda: DescriptionMatrix(library, knowledge), reps.build)
    matrix = DescriptionMatrix(library, knowledge)
    root = Node.root(len(library))

    def first_choice() -> None:
        matrix.root_splits.clear()
        forget_nodes(matrix)
        rank(root, START, Context(matrix, crit, estimator), {})

    first = median_time(first_choice, reps.choice)
    # a new object's session: its own context (a chooser's scratch is per session), the
    # matrix's memos kept
    choice = median_time(lambda: rank(root, START, Context(matrix, crit, estimator), {}), reps.choice)
    matrix.labels  # the leaves' per-row labels, made once per matrix as the root's memo is
    alone, decisions = [], []
    for row in objects:  # each as if the first object of its kind: nothing below the root memoised
        matrix.node_splits.clear()
        forget_nodes(matrix)  # nor the exact search's nodes (cs-id3-failure-exact)
        began = CLOCK()
        decisions.append(recognise(matrix, crit, estimator, row))
        alone.append(CLOCK() - began)
    matrix.node_splits.clear()
    forget_nodes(matrix)
    per_object = []
    for row in objects:  # one after another, as a robot meets them: a node met before is memoised
        began = CLOCK()
        recognise(matrix, crit, estimator, row)
        per_object.append(CLOCK() - began)
    path = folder / f"library-{len(library)}.json"
    write_library_json(path, library)
    load = median_time(lambda: read_library_json(path), reps.load)
    columnar = folder / f"library-{len(library)}-columnar.json"
    write_library_json(columnar, library, columnar=True)
    load_columnar = median_time(lambda: read_library_json(columnar), reps.load)
    columnar.unlink()
    db = folder / f"library-{len(library)}.sqlite"
    with LibraryStore(db) as store:
        store.add(library)
        stored = median_time(store.descriptions, reps.load)
    db.unlink()
    tests = len(matrix.tests)
    tracemalloc.start()
    loaded = read_library_json(path)
    rank(Node.root(len(loaded)), START, Context(DescriptionMatrix(loaded, knowledge), crit, estimator), {})
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    path.unlink()
    return Row(label, len(library), tests, build, first, choice, statistics.median(alone),
               statistics.median(per_object),
               statistics.mean(decisions), load, load_columnar, stored, peak)


def slope(rows: Sequence[Row], of: Callable[[Row], float]) -> float:
    """Least-squares slope of log(of(row)) against log(descriptions): 1 is linear."""
    if len(rows) < 2:
        return math.nan
    return float(np.polyfit(np.log([r.n for r in rows]), np.log([of(r) for r in rows]), 1)[0])


def machine() -> str:
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (f"{model}, {os.cpu_count()} CPUs, {platform.system()} {platform.release()}, "
            f"Python {platform.python_version()}, numpy {np.__version__}")


def ms(seconds: float) -> str:
    return f"{seconds * 1e3:.3g}" if seconds < 1 else f"{seconds * 1e3:.0f}"


MEASURES: tuple[tuple[str, Callable[[Row], float]], ...] = (
    ("build matrix", lambda r: r.build_s),
    ("first root choice", lambda r: r.first_choice_s),
    ("root choice", lambda r: r.choice_s),
    ("one object alone", lambda r: r.object_alone_s),
    ("one object in a run", lambda r: r.object_s),
    ("load JSON", lambda r: r.load_s),
    ("load JSON columnar", lambda r: r.load_columnar_s),
    ("load store", lambda r: r.store_s),
    ("peak memory", lambda r: float(r.peak_bytes)),
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=SIZES[-1],
                    help=f"largest library size to measure (sizes: {', '.join(map(str, SIZES))})")
    ap.add_argument("--objects", type=int, default=5, help="descriptions walked as the object, per size")
    ap.add_argument("--seed", type=int, default=0, help="seed of the synthetic libraries and of the objects")
    ap.add_argument("--cpu", action="store_true",
                    help="time in CPU seconds of this process (steadier on a shared machine) instead of wall time")
    ap.add_argument("--criterion", default=DEFAULT_CRITERION, choices=sorted(MEASURED), metavar="NAME",
                    help=f"the learner's test-selection rule, a product criterion or an ablation "
                         f"(default: {DEFAULT_CRITERION}, the executive's)")
    args = ap.parse_args()
    if args.cpu:
        global CLOCK
        CLOCK = time.process_time
    if args.max < SIZES[0]:
        ap.error(f"--max must be at least {SIZES[0]}, got {args.max}")
    if args.objects < 1:
        ap.error(f"--objects must be at least 1, got {args.objects}")
    knowledge = load_knowledge(KNOWLEDGE)
    estimator = ModelMoveCost(knowledge.move)
    crit = criterion(args.criterion)
    base = read_library_json(EXAMPLE_LIBRARY)
    picker = np.random.default_rng(args.seed)
    began = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        rows.append(measure("shipped", base, knowledge, crit, estimator, range(len(base)), Path(folder)))
        print(f"measured the shipped library ({len(base)})", file=sys.stderr, flush=True)
        for n in (s for s in SIZES if s <= args.max):
            library = synthetic_library(knowledge, n, args.seed, base=base)
            objects = sorted(picker.choice(n, size=min(args.objects, n), replace=False).tolist())
            rows.append(measure(f"{n:,}", library, knowledge, crit, estimator, objects, Path(folder)))
            print(f"measured {n:,} ({time.perf_counter() - began:.0f} s so far)", file=sys.stderr, flush=True)
    total = time.perf_counter() - began

    print(f"date: {datetime.date.today().isoformat()}")
    print(f"machine: {machine()}")
    print(f"command: python bench/bench_scaling.py {' '.join(sys.argv[1:])}".rstrip())
    print(f"criterion: {args.criterion}")
    print(f"total wall time: {total:.0f} s; times below are {'CPU' if args.cpu else 'wall'} time")
    print()
    print("| descriptions | tests | build matrix ms | first root choice ms | root choice ms "
          "| one object alone ms (mean decisions) | one object in a run ms | load JSON ms "
          "| load JSON columnar ms | load store ms | peak memory MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r.label} | {r.tests} | {ms(r.build_s)} | {ms(r.first_choice_s)} | {ms(r.choice_s)} "
              f"| {ms(r.object_alone_s)} ({r.decisions:.1f}) | {ms(r.object_s)} | {ms(r.load_s)} "
              f"| {ms(r.load_columnar_s)} | {ms(r.store_s)} "
              f"| {r.peak_bytes / 2**20:.1f} |")
    synthetic = rows[1:]
    tail = [r for r in synthetic if r.n >= 3_000]
    print()
    print("| log-log slope | " + " | ".join(name for name, _ in MEASURES) + " |")
    print("|---" * (len(MEASURES) + 1) + "|")
    print(f"| {synthetic[0].n:,}-{synthetic[-1].n:,} | "
          + " | ".join(f"{slope(synthetic, of):.2f}" for _, of in MEASURES) + " |")
    if len(tail) >= 2:
        print(f"| {tail[0].n:,}-{tail[-1].n:,} | "
              + " | ".join(f"{slope(tail, of):.2f}" for _, of in MEASURES) + " |")
    print()
    goals(rows)


def goals(rows: Sequence[Row]) -> None:
    """The issue's targets, met or not, at the sizes they name."""
    by_n = {r.n: r for r in rows[1:]}
    shipped = rows[0]
    print(f"- one object's whole run-time tree at the shipped size ({shipped.n}): "
          f"{ms(shipped.object_s)} ms (goal < 50 ms): {'met' if shipped.object_s < 0.05 else 'NOT met'}")
    for n, choice_goal, object_goal in ((10_000, 0.005, 0.05), (100_000, 0.05, 0.25)):
        if n in by_n:
            r = by_n[n]
            verdict = ("met" if r.first_choice_s < choice_goal
                       else "met only repeated" if r.choice_s < choice_goal else "NOT met")
            walk = ("met" if r.object_alone_s < object_goal
                    else "met in a run" if r.object_s < object_goal else "NOT met")
            print(f"- at {n:,} descriptions: first root choice {ms(r.first_choice_s)} ms, repeated "
                  f"{ms(r.choice_s)} ms (goal < {ms(choice_goal)} ms): {verdict}; one object alone "
                  f"{ms(r.object_alone_s)} ms, in a run {ms(r.object_s)} ms (goal < {ms(object_goal)} ms): {walk}")
    if 100_000 in by_n:
        r = by_n[100_000]
        print(f"- loading a 100,000-description library: store {r.store_s:.2f} s, JSON {r.load_s:.2f} s, "
              f"columnar JSON {r.load_columnar_s:.2f} s (goal < 2 s): store {'met' if r.store_s < 2 else 'NOT met'}, "
              f"columnar JSON {'met' if r.load_columnar_s < 2 else 'NOT met'}")


if __name__ == "__main__":
    main()

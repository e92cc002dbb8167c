"""Learning one object at 100 to 100,000 descriptions: appending against rebuilding.

For each size a synthetic library (``synthetic_library`` perturbed from the shipped
one) seeds a ``LocalLearner`` on a SQLite file in a temporary folder and its
description matrix is built once. Then, per learned object (descriptions drawn from
another seed of the same generator, so they fit the matrix's columns as a grasped lab
object does):

- ``now``: ``LocalLearner.learn`` (admission, one SQLite transaction with the key and
  the version, the snapshot extended) plus ``DescriptionMatrix.extended_to`` the new
  snapshot, as the executive's ``LibraryMatrix`` does — what a robot pays after a grasp;
- ``merge``: the first read of the appended matrix's sort orders (paid by the next
  choice, once per learned object), reported apart;
- ``rebuild``: the path before incremental learning: the whole store re-read
  (``LibraryStore.descriptions``) and the matrix built from scratch;
- ``root choice after``: CPU of the next root choice (``partition_columns`` of every row
  and column) on the appended matrix, ``new`` with its known values updated by the
  new row (``KnownValues.appended``), ``old`` with them rebuilt wholesale after the
  sort orders' merge, as before; the two partitions must be equal;
- ``one bare commit``: a one-row transaction on the same store, the floor any durable
  learn pays on this disk (its fsync), whatever the library's size.

Medians over the learned objects (``--learns``, fewer for the slow rebuild). The
appended matrix must equal the rebuilt one, or the bench stops.
"""

from __future__ import annotations

import argparse
import datetime
import platform
import statistics
import sys
import tempfile
import time
import uuid
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from learner.choosing.gain import partition_columns  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.library.store import LibraryStore  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner.service.local import LocalLearner  # noqa: E402

SIZES = (100, 1_000, 10_000, 100_000)


def timed(run: Callable[[], object]) -> tuple[float, object]:
    start = time.perf_counter()
    out = run()
    return time.perf_counter() - start, out


def cpu_timed(run: Callable[[], object]) -> tuple[float, float, object]:
    """Wall and CPU seconds: on a shared machine the CPU time shows the work itself,
    the wall time adds waiting for the disk's fsync and for the other processes."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = run()
    return time.perf_counter() - wall, time.process_time() - cpu, out


def same(a: DescriptionMatrix, b: DescriptionMatrix) -> bool:
    return (a.tests == b.tests and a.classes == b.classes
            and np.array_equal(a.values, b.values, equal_nan=True) and np.array_equal(a.class_of, b.class_of)
            and np.array_equal(a.order, b.order)
            and np.array_equal(a.sorted_values, b.sorted_values, equal_nan=True))


def measure(n: int, learns: int, rebuilds: int) -> dict[str, float]:
    knowledge = load_knowledge(KNOWLEDGE)
    base = read_library_json(EXAMPLE_LIBRARY)
    library = synthetic_library(knowledge, n, 0, base=base)
    to_learn = synthetic_library(knowledge, learns, 1, base=base)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "library.sqlite"
        learner = LocalLearner(path, seed_library=library, knowledge=knowledge)
        matrix = DescriptionMatrix(learner.library().descriptions, knowledge)
        matrix.known  # the session before the learn made its choices
        now, now_cpu, merge, rebuild, choice_new, choice_old = [], [], [], [], [], []
        for i, d in enumerate(to_learn):
            def learn_and_append(d=d, matrix=matrix):  # noqa: ANN001, ANN202
                learner.learn(d, str(uuid.uuid4()))
                return matrix.extended_to(learner.library().descriptions)  # as the executive's LibraryMatrix
            seconds, cpu, matrix = cpu_timed(learn_and_append)
            now.append(seconds)
            now_cpu.append(cpu)
            old = object.__new__(DescriptionMatrix)  # the same grown matrix, its known values dropped as before
            old.__dict__.update(matrix.__dict__)
            old._known, old.root_splits = None, {}
            everyone, columns = tuple(range(len(matrix.descriptions))), np.arange(len(matrix.tests))
            _, cpu_old, split_old = cpu_timed(lambda: partition_columns(everyone, old, columns))  # noqa: B023
            _, cpu_new, split_new = cpu_timed(lambda: partition_columns(everyone, matrix, columns))  # noqa: B023
            if split_old.ranges != split_new.ranges or not np.array_equal(split_old.gains, split_new.gains):
                sys.exit(f"at {n}: the updated known values choose otherwise than the rebuilt ones")
            choice_new.append(cpu_new)
            choice_old.append(cpu_old)
            merge.append(timed(lambda: matrix.order)[0])  # noqa: B023
            if i < rebuilds:
                def reread_and_build() -> DescriptionMatrix:
                    with LibraryStore(path) as store:
                        return DescriptionMatrix(store.descriptions(), knowledge)
                seconds, rebuilt = timed(reread_and_build)
                rebuild.append(seconds)
                if not same(matrix, rebuilt):
                    sys.exit(f"at {n}: the appended matrix differs from the rebuilt one")
        learner.close()
        with LibraryStore(path) as store:  # the floor: one committed transaction on this disk, at this size
            commit = [timed(lambda i=i: store.set_meta("bench", str(i)))[0] for i in range(learns)]  # noqa: B023
    return {"commit": statistics.median(commit), "now": statistics.median(now), "now_cpu": statistics.median(now_cpu), "merge": statistics.median(merge),
            "rebuild": statistics.median(rebuild), "max_now": max(now),
            "choice_new": statistics.median(choice_new), "choice_old": statistics.median(choice_old)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=SIZES[-1], help="largest library size (default 100000)")
    ap.add_argument("--learns", type=int, default=20, help="learned objects per size (default 20)")
    args = ap.parse_args()
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_learn.py "
          f"{' '.join(sys.argv[1:])}; machine: {platform.processor() or platform.machine()}, "
          f"{platform.python_implementation()} {platform.python_version()}, numpy {np.__version__}")
    print("| descriptions | learn + append (median) | its CPU | one bare commit | worst | first choice's merge "
          "| re-read + rebuild | ratio | root choice after, CPU: new | old | ratio |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n in (s for s in SIZES if s <= args.max):
        rebuilds = 5 if n <= 10_000 else 1  # a rebuild at 100k takes about a minute
        r = measure(n, args.learns, rebuilds)
        print(f"| {n:,} | {r['now'] * 1e3:.2f} ms | {r['now_cpu'] * 1e3:.2f} ms | {r['commit'] * 1e3:.2f} ms | {r['max_now'] * 1e3:.2f} ms | {r['merge'] * 1e3:.1f} ms | "
              f"{r['rebuild']:.2f} s | {r['rebuild'] / r['now']:,.0f}x | {r['choice_new'] * 1e3:.1f} ms | "
              f"{r['choice_old'] * 1e3:.1f} ms | {r['choice_old'] / r['choice_new']:.1f}x |", flush=True)


if __name__ == "__main__":
    main()

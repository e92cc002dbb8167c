"""Choosing at 10,000 and 100,000 descriptions: today's paths against the ones they replaced.

Synthetic libraries (perturbed from the shipped one) are stored in a SQLite store in a
temporary folder and loaded from it, as a robot's are (equal observations shared).
Per size, medians of CPU time (``time.process_time``: the machine is shared) of:

- building the matrix: ``DescriptionMatrix`` (one pass over the distinct observations,
  spread with array operations) against each row built alone (``_row``: the per
  description path the build used before, and appending still uses);
- a node's partition (``partition_columns``, memos cleared: the work of a first choice)
  against the previous dense one (kept below verbatim), at the root and at a node
  holding every other row;
- the same partitions against the per-entry one they replaced (over every known entry
  of the node's rows, ``tests/learner/reference_paths.py``), where today's works
  on each column's distinct values with their counts per class;
- a leaf's grasp options (``leaf.grasp_options``) at that node, read as per-row
  arrays, against the row-by-row reading they replaced (the labels made once per
  matrix, outside the timing, as a session finds them);
- every grasp test's failure share at the root (``scoring._failure_share``, what a
  ``cs-id3-failure`` choice prices each grasp tried as a feature by), over numpy
  arrays, against the Python sum row by row it replaced.

Both paths must give equal results, or the bench stops.

    python bench/bench_choice_paths.py [--max 100000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import datetime
import statistics
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from learner.choosing.criteria import criterion  # noqa: E402
from learner.choosing.gain import _EPS, entropy, partition_columns  # noqa: E402
from learner.choosing.leaf import grasp_options  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.choosing.node import Context, Node  # noqa: E402
from learner.choosing.partition import Split  # noqa: E402
from learner.choosing.scoring import _failure_share  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.library.store import LibraryStore  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner.position import Position  # noqa: E402
from tests.learner.reference_paths import entries, entry_partition, simple_failure_share, simple_grasp_options  # noqa: E402

START = Position(60.0, 0.0)  # as bench_scaling.py
SIZES = (10_000, 100_000)


def dense_partition(rows: Sequence[int], matrix: DescriptionMatrix, columns: np.ndarray) -> Split:
    """The previous partition, verbatim: the dense (columns x rows) arrays, NaN included."""
    n, k, m = len(rows), len(matrix.classes), len(columns)
    order, vals = matrix.order[columns], matrix.sorted_values[columns]
    if n < len(matrix.descriptions):  # keep the node's rows, still sorted by value, NaN last
        member = np.zeros(len(matrix.descriptions), dtype=bool)
        member[list(rows)] = True
        keep = member[order]
        order, vals = order[keep].reshape(m, n), vals[keep].reshape(m, n)
    vcls = matrix.class_of[order]
    known = ~np.isnan(vals)
    n_known = known.sum(axis=1)
    err = matrix.errors[columns][:, None]
    step = np.zeros_like(vals)
    step[:, 1:] = vals[:, 1:] - vals[:, :-1]
    breaks = known & (step > err + _EPS)
    starts = breaks.copy()
    starts[:, 0] = known[:, 0]
    range_id = np.cumsum(starts, axis=1, dtype=np.int32) - 1
    n_ranges = starts.sum(axis=1)

    # the "unknown" subset: the ranges widened by the error leave part of the domain open
    last = np.take_along_axis(vals, np.maximum(n_known - 1, 0)[:, None], axis=1)[:, 0]
    widest_gap = np.where(breaks, step, 0.0).max(axis=1) if n > 1 else np.zeros(m)
    e = err[:, 0]
    numeric_covered = ((vals[:, 0] - e <= matrix.span_lo[columns] + _EPS)
                       & (last + e >= matrix.span_hi[columns] - _EPS) & (widest_gap <= 2 * e + _EPS))
    unknown = np.where(matrix.binary[columns], n_ranges < 2, ~numeric_covered) & ~matrix.is_grasp[columns]

    subsets = n_ranges + unknown
    max_r = int(n_ranges.max()) + 1 if m else 1
    col = np.arange(m, dtype=np.int32)[:, None]
    counts = np.bincount(((col * max_r + range_id) * k + vcls)[known],
                         minlength=m * max_r * k).astype(float).reshape(m, max_r, k)
    missing = np.bincount((col * k + vcls)[~known], minlength=m * k).astype(float).reshape(m, k)
    share = missing / np.maximum(subsets, 1)[:, None]
    in_range = np.arange(max_r)[None, :] < n_ranges[:, None]
    counts += np.where(in_range[:, :, None], share[:, None, :], 0.0)
    weights = np.concatenate([counts, np.where(unknown[:, None], share, 0.0)[:, None, :]], axis=1)
    totals = np.bincount(matrix.class_of[list(rows)], minlength=k).astype(float)
    h_total = entropy(totals[None, :])[0]
    remainder = (weights.sum(axis=2) / max(n, 1) * entropy(weights)).sum(axis=1)
    gains = np.where(n_ranges >= 2, np.maximum(h_total - remainder, 0.0), 0.0)

    ends = starts.copy()
    ends[:, :-1] = starts[:, 1:]
    ends[:, -1] = False
    ends |= known & (np.arange(n)[None, :] == (n_known - 1)[:, None])
    los, his = vals[starts].tolist(), vals[ends].tolist()
    bounds = np.concatenate([[0], np.cumsum(n_ranges)]).tolist()
    ranges = [list(zip(los[bounds[j]:bounds[j + 1]], his[bounds[j]:bounds[j + 1]])) for j in range(m)]
    return Split(ranges, unknown, gains, n_ranges, counts.sum(axis=2) / max(n, 1))


def cpu(fn: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        began = time.process_time()
        fn()
        times.append(time.process_time() - began)
    return statistics.median(times)


def same(a: Split, b: Split) -> bool:
    return (a.ranges == b.ranges and np.array_equal(a.unknown, b.unknown) and np.array_equal(a.gains, b.gains)
            and np.array_equal(a.n_ranges, b.n_ranges) and np.array_equal(a.mass, b.mass))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=SIZES[-1], help=f"largest size (sizes: {SIZES})")
    ap.add_argument("--repeats", type=int, default=5, help="runs per measure (median)")
    args = ap.parse_args()
    if args.repeats < 1:
        ap.error(f"--repeats must be at least 1, got {args.repeats}")
    knowledge = load_knowledge(KNOWLEDGE)
    base = read_library_json(EXAMPLE_LIBRARY)
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_choice_paths.py "
          f"--max {args.max} --repeats {args.repeats}; CPU seconds, medians")
    print("| descriptions | measure | before s | now s | ratio |")
    print("|---:|---|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for n in (s for s in SIZES if s <= args.max):
            with LibraryStore(Path(folder) / f"library-{n}.sqlite") as store:
                store.add(synthetic_library(knowledge, n, 0, base=base))
                library = store.descriptions()
            matrix = DescriptionMatrix(library, knowledge)
            alone = np.array([matrix._row(d) for d in library])  # noqa: SLF001
            if not np.array_equal(alone, matrix.values, equal_nan=True):
                sys.exit(f"{n}: the bulk build differs from the rows built alone")
            rows_of = {"root": list(range(n)), "every other row": list(range(0, n, 2))}
            columns = np.arange(len(matrix.tests))

            def fresh(rows: Sequence[int]) -> Split:
                matrix.root_splits.clear()
                matrix.node_splits.clear()
                return partition_columns(rows, matrix, columns)

            measures: list[tuple[str, Callable[[], object], Callable[[], object]]] = [
                ("build the matrix", lambda: [matrix._row(d) for d in library],  # noqa: B023, SLF001
                 lambda: DescriptionMatrix(library, knowledge))]  # noqa: B023
            for name, rows in rows_of.items():
                if not same(dense_partition(rows, matrix, columns), fresh(rows)):
                    sys.exit(f"{n}: the partitions at {name} differ")
                measures.append((f"partition at {name}", lambda r=rows: dense_partition(r, matrix, columns),  # noqa: B023
                                 lambda r=rows: fresh(r)))
            known = entries(matrix)  # as the matrix kept them before
            for name, rows in rows_of.items():
                if not same(entry_partition(rows, matrix, columns, known), fresh(rows)):
                    sys.exit(f"{n}: the partitions over entries and over distinct values at {name} differ")
                measures.append((f"partition at {name}, before: per entry",
                                 lambda r=rows: entry_partition(r, matrix, columns, known),  # noqa: B023
                                 lambda r=rows: fresh(r)))
            ctx = Context(matrix, criterion("cs-id3"), ModelMoveCost(knowledge.move))
            every_other = Node(tuple(range(0, n, 2)), (False,) * len(range(0, n, 2)))
            if grasp_options(every_other, START, ctx) != simple_grasp_options(every_other, START, ctx):
                sys.exit(f"{n}: the grasp options read as arrays differ from the row-by-row reading")
            measures.append(("grasp options at a node of every other row, before: row by row",
                             lambda: simple_grasp_options(every_other, START, ctx),  # noqa: B023
                             lambda: grasp_options(every_other, START, ctx)))  # noqa: B023
            grasps = [t for t in matrix.tests if t.is_grasp]
            root = Node(tuple(range(n)), (False,) * n)

            def shares() -> list[float]:
                rows = np.fromiter(root.rows, dtype=np.int64, count=n)  # noqa: B023
                return [_failure_share(root.weight_array(), rows, matrix, t) for t in grasps]  # noqa: B023

            if not np.allclose(shares(), [simple_failure_share(root, matrix, t) for t in grasps], rtol=1e-12):
                sys.exit(f"{n}: the failure shares over arrays differ from the row-by-row sums")
            measures.append(("every grasp's failure share at the root, before: row by row",
                             lambda: [simple_failure_share(root, matrix, t) for t in grasps],  # noqa: B023
                             shares))
            for name, old, new in measures:
                t_old, t_new = cpu(old, args.repeats), cpu(new, args.repeats)
                print(f"| {n:,} | {name} | {t_old:.3f} | {t_new:.3f} | {t_old / t_new:.1f}x |", flush=True)


if __name__ == "__main__":
    main()

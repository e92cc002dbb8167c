"""The simple paths the faster ones replaced, kept for the tests and benches
that compare them (tests/learner/test_fast_paths.py, bench/bench_choice_paths.py):

- the partition entry by entry over every known value of the node's rows, each
  column's sorted from the matrix's order, which ``learner.choosing.gain.partition_columns``
  (over distinct values) must match bit for bit;
- a leaf's grasp options read description by description, which
  ``learner.choosing.leaf.grasp_options`` (per-row arrays) must equal;
- a grasp test's failure share summed row by row in Python, which
  ``learner.choosing.scoring._failure_share`` (numpy over the node's rows) must match.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from learner.choosing.gain import entropy
from learner.choosing.leaf import GraspLeaf
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.node import Context, Node, target_for
from learner.choosing.partition import Split
from learner.position import Position

_EPS = 1e-9


@dataclass(frozen=True)
class Entries:
    """Every known value, column after column, sorted: what the matrix kept for this."""

    rows: np.ndarray
    values: np.ndarray
    column: np.ndarray
    class_of: np.ndarray
    within: np.ndarray


def entries(matrix: DescriptionMatrix) -> Entries:
    present = ~np.isnan(matrix.sorted_values)
    rows = matrix.order[present].astype(np.int32)
    column = np.repeat(np.arange(len(matrix.tests), dtype=np.int32), present.sum(axis=1))
    return Entries(rows, matrix.sorted_values[present], column, matrix.class_of[rows], matrix.errors[column] + _EPS)


def entry_partition(rows: Sequence[int], matrix: DescriptionMatrix, columns: np.ndarray,
                    known: Entries | None = None) -> Split:
    """``known``: :func:`entries` of ``matrix``, made once (as the matrix kept them)."""
    known = known or entries(matrix)
    n, k, t = len(rows), len(matrix.classes), len(matrix.tests)
    row_index = np.asarray(rows, dtype=np.int64)
    totals = np.bincount(matrix.class_of[row_index], minlength=k).astype(float)
    vals, vcls, col, within = known.values, known.class_of, known.column, known.within
    if n != len(matrix.descriptions):  # keep the node's rows, still sorted by value
        member = np.zeros(len(matrix.descriptions), dtype=bool)
        member[row_index] = True
        keep = np.flatnonzero(member[known.rows])
        vals, vcls, col = vals[keep], vcls[keep], col[keep]
        within = (matrix.errors + _EPS)[col]
    n_known = np.bincount(col, minlength=t)
    step = np.diff(vals)
    same_column = col[1:] == col[:-1]
    breaks = same_column & (step > within[1:])
    starts = np.ones(len(vals), dtype=bool)
    starts[1:] = breaks | ~same_column
    range_global = np.cumsum(starts) - 1
    n_ranges = np.bincount(col[starts], minlength=t)
    max_r = int(n_ranges.max()) + 1 if t else 1
    first_range = np.cumsum(n_ranges) - n_ranges
    cell = (col * max_r + (range_global - first_range[col])) * k + vcls
    counts = np.bincount(cell, minlength=t * max_r * k).astype(float).reshape(t, max_r, k)
    missing = totals[None, :] - counts.sum(axis=1)
    padded = np.append(vals, np.nan)
    after = np.cumsum(n_known)
    first_value = padded[np.where(n_known > 0, after - n_known, len(vals))]
    last = padded[np.where(n_known > 0, after - 1, len(vals))]
    widest_gap = np.zeros(t)
    np.maximum.at(widest_gap, col[1:][breaks], step[breaks])
    err = matrix.errors
    numeric_covered = ((first_value - err <= matrix.span_lo + _EPS)
                       & (last + err >= matrix.span_hi - _EPS) & (widest_gap <= 2 * err + _EPS))
    unknown = np.where(matrix.binary, n_ranges < 2, ~numeric_covered) & ~matrix.is_grasp
    ends = np.ones(len(vals), dtype=bool)
    ends[:-1] = starts[1:]
    los, his = vals[starts].tolist(), vals[ends].tolist()
    bounds = np.concatenate([[0], np.cumsum(n_ranges)]).tolist()
    counts, missing, n_ranges, unknown = counts[columns], missing[columns], n_ranges[columns], unknown[columns]
    max_r = int(n_ranges.max()) + 1 if len(columns) else 1
    counts = counts[:, :max_r]
    subsets = n_ranges + unknown
    share = missing / np.maximum(subsets, 1)[:, None]
    in_range = np.arange(max_r)[None, :] < n_ranges[:, None]
    counts += np.where(in_range[:, :, None], share[:, None, :], 0.0)
    weights = np.concatenate([counts, np.where(unknown[:, None], share, 0.0)[:, None, :]], axis=1)
    h_total = entropy(totals[None, :])[0]
    remainder = (weights.sum(axis=2) / max(n, 1) * entropy(weights)).sum(axis=1)
    gains = np.where(n_ranges >= 2, np.maximum(h_total - remainder, 0.0), 0.0)
    ranges = [list(zip(los[bounds[j]:bounds[j + 1]], his[bounds[j]:bounds[j + 1]])) for j in columns.tolist()]
    return Split(ranges, unknown, gains, n_ranges, counts.sum(axis=2) / max(n, 1))


def simple_grasp_options(node: Node, current: Position, ctx: Context) -> list[GraspLeaf]:
    """The row-by-row reading the array path replaced (as it was before the array path)."""
    genuine = [r for r, c in zip(node.rows, node.carried) if not c]
    by_grasp: dict[str, list[int]] = {}
    for r in genuine or list(node.rows):
        by_grasp.setdefault(ctx.matrix.descriptions[r].grasp, []).append(r)
    options = []
    for grasp, rows in by_grasp.items():
        best = None
        for position in sorted({ctx.matrix.descriptions[r].grasp_position for r in rows}):
            target = target_for(Test(grasp, position, grasp, is_grasp=True), current, ctx)
            move = ctx.estimator.move_cost(current, target)
            leaf = GraspLeaf(grasp, target, move, ctx.knowledge.grasp(grasp).time_s,
                             tuple(sorted(ctx.matrix.descriptions[r].object_id for r in rows)),
                             library_position=position)
            if best is None or leaf.move_cost < best.move_cost:
                best = leaf
        options.append(best)
    return sorted(options, key=lambda o: (not ctx.knowledge.grasp(o.grasp).verifiable,
                                          o.move_cost + ctx.knowledge.grasp(o.grasp).feature_cost_s, o.grasp))


def simple_failure_share(node: Node, matrix: DescriptionMatrix, test: Test) -> float:
    """The weight of the node's rows whose grasp column is 0, row by row."""
    values = matrix.values[list(node.rows), matrix.column[test]]
    return float(sum(w for w, v in zip(node.weights(), values.tolist()) if v < 0.5))

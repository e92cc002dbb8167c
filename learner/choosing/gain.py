"""Information gain over noise-tolerant partitions: one feature's, and a procedure's joint.

Gains for all columns of a node are computed at once on the :class:`DescriptionMatrix`
(docs/method.md §3): values within the feature's error chain into one range; descriptions
lacking the value are spread evenly over the ranges (plus an "unknown" subset when the
ranges, widened by the error, leave part of the feature's domain uncovered).

One application of a sensing procedure yields all of its features for one cost (a D-Scan
gives Height, Depth and Top-Hole?), so :func:`joint_gain` measures what the application
as a whole tells: the gain of the product of its features' partitions, each description
lacking a value spread over that feature's subsets as above, independently per feature.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence

import numpy as np

from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.partition import Range, Split

_EPS = 1e-9


def partition_columns(rows: Sequence[int], matrix: DescriptionMatrix, columns: np.ndarray) -> Split:
    """Chain-merged ranges and information gain of ``columns`` at once.

    The work is on each column's distinct values, not on its entries: a library of
    100,000 descriptions has 4.3 million known entries but few distinct
    (column, value) pairs, some 17,000 (:attr:`DescriptionMatrix.known`). At the root their class
    counts are made once per matrix; below it, one pass over the entries counts the
    node's rows. The ranges, masses and gains are those the entries give: equal values
    always share a range, and the step between two values is the step between the
    entries either side. Every column is worked on whole and the asked columns picked
    at the end (a choice asks for nearly all of them); a column's missing rows are the
    node's rows less its known ones, counted per class by subtraction.
    """
    n, k, t = len(rows), len(matrix.classes), len(matrix.tests)
    everyone = n == len(matrix.descriptions)  # rows are distinct: the root of a whole library
    if everyone and (found := matrix.root_splits.get(columns.tobytes())) is not None:
        return found
    row_index = np.asarray(rows, dtype=np.int64)
    node_key = None if everyone else _node_key(row_index, columns)
    if node_key is not None and (found := matrix.node_splits.get(node_key)) is not None:
        return found
    known = matrix.known
    totals = np.bincount(matrix.class_of[row_index], minlength=k).astype(float)
    if everyone:
        by_value = known.root_counts
    else:  # the node's rows' count of each (column, value) and class: one pass over the entries
        member = np.zeros(len(matrix.descriptions), dtype=bool)
        member[row_index] = True
        by_value = np.bincount(known.cell[member[known.rows]], minlength=known.root_counts.size
                               ).reshape(known.root_counts.shape).astype(float)
    present = np.flatnonzero(by_value.any(axis=1))  # the values the node has, column after column
    held, col = by_value[present], known.value_column[present]
    lows, highs = known.value_first[present], known.value_last[present]
    within = (matrix.errors + _EPS)[col]
    step = lows[1:] - highs[:-1]  # from one value to the next, as between consecutive entries
    same_column = col[1:] == col[:-1]
    breaks = same_column & (step > within[1:])
    starts = np.ones(len(col), dtype=bool)
    starts[1:] = breaks | ~same_column
    n_ranges = np.bincount(col[starts], minlength=t)
    max_r = int(n_ranges.max()) + 1 if t else 1
    range_start = np.flatnonzero(starts)
    range_column = col[range_start]
    counts = np.zeros((t, max_r, k))
    if len(range_start):
        local = np.arange(len(range_start)) - (np.cumsum(n_ranges) - n_ranges)[range_column]
        counts[range_column, local] = np.add.reduceat(held, range_start, axis=0)
    missing = totals[None, :] - counts.sum(axis=1)

    # the "unknown" subset: the ranges widened by the error leave part of the domain open
    n_values = np.bincount(col, minlength=t)
    after = np.cumsum(n_values)
    # a column with no known value reads the NaN past the end
    first_value = np.append(lows, np.nan)[np.where(n_values > 0, after - n_values, len(col))]
    last = np.append(highs, np.nan)[np.where(n_values > 0, after - 1, len(col))]
    widest_gap = np.zeros(t)
    np.maximum.at(widest_gap, col[1:][breaks], step[breaks])
    err = matrix.errors
    numeric_covered = ((first_value - err <= matrix.span_lo + _EPS)
                       & (last + err >= matrix.span_hi - _EPS) & (widest_gap <= 2 * err + _EPS))
    unknown = np.where(matrix.binary, n_ranges < 2, ~numeric_covered) & ~matrix.is_grasp

    ends = np.ones(len(col), dtype=bool)
    ends[:-1] = starts[1:]
    los, his = lows[starts].tolist(), highs[ends].tolist()
    bounds = np.concatenate([[0], np.cumsum(n_ranges)]).tolist()

    # the asked columns only, from here on
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
    found = Split(ranges, unknown, gains, n_ranges, counts.sum(axis=2) / max(n, 1))
    if everyone:  # every object's session starts here: work it out once per matrix
        matrix.root_splits[columns.tobytes()] = found
    else:
        matrix.remember_node_split(node_key, found)
    return found


def _node_key(rows: np.ndarray, columns: np.ndarray) -> bytes:
    """A short key for a node's partition: a digest of its rows and the columns asked
    (the partition depends on the set of rows only, and the sessions of one matrix
    pass the same node in the same order)."""
    digest = hashlib.blake2b(rows.tobytes(), digest_size=16)
    digest.update(columns.tobytes())
    return digest.digest()


def joint_gain(rows: Sequence[int], matrix: DescriptionMatrix, columns: Sequence[int],
               ranges: Sequence[Sequence[Range]], unknown: Sequence[bool]) -> float:
    """The gain of testing ``columns`` together (one procedure application): the gain of
    the product of their partitions (``ranges`` and ``unknown`` per column, as
    :func:`partition_columns` found them at this node).

    For one column it is that column's gain; a column that cannot make two branches
    adds nothing (its lone range and unknown subset would only spread missing rows).
    """
    n, k = len(rows), len(matrix.classes)
    idx = np.asarray(rows, dtype=np.int64)
    cells = np.eye(k)[matrix.class_of[idx]]  # (rows, classes x cells so far)
    for j, col_ranges, col_unknown in zip(columns, ranges, unknown):
        if len(col_ranges) < 2:
            continue
        cells = (cells[:, :, None] * _subset_weights(matrix.values[idx, j], col_ranges, col_unknown)[:, None, :]
                 ).reshape(n, -1)
    counts = cells.sum(axis=0).reshape(k, -1).T  # (cells, classes)
    totals = counts.sum(axis=0)
    remainder = float((counts.sum(axis=1) / max(n, 1) * entropy(counts)).sum())
    return max(float(entropy(totals[None, :])[0]) - remainder, 0.0)


def _subset_weights(values: np.ndarray, ranges: Sequence[Range], unknown: bool) -> np.ndarray:
    """Each row's weight in each subset of one column: 1 in the range holding its value,
    or spread evenly over every subset (the unknown one too) when the value is missing."""
    lo = np.array([r[0] for r in ranges])[None, :]
    hi = np.array([r[1] for r in ranges])[None, :]
    v = values[:, None]
    inside = ((v >= lo - _EPS) & (v <= hi + _EPS)).astype(float)
    if unknown:
        inside = np.concatenate([inside, np.zeros((len(values), 1))], axis=1)
    missing = np.isnan(values)
    inside[missing] = 1.0 / inside.shape[1]
    return inside


def entropy(counts: np.ndarray) -> np.ndarray:
    """Entropy in bits along the last axis of (fractional) class counts."""
    total = counts.sum(axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(total > 0, counts / total, 0.0)
        terms = np.where(p > 0, p * np.log2(np.where(p > 0, p, 1.0)), 0.0)
    return -terms.sum(axis=-1)

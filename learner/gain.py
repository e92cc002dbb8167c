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

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from learner.matrix import DescriptionMatrix
from learner.partition import Range

_EPS = 1e-9


@dataclass(frozen=True)
class Split:
    """Per-column partition of a node's rows: the ranges, whether an "unknown" subset
    joins them, the information gain, and each range's share of the node's weight."""

    ranges: list[list[Range]]
    unknown: np.ndarray
    gains: np.ndarray
    n_ranges: np.ndarray
    mass: np.ndarray  # (columns, max ranges): weight of each range / rows, missing rows spread


def partition_columns(rows: Sequence[int], matrix: DescriptionMatrix, columns: np.ndarray) -> Split:
    """Chain-merged ranges and information gain of ``columns`` at once.

    Only the known values are read (:attr:`DescriptionMatrix.known`), every column's one
    after another in one flat array, worked on whole and the asked columns picked at
    the end (a choice asks for nearly all of them); a column's missing rows are the
    node's rows less its known ones, counted per class by subtraction.
    """
    n, k, t = len(rows), len(matrix.classes), len(matrix.tests)
    everyone = n == len(matrix.descriptions)  # rows are distinct: the root of a whole library
    if everyone and (found := matrix.root_splits.get(columns.tobytes())) is not None:
        return found
    known = matrix.known
    row_index = np.asarray(rows, dtype=np.int64)
    totals = np.bincount(matrix.class_of[row_index], minlength=k).astype(float)
    vals, vcls, col, within = known.values, known.class_of, known.column, known.within
    if not everyone:  # keep the node's rows, still sorted by value
        member = np.zeros(len(matrix.descriptions), dtype=bool)
        member[row_index] = True
        keep = member[known.rows]
        vals, vcls, col, within = vals[keep], vcls[keep], col[keep], within[keep]
    n_known = np.bincount(col, minlength=t) if not everyone else np.diff(known.start)
    step = np.diff(vals)
    same_column = col[1:] == col[:-1]
    breaks = same_column & (step > within[1:])
    starts = np.ones(len(vals), dtype=bool)
    starts[1:] = breaks | ~same_column
    range_global = np.cumsum(starts, dtype=np.int32) - 1
    n_ranges = np.bincount(col[starts], minlength=t)
    max_r = int(n_ranges.max()) + 1 if t else 1
    first_range = (np.cumsum(n_ranges) - n_ranges).astype(np.int32)
    cell = (col * max_r + (range_global - first_range[col])) * k + vcls
    counts = np.bincount(cell, minlength=t * max_r * k).astype(float).reshape(t, max_r, k)
    missing = totals[None, :] - counts.sum(axis=1)

    # the "unknown" subset: the ranges widened by the error leave part of the domain open
    padded = np.append(vals, np.nan)  # a column with no known value reads the NaN past the end
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
    return found


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

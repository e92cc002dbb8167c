"""Noise-tolerant partitions of a feature's values, and matching a measurement to them.

Sonar values wobble within a procedure's expected error, so two observations that close
cannot be told apart: they share a branch. Merging chains (a, a+e, a+2e are one branch)
because each neighbour is indistinguishable from the next (docs/method.md §3).

A node's partition of every column at once (:class:`Split`, worked out by
``learner.choosing.gain``) is kept by the matrix it was computed on, so the type lives
here, below both.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

Range = tuple[float, float]

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


def partition(values: Iterable[float], error: float) -> list[Range]:
    """Merge sorted values into ranges ``[lo, hi]`` where neighbours are within ``error``."""
    ranges: list[Range] = []
    for v in sorted(values):
        if ranges and v - ranges[-1][1] <= error + _EPS:
            ranges[-1] = (ranges[-1][0], v)
        else:
            ranges.append((v, v))
    return ranges


def match(value: float, ranges: Sequence[Range], error: float) -> int | None:
    """The branch a measured value belongs to, or None when it is unreliable.

    It matches when it falls in exactly one branch's range widened by the feature's
    error; in none (between or beyond the ranges) or in two (where widened ranges
    overlap) it is not to be trusted, and the executive reselects.
    """
    hits = [i for i, (lo, hi) in enumerate(ranges) if lo - error - _EPS <= value <= hi + error + _EPS]
    return hits[0] if len(hits) == 1 else None


def nearest(value: float, ranges: Sequence[Range]) -> int:
    """The branch whose range is nearest the value (the last resort of docs/method.md §5)."""
    def gap(r: Range) -> float:
        lo, hi = r
        return max(lo - value, 0.0, value - hi)

    return min(range(len(ranges)), key=lambda i: (gap(ranges[i]), i))

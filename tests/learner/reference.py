"""Information gain over noise-tolerant partitions, with missing values spread evenly.

Descriptions lacking a feature are spread evenly over its subsets (plus an "unknown"
subset when the known ranges do not cover the feature's domain), so a feature few
objects were measured on scores lower: its split is less certain (docs/method.md §3).
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence


def entropy(counts: Mapping[str, float] | Iterable[float]) -> float:
    """Shannon entropy in bits of (possibly fractional) class counts."""
    weights = list(counts.values()) if isinstance(counts, Mapping) else list(counts)
    total = sum(weights)
    if total <= 0:
        return 0.0
    return -sum((w / total) * math.log2(w / total) for w in weights if w > 0)


def information_gain(
    known: Sequence[tuple[str, int]],
    missing: Sequence[str],
    n_ranges: int,
    unknown_subset: bool,
) -> float:
    """``I(F) = H(C) - sum_v p(F=v) H(C | F=v)``.

    ``known`` pairs each description's class with the index of its range; ``missing``
    lists the classes of descriptions without a value, each spread as weight ``1/k``
    over the ``k`` subsets (``n_ranges``, plus one for the unknown subset).
    """
    subsets = n_ranges + (1 if unknown_subset else 0)
    if subsets == 0:
        return 0.0
    by_subset: list[dict[str, float]] = [defaultdict(float) for _ in range(subsets)]
    totals: dict[str, float] = defaultdict(float)
    for cls, idx in known:
        by_subset[idx][cls] += 1.0
        totals[cls] += 1.0
    share = 1.0 / subsets
    for cls in missing:
        totals[cls] += 1.0
        for s in by_subset:
            s[cls] += share
    n = float(len(known) + len(missing))
    if n == 0:
        return 0.0
    remainder = sum((sum(s.values()) / n) * entropy(s) for s in by_subset)
    return max(entropy(totals) - remainder, 0.0)

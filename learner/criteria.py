"""Evaluation functions: how a test's information gain trades against its cost.

``cs-id3`` is CSL's ``I^2 / C``. The others are the usual baselines, so runs can be
compared side by side: ``id3`` ignores cost, ``idx`` is ``I / C`` (Norton 1989), and
``eg2`` is Nunez's ``(2^I - 1) / (C + 1)^w``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Criterion:
    """A named evaluation function of (gain in bits, cost in seconds); higher is better."""

    name: str
    score: Callable[[float, float], float]
    cost_sensitive: bool


def _ratio(numerator: float, cost: float) -> float:
    """A free test (its value already known) beats every paid one."""
    if cost <= 0:
        return math.inf if numerator > 0 else 0.0
    return numerator / cost


def criterion(name: str, eg2_w: float = 1.0) -> Criterion:
    """The criterion called ``name``; unknown names are rejected with the valid ones."""
    if name == "cs-id3":
        return Criterion(name, lambda i, c: _ratio(i * i, c), True)
    if name == "id3":
        return Criterion(name, lambda i, c: i, False)
    if name == "idx":
        return Criterion(name, lambda i, c: _ratio(i, c), True)
    if name == "eg2":
        if not (eg2_w >= 0 and math.isfinite(eg2_w)):
            raise ValueError(f"eg2 weight w must be a finite number >= 0, got {eg2_w}")
        return Criterion(name, lambda i, c: (2.0**i - 1.0) / (c + 1.0) ** eg2_w, True)
    raise ValueError(f"unknown criterion {name!r} (choose from: {', '.join(CRITERIA)})")


CRITERIA = ("cs-id3", "id3", "idx", "eg2")

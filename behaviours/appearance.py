"""The learner's appearance of an object from the planner's camera region.

The executive hands the learner plain values (docs/method.md §5): whether the region looks
round, its area and its elongation, measured from its pixels. A region drawn by hand
(no pixel measures) has no appearance, and nothing is ruled out by it; nor has a cluster
(two or more objects touching, docs/planner.md "Clutter"): its footprint is no one object's.
"""

from __future__ import annotations

from learner.appearance import Appearance
from planner import Region


def appearance_of(region: Region) -> Appearance | None:
    """``region``'s footprint as the learner compares it, or None when not measured or a cluster;
    to 0.001 (what a library file keeps, so a reloaded description equals the learned one)."""
    if region.cluster or region.area_in2 is None or region.elongation is None:
        return None
    return Appearance(region.round, round(region.area_in2, 3), round(region.elongation, 3))

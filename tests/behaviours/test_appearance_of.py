"""What the learner is told an object looks like (behaviours/appearance.py)."""

from __future__ import annotations

import dataclasses

from behaviours.appearance import appearance_of
from learner.appearance import Appearance
from planner import Region

# a 9 x 4 in box seen from above: 56 pixels of 0.64 in², axes 2.25 : 1
BOX = Region(((95.5, 88.0), (104.5, 88.0), (104.5, 92.0), (95.5, 92.0)), (100.0, 90.0), 56, 0.0, False,
             9.0, 4.0, area_in2=35.84, elongation=2.2512)


def test_a_measured_region_is_its_roundness_area_and_elongation_to_a_thousandth() -> None:
    assert appearance_of(BOX) == Appearance(False, 35.84, 2.251)


def test_a_region_drawn_by_hand_or_a_cluster_has_no_appearance() -> None:
    assert appearance_of(dataclasses.replace(BOX, area_in2=None, elongation=None)) is None
    assert appearance_of(dataclasses.replace(BOX, cluster=True)) is None  # two objects' footprint is no one's

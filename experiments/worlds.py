"""Floors for the experiment: one object set at random poses, a new layout per seed.

The paper tested "unseen objects in arbitrary poses"; the shipped lab has one fixed
layout, so each episode here draws its own: the set's objects shuffled over a grid of
slots, each jittered and turned at random. Slots are far enough apart that the robot
can sense one object from 24 in without touching another (the paper's objects were
"apart"), and the simulator's world loader re-checks that nothing overlaps.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from hero_driver.sim.catalogue import profile_and_catalogue

SLOT_SPACING_IN = 62.0  # centre to centre; the training floor's objects are 65-70 in apart
JITTER_IN = 6.0  # each object's centre moves up to this much from its slot, per axis
COLUMNS = 4
MARGIN_IN = 45.0  # room wall to the first slot: the robot starts in the corner


def set_members(object_set: str) -> list[str]:
    """Catalogue ids of one object set (``training``: Table 3; ``test``: the unseen ones)."""
    _, catalogue = profile_and_catalogue()
    ids = sorted(e.id for e in catalogue.values() if e.set == object_set)
    if not ids:
        raise ValueError(f"the simulator catalogue has no objects in set {object_set!r}")
    return ids


def random_floor(object_set: str, seed: int) -> dict[str, object]:
    """A world (as the JSON a world file holds) with every object of ``object_set`` at a
    random pose drawn from ``seed``."""
    ids = set_members(object_set)
    rng = np.random.default_rng(seed)
    rows = math.ceil(len(ids) / COLUMNS)
    slots = [(MARGIN_IN + c * SLOT_SPACING_IN, MARGIN_IN + r * SLOT_SPACING_IN)
             for r in range(rows) for c in range(COLUMNS)]
    order = rng.permutation(len(slots))[:len(ids)]
    objects = []
    for entry_id, slot in zip(ids, order):
        x, y = slots[int(slot)]
        objects.append({"id": entry_id,
                        "x_in": round(x + float(rng.uniform(-JITTER_IN, JITTER_IN)), 1),
                        "y_in": round(y + float(rng.uniform(-JITTER_IN, JITTER_IN)), 1),
                        "yaw_deg": round(float(rng.uniform(0.0, 360.0)), 1)})
    return {
        "about": f"experiment floor: the {object_set} objects at random poses (seed {seed})",
        "name": f"{object_set}-{seed}",
        "room": {"width_in": 2 * MARGIN_IN + (COLUMNS - 1) * SLOT_SPACING_IN,
                 "depth_in": 2 * MARGIN_IN + (rows - 1) * SLOT_SPACING_IN},
        "furniture": [],
        "robot": {"x_in": 15.0, "y_in": 15.0, "heading_deg": 45.0},
        "objects": objects,
    }


def write_floor(folder: Path, object_set: str, seed: int) -> Path:
    """:func:`random_floor` as a world file in ``folder`` (the simulator reads files)."""
    path = folder / f"{object_set}-{seed}.json"
    path.write_text(json.dumps(random_floor(object_set, seed)), encoding="utf-8")
    return path

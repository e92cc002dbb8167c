"""Which learned descriptions came from a disturbed attempt: ground truth from the
simulator set against what the executive noticed.

An object's attempt was disturbed, for this count, when the simulator disturbed it
(nudged, swapped) more often than the executive's camera check found it moved or
changed: at least one disturbance went unnoticed, so some value the session kept was
measured on an object that was no longer where, or what, the session believed. Such
a description is wrong and must never be saved; with the check on the
count is 0 by construction of the tree, and the experiment measures it with the check
off.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence

from behaviours.disturbance import CHANGED, MOVED
from behaviours.records import ObjectRecord
from hero_driver.sim.disturber import Happened
from hero_driver.sim.world import ObjectTruth


def sim_index(record: ObjectRecord, start: Sequence[ObjectTruth]) -> int:
    """The simulator's object the executive's record is about: the one nearest where
    the camera first saw it."""
    x, y = record.first_region.centroid
    return min(start, key=lambda t: math.hypot(t.x_in - x, t.y_in - y)).index


def unnoticed(records: Sequence[ObjectRecord], events: Sequence[Mapping[str, object]],
              happened: Sequence[Happened], start: Sequence[ObjectTruth]) -> list[int]:
    """The records (by index) with a disturbance the executive did not notice."""
    noticed = Counter(e.get("object") for e in events
                      if e.get("event") == "disturbance" and e.get("found") in (MOVED, CHANGED))
    disturbed = Counter(h.object for h in happened)
    return [r.index for r in records if disturbed[sim_index(r, start)] > noticed[r.index]]


def saved_from_disturbed(records: Sequence[ObjectRecord], events: Sequence[Mapping[str, object]],
                         happened: Sequence[Happened], start: Sequence[ObjectTruth]) -> int:
    """How many descriptions the learner saved from disturbed attempts."""
    bad = set(unnoticed(records, events, happened, start))
    return sum(1 for r in records if r.learned_id is not None and r.index in bad)

"""Whether this robot can use a library: every grasp and feature known, every value in
its feature's domain.

The format (``learner.library.format``) checks a document's shape, which needs no
robot; this check needs the robot's knowledge, and is made on import, before a run and
by the learner service before it admits a description, so a bad entry is refused at
the door rather than failing a tree later.
"""

from __future__ import annotations

from collections.abc import Iterable

from learner.description import ObjectDescription
from learner.knowledge import Knowledge


def check_library(descriptions: Iterable[ObjectDescription], knowledge: Knowledge, source: str) -> None:
    """Reject descriptions this robot cannot use: an unknown grasp or feature, or a value
    outside the feature's domain. Checked on import and before a run, so a bad entry
    is refused at the door rather than failing a tree later."""
    for d in descriptions:
        where = f"{source}: description {d.object_id!r}"
        if not knowledge.has_grasp(d.grasp):
            raise ValueError(f"{where}: grasp {d.grasp!r} is not in the knowledge file {knowledge.source}")
        for o in d.observations:
            if not knowledge.has_feature(o.feature):
                raise ValueError(f"{where}: feature {o.feature!r} is not yielded by any sensing procedure "
                                 f"in {knowledge.source}")
            spec = knowledge.feature(o.feature)
            if spec.binary and o.value not in (0.0, 1.0):
                raise ValueError(f"{where}: {o.feature} is 0 or 1, got {o.value:g}")
            lo, hi = spec.span
            if not spec.binary and not lo - spec.error <= o.value <= hi + spec.error:
                raise ValueError(f"{where}: {o.feature}{o.position} = {o.value:g} is outside [{lo:g}, {hi:g}]")

"""Which grasps pick an object up, and what a failed grasp does to it.

Success is decided by the catalogue's truth (the grasp and the approach), not by a
physical finger model: the learner only ever sees the finger sensor's yes/no, and the
paper's classes are defined by which grasp works. Side effects are drawn from the
entry's probabilities with the world's seeded generator, so a run is repeatable.
"""

from __future__ import annotations

import numpy as np

from hero_driver.sim.catalogue import CatalogueEntry

NO_GRAB = "No-Grab"  # the class of objects left alone: the procedure touches nothing

NOTHING, PUSHED, KNOCKED_OVER, JAMMED, LIFTED = "nothing", "pushed", "knocked_over", "jammed", "lifted"


def picks_up(entry: CatalogueEntry, procedure: str, end_on: bool) -> bool:
    """Whether ``procedure`` lifts the object when approached end-on (or from the side).

    No-Grab never lifts anything, so the finger sensor reports failure even on a
    No-Grab object: "success" there means leaving it alone, which the executive
    recognises from the procedure name, not from the fingers.
    """
    if procedure == NO_GRAB:
        return False
    for rule in entry.grasps:
        if rule.procedure == procedure and (rule.approach == "any" or (rule.approach == "end") == end_on):
            return True
    return False


def failure_effect(entry: CatalogueEntry, procedure: str, rng: np.random.Generator) -> str:
    """What a failed ``procedure`` does: jam (listed in the entry's jams: the fingers
    stop on the object, nothing moves), knock over, push, or nothing. No-Grab touches
    nothing. One uniform draw per failed grasp keeps the random stream aligned."""
    if procedure == NO_GRAB:
        return NOTHING
    effects = entry.side_effects
    if procedure in effects.jams:
        return JAMMED
    draw = float(rng.random())
    if draw < effects.knock_over_p:
        return KNOCKED_OVER
    if draw < effects.knock_over_p + effects.push_p:
        return PUSHED
    return NOTHING

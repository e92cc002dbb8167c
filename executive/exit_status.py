"""What ``csl``'s exit status tells a script, in one place (README "Exit status").

A run is judged by its objects, not by the behaviour tree's status: the tree succeeds
once every object has been *dealt with*, which includes giving up on one. A script
that runs ``csl run`` unattended needs to know that an object was left on the floor,
and whether to fix its own arguments (2) or to look at the robot or the learner (3).
"""

from __future__ import annotations

from collections.abc import Sequence

ALL_HANDLED = 0
"""Every object located was grasped (or left, for a grasp the robot cannot confirm)."""
SOME_FAILED = 1
"""At least one object was not handled, or none was located."""
BAD_INPUT = 2
"""A file, flag or argument is wrong: nothing was started (one line says which)."""
LOST = 3
"""The robot's driver or the learner service refused, vanished or could not be reached."""

HANDLED_OUTCOMES = frozenset({"grasped", "left"})
NOT_FAILED = HANDLED_OUTCOMES | {"gone"}
"""Handled, or ``gone``: taken away while the robot worked on it (docs/executive.md,
"Disturbances"), which no executive could retrieve: reported, not a failure."""


def episode_status(outcomes: Sequence[str | None]) -> tuple[int, str]:
    """The exit status of an episode whose objects ended with ``outcomes`` (None: the
    object never finished), and the line that says why.

    No object at all is a failure too: a camera that sees nothing is more often a broken
    camera (or a driver drawing objects in the wrong grey) than an empty floor, and a
    script must not read "nothing done" as "done".
    """
    if not outcomes:
        return SOME_FAILED, "no object was located on the floor: nothing was retrieved"
    missed = [o for o in outcomes if o not in NOT_FAILED]
    if missed:
        return SOME_FAILED, f"{len(missed)} of {len(outcomes)} objects were not handled"
    gone = outcomes.count("gone")
    if gone:
        return ALL_HANDLED, f"{len(outcomes) - gone} of {len(outcomes)} objects were handled, {gone} gone (taken away)"
    return ALL_HANDLED, f"all {len(outcomes)} objects were handled"

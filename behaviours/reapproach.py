"""A procedure refused as out of range: re-approach its position and try it again.

A driver refuses a sensing or grasping procedure ``out_of_range`` when the object is not
within the procedure's distance of the sonar: nothing was tried. The robot then stands
off the position its dead reckoning claims (drift the look before the verb corrected,
docs/simulator.md "Drift"), so counting the refusal as a failed grasp would drop the
right grasp, and counting it as an unusable test would lose every test at that
position. Each verb that can be refused so sits in a branch (:func:`reapproached`)
that ``csl bt`` shows::

    ApplyTest or re-approach     (or Grasp ...)
      ApplyTest                  the verb; a refusal for range is recorded on the step
      re-approach
        RefusedForRange?         refused for range, a try left, and a look has
                                 corrected the pose since the robot arrived
        Reapproach               counted (event ``reapproach``); the step ends

The next step's move then drives to the same position, planned from where the camera
last placed the robot (``MoveTo``, ``ObjectRecord.off_position``), and the verb is
tried again. Only when a look has corrected the pose since the robot arrived: else the
same plan from the same pose would end where it stands. Bounded by
``Params.reapproach_tries`` per procedure and object; past it, or with nothing
corrected, ``RefusedForRange?`` counts the refusal as the verb failing, as every
refusal counted before (the grasp failed, or the test is unusable here).
"""

from __future__ import annotations


import py_trees
from py_trees.common import Status
from py_trees.composites import Selector, Sequence

from behaviours.actions import count_verb_failed
from behaviours.base import CslBehaviour, DriverAction
from behaviours.events import Event
from behaviours.records import ObjectRecord, Refusal


class RefusedForRange(CslBehaviour):
    """Condition ``RefusedForRange?``: the step's verb was refused as out of range
    (``Step.refusal``) and a re-approach may help. When it may not (tries spent, or no
    look corrected the pose), the refusal counts as the verb failing and it fails."""

    def __init__(self, robot: str, name: str = "RefusedForRange?") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        refusal = self.step.refusal
        if refusal is None:
            self.feedback_message = "not refused for range"
            return Status.FAILURE
        obj = self.obj
        why_not = self._why_not(obj, refusal)
        if why_not is None:
            self.feedback_message = f"{refusal.procedure} refused for range: re-approach"
            return Status.SUCCESS
        count_verb_failed(self.step, obj, refusal.grasp)
        self.feedback_message = f"{refusal.procedure} refused for range, counted as failed: {why_not}"
        return Status.FAILURE

    def _why_not(self, obj: ObjectRecord, refusal: Refusal) -> str | None:
        if obj.reapproaches[refusal.procedure] >= self.services.params.reapproach_tries:
            return "no re-approach left"
        if obj.arrived is not None and self.bb.pose == obj.arrived:
            return "nothing has corrected where the robot stands since it arrived"
        return None


class Reapproach(CslBehaviour):
    """Mark the object off position so the next step's move drives to the same position
    again, count the re-approach and log it (``reapproach``, under the name of the
    behaviour whose verb was refused); fails, so the step under way ends."""

    def __init__(self, robot: str, name: str = "Reapproach") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        obj, refusal = self.obj, self.step.refusal
        assert refusal is not None
        obj.reapproaches[refusal.procedure] += 1
        obj.off_position = True
        obj.ledger.recoveries["re-approach"] += 1
        self.services.log.event(Event.REAPPROACH, object=obj.index, behaviour=refusal.by,
                                procedure=refusal.procedure, tries=obj.reapproaches[refusal.procedure],
                                message=refusal.message)
        self.feedback_message = f"re-approach for {refusal.procedure} (try {obj.reapproaches[refusal.procedure]})"
        return Status.FAILURE


def reapproached(robot: str, action: DriverAction) -> py_trees.behaviour.Behaviour:
    """``action`` (a sensing or a grasp) with the re-approach branch: see the module docstring."""
    return Selector(f"{action.name} or re-approach", memory=True, children=[
        action, Sequence("re-approach", memory=True, children=[RefusedForRange(robot), Reapproach(robot)])])

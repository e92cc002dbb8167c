"""Whether a state publication can be true: a state that nothing the client asked of the
robot explains is refused, not believed.

Anyone who can publish on ``hero/<robot>/state`` could steer a client that takes every
publication at its word (a pose far from the robot, a battery about to run out). The
router's access control keeps other identities off the key (docs/security.md); this is
the check beyond it, on what a publication says: the pose moves only while a verb that
moves the robot (``move``, ``reset``, ``charge``) is under way or has just answered; the
battery rises only with ``charge`` or ``reset``; the clock runs backwards only after a
``reset``. A driver's own publications always pass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hero_driver.interface import RobotState

MOVES_ROBOT = frozenset({"move", "reset", "charge"})  # verbs after which the pose may differ
CHARGES = frozenset({"charge", "reset"})  # verbs after which the battery may be fuller
RESETS_CLOCK = frozenset({"reset"})
POSE_SLACK_IN = 2.0  # inches the pose may wander with no move: a real base's odometry settling
HEADING_SLACK_DEG = 2.0
BATTERY_SLACK = 0.005  # a gauge's own jitter upwards


@dataclass
class StateCheck:
    """The last state believed, and the verbs that could have changed it since: those
    under way (``started``, counted) and those answered since it was believed."""

    last: RobotState | None = None
    under_way: dict[str, int] = field(default_factory=dict)
    answered: set[str] = field(default_factory=set)

    def started(self, verb: str) -> None:
        self.under_way[verb] = self.under_way.get(verb, 0) + 1

    def finished(self, verb: str) -> None:
        if self.under_way.get(verb, 0) > 0:
            self.under_way[verb] -= 1
        self.answered.add(verb)

    def forget(self) -> None:
        """A new driver (or none): its first state is believed as it comes."""
        self.last, self.under_way, self.answered = None, {}, set()

    def judge(self, state: RobotState) -> str:
        """Why ``state`` cannot be true ("" when it can); a state that can is believed."""
        why = "" if self.last is None else self._impossible(self.last, state)
        if not why:
            self.last, self.answered = state, set()
        return why

    def _may(self, verbs: frozenset[str]) -> bool:
        return any(self.under_way.get(v, 0) > 0 or v in self.answered for v in verbs)

    def _impossible(self, last: RobotState, state: RobotState) -> str:
        a, b = last.pose, state.pose
        moved_in = math.hypot(b.x_in - a.x_in, b.y_in - a.y_in)
        turned = abs((b.heading_deg - a.heading_deg + 180.0) % 360.0 - 180.0)
        if (moved_in > POSE_SLACK_IN or turned > HEADING_SLACK_DEG) and not self._may(MOVES_ROBOT):
            return (f"the pose moved {moved_in:.1f} in and turned {turned:.1f} deg, to ({b.x_in:.1f}, {b.y_in:.1f}, "
                    f"{b.heading_deg:.1f} deg), with no move, reset or charge under way")
        if state.battery > last.battery + BATTERY_SLACK and not self._may(CHARGES):
            return f"the battery rose from {last.battery:.3f} to {state.battery:.3f} with no charge"
        if state.clock_s < last.clock_s and not self._may(RESETS_CLOCK):
            return f"the clock went back from {last.clock_s:.1f} to {state.clock_s:.1f} s with no reset"
        return ""

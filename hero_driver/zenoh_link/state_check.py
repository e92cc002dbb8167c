"""Whether a state publication can be true: a state that nothing the client asked of the
robot explains is refused, not believed.

Anyone who can publish on ``hero/<robot>/state`` could steer a client that takes every
publication at its word (a pose far from the robot, a battery about to run out). The
router's access control keeps other identities off the key (docs/security.md); this is
the check beyond it, on what a publication says: the pose moves only while a verb that
moves the robot (``move``, ``reset``, ``charge``) is under way or has just answered; the
battery rises only with ``charge`` or ``reset``. A driver's own publications always pass.

A publication whose clock is behind the last believed state's, with no ``reset`` to
explain it, is *stale*: made before that state and delivered after it (a verb's reply
is believed when it comes, and the publications the driver made while the verb ran may
reach the client later on a loaded machine). It is dropped, neither believed nor
refused: its pose and battery are the robot's past, and judging them against the
present would count an honest driver's publications as forgeries. A forger gains
nothing by it either: a stale state is never believed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hero_driver.interface import Pose, RobotState

MOVES_ROBOT = frozenset({"move", "reset", "charge"})  # verbs after which the pose may differ
CHARGES = frozenset({"charge", "reset"})  # verbs after which the battery may be fuller
RESETS_CLOCK = frozenset({"reset"})
SETTLING_STATES = 10
"""Believed publications an answered verb's allowance outlasts while they have not yet
reached the pose its reply gave: publications made while it ran may arrive after its
reply (a loaded machine, a busy router), and the one with the final pose after them."""
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
    settles_at: Pose | None = None  # the pose an answered verb's reply gave, not yet published
    settling: int = 0  # believed publications since, while they have not reached it

    def started(self, verb: str) -> None:
        self.under_way[verb] = self.under_way.get(verb, 0) + 1

    def finished(self, verb: str, pose: Pose | None = None) -> None:
        """``verb`` answered; ``pose``: where its reply says the robot ended (a move's),
        so the allowance lasts until a publication reaches it, not one publication."""
        if self.under_way.get(verb, 0) > 0:
            self.under_way[verb] -= 1
        self.answered.add(verb)
        if pose is not None:
            self.settles_at, self.settling = pose, 0

    def forget(self) -> None:
        """A new driver (or none): its first state is believed as it comes."""
        self.last, self.under_way, self.answered, self.settles_at = None, {}, set(), None

    def stale(self, state: RobotState) -> bool:
        """Whether ``state`` is older than the last state believed (the module docstring):
        its clock behind, with no ``reset`` under way or just answered."""
        return self.last is not None and state.clock_s < self.last.clock_s and not self._may(RESETS_CLOCK)

    def judge(self, state: RobotState) -> str:
        """Why ``state`` cannot be true ("" when it can); a state that can is believed.
        Ask :meth:`stale` first: a stale state is to be dropped, not judged."""
        why = "" if self.last is None else self._impossible(self.last, state)
        if not why:
            self.last = state
            self._settle(state.pose)
        return why

    def _settle(self, pose: Pose) -> None:
        """After a believed publication: the answered verbs' allowance ends, unless a
        reply's pose is still to be published (then after :data:`SETTLING_STATES`)."""
        if self.settles_at is not None:
            self.settling += 1
            if _apart(self.settles_at, pose) is not None and self.settling < SETTLING_STATES:
                return
            self.settles_at = None
        self.answered = set()

    def _may(self, verbs: frozenset[str]) -> bool:
        return any(self.under_way.get(v, 0) > 0 or v in self.answered for v in verbs)

    def _impossible(self, last: RobotState, state: RobotState) -> str:
        b = state.pose
        apart = _apart(last.pose, b)
        if apart is not None and not self._may(MOVES_ROBOT):
            moved_in, turned = apart
            return (f"the pose moved {moved_in:.1f} in and turned {turned:.1f} deg, to ({b.x_in:.1f}, {b.y_in:.1f}, "
                    f"{b.heading_deg:.1f} deg), with no move, reset or charge under way")
        if state.battery > last.battery + BATTERY_SLACK and not self._may(CHARGES):
            return f"the battery rose from {last.battery:.3f} to {state.battery:.3f} with no charge"
        return ""


def _apart(a: Pose, b: Pose) -> tuple[float, float] | None:
    """How far apart two poses are (inches, degrees), or None when within the slack."""
    moved_in = math.hypot(b.x_in - a.x_in, b.y_in - a.y_in)
    turned = abs((b.heading_deg - a.heading_deg + 180.0) % 360.0 - 180.0)
    return (moved_in, turned) if moved_in > POSE_SLACK_IN or turned > HEADING_SLACK_DEG else None

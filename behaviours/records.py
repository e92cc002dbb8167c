"""What the tree knows while it runs: one record per object, one per recognition step.

Per-object facts (its region, run-time session, costs, outcome) live in
:class:`ObjectRecord` for the whole object. What one step decided (the test chosen, the
values it yielded, the grasp tried, what the camera saw after a failure) lives in a
:class:`Step` that the episode loop replaces in one line at every step, so nothing from
an earlier step can leak into the next. Each field names its one writer. What the
learner knows (which values were unreliable, what is still consistent) is owned by the
learner's session, not copied here.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field

import py_trees

from behaviours.bridge import PlannerMoveCost
from behaviours.services import namespace
from hero_driver.interface import Pose as DriverPose
from learner.choosing.node import ScoredTest
from learner.position import Position
from learner.runtime import RecognitionSession
from planner import Region


@dataclass
class Ledger:
    """Robot seconds by kind for one object, and the computation spent choosing."""

    moving_s: float = 0.0
    sensing_s: float = 0.0
    grasping_s: float = 0.0
    computing_s: float = 0.0  # wall seconds in the learner and planner
    tests: list[str] = field(default_factory=list)
    """Every test applied to recognize the object, as ``test=value``: each paid sensing
    procedure and each grasp tried as a binary feature (=1 held, =0 did not). A value
    re-used for free, a grasp executed at a leaf, and the measurements taken after a wrong
    prediction to learn (Discriminate) are not tests: the report's ``tests`` column counts these."""
    recoveries: Counter[str] = field(default_factory=Counter)

    @property
    def robot_s(self) -> float:
        return self.moving_s + self.sensing_s + self.grasping_s


@dataclass(frozen=True)
class GraspAttempt:
    """A grasp tried in the current step: at a leaf, or as a feature (``as_feature``).

    ``success`` is None until the grasp was executed (or found unreachable).
    """

    grasp: str
    position: Position
    as_feature: ScoredTest | None = None
    success: bool | None = None

    @property
    def failed(self) -> bool:
        return self.success is False


@dataclass(frozen=True)
class Refusal:
    """A procedure the driver refused as out of range (nothing was tried): which, whether
    it is a grasp, the driver's words, and the behaviour that sent it."""

    procedure: str
    grasp: bool
    message: str
    by: str


@dataclass
class Step:
    """What one recognition step decided; replaced by the loop before every step."""

    test: ScoredTest | None = None  # the choosers: BestTest, Reselect, Backtrack
    values: Mapping[str, float | None] | None = None  # ApplyTest: what the procedure yielded
    no_alternative: bool = False  # Backtrack: nothing reliable is left to choose up to the root
    attempt: GraspAttempt | None = None  # chosen by ChooseGrasp/AmbiguousLeaf/the choosers; its
    #   success set by whoever executed or gave up on it (Grasp, ApplyTest, MoveTo, OtherEnd)
    side_effect: str | None = None  # SideEffects?: pushed | changed | None
    refusal: Refusal | None = None  # DriverAction.refused_for_range (ApplyTest, Grasp): read by RefusedForRange?


@dataclass
class ObjectRecord:
    """One object being approached and recognized: its region, session, and costs."""

    index: int
    region: Region  # where it is now (SideEffects? follows it when pushed)
    pixels_before: int
    session: RecognitionSession
    estimator: PlannerMoveCost
    first_region: Region  # where it was first seen
    ledger: Ledger = field(default_factory=Ledger)
    outcome: str | None = None  # grasped | left | failed
    grasp: str | None = None
    grasp_position: Position | None = None
    learned_id: str | None = None  # Learn
    steps: int = 0  # UntilHandled
    off_position: bool = False  # a verb refused as out of range: the robot is not where the session
    #   says, so the next move drives even to the position it believes it stands at (set by
    #   Reapproach, behaviours.reapproach; cleared by MoveTo)
    arrived: DriverPose | None = None  # MoveTo: where its last move ended, before any look corrected it
    reapproaches: Counter[str] = field(default_factory=Counter)  # re-approaches per procedure refused
    verified: bool = True  # False from a grasp reported held until GraspVerified? checked it (finish, and
    #   GraspVerified?, behaviours.verified_grasp)

    @property
    def done(self) -> bool:
        return self.outcome is not None

    @property
    def clustered(self) -> bool:
        """Vision saw touching objects as this one region, when first seen or since
        (``Region.cluster``, docs/planner.md "Clutter")."""
        return self.region.cluster or self.first_region.cluster

    @property
    def settled(self) -> bool:
        """Done, and a grasp reported held checked by the camera: what the run may report."""
        return self.done and self.verified

    def finish(self, outcome: str, grasp: str | None = None, position: Position | None = None) -> None:
        """The object is handled (grasped, left) or given up on (failed); a grasp is
        the driver's word until the camera verified it."""
        self.outcome, self.grasp, self.grasp_position = outcome, grasp, position
        self.verified = outcome != "grasped"


DRIVER_LOST = "driver_lost"
"""Blackboard: the verb under way lost with its driver (a :class:`LostVerb`; None: none).
Written by ``behaviours.base.DriverAction``, read by the reconnect branch (``behaviours.reconnect``)."""
DRIVER_BACK = "driver_back"
"""Blackboard: the :class:`LostVerb` for which a driver came back and the objects were
located again. Written by ``LocateAgain`` (``behaviours.reconnect``), read by the
action whose verb was lost, which then ends."""


@dataclass(frozen=True, eq=False)
class LostVerb:
    """A verb lost with its driver: which behaviour sent it, and since when (by the
    services' clock). Compared by identity: each loss is its own."""

    behaviour: str
    since: float


def reset_blackboard(robot: str) -> None:
    """The robot's blackboard keys as an episode starts: no objects located yet, no
    results, no object or step under way, no pose known, no driver lost; and nothing
    else an earlier episode of this process left under the robot's namespace (the
    blackboard is py_trees' process-wide store: an onboard tree's exploration keys, a
    view or the seconds explored, must not carry into the next episode)."""
    prefix = f"{namespace(robot)}/"
    for stale in [key for key in py_trees.blackboard.Blackboard.storage if key.startswith(prefix)]:
        py_trees.blackboard.Blackboard.unset(stale)
    for key, value in (("objects", []), ("results", []), ("object", None), ("step", Step()), ("pose", None),
                       (DRIVER_LOST, None), (DRIVER_BACK, None)):
        py_trees.blackboard.Blackboard.set(f"{namespace(robot)}/{key}", value)

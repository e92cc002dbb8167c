"""What each grasp attempt actually cost, read from the episode's events, and which of
them the learner may count (docs/method.md §5.7).

The learner keeps per-grasp cost totals (``learner.costs.GraspCostRecord``); what one
attempt cost is the executive's to say, and its log already holds every grasp with its
outcome and robot seconds. An attempt costs the grasp's own seconds; a failure that
*changed* the object (knocked over: the camera saw a new region, the session starts
over with everything sensed void) also costs the sensing it voided, since that must be
paid again. A push or a clean failure voids nothing measured, so costs no more here
(the moves that follow are priced by the planner as any move). This is the recovery
cost the paper's knowledge folded into its side-effect penalty.

An object the world disturbed (someone moved, swapped or took it: a ``disturbance``
event, ``behaviours.disturbance``) is not counted at all: what its grasps cost says
how the world behaved, not what the grasp costs on this robot.

Nor is an attempt whose duration is implausible against its procedure's ``time_s`` in
the robot profile (more than :data:`DURATION_FACTOR` times longer or shorter): a
driver reporting milliseconds, or minutes, would otherwise price that grasp for every
later object. Each one left out is a ``grasp_cost_ignored`` event, and the run's
closing lines count them (``executive.exit_status``).
"""

from __future__ import annotations

import uuid
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from behaviours.events import Event
from behaviours.records import ObjectRecord
from behaviours.services import EventSink, LibraryMatrix
from learner.costs import DURATION_FACTOR, implausible_attempt, with_learned_grasp_costs
from learner.knowledge import Knowledge
from learner.service.interface import KeepsGraspCosts




@dataclass(frozen=True)
class AttemptCost:
    """One executed grasp: which, on which object, whether it held, what it cost."""

    object: int
    grasp: str
    success: bool
    seconds: float

    def as_record(self) -> tuple[str, float, bool]:
        """``(grasp, seconds, success)`` as the library store records an attempt."""
        return self.grasp, self.seconds, self.success


def attempt_costs(events: Iterable[Mapping[str, object]]) -> list[AttemptCost]:
    """Every grasp the robot executed in ``events`` (in order), failures charged with
    the sensing a start-over of a changed object voided (module docstring)."""
    sensed: dict[int, float] = defaultdict(float)  # robot seconds sensed per object since its last change
    out: list[AttemptCost] = []
    last_failure: dict[int, int] = {}  # object -> index in out of its latest failed attempt
    for event in events:
        index, kind = event.get("object"), event.get("event")
        if not isinstance(index, int):
            continue
        seconds = event.get("seconds")
        if kind in (Event.SENSE, Event.DISCRIMINATE) and isinstance(seconds, (int, float)):
            sensed[index] += float(seconds)
        elif kind == Event.GRASP and isinstance(seconds, (int, float)):
            success = bool(event.get("success"))
            out.append(AttemptCost(index, str(event.get("grasp")), success, float(seconds)))
            if success:
                last_failure.pop(index, None)
            else:
                last_failure[index] = len(out) - 1
        elif kind == Event.START_OVER and event.get("changed") and index in last_failure:
            i = last_failure.pop(index)
            failed = out[i]
            out[i] = AttemptCost(failed.object, failed.grasp, False, failed.seconds + sensed[index])
            sensed[index] = 0.0
    return out


def plausible_duration(grasp: str, seconds: float, knowledge: Knowledge) -> bool:
    """Whether a ``grasp`` the driver says took ``seconds`` lies within
    :data:`DURATION_FACTOR` of the procedure's ``time_s`` either way (a grasp the profile
    prices at 0 s, or does not know, takes no judging: nothing to compare with)."""
    return implausible_attempt(knowledge, grasp, seconds, success=True) is None  # a held grasp's bounds: its own


def implausible_grasps(events: Iterable[Mapping[str, object]], knowledge: Knowledge) -> list[Mapping[str, object]]:
    """The ``grasp`` events of ``events`` whose seconds are implausible (:func:`plausible_duration`)."""
    return [e for e in events if e.get("event") == Event.GRASP and isinstance(s := e.get("seconds"), (int, float))
            and not plausible_duration(str(e.get("grasp")), float(s), knowledge)]


def disturbed_objects(events: Iterable[Mapping[str, object]]) -> frozenset[int]:
    """The objects the camera check found moved, changed or gone at least once."""
    return frozenset(index for e in events
                     if e.get("event") == Event.DISTURBANCE and isinstance(index := e.get("object"), int))


def recordable_attempts(events: Iterable[Mapping[str, object]], objects: Iterable[int]) -> list[AttemptCost]:
    """The attempts on ``objects`` the learner may count: each object's grasps as
    :func:`attempt_costs` prices them, none of an object that was disturbed."""
    events = list(events)
    wanted = set(objects) - disturbed_objects(events)
    return attempt_costs(e for e in events if e.get("object") in wanted)


class LearnedGraspCosts:
    """The executive's side of learned grasp costs (docs/method.md §5.7): after each
    object, its attempts go to the learner (under a key made once per object, so a
    retried record never counts twice), and the learner's choices from the next object
    on are priced by every record so far, the knowledge file's costs the prior."""

    def __init__(self, learner: KeepsGraspCosts, knowledge: Knowledge, library: LibraryMatrix,
                 events: Sequence[Mapping[str, object]], log: EventSink | None = None,
                 robot: str | None = None) -> None:
        """``log`` hears of each attempt left out for an implausible duration
        (``grasp_cost_ignored``); None: nobody is told. ``robot``: whose attempts they
        are, one robot's weight in the fleet's prices (None: unnamed)."""
        self.learner, self.knowledge, self.library, self.events = learner, knowledge, library, events
        self.robot = robot
        self.log = log
        self._episode = uuid.uuid4().hex  # keys are this episode's object indices under it
        self.reprice()

    def reprice(self) -> None:
        """Price the learner's choices by what the grasps have cost so far."""
        self.library.priced_by(with_learned_grasp_costs(self.knowledge, self.learner.grasp_costs()))

    def finished(self, record: ObjectRecord) -> list[AttemptCost]:
        """Record what ``record``'s grasps cost (none when it was disturbed, none whose
        duration is implausible) and reprice; returns what was recorded."""
        ignored = implausible_grasps((e for e in self.events if e.get("object") == record.index), self.knowledge)
        for event in ignored:
            if self.log is not None:
                grasp = str(event.get("grasp"))
                self.log.event(Event.GRASP_COST_IGNORED, object=record.index, behaviour="LearnedGraspCosts",
                               grasp=grasp, seconds=event.get("seconds"),
                               expected=self.knowledge.grasp(grasp).time_s, factor=DURATION_FACTOR)
        attempts = recordable_attempts((e for e in self.events if not any(e is i for i in ignored)), [record.index])
        # what the learner would refuse (a failure with more voided sensing than any robot
        # pays): left out here, said, so one object's record never fails the whole batch
        refused = [a for a in attempts if implausible_attempt(self.knowledge, a.grasp, a.seconds, a.success)]
        attempts = [a for a in attempts if a not in refused]
        for a in refused:
            if self.log is not None:
                self.log.event(Event.GRASP_COST_IGNORED, object=record.index, behaviour="LearnedGraspCosts",
                               grasp=a.grasp, seconds=round(a.seconds, 1), expected=self.knowledge.grasp(a.grasp).time_s,
                               factor=DURATION_FACTOR)
        if attempts:
            self.learner.record_grasp_attempts([a.as_record() for a in attempts],
                                               key=f"{self._episode}/{record.index}", robot=self.robot)
            self.reprice()
        return attempts

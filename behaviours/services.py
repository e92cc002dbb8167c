"""What a behaviour may call: the executive's dependencies, handed in at ``setup()``.

The tree is built without resources (``executive.behaviour_tree.build_tree``) and the services
arrive through ``BehaviourTree.setup(services=...)``, as py_trees intends: a tree can
be drawn, snapshot and tested without a robot, a planner or a library. Everything here
is a dependency or a setting; what changes while the tree runs (objects, steps, where
the robot stands) lives on the blackboard (``behaviours.records``).
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

from behaviours.perception import CeilingCamera, Perception
from hero_driver.interface import Driver
from learner.choosing.criteria import Criterion
from learner.choosing.matrix import DescriptionMatrix
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.service.interface import LearnerService
from planner import Navigator
from robot_profile import ProfileStamp

NAMESPACE = "/csl"


def namespace(robot: str) -> str:
    """Blackboard namespace of one robot's tree (two robots never share keys)."""
    return f"{NAMESPACE}/{robot}"


@dataclass(frozen=True)
class Params:
    """The control strategies' knobs (docs/method.md §5): what a run may set. Thresholds
    no run changes are constants where they are used (:mod:`behaviours.sameness`,
    :data:`executive.executive.OVERDUE_WAIT_S`)."""

    max_alternatives: int = 3  # N: alternatives tried at a node before backtracking
    nearest_after: int | None = None  # unreliable values before nearest neighbour; None: last resort
    max_steps: int = 40  # recognition steps per object before giving up
    seed: int = 0  # for choices the criterion leaves to chance; object i draws from seed + i
    use_appearance: bool = True  # rule candidates out by the camera's area and elongation, free (results §7)
    battery_low: float = 0.2  # below this charge the guard sends the robot to its dock; 0: guard off
    price_detours: bool = False  # price the dock detour into moves that would cross battery_low (battery_cost.py)
    wait_driver_s: float = 0.0  # a lost driver: wait this long for one under the same name; 0: stop at once
    check_in_place: bool = True  # a camera look before each sensing and grasp (behaviours.disturbance)
    localise: bool = True  # correct the driver's dead reckoning by the robot in each image (behaviours.localisation)
    beam_check: bool = True  # a test whose sonar beam meets another object is unusable there (behaviours.clutter)
    learned_grasp_costs: bool = True  # record each object's grasp costs and price grasps by them (method §5.7)
    blocked_tries: int = 8  # a move a moving obstacle blocked: re-planned or retried this often; 0: branch off
    blocked_wait_s: float = 20.0  # and before a retry, the robot waits this long for the obstacle to pass
    reapproach_tries: int = 2  # a procedure refused as out of range: re-approached and tried again this
    #   often per object, then the refusal counts as the verb failing; 0: at once (behaviours.reapproach)
    max_views: int = 200  # exploring without a ceiling camera: rounds (look, go to the next view) at most
    verify_grasps: bool = True  # a grasp reported held: one camera look that it left the floor
    #   (behaviours.verified_grasp); off: the driver's word, and no image taken


class GivenUp:
    """The objects given up because the robot left one of their verbs unanswered: no
    further verb is sent for them (the rest of their step only decides, then ends)."""

    def __init__(self) -> None:
        self._records: list[object] = []

    def add(self, record: object) -> None:
        self._records.append(record)

    def __contains__(self, record: object) -> bool:
        return any(given is record for given in self._records)  # by identity: records are not hashable


class EventSink(Protocol):
    """Where behaviours report what they decided, measured and paid (the episode log)."""

    def event(self, kind: str, **data: object) -> None: ...


class LibraryMatrix:
    """The learner's library as a description matrix, changed only when its version
    changed: every object of an episode shares one matrix until something is learned,
    and what was learned is appended to it (the library only grows), not rebuilt."""

    def __init__(self, learner: LearnerService, knowledge: Knowledge) -> None:
        self._learner, self._knowledge = learner, knowledge
        self._built: tuple[int, DescriptionMatrix] | None = None

    @property
    def knowledge(self) -> Knowledge:
        """What the learner's choices are priced by."""
        return self._knowledge

    def priced_by(self, knowledge: Knowledge) -> None:
        """Price the choices of objects started from now on by ``knowledge`` (the same
        robot, its grasps priced by what they cost: docs/method.md §5.7). Prices are
        read at choice time and change no value in the matrix, so the matrix is the same
        rows under new prices, not rebuilt; a session under way keeps the one it has."""
        self._knowledge = knowledge
        if self._built is not None:
            repriced = copy.copy(self._built[1])
            repriced.knowledge = knowledge
            self._built = (self._built[0], repriced)

    def current(self) -> DescriptionMatrix:
        version = self._learner.version()
        if self._built is None or self._built[0] != version:
            snapshot = self._learner.library()
            self._built = (snapshot.version, self._grown(snapshot.descriptions))
        return self._built[1]

    def _grown(self, descriptions: Sequence[ObjectDescription]) -> DescriptionMatrix:
        """The current matrix with the new descriptions appended when ``descriptions``
        extends what it holds; built anew otherwise (a first library, a swapped one)."""
        grown = None if self._built is None else self._built[1].extended_to(descriptions)
        return grown if grown is not None else DescriptionMatrix(descriptions, self._knowledge)


@dataclass(frozen=True)
class Services:
    """Everything a behaviour may call, shared by the whole tree."""

    driver: Driver
    navigator: Navigator
    learner: LearnerService
    knowledge: Knowledge
    criterion: Criterion
    params: Params
    log: EventSink
    library: LibraryMatrix
    clock: Callable[[], float] = field(default=time.perf_counter)
    given_up: GivenUp = field(default_factory=GivenUp)
    served: ProfileStamp | None = None  # the robot profile the driver said it served at the start (None: unsaid)
    perception: Perception = None  # type: ignore[assignment]  # how looks are taken; None: the ceiling camera

    def __post_init__(self) -> None:
        if self.perception is None:
            object.__setattr__(self, "perception", CeilingCamera(self.driver, self.navigator))

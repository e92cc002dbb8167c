"""What ``csl``'s exit status tells a script, in one place (README "Exit status").

A run is judged by its objects, not by the behaviour tree's status: the tree succeeds
once every object has been *dealt with*, which includes giving up on one. A script
that runs ``csl run`` unattended needs to know that an object was left on the floor,
and whether to fix its own arguments (2) or to look at the robot or the learner (3).

A run is also judged by what the robot said that the executive could check
(docs/executive.md, "Verifying the robot"): a driver that failed verbs (``internal`` or
malformed replies), claimed grasps the camera did not confirm, reported durations
its profile rules out, or sensed values of a feature most of which were implausible (a
sensor in another unit; an occasional outlier is noise, and only said) has results
nobody should trust, whatever the objects' outcomes say, so the run ends 3: look at
the robot.
"""

from __future__ import annotations

import dataclasses
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from behaviours.events import Event
from hero_driver.interface import OUT_OF_RANGE

ALL_HANDLED = 0
"""Every object located was grasped (or left, for a grasp the robot cannot confirm)."""
SOME_FAILED = 1
"""At least one object was not handled, none was located, or none was grasped."""
BAD_INPUT = 2
"""A file, flag or argument is wrong: nothing was started (one line says which)."""
LOST = 3
"""The robot's driver or the learner service refused, vanished or could not be reached;
or the driver is suspect: it failed verbs, or said what the executive checked and found
untrue (a grasp held that the camera saw on the floor, a duration its profile rules out,
most values of a feature outside what the feature can be)."""

WRONG_UNIT_MIN = 3
"""Implausible values of one feature before most of them being so makes the driver suspect."""

HANDLED_OUTCOMES = frozenset({"grasped", "left"})
NOT_FAILED = HANDLED_OUTCOMES | {"gone"}
"""Handled, or ``gone``: taken away while the robot worked on it (docs/executive.md,
"Disturbances"), which no executive could retrieve: reported, not a failure."""


def episode_status(outcomes: Sequence[str | None]) -> tuple[int, str]:
    """The exit status of an episode whose objects ended with ``outcomes`` (None: the
    object never finished), and the line that says why.

    No object at all is a failure too: a camera that sees nothing is more often a broken
    camera (or a driver drawing objects in the wrong grey) than an empty floor, and a
    script must not read "nothing done" as "done". So is a run in which no object was
    grasped, every one left as No-Grab or failed: what a driver whose sonar reads in the
    wrong unit produces (every procedure refused for range, every grasp dropped until
    only No-Grab is left), and never a floor worth reporting as done.
    """
    if not outcomes:
        return SOME_FAILED, "no object was located on the floor: nothing was retrieved"
    missed = [o for o in outcomes if o not in NOT_FAILED]
    if "grasped" not in outcomes and all(o in ("left", "failed", None) for o in outcomes):
        left = outcomes.count("left")
        return SOME_FAILED, (f"nothing really done: no object of {len(outcomes)} was grasped "
                             f"({left} left as No-Grab, {len(outcomes) - left} not handled)")
    if missed:
        return SOME_FAILED, f"{len(missed)} of {len(outcomes)} objects were not handled"
    gone = outcomes.count("gone")
    if gone:
        return ALL_HANDLED, f"{len(outcomes) - gone} of {len(outcomes)} objects were handled, {gone} gone (taken away)"
    return ALL_HANDLED, f"all {len(outcomes)} objects were handled"


@dataclass(frozen=True)
class Doubts:
    """What the episode's events say about the robot's word: driver faults per verb,
    the objects whose grasp the camera did not confirm, implausible values per feature,
    grasp durations left out of the learned costs, and refusals for range."""

    faults: Mapping[str, int]
    unverified: tuple[int, ...]
    implausible: Mapping[str, int]
    durations_ignored: int
    range_refusals: int
    refused_states: int = 0  # state publications nothing asked of the robot explained (the driver link's count)
    readings: Mapping[str, int] = dataclasses.field(default_factory=dict)  # values sensed per feature

    @property
    def wrong_units(self) -> dict[str, int]:
        """The features most of whose values were implausible (at least
        :data:`WRONG_UNIT_MIN` of them): a sensor answering in another unit, not noise.
        A sonar's outliers make a value implausible now and then; a sonar that reads
        centimetres where the profile says inches makes nearly every one so."""
        return {f: n for f, n in self.implausible.items()
                if n >= WRONG_UNIT_MIN and 2 * n > max(self.readings.get(f, 0), n)}

    @classmethod
    def of(cls, events: Iterable[Mapping[str, object]]) -> Doubts:
        faults: Counter[str] = Counter()
        implausible: Counter[str] = Counter()
        readings: Counter[str] = Counter()
        unverified: list[int] = []
        ignored = refusals = 0
        for e in events:
            kind = e.get("event")
            if kind == Event.SENSE and isinstance(values := e.get("values"), Mapping):
                readings.update(str(f) for f in values)
            elif kind == Event.DRIVER_FAULT:
                faults[str(e.get("verb"))] += 1
            elif kind == Event.IMPLAUSIBLE:
                implausible[str(e.get("feature"))] += 1
            elif kind == Event.GRASP_UNVERIFIED and isinstance(index := e.get("object"), int):
                unverified.append(index)
            elif kind == Event.GRASP_COST_IGNORED:
                ignored += 1
            elif kind == Event.DRIVER_ERROR and e.get("code") == OUT_OF_RANGE:
                refusals += 1
        return cls(dict(faults), tuple(unverified), dict(implausible), ignored, refusals, readings=dict(readings))

    def lines(self, robot: str, refusals: bool = False) -> list[str]:
        """One line per kind of doubt, for the run's closing lines (none: nothing
        doubted); with ``refusals``, the refusals for range too (a run that did nothing)."""
        out: list[str] = []
        if self.faults:
            out.append(f"{sum(self.faults.values())} driver faults ({_counts(self.faults)}): driver {robot} failed "
                       "verbs (`internal` or malformed replies); look at the robot")
        if self.unverified:
            out.append(f"driver {robot} suspect: {len(self.unverified)} grasps reported held while the look after "
                       f"(the camera's, or a rescan) still saw the object on the floor (objects {', '.join(map(str, self.unverified))}); "
                       "check its finger sensor")
        if self.durations_ignored:
            out.append(f"driver {robot} suspect: {self.durations_ignored} grasp durations implausible against the "
                       "profile's times, left out of the learned grasp costs; check the unit of duration_s")
        if self.wrong_units:
            out.append(f"driver {robot} suspect: most values of {', '.join(sorted(self.wrong_units))} were implausible "
                       f"({', '.join(f'{f}: {n} of {self.readings.get(f, n)}' for f, n in sorted(self.wrong_units.items()))}); "
                       "check that sensor's unit against the profile")
        elif self.implausible:
            out.append(f"{sum(self.implausible.values())} implausible values ({_counts(self.implausible)}): "
                       "those tests were reselected; check the sensors' units")
        if self.refused_states:
            out.append(f"{self.refused_states} state publications for {robot} refused: nothing asked of the robot "
                       "explained them (a second client driving it, a driver that restarted with a fresh world, or a "
                       "forged state; docs/security.md)")
        if refusals and self.range_refusals:
            out.append(f"{self.range_refusals} procedures refused for range: check the sonar's unit and the "
                       "robot's range check against the profile")
        return out

    @property
    def driver_suspect(self) -> bool:
        """The driver failed verbs or said what was checked and found untrue."""
        return bool(self.faults or self.unverified or self.durations_ignored or self.refused_states
                    or self.wrong_units)


def run_status(outcomes: Sequence[str | None], events: Iterable[Mapping[str, object]],
               robot: str = "r1", refused_states: int = 0) -> tuple[int, str, list[str]]:
    """The exit status of a run: :func:`episode_status` of its objects, made 3 (LOST)
    when the driver is suspect (:class:`Doubts`); with the line that says why and the
    closing lines that say what was doubted (driver faults per verb, unconfirmed grasps,
    implausible values and durations, ``refused_states`` the driver link would not
    believe; refusals for range when the run did not succeed)."""
    status, why = episode_status(outcomes)
    doubts = dataclasses.replace(Doubts.of(events), refused_states=refused_states)
    lines = doubts.lines(robot, refusals=status != ALL_HANDLED)
    if doubts.driver_suspect:
        return LOST, f"{lines[0]}; {why}", lines
    return status, why, lines


def _counts(counts: Mapping[str, int]) -> str:
    return ", ".join(f"{key}: {n}" for key, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))

"""``csl demo`` and ``csl run`` with ``--perception onboard``: a robot without a ceiling
camera, which explores the home with its own range scans before it handles the objects
it found (``executive.onboard``, ``behaviours.exploration``).

What the command adds around the episode, apart from ``csl_cli/commands/episode.py``
so that the ceiling camera's path reads as it did:

- the checks before any robot or training time, each one line, exit 2 (the user's
  inputs disagree, as a calibration of another camera or a driver of another robot
  profile): the overhead camera's options given with onboard; a driver that offers no
  scans with onboard; a world with no ceiling camera with ceiling (the simulator's
  homes), which says to add ``--perception onboard``;
- the closing lines: the exploration (its robot time, from the ``mapped`` event, and
  the object candidates found) and, when the driver is the simulator, the objects it
  placed that were never found, which fail the run (exit 1): a home's objects are the
  job whether or not the robot's scans came upon them;
- ``map.png``: the map built from the scans beside the true one (``reporting.built_map``).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from behaviours.events import Event
from behaviours.records import ObjectRecord
from csl_cli.args import CEILING, ONBOARD
from executive.executive import Executive
from executive.exit_status import ALL_HANDLED, SOME_FAILED
from hero_driver.interface import NO_CAMERA, VERB_BY_NAME, Driver, DriverError, Scanner
from reporting.report import FOUND_WITHIN_IN, Truth, found_truth

SCAN_FEATURE = VERB_BY_NAME["scan"].feature
"""The driver protocol's optional feature that brings the ``scan`` verb."""
CAMERA_OPTIONS = (("appearance", "--appearance"), ("camera", "--camera"),
                  ("camera_calibration", "--camera-calibration"))
"""The overhead camera's options (namespace field, flag): none goes with onboard."""


def check_options(args: argparse.Namespace) -> None:
    """With ``--perception onboard``, refuse the overhead camera's options in one line:
    there is no camera to measure an appearance, render or calibrate."""
    if args.perception != ONBOARD:
        return
    for field, flag in CAMERA_OPTIONS:
        if getattr(args, field, None) not in (None, False):  # --no-appearance is what onboard has anyway
            raise ValueError(f"{flag} is the overhead camera's and goes with --perception ceiling: with onboard "
                             "the robot sees with its own range scans"
                             + (" (and the appearance is off)" if field == "appearance" else ""))


def check_world_camera(driver: Driver, args: argparse.Namespace) -> None:
    """With ``--perception ceiling`` on the in-process simulator, a world with no ceiling
    camera (a home) is refused before training or robot time, saying what to add."""
    if args.perception != CEILING:
        return
    world = getattr(driver, "world", None)  # the simulator's own, for probes and reports
    spec = getattr(world, "spec", None)
    if spec is not None and not spec.home.ceiling_camera:
        raise ValueError(no_camera_line(f"world {spec.name!r}"))


def no_camera_line(what: str) -> str:
    """The one line for a robot with no ceiling camera run with ceiling perception."""
    return (f"{what} has no ceiling camera: add --perception onboard (the robot explores it with its own range "
            "scans)")


def camera_refused(exc: DriverError, driver: Driver) -> ValueError | None:
    """The one-line error for a driver whose ``camera`` verb answered ``no_camera``
    (None for any other error, which stays the robot's)."""
    if exc.code != NO_CAMERA:
        return None
    return ValueError(no_camera_line(f"driver {driver.robot}'s robot"))


def offers_scans(driver: Driver) -> bool:
    """Whether ``driver`` has the ``scan`` feature: the method, and over zenoh the
    feature listed in its ``hello`` (the client has the method for every driver, and
    asks it only of one that lists it)."""
    if not isinstance(driver, Scanner):
        return False
    if hasattr(driver, "agreement"):  # the zenoh client: what the live driver's hello listed
        agreement = driver.agreement  # type: ignore[attr-defined]
        return agreement is not None and SCAN_FEATURE in agreement.features
    return True


def check_scans(driver: Driver, args: argparse.Namespace) -> None:
    """With ``--perception onboard``, a driver without scans is refused in one line
    before the robot moves."""
    if args.perception == ONBOARD and not offers_scans(driver):
        raise ValueError(f"--perception onboard: driver {driver.robot} offers no range scans (no {SCAN_FEATURE} "
                         "feature in its hello; docs/driver-protocol.md, Scans): run it with --perception ceiling, "
                         "or drive a robot that scans")


@dataclass(frozen=True)
class Exploration:
    """What the exploration did, from the episode's events: views taken, robot seconds
    (the ``mapped`` event's), why it ended, and the object candidates found."""

    views: int
    robot_s: float
    reason: str
    candidates: int

    def line(self) -> str:
        return (f"exploration: {self.reason} after {_count(self.views, 'view')}, {self.robot_s / 60:.1f} robot "
                f"min; {_count(self.candidates, 'object candidate')} found")


def exploration(events: Sequence[dict[str, object]]) -> Exploration | None:
    """The exploration of an episode's events (None when it never ended: no ``mapped``).
    The candidates are the ``mapped`` event's."""
    at = next((i for i, e in enumerate(events) if e.get("event") == Event.MAPPED), None)
    if at is None:
        return None
    mapped = events[at]
    return Exploration(views=int(str(mapped["views"])), robot_s=float(str(mapped["seconds"])),
                       reason=str(mapped["reason"]), candidates=int(str(mapped["candidates"])))


def never_found(records: Sequence[ObjectRecord], present: Sequence[Truth]) -> list[Truth]:
    """The objects placed (``present``, the simulator's truth at the start) that no
    located object found (``reporting.report.found_truth``)."""
    found = {id(truth) for truth in (found_truth(record, present) for record in records) if truth is not None}
    return [t for t in present if id(t) not in found]


def still_there(records: Sequence[ObjectRecord], present: Sequence[Truth],
                on_floor: Sequence[tuple[float, float] | None]) -> list[Truth]:
    """The objects the run reported ``gone`` (taken away while the robot worked on them)
    that the simulator still has on the floor where the robot last saw them (within
    :data:`~reporting.report.FOUND_WITHIN_IN`). ``present``: the simulator's truth at the
    start; ``on_floor``: each of those objects' position now, in the same order, None when
    it left the floor (held, or put away).

    ``gone`` does not fail a run (``executive.exit_status.NOT_FAILED``): no executive can
    retrieve an object someone took. Without a ceiling camera the robot judges "gone"
    from its own scans, and a scan that saw past an object (a grazing view beside a shelf,
    a wall's returns read as the place empty) reports an object gone that never left; in
    the simulator that is checked, and fails the run."""
    if len(on_floor) != len(present):
        return []  # not the simulator's truth for these objects: nothing to check against
    now_of = {id(truth): now for truth, now in zip(present, on_floor)}
    out = []
    for record in records:
        truth = found_truth(record, present) if record.outcome == "gone" else None
        now = None if truth is None else now_of[id(truth)]
        if now is not None and math.dist(now, record.region.centroid) <= FOUND_WITHIN_IN:
            out.append(truth)
    return out


def judged(status: int, why: str, missing: Sequence[Truth], present: Sequence[Truth],
           left_there: Sequence[Truth] = ()) -> tuple[int, str]:
    """The run's exit status and line with the objects never found counted, and those
    reported gone that are still there (:func:`still_there`): an episode whose located
    objects were all handled still failed its job (exit 1) when the home held objects it
    never found or wrongly gave up as gone; a worse status stays."""
    said = []
    if missing:
        said.append(f"{len(missing)} of {len(present)} objects the simulator placed {_was(len(missing))} never found")
    if left_there:
        said.append(f"{len(left_there)} reported gone {_was(len(left_there))} still on the floor")
    if not said:
        return status, why
    return (SOME_FAILED, "; ".join(said)) if status == ALL_HANDLED else (status, "; ".join([why, *said]))


def still_there_line(left_there: Sequence[Truth]) -> str:
    """The closing line naming each object reported gone that never left the floor."""
    return (f"csl: {_count(len(left_there), 'object')} reported gone {_was(len(left_there))} still on the floor "
            "where the robot last saw them (its scans saw past them): "
            + ", ".join(f"{t.name} at ({t.x_in:.0f}, {t.y_in:.0f})" for t in left_there))


def never_found_line(missing: Sequence[Truth], present: Sequence[Truth]) -> str:
    """The closing line naming each object placed and never found, and where it was."""
    return (f"csl: {len(missing)} of {len(present)} objects the simulator placed {_was(len(missing))} never found: "
            + ", ".join(f"{t.name} at ({t.x_in:.0f}, {t.y_in:.0f})" for t in missing))


def _count(n: int, what: str) -> str:
    return f"{n} {what}{'' if n == 1 else 's'}"


def _was(n: int) -> str:
    return "was" if n == 1 else "were"


def plot_map(out: Path, executive: Executive, driver: Driver, records: Sequence[ObjectRecord],
             labels: Sequence[str], present: Sequence[Truth], events: Sequence[dict[str, object]]) -> bool:
    """``map.png``: the map the scans built, the route (the corrected pose of each scan,
    and each move to an object as planned), the objects found; beside it the true map
    when the driver is the simulator. False when no scan was read (nothing was built)."""
    from reporting.built_map import plot_built_map  # matplotlib: only when plotting
    from reporting.plots import legs

    perception = executive.perception
    if perception is None or perception.grid is None:
        return False
    plot_built_map(out, perception.grid, _truth_map(driver, perception.grid.inches_per_cell),
                   route=[(corrected.x_in, corrected.y_in) for _, _, corrected in perception.poses],
                   moves=legs(events, None), records=records, labels=labels, present=present)
    return True


def _truth_map(driver: Driver, resolution_in: float):  # noqa: ANN202 - TruthMap | None, imported here
    """The simulator's true map at the built map's resolution (None for another driver)."""
    world = getattr(driver, "world", None)
    if getattr(world, "spec", None) is None:
        return None
    from hero_driver.sim.truth_map import truth_map

    return truth_map(world.spec, world.catalogue, resolution_in)

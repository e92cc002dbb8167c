"""How the robot sees its floor: one look (a verb) and the scene it gives.

Every behaviour that looks — locating the objects, the checks before sensing and
grasping, the side-effect check after a failed grasp, the grasp's verification, the
blocked-move and clutter branches, the reconnect branch — asks the executive's
:class:`Perception` for a look and reads the :class:`~planner.vision.Scene` it makes:
object regions, where the robot stands, and (made the planner's map on the way) where
it may drive. Two sources implement it:

- :class:`CeilingCamera`, the paper's: the overhead image (the driver's ``camera``
  verb), segmented by the planner's vision; it sees the whole room at once, so there is
  nowhere to go to see more.
- the onboard one (``executive.onboard``): the robot's own range scan (the ``scan``
  verb), matched to the map of the scans before it, whose object regions are the
  candidates the scans found and whose map is the occupancy grid they built; the home
  is larger than one scan, so it says where to look from next until the home is mapped
  (the exploration branch, :mod:`behaviours.exploration`).

The behaviours stay as they are: only what a look is, and what it costs, differs.
"""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any, Protocol

from camera_model.image import CameraImage
from hero_driver.interface import Driver
from planner import Navigator, Pose, Scene
from planner.vision import look


class Perception(Protocol):
    """A source of looks. ``verb`` is the driver verb a look sends (a driver fault is
    counted under it); ``corrects_heading``: the robot pose a scene gives carries a
    heading to trust (the scan matcher's), not only a position (the camera's);
    ``leg_in``: how far a move may drive between two looks (None: any distance), for a
    source that corrects the dead reckoning only over short steps (``behaviours.legs``)."""

    verb: str
    corrects_heading: bool
    leg_in: float | None
    measures_ahead: bool  # distance_ahead can answer: a move's final approach is checked (behaviours.legs)
    stranded: str | None  # why next_view offered none though the floor is not all seen (None: it is)

    def look(self) -> Future[Any]:
        """Start one look (the robot's time: a scan may turn the base in place)."""

    def scene(self, observation: Any) -> Scene:
        """What ``observation`` shows, made the planner's map from now on."""

    def glance(self, observation: Any) -> Scene:
        """What ``observation`` shows, the planner's map left as it is (a check that
        must not change where later plans go: the grasp's verification)."""

    def distance_ahead(self, observation: Any) -> float | None:
        """The sonar's distance to the first thing straight ahead of the robot in
        ``observation`` (what a learner position's distance measures), seen from where
        the robot stands; None when the look cannot tell, or nothing answered."""

    def next_view(self, robot: Pose) -> Pose | None:
        """Where to look from next to see more of the floor (None: nothing more to see,
        or nothing more reachable; ``stranded`` then says whether the robot itself
        could go nowhere)."""

    def unreachable(self, view: Pose) -> None:
        """``view`` could not be reached: not to be offered again."""

    def bumped(self, pose: Pose) -> tuple[float, float] | None:
        """A move stopped collided at ``pose`` (heading where it drove): where the map
        now keeps the base out, when the look could not see what it met; else None."""


class CeilingCamera:
    """The overhead camera (the module docstring): the driver's image, the navigator's vision."""

    verb = "camera"
    corrects_heading = False
    leg_in = None  # it sees the robot wherever it drives: a move is driven whole, as in the paper
    measures_ahead = False  # from above, the distance to an object's face is the map's, not a measurement
    stranded = None  # it sees the whole room: there is never a view to offer

    def __init__(self, driver: Driver, navigator: Navigator) -> None:
        self._driver, self._navigator = driver, navigator

    def look(self) -> Future[CameraImage]:
        return self._driver.camera()

    def scene(self, observation: CameraImage) -> Scene:
        return self._navigator.observe(observation)

    def glance(self, observation: CameraImage) -> Scene:
        return look(observation, self._navigator.camera)

    def distance_ahead(self, observation: CameraImage) -> float | None:
        return None

    def next_view(self, robot: Pose) -> Pose | None:
        return None  # the camera sees the whole room at once

    def unreachable(self, view: Pose) -> None:
        return None

    def bumped(self, pose: Pose) -> tuple[float, float] | None:
        return None  # the camera sees whatever the base can meet (a mover's stop is `blocked`, not a bump)

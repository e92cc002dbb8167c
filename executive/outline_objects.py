"""Training objects from their outlines as the robot's own scans see them: training
without the ceiling camera (the paper's closing step).

The paper finds each training object's faces from its footprint as the ceiling camera
sees it, and stands the robot square to each (docs/method.md §4). Here the footprint is
the object's outline from a planar range scanner on the robot (``mapping/outline.py``):
each catalogue object stands alone where the team put it, the robot is staged at each
pose of the survey round it (four views at 24 in, facing it, as a team would stand it
there, like :class:`~executive.training_sources.SimulatorSource` does for the training
positions), takes one scan through the driver's ``scan`` verb at each, and the outline
fitted to those scans gives the polygon, the reference axis and whether it is round.
From there training goes on exactly as from the camera's polygons
(:func:`~executive.training_sources.seen_objects`).

A planar scan gives no appearance (the camera's pixel area and elongation): these
training objects carry none, so their descriptions are recognised by the sensing tests
alone. The survey's robot time (four moves and scans an object) is not counted in the
training figures, as the camera's look is not.

The scans must come from a thin-beamed scanner (a lidar). HERO's sonar swept in place
answers each wide beam with the nearest echo anywhere across it, and at the survey's
standoff a beam is wider than a training object: its returns outline the beams, not the
object, so a wide-beamed scanner is refused before any survey, in one line naming the
profile. An outline the fit refuses (too few returns, something else near, too big) is
one line naming the object and the scanner.
"""

from __future__ import annotations

from executive.onboard import planar_scan
from executive.training_sources import SeenObjects, Sighting, seen_objects
from hero_driver.interface import Pose as DriverPose
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.probe import probe_world
from hero_driver.sim.scan import scanner_of
from hero_driver.sim.world import SimWorld
from mapping.outline import SURVEY_STANDOFF_IN, outline, survey_plan
from mapping.scan import PlanarScan
from planner.geometry import Pose
from robot_profile import RobotProfile

EXACT_RANGE_SIGMA_IN = 0.01
"""The range noise the outline is told of when the simulator's scans are exact: the fit
needs a positive figure (it scales its gates and its test for round), and exact ranges
have none. A hundredth of an inch is far above floating-point error and far under the
residual any catalogue rectangle leaves on a circle fitted to it."""


def outline_objects(object_set: str = "training", profile: RobotProfile | None = None, seed: int = 0,
                    noise: bool = False) -> SeenObjects:
    """The catalogue's objects of one set, each alone on the floor (aligned with the
    room, as a team stages training objects) and outlined from the robot's scans of it
    by the scanner of ``profile`` (default: the shipped HERO 2000's lidar).

    As with the camera, the footprint, its reference axis (along the outline's longer
    sides) and whether it is round are the perception's, not the catalogue's; only the
    grasp label is the teacher's. No appearance. ValueError in one line: naming the
    profile when its scanner's beams are wide, naming the object when its outline
    cannot be fitted.
    """
    loaded, _ = profile_and_catalogue(profile)
    spec = scanner_of(loaded)
    if spec.beam_deg > 0:
        raise ValueError(f"onboard perception: {loaded.source}: [scanner]: the {spec.model}'s beams are "
                         f"{spec.beam_deg:g}° wide, and an echo from anywhere across a beam cannot be placed on an "
                         "object's outline: outlines need a thin-beamed scanner (a lidar)")
    return seen_objects(object_set, lambda object_id: _outline_sighting(object_id, profile, seed, noise))


def _survey(sim: SimWorld, centre: tuple[float, float]) -> list[tuple[PlanarScan, Pose]]:
    """One scan from each pose of the survey round ``centre`` (:func:`survey_plan`), the
    robot staged there; each with the pose the driver reported it was taken from."""
    views = []
    for pose in survey_plan(centre):
        sim.pose = DriverPose(pose.x_in, pose.y_in, pose.heading_deg)
        scan = sim.scan()
        views.append((planar_scan(scan), Pose(scan.pose.x_in, scan.pose.y_in, scan.pose.heading_deg)))
    return views


def _range_sigma_in(sim: SimWorld) -> float:
    """The scanner's range noise on a surveyed object: the simulator's error grows with the
    range, and every face of an object lies nearer than the survey's standoff."""
    sigma = sim.noise.scan_range_frac * SURVEY_STANDOFF_IN
    return sigma if sigma > 0 else EXACT_RANGE_SIGMA_IN


def _outline_sighting(object_id: str, profile: RobotProfile | None, seed: int, noise: bool) -> Sighting:
    sim = probe_world(object_id, seed, noise, profile)
    staged = sim.spec.objects[0]  # where the team put it (at yaw 0: the catalogue's axis is world +x)
    centre = (staged.x_in, staged.y_in)
    try:
        found = outline(_survey(sim, centre), centre, _range_sigma_in(sim))
    except ValueError as exc:
        spec = sim.scanner
        raise ValueError(f"onboard perception: {object_id!r}: {exc} (the scanner: {spec.model}, {spec.beams} "
                         f"beams {spec.step_deg:g}° apart)") from None
    return Sighting(found.axis_deg, found.object_frame(), found.round, None)

"""mapping: onboard mapping and localisation from planar range scans.

Scan matching corrects the odometry (:mod:`mapping.localisation`, small_gicp), an
occupancy grid is built from the scans at the corrected poses (:mod:`mapping.occupancy`),
frontiers say where to explore (:mod:`mapping.frontiers`, :mod:`mapping.exploration`),
object candidates come from the scans' returns that are not structure
(:mod:`mapping.candidates`), and the grid is handed to the
OMPL planner as the map it plans on (:mod:`mapping.planning`). Depends on numpy, OpenCV,
small_gicp, the camera model's floor grid and the planner's map and pose types; knows
nothing of the learner, the behaviours, the executive or the driver (the caller converts
the driver's scan into a :class:`PlanarScan`). See docs/mapping.md.
"""

from mapping.accuracy import LocalisationError, localisation_error, occupied_iou
from mapping.candidates import Candidate, CandidateFinder, CandidateSettings
from mapping.exploration import ExplorationGoal, ExplorationSettings, is_mapped, next_goal
from mapping.frontiers import Frontier, frontiers
from mapping.localisation import Correction, MatcherSettings, ScanMatcher
from mapping.occupancy import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from mapping.planning import map_image, planning_map
from mapping.scan import PlanarScan

__all__ = [
    "FREE", "OCCUPIED", "UNKNOWN", "Candidate", "CandidateFinder", "CandidateSettings", "ExplorationGoal",
    "ExplorationSettings", "is_mapped", "next_goal", "Correction", "Frontier", "LocalisationError", "MatcherSettings",
    "OccupancyGrid", "PlanarScan", "ScanMatcher", "frontiers", "localisation_error", "map_image",
    "occupied_iou", "planning_map",
]

"""Does the room still look like the one the camera was calibrated on?

A real camera's images are read against the calibration's *empty floor*
(:mod:`planner.segmentation`). When the room changes after calibration in a way
segmentation cannot divide out (the floor re-laid, a rug put down, a light that is
neither smooth nor a shadow), every look reports texture as objects: a run would send
the robot to phantoms, or, worse, miss a real object, without a word. So each look is
measured against the empty floor before its regions are used, and a look past either
bound below stops the run with one line naming what was measured and the cure
(recalibrate). Robot time is never spent on what the check refuses.

The two measures (docs/camera.md, "When the room changes"):

- the *foreground share*: of the bare floor the camera sees (walls, furniture, the
  board's paper and the robot left out), the share whose brightness over the empty
  floor is off by more than :data:`UNLIKE_BY`: objects, their shadows, people, and
  whatever changed;
- the *regions*: how many separate object blobs the look found, against how many the
  floor could hold (one per :data:`FLOOR_PER_REGION_IN2` of it).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

# Brighter or darker than the empty floor (after the look's exposure and light are
# divided out) by more than this share: not bare floor. The ratio's noise is the
# sensor's (sigma^2 = 2^2 + 0.04 level: 3 % at a floor level of about 100) less what
# rectifying 0.5 in pixels onto 0.8 in ones averages out, so noise alone passes this
# on a small share of the floor only; two floors of the same kind (the realistic
# preset's 7 % mottle, tile joints 15 % darker) differ by more over a large share.
UNLIKE_BY = 0.08
# Of the bare floor, at most this share may be unlike the empty floor. What belongs on
# a floor covers a small share of it: on the lab's 40,000 in^2 of floor a 30 x 20 in
# cart 1.5 %, a person 0.6 %, the seven objects' footprints 0.5 % and their shadows
# about as much again. Past several times that, it is the floor itself that changed.
MAX_FOREGROUND_SHARE = 0.08
# The robot must reach each object from some side, so objects the robot can work on
# stand about a robot's width apart (a HERO base is 18 in across; touching objects
# show as one region): each has about a 24 in square of floor to itself. A floor
# showing more regions than one per that much floor shows texture, not objects.
FLOOR_PER_REGION_IN2 = 576.0
MIN_REGION_PIXELS = 2  # as vision: one stray pixel is not a region
RECALIBRATE = "recalibrate (csl camera calibrate)"


class SceneChanged(ValueError):
    """The image no longer matches the calibration's empty floor: one line saying what
    was measured and to recalibrate (a ``ValueError``, so ``csl`` exits 2 with it)."""


@dataclass(frozen=True)
class SceneMeasure:
    """What one look shows against its empty floor: ``unlike_share`` of the
    ``floor_px`` bare-floor pixels were unlike it, in ``regions`` object blobs, and the
    floor of ``floor_in2`` square inches could hold ``regions_allowed``."""

    unlike_share: float
    regions: int
    floor_px: int
    floor_in2: float

    @property
    def regions_allowed(self) -> int:
        return max(1, int(self.floor_in2 // FLOOR_PER_REGION_IN2))

    def problems(self) -> list[str]:
        """What is past its bound, in words (empty: the look matches the calibration)."""
        found = []
        if self.unlike_share > MAX_FOREGROUND_SHARE:
            found.append(f"foreground share {100 * self.unlike_share:.0f}% of the floor "
                         f"(at most {100 * MAX_FOREGROUND_SHARE:.0f}%)")
        if self.regions > self.regions_allowed:
            found.append(f"{self.regions} regions (a floor of {self.floor_in2 / 144:.0f} sq ft holds at most "
                         f"{self.regions_allowed})")
        return found


def measure(brightness: np.ndarray, bare: np.ndarray, objects: np.ndarray, inches_per_pixel: float) -> SceneMeasure:
    """The measures of one look: ``brightness`` is the image over the empty floor
    (1 = as calibrated), ``bare`` where bare floor should show (bool), ``objects`` the
    object mask segmentation found."""
    floor_px = int(np.count_nonzero(bare))
    unlike = bare & (np.abs(brightness - 1.0) > UNLIKE_BY)
    share = float(np.count_nonzero(unlike)) / floor_px if floor_px else 0.0
    count, _, stats, _ = cv2.connectedComponentsWithStats(np.asarray(objects, np.uint8), connectivity=4)
    regions = int(np.count_nonzero(stats[1:, cv2.CC_STAT_AREA] >= MIN_REGION_PIXELS)) if count > 1 else 0
    return SceneMeasure(share, regions, floor_px, floor_px * inches_per_pixel ** 2)


def check(scene: SceneMeasure) -> None:
    """Raise :class:`SceneChanged` when the look is past a bound, in one line."""
    problems = scene.problems()
    if problems:
        raise SceneChanged(f"the floor no longer matches the calibration: {', '.join(problems)}; {RECALIBRATE}")

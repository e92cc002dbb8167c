"""Disturbances carried out: someone nudges, takes away or swaps an object while the
robot works (docs/simulator.md, "Disturbances"; what may happen and when is declared in
:mod:`hero_driver.sim.events`).

A disturbance takes effect at the end of the verb during which it happens, so every
verb sees the world either wholly before or wholly after it, and the camera image
taken next shows it. Each one that happened is kept in :attr:`Disturber.happened`,
ground truth for tests and the experiment (never for the executive).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pymunk

from hero_driver.sim.catalogue import CatalogueEntry, Footprint
from hero_driver.sim.events import Disturbance, DisturbPreset
from hero_driver.sim.physics import Physics, SimObject

PRESET_NUDGE_IN = (4.0, 10.0)  # a preset nudge moves the object this far (uniform), in a random direction
PRESET_NUDGE_YAW_DEG = 30.0  # and turns it by up to this much either way
PRESET_AREA_RATIO = 2.0  # a preset swap takes an entry at least twice as large or small: the camera sees it
NUDGE_TRIES = 8  # preset nudges drawn until one leaves the object clear of everything
CLEARANCE_IN = 1.0  # ... by this much, and clear of the robot's base


@dataclass(frozen=True)
class Happened:
    """A disturbance that took place: after robot step ``step`` at ``clock_s``, on object
    ``object``; ``detail`` says how far a nudge moved it or what replaced it."""

    step: int
    clock_s: float
    object: int
    do: str
    detail: str


def clear_at(physics: Physics, obj: SimObject, pose: tuple[float, float, float],
             base: tuple[float, float, float]) -> bool:
    """Whether ``obj`` placed at ``pose`` (x, y, yaw) stays ``CLEARANCE_IN`` clear of
    every wall, furniture and other object, and of the robot's base (x, y, radius)."""
    probe = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    probe.position, probe.angle = (pose[0], pose[1]), math.radians(pose[2])
    fp = obj.entry.footprint
    shape: pymunk.Shape = (pymunk.Circle(probe, fp.radius_in + CLEARANCE_IN) if fp.shape == "circle" else
                           pymunk.Poly.create_box(probe, (fp.length_in, fp.width_in), radius=CLEARANCE_IN))
    shape.cache_bb()
    if any(hit.shape is not obj.shape for hit in physics.space.shape_query(shape)):
        return False
    return shape.point_query((base[0], base[1])).distance > base[2]


def area(footprint: Footprint) -> float:
    """The overhead area of a footprint, in square inches (what the camera counts)."""
    if footprint.shape == "circle":
        return math.pi * footprint.radius_in ** 2
    return footprint.length_in * footprint.width_in


class Disturber:
    """Carries out a world's scheduled disturbances and a preset's random ones.

    The random stream is its own (seeded from the world's seed), so turning a preset on
    changes nothing else a seed decides: the sonar's noise, the grasps' side effects."""

    def __init__(self, scheduled: Sequence[Disturbance], preset: DisturbPreset, seed: int,
                 catalogue: Mapping[str, CatalogueEntry]) -> None:
        self.pending = list(scheduled)
        self.preset = preset
        self.catalogue = catalogue
        self.rng = np.random.default_rng([seed, 0xD157])
        self.steps = 0
        self.drawn: set[int] = set()  # objects the preset has decided about
        self.happened: list[Happened] = []

    def after_verb(self, physics: Physics, clock_s: float, base: tuple[float, float, float],
                   sensed: SimObject | None = None) -> None:
        """A robot verb (move, sensing, grasp, charge) ended at ``clock_s`` with the base
        at ``base`` (x, y, radius); ``sensed`` is the object the sonar just measured."""
        self.steps += 1
        for event in [e for e in self.pending if e.due(self.steps, clock_s)]:
            self.pending.remove(event)
            obj = physics.objects[event.object]
            if obj.status != "floor":
                continue  # already in the hand or the bin: nobody can move it
            if event.do == "nudge":
                self._nudge(physics, obj, event.nudge, clock_s)
            elif event.do == "remove":
                self._remove(physics, obj, clock_s)
            else:
                assert event.entry is not None
                self._replace(physics, obj, self.catalogue[event.entry], clock_s)
        if sensed is not None and self.preset.active and sensed.index not in self.drawn:
            self.drawn.add(sensed.index)
            self._preset(physics, sensed, clock_s, base)

    def _preset(self, physics: Physics, obj: SimObject, clock_s: float, base: tuple[float, float, float]) -> None:
        u, edge = float(self.rng.random()), 0.0
        for kind, p in self.preset.rates:
            edge += p
            if u < edge:
                break
        else:
            return
        if kind == "remove":
            self._remove(physics, obj, clock_s)
        elif kind == "replace":
            other = self._swap_for(obj.entry)
            if other is not None:
                self._replace(physics, obj, other, clock_s)
        else:
            nudge = self._clear_nudge(physics, obj, base)
            if nudge is not None:
                self._nudge(physics, obj, nudge, clock_s)

    def _clear_nudge(self, physics: Physics, obj: SimObject,
                     base: tuple[float, float, float]) -> tuple[float, float, float] | None:
        """A random nudge that leaves the object clear of walls, furniture, the other
        objects and the robot's base; None when none of a few draws does."""
        for _ in range(NUDGE_TRIES):
            dist = float(self.rng.uniform(*PRESET_NUDGE_IN))
            angle = float(self.rng.uniform(0.0, 2.0 * math.pi))
            dyaw = float(self.rng.uniform(-PRESET_NUDGE_YAW_DEG, PRESET_NUDGE_YAW_DEG))
            dx, dy = dist * math.cos(angle), dist * math.sin(angle)
            if clear_at(physics, obj, (obj.x_in + dx, obj.y_in + dy, obj.yaw_deg + dyaw), base):
                return dx, dy, dyaw
        return None

    def _swap_for(self, entry: CatalogueEntry) -> CatalogueEntry | None:
        """A catalogue entry clearly larger or smaller than ``entry`` (so the overhead
        camera can see the swap), drawn at random; None when there is none."""
        own = area(entry.footprint)
        choices = sorted(e.id for e in self.catalogue.values()
                         if max(area(e.footprint), own) >= PRESET_AREA_RATIO * min(area(e.footprint), own))
        return self.catalogue[choices[int(self.rng.integers(len(choices)))]] if choices else None

    def _nudge(self, physics: Physics, obj: SimObject, nudge: tuple[float, float, float], clock_s: float) -> None:
        x0, y0 = obj.x_in, obj.y_in
        obj.body.position = (x0 + nudge[0], y0 + nudge[1])
        obj.body.angle += math.radians(nudge[2])
        physics.space.reindex_shapes_for_body(obj.body)
        physics.settle()  # a world file's nudge into something is pushed back out
        moved = math.hypot(obj.x_in - x0, obj.y_in - y0)
        self.happened.append(Happened(self.steps, clock_s, obj.index, "nudge",
                                      f"moved {moved:.1f} in, turned {nudge[2]:+.0f} deg"))

    def _remove(self, physics: Physics, obj: SimObject, clock_s: float) -> None:
        physics.lift(obj)
        obj.status = "removed"
        self.happened.append(Happened(self.steps, clock_s, obj.index, "remove", "taken away"))

    def _replace(self, physics: Physics, obj: SimObject, entry: CatalogueEntry, clock_s: float) -> None:
        was = obj.entry.id
        physics.replace(obj, entry, obj.x_in, obj.y_in, obj.yaw_deg)
        physics.settle()
        self.happened.append(Happened(self.steps, clock_s, obj.index, "replace", f"{was} -> {entry.id}"))

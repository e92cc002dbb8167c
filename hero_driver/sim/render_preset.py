"""The overhead image of a simulated world through a named camera preset.

``SimWorld.camera()`` draws its own preset through this; benches and tests that
compare presets on identical scenes call it with each (the objects on the floor at
their drawn camera yaw, the true pose).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from hero_driver.interface import CameraImage
from hero_driver.sim import camera

if TYPE_CHECKING:
    from hero_driver.sim.world import SimWorld


def render_world(sim: SimWorld, preset: str) -> CameraImage:
    """What ``sim``'s overhead camera shows with ``preset`` (one of camera.PRESETS)."""
    floor = [(o.entry.footprint, o.x_in, o.y_in,
              o.yaw_deg + sim.camera_yaw.error(o.index, (o.x_in, o.y_in, o.yaw_deg), sim.noise, sim.rng))
             for o in sim.physics.objects if o.status == "floor"]
    return camera.render(sim.spec, floor, sim.pose, sim.profile.robot.geometry.base_radius_in, sim.noise,
                         sim.rng, sim.clock_s, preset=preset, movers=sim.physics.movers.outlines())

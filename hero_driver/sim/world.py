"""The simulated HERO 2000 in its world: one mutable aggregate that owns the physics,
the robot's pose, the simulated clock and the seeded random stream.

Every verb charges the profile's robot time to the clock and nothing else advances it,
so a run is as fast as the CPU allows and repeatable for a seed. Verbs raise
:class:`DriverError`; wrapping them in futures is the driver's business.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camera_model.image import CameraImage
from hero_driver.interface import (
    BAD_REQUEST, NO_CAMERA, NO_TARGET, OUT_OF_RANGE, UNKNOWN_PROCEDURE, DriverError, GraspResult, MoveResult, Obstacle,
    Pose, RangeScan, RobotState, SenseResult,
)
from hero_driver.sim import camera, grasping, scan, sonar
from hero_driver.sim.battery import DOCK_REACH_IN, GRASPING_PER_S, MOVING_PER_S, SENSING_PER_S, Battery
from hero_driver.sim.camera import PRESETS
from hero_driver.sim.catalogue import GraspRule, profile_and_catalogue
from hero_driver.sim.disturber import Disturber, Happened
from hero_driver.sim.events import DisturbPreset
from hero_driver.sim.home import check_doorways
from hero_driver.sim.movers import STEP_S, MoverPreset, MoverTruth, preset_movers
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.odometry import Drift, heading_slip, slip
from hero_driver.sim.physics import Physics, SimObject
from hero_driver.sim.readings import perturb, perturb_flag, specular_miss, specular_value
from hero_driver.sim.worldfile import WorldSpec, load_world
from robot_profile import RobotProfile

RANGE_TOLERANCE_IN = 1.5  # docs/conventions.md: a procedure accepts its range ± this
CENTRING_RADIUS_IN = 12.0  # sonar centring finds an object whose centre is this near `face`
COLLISION_BACKOFF_IN = 0.1  # the bumper stops the base this short of contact
KNOCK_YAW_SIGMA_DEG = 5.0
PUSH_SPREAD = (0.6, 1.4)  # a push travels this fraction of the entry's push_in
ROLL_FACTOR = 3.0  # a rolling object travels this much farther than a sliding one
SAFETY_IN = 6.0  # blocked_moves: a mover this near ahead of the base stops it (docs/simulator.md)
PAUSE_S = 6.0  # ... for at most this long: the move goes on if the way clears, else it ends blocked


@dataclass(frozen=True)
class ObjectTruth:
    """Ground truth about one object, for reports and tests (never for the executive's
    decisions: the robot cannot know it)."""

    index: int
    entry_id: str
    name: str
    pose: str
    x_in: float
    y_in: float
    yaw_deg: float
    grasps: tuple[GraspRule, ...]
    round: bool
    held: bool
    binned: bool


def _wrap_deg(angle: float) -> float:
    return (angle + 180.0) % 360.0 - 180.0


def normalise_deg(angle: float) -> float:
    """An angle in [0, 360): float modulo can return 360.0 for a tiny negative."""
    wrapped = angle % 360.0
    return 0.0 if wrapped >= 360.0 - 1e-9 else wrapped


class SimWorld:
    """The simulated robot and its world; see the module docstring.

    ``pose`` is the true pose (what the sonar, the bumper and the camera see); the
    verbs report ``reported_pose()``, the true pose less the dead-reckoning ``drift``.
    ``camera_preset`` is how the overhead camera draws (``camera.PRESETS``: the grey
    bands, or what a real ceiling camera would show, docs/camera.md).
    """

    def __init__(self, world: str | Path | WorldSpec | None = None, seed: int = 0,
                 profile: RobotProfile | None = None, noise: NoiseConfig | None = None,
                 camera: str = "simple", disturb: DisturbPreset = DisturbPreset(),
                 movers: MoverPreset = MoverPreset(), stop_for_movers: bool = True) -> None:
        if camera not in PRESETS:
            raise ValueError(f"camera preset {camera!r}: expected one of {', '.join(PRESETS)}")
        self.profile, self.catalogue = profile_and_catalogue(profile)
        self.camera_preset = camera
        self._explicit_noise = noise
        self.disturb = disturb  # the --disturb preset, kept across resets like the noise
        self.mover_preset = movers  # the --movers preset, kept across resets too
        self.stop_for_movers = stop_for_movers  # the blocked_moves feature (off: the base drives into movers)
        self.load(world if isinstance(world, WorldSpec) else load_world(world, self.catalogue), seed)

    def load(self, spec: WorldSpec, seed: int) -> None:
        """Put the world back to the spec's initial state with a fresh random stream.

        Everything is built before any of it is kept: a spec or seed that fails part-way
        (a start overlapping something, a battery level out of range, a seed numpy
        refuses) leaves the world as it was, so the next reset of it still works."""
        rng = np.random.default_rng(seed)
        scan_rng = scan.scan_rng(seed)
        physics = Physics(spec, self.catalogue, spec.movers + preset_movers(
            self.mover_preset, spec.room_width_in, spec.room_depth_in, seed))
        x, y, heading = spec.robot
        check_doorways(spec.home, spec.source, self.profile.robot.geometry.base_radius_in)
        physics.movers.make_room((x, y, self.profile.robot.geometry.base_radius_in))
        if physics.overlaps_disc((x, y), self.profile.robot.geometry.base_radius_in):
            raise ValueError(f"{spec.source}: robot: base at ({x:g}, {y:g}) overlaps a wall, furniture or object")
        metered = spec.dock is not None or spec.battery is not None  # else tethered (docs/simulator.md)
        battery = Battery(1.0 if spec.battery is None else spec.battery, metered)
        disturber = Disturber(spec.events, self.disturb, seed, self.catalogue)
        self.spec, self.seed, self.physics, self.rng = spec, seed, physics, rng
        self.scanner, self.scan_rng = scan.scanner_of(self.profile), scan_rng  # the scan feature's own stream
        self.noise = next((n for n in (self._explicit_noise, spec.noise) if n is not None), NoiseConfig())
        self.pose = Pose(x, y, normalise_deg(heading))
        self.drift = Drift()
        self.camera_yaw = camera.YawErrors()
        self.clock_s = 0.0
        self.battery, self.disturber = battery, disturber
        self.held: SimObject | None = None
        self.last_effect = grasping.NOTHING
        self.contacts = 0  # times the base touched anything: the bumper, or a mover (ground truth)

    def movers(self) -> list[MoverTruth]:
        """Where every mover is now (ground truth, docs/simulator.md)."""
        return [m.truth() for m in self.physics.movers.all]

    def safety_in(self) -> float | None:
        """The blocked_moves feature: how near ahead a mover stops a move; None (off)
        when this simulator ignores movers (``stop_for_movers`` false). The safety stop
        is the driver's, not the world's: a world without movers offers it too (nothing
        ever blocks there), so a run on the lab does not announce a branch that is off."""
        return SAFETY_IN if self.stop_for_movers else None

    def _pass(self, seconds: float, at: tuple[float, float], heading_deg: float | None = None) -> None:
        """Robot time passes with the base standing at ``at`` (facing ``heading_deg``;
        None: as it stands): the movers walk on."""
        if self.physics.movers.all:
            self.physics.movers.advance(seconds, (at[0], at[1], self.profile.robot.geometry.base_radius_in),
                                        self.pose.heading_deg if heading_deg is None else heading_deg)

    def wait(self, seconds: float) -> RobotState:
        """Stand still for ``seconds`` (the blocked_moves feature's wait verb)."""
        if not (math.isfinite(seconds) and 0.0 <= seconds <= 3600.0):
            raise DriverError(BAD_REQUEST, f"wait: seconds must be from 0 to 3600, got {seconds!r}")
        self._pass(seconds, (self.pose.x_in, self.pose.y_in))
        self.clock_s += seconds
        self._verb_ended()
        return self.state()

    @property
    def disturbances(self) -> list[Happened]:
        """Every disturbance that took place so far (ground truth, docs/simulator.md)."""
        return list(self.disturber.happened)

    def _verb_ended(self, sensed: SimObject | None = None) -> None:
        """A move, sensing, grasp or charge ended: whatever disturbance was due during
        it takes effect now (hero_driver.sim.events)."""
        base = (self.pose.x_in, self.pose.y_in, self.profile.robot.geometry.base_radius_in)
        self.disturber.after_verb(self.physics, self.clock_s, base, sensed)

    # -- state -------------------------------------------------------------------

    def state(self) -> RobotState:
        return RobotState(self.reported_pose(), self.clock_s, self.battery.level)

    def dock(self) -> Pose | None:
        """Where the charging dock is, as the robot's dead reckoning places it."""
        dock = self.spec.dock
        return None if dock is None else self._reckoned(dock.pose)

    def charge(self) -> RobotState:
        """Charge to full at the dock (docs/simulator.md, Battery). The beacon guides the
        base the last inches onto the contacts (driving time, drained as moving), where
        the robot knows exactly where it is: its drift is gone."""
        dock = self.spec.dock
        if dock is None:
            raise DriverError(OUT_OF_RANGE, "charge: this world has no charging dock")
        off = math.hypot(self.pose.x_in - dock.x_in, self.pose.y_in - dock.y_in)
        if off > DOCK_REACH_IN:
            raise DriverError(OUT_OF_RANGE, f"charge: the base is {off:.1f} in from the dock; the beacon "
                                            f"guides it in from {DOCK_REACH_IN:g} in")
        approach_s = off / self.profile.robot.motion.speed_in_per_s
        self.battery.drain(approach_s, MOVING_PER_S)
        self.pose, self.drift = dock.pose, Drift()
        self.clock_s += approach_s + self.battery.charge()
        self._verb_ended()
        return self.state()

    def reported_pose(self) -> Pose:
        """Where the robot's dead reckoning says it is (docs/simulator.md, Moving)."""
        return self._reckoned(self.pose)

    def _reckoned(self, pose: Pose) -> Pose:
        """A true pose as the robot's dead reckoning places it: less the drift."""
        x, y = self.drift.to_reckoned((pose.x_in, pose.y_in))
        if self.drift.dheading_deg == 0.0:
            return Pose(x, y, pose.heading_deg)
        return Pose(x, y, normalise_deg(pose.heading_deg - self.drift.dheading_deg))

    def truth(self) -> list[ObjectTruth]:
        return [ObjectTruth(o.index, o.entry.id, o.entry.name, o.entry.pose, o.x_in, o.y_in, o.yaw_deg,
                            o.entry.grasps, o.entry.round, o.status == "held", o.status == "binned")
                for o in self.physics.objects]

    def sonar_point(self) -> tuple[float, float]:
        h = math.radians(self.pose.heading_deg)
        off = self.profile.robot.geometry.sensor_offset_in
        return self.pose.x_in + off * math.cos(h), self.pose.y_in + off * math.sin(h)

    # -- moving ------------------------------------------------------------------

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None) -> MoveResult:
        """Drive straight segments through the waypoints (turning in place onto each),
        stop short of any contact, then turn to ``face`` and centre the sonar on the
        object there, or else to the last waypoint's heading.

        Waypoints and ``face`` are where the robot believes they are: it drives by dead
        reckoning, so each lies off by the drift accumulated so far, which grows with
        every inch driven."""
        if not waypoints or not all(isinstance(w, Pose) for w in waypoints):
            raise DriverError(BAD_REQUEST, "move: waypoints must be a non-empty list of Pose")
        width, depth = self.spec.room_width_in, self.spec.room_depth_in
        margin = math.hypot(width, depth)  # driving at a wall is allowed (the bumper stops it); 1e308 is not
        for i, wp in enumerate(waypoints):
            if not (-margin <= wp.x_in <= width + margin and -margin <= wp.y_in <= depth + margin):
                raise DriverError(BAD_REQUEST, f"move: waypoints[{i}] ({wp.x_in:g}, {wp.y_in:g}) is far outside "
                                               f"the room (0-{width:g} x 0-{depth:g} in)")
        self.battery.require("move")
        motion, radius = self.profile.robot.motion, self.profile.robot.geometry.base_radius_in
        duration = motion.vision_s
        x, y, heading = self.pose.x_in, self.pose.y_in, self.pose.heading_deg
        self._pass(motion.vision_s, (x, y))
        collided, blocked = False, None
        for wp in waypoints:
            towards = self.drift.to_true((wp.x_in, wp.y_in))
            dx, dy = towards[0] - x, towards[1] - y
            length = math.hypot(dx, dy)
            if length < 1e-6:
                continue
            course = math.degrees(math.atan2(dy, dx))
            turned = abs(_wrap_deg(course - heading))
            turn_s = turned / motion.turn_deg_per_s
            duration += turn_s
            self._pass(turn_s, (x, y), course)
            heading = course
            alpha = self.physics.sweep_circle((x, y), towards, radius)
            travel = length if alpha is None else max(0.0, alpha * length - COLLISION_BACKOFF_IN)
            collided = alpha is not None
            travel, met, blocked, paused_s = self._drive_among_movers((x, y), (dx / length, dy / length), travel)
            collided = (collided and not met and blocked is None) or met
            duration += travel / motion.speed_in_per_s + paused_s
            stop = (x + travel * dx / length, y + travel * dy / length) if collided or blocked else towards
            self.contacts += int(collided)
            x, y = self._slip(self._odometry(stop, course, travel), travel)
            self._heading_slip(turned, travel, (x, y))
            if collided or blocked is not None:
                break
        centred = False
        if not collided and blocked is None:
            if face is not None:
                face = self.drift.to_true(face)
                target = self._centring_target(x, y, face)
                goal = (target.x_in, target.y_in) if target is not None else face
                final = math.degrees(math.atan2(goal[1] - y, goal[0] - x))
                duration += abs(_wrap_deg(final - heading)) / motion.turn_deg_per_s + motion.centring_s
                self._pass(abs(_wrap_deg(final - heading)) / motion.turn_deg_per_s + motion.centring_s, (x, y), final)
                centred = target is not None
                self._heading_slip(abs(_wrap_deg(final - heading)), 0.0, (x, y))
                heading = final if centred else final + self._heading_error()
            else:
                final = waypoints[-1].heading_deg + self.drift.dheading_deg
                duration += abs(_wrap_deg(final - heading)) / motion.turn_deg_per_s
                self._pass(abs(_wrap_deg(final - heading)) / motion.turn_deg_per_s, (x, y), final)
                self._heading_slip(abs(_wrap_deg(final - heading)), 0.0, (x, y))
                heading = final + self._heading_error()
        self.pose = Pose(x, y, normalise_deg(heading))
        self.clock_s += duration
        self.battery.drain(duration, MOVING_PER_S)
        self._verb_ended()
        return MoveResult(self.reported_pose(), duration, collided, centred, blocked)

    def _drive_among_movers(self, start: tuple[float, float], u: tuple[float, float],
                            travel: float) -> tuple[float, bool, Obstacle | None, float]:
        """Drive ``travel`` inches from ``start`` along the unit vector ``u`` in steps of
        ``STEP_S`` with the movers walking on; answer how far the base got, whether it
        met a mover (the bumper stopped it: the feature is off), the mover that stopped
        it short for longer than ``PAUSE_S`` (the feature is on; reckoned position) and
        the seconds it stood paused for movers."""
        movers = self.physics.movers
        if not movers.all or travel <= 0.0:
            return travel, False, None, 0.0
        radius, speed = self.profile.robot.geometry.base_radius_in, self.profile.robot.motion.speed_in_per_s
        heading = math.degrees(math.atan2(u[1], u[0]))
        steps = math.ceil(travel / (speed * STEP_S))
        done, paused = 0.0, 0.0
        for i in range(1, steps + 1):
            here = (start[0] + done * u[0], start[1] + done * u[1], radius)
            if self.stop_for_movers:
                mover, waited = movers.ahead(here, u, SAFETY_IN), 0.0
                while mover is not None and waited < PAUSE_S:
                    movers.advance(STEP_S, here, heading)
                    waited += STEP_S
                    mover = movers.ahead(here, u, SAFETY_IN)
                paused += waited
                if mover is not None:
                    at = mover.truth()
                    obstacle = Obstacle(*self.drift.to_reckoned((at.x_in, at.y_in)), at.reach_in)
                    return done, False, obstacle, paused
            step_to = travel * i / steps
            if movers.nearest_gap((start[0] + step_to * u[0], start[1] + step_to * u[1]), radius) < 0.0:
                return max(0.0, done - COLLISION_BACKOFF_IN), True, None, paused
            done = step_to
            movers.advance((travel / steps) / speed, (start[0] + done * u[0], start[1] + done * u[1], radius), heading)
        return done, False, None, paused

    def _odometry(self, stop: tuple[float, float], course_deg: float, travel: float) -> tuple[float, float]:
        """Where the base really ends when told to ``stop`` after driving ``travel``
        along ``course``: off by a Gaussian error proportional to the distance, unless
        that would put it into something (the bumper would have stopped it)."""
        sigma = self.noise.odometry_frac * travel
        if sigma <= 0:
            return stop
        c, s = math.cos(math.radians(course_deg)), math.sin(math.radians(course_deg))
        along, across = self.rng.normal(0.0, sigma, 2)
        jx, jy = stop[0] + along * c - across * s, stop[1] + along * s + across * c
        if self.physics.overlaps_disc((jx, jy), self.profile.robot.geometry.base_radius_in):
            return stop
        return float(jx), float(jy)

    def _slip(self, at: tuple[float, float], travel: float) -> tuple[float, float]:
        """Where the base really is after wheel slip it cannot sense: ``at`` moved by
        the drift drawn for ``travel`` inches, which the reported pose never shows
        (kept at ``at`` if the slip would put the base into something)."""
        dx, dy = slip(travel, self.noise.odometry_drift, self.rng)
        moved = (at[0] + dx, at[1] + dy)
        if (dx, dy) == (0.0, 0.0) or self.physics.overlaps_disc(moved, self.profile.robot.geometry.base_radius_in):
            return at
        self.drift = self.drift.plus(dx, dy)
        return moved

    def _heading_slip(self, turned_deg: float, travel_in: float, at: tuple[float, float]) -> None:
        """A world that drifts in heading (``home.heading_drift``): turning ``turned_deg``
        and driving ``travel_in`` with the base ending truly at ``at`` turns the
        reckoned frame about ``at`` by an unsensed error (hero_driver.sim.odometry)."""
        if not self.spec.home.heading_drift:
            return
        error = heading_slip(turned_deg, travel_in, self.noise.heading_drift_turn, self.noise.heading_drift_travel,
                             self.rng)
        if error != 0.0:
            self.drift = self.drift.turned(error, at)

    def _heading_error(self) -> float:
        sigma = self.noise.odometry_heading_deg
        return float(self.rng.normal(0.0, sigma)) if sigma > 0 else 0.0

    def _centring_target(self, x: float, y: float, face: tuple[float, float]) -> SimObject | None:
        best, best_d = None, CENTRING_RADIUS_IN
        for o in self.physics.objects:
            d = math.hypot(o.x_in - face[0], o.y_in - face[1])
            if o.status == "floor" and d <= best_d:
                best, best_d = o, d
        return best

    # -- sensing -----------------------------------------------------------------

    def _aim(self, procedure: str, range_in: tuple[float, float]) -> sonar.Aim:
        """The object in front of the sonar, checked against a procedure's range."""
        origin = self.sonar_point()
        reach = math.hypot(self.spec.room_width_in, self.spec.room_depth_in) + 50.0
        target, distance = sonar.find_target(self.physics, origin, self.pose.heading_deg, reach)
        if target is None:
            raise DriverError(NO_TARGET, f"{procedure}: no object in front of the sonar")
        lo, hi = range_in
        if not lo - RANGE_TOLERANCE_IN <= distance <= hi + RANGE_TOLERANCE_IN:
            raise DriverError(OUT_OF_RANGE, f"{procedure}: object at {distance:.1f} in, range is {lo:g}-{hi:g} in")
        geometry = self.profile.robot.geometry
        return sonar.Aim(origin, self.pose.heading_deg, target, distance, geometry.sensor_height_in,
                         hi + RANGE_TOLERANCE_IN, geometry.raised_sensor_height_in)

    def sense(self, procedure: str) -> SenseResult:
        spec = self.profile.sensing_procedure(procedure)
        model = sonar.PROCEDURES.get(procedure)
        if spec is None or model is None:
            raise DriverError(UNKNOWN_PROCEDURE, f"sense: unknown sensing procedure {procedure!r:.120}")
        self.battery.require("sense")
        aim = self._aim(procedure, spec.range_in)
        ideal = model(self.physics, aim)
        missed = (self.noise.specular_p > 0 and procedure in sonar.SIDE_LOOKING
                  and specular_miss(sonar.incidence_deg(aim), self.rng, self.noise))
        values: dict[str, float | None] = {}
        for feature in spec.features:
            if feature.name not in ideal:
                raise DriverError(UNKNOWN_PROCEDURE, f"{procedure}: simulator cannot compute feature '{feature.name}'")
            value, step = ideal[feature.name]
            if feature.binary:
                values[feature.name] = perturb_flag(value > 0.5, self.rng, self.noise)
                continue
            if missed:
                value = specular_value(value, self.rng)
            elif feature.name == "Depth" and self._curved_end_on(aim):
                value *= float(self.rng.uniform(0.25, 0.5))
            values[feature.name] = perturb(value, feature.error, step, self.rng, self.noise)
        self._pass(spec.time_s, (self.pose.x_in, self.pose.y_in))
        self.clock_s += spec.time_s
        self.battery.drain(spec.time_s, SENSING_PER_S)
        self._verb_ended(aim.target)
        return SenseResult(procedure, values, spec.time_s, aim.distance_in)

    def _curved_end_on(self, aim: sonar.Aim) -> bool:
        """The paper's curved-surface effect: looking end-on along a lying round object,
        the echo over its top is often lost early, so Depth comes out far too small."""
        return (aim.target.entry.rolls and sonar.approach_is_end_on(aim.heading_deg, aim.target)
                and self.noise.curved_depth_p > 0 and self.rng.random() < self.noise.curved_depth_p)

    def scan(self) -> RangeScan:
        """One planar range scan (docs/simulator.md, Scans): cast from the true pose,
        stamped with the reported one; the robot stands while it takes the scanner's
        time (the sonar's base turns a full circle and ends where it began)."""
        self.battery.require("scan")
        taken = scan.take(self.physics, self.pose, self.scanner, self.noise, self.scan_rng)
        pose = self.reported_pose()
        self._pass(self.scanner.time_s, (self.pose.x_in, self.pose.y_in))
        self.clock_s += self.scanner.time_s
        self.battery.drain(self.scanner.time_s, SENSING_PER_S)
        self._verb_ended()
        low, high = self.scanner.range_in
        return RangeScan(pose, self.clock_s, taken.angles_deg, taken.ranges_in, low, high)

    # -- grasping ----------------------------------------------------------------

    def grasp(self, procedure: str) -> GraspResult:
        spec = self.profile.grasping_procedure(procedure)
        if spec is None:
            raise DriverError(UNKNOWN_PROCEDURE, f"grasp: unknown grasping procedure {procedure!r:.120}")
        if self.held is not None:
            raise DriverError(BAD_REQUEST, f"grasp: the hand holds object {self.held.index}; release it first")
        self.battery.require("grasp")
        aim = self._aim(procedure, spec.range_in)
        obj = aim.target
        end_on = sonar.approach_is_end_on(aim.heading_deg, obj)
        success = grasping.picks_up(obj.entry, procedure, end_on)
        if success:
            self.physics.lift(obj)
            self.held = obj
            self.last_effect = grasping.LIFTED
        else:
            self.last_effect = grasping.failure_effect(obj.entry, procedure, self.rng)
            if self.last_effect == grasping.PUSHED:
                self._push(obj, aim.u)
            elif self.last_effect == grasping.KNOCKED_OVER:
                self._knock_over(obj, aim.u)
        self._pass(spec.time_s, (self.pose.x_in, self.pose.y_in))
        self.clock_s += spec.time_s
        self.battery.drain(spec.time_s, GRASPING_PER_S)
        self._verb_ended()
        return GraspResult(procedure, success, spec.time_s)

    def _push(self, obj: SimObject, u: tuple[float, float]) -> None:
        """The fingers shove the object away from the robot; a lying round object rolls
        across its axis unless it was pushed nearly end-on."""
        distance = obj.entry.side_effects.push_in * float(self.rng.uniform(*PUSH_SPREAD))
        direction, rolling = u, False
        if obj.entry.rolls:
            yaw = obj.body.angle
            ax, ay = math.cos(yaw), math.sin(yaw)
            along = u[0] * ax + u[1] * ay
            px, py = u[0] - along * ax, u[1] - along * ay
            norm = math.hypot(px, py)
            if norm > 0.5:
                direction, rolling, distance = (px / norm, py / norm), True, distance * ROLL_FACTOR
        self.physics.push(obj, direction, distance, rolling)

    def _knock_over(self, obj: SimObject, u: tuple[float, float]) -> None:
        """The object tips away from the robot about its far bottom edge: the lying
        entry's axis points along the push, its centre r + H/2 beyond the old one; an
        open top ends up facing away (the lying entry's +x end)."""
        old, new = obj.entry, self.catalogue[obj.entry.side_effects.knocks_to or obj.entry.id]
        reach = old.footprint.radius_in + new.footprint.length_in / 2
        heading = math.degrees(math.atan2(u[1], u[0]))
        yaw = heading if old.top_hole or new.front_hole is None else heading + 180.0
        yaw += float(self.rng.normal(0.0, KNOCK_YAW_SIGMA_DEG))
        self.physics.replace(obj, new, obj.x_in + reach * u[0], obj.y_in + reach * u[1], yaw)
        self.physics.settle()

    def release(self) -> RobotState:
        """Drop a held object into the robot's bin (takes no robot time)."""
        if self.held is not None:
            self.held.status = "binned"
            self.held = None
        return self.state()

    # -- camera ------------------------------------------------------------------

    def camera(self) -> CameraImage:
        """The overhead image through this world's camera preset (vision time is
        charged to moves, not here); each object's orientation is drawn off by its
        camera error. A world without a ceiling camera (a home) answers ``no_camera``:
        there the robot must find its way with its own sensors."""
        if not self.spec.home.ceiling_camera:
            raise DriverError(NO_CAMERA, f"camera: world '{self.spec.name}' has no ceiling camera; "
                                         "it needs onboard perception (range scans)")
        return self.render(self.camera_preset)

    def render(self, preset: str) -> CameraImage:
        """What the overhead camera shows with ``preset`` (one of camera.PRESETS): the
        objects on the floor at their drawn camera yaw, the true pose. Benches and tests
        that compare presets on identical scenes call it with each."""
        floor = [(o.entry.footprint, o.x_in, o.y_in,
                  o.yaw_deg + self.camera_yaw.error(o.index, (o.x_in, o.y_in, o.yaw_deg), self.noise, self.rng))
                 for o in self.physics.objects if o.status == "floor"]
        return camera.render(self.spec, floor, self.pose, self.profile.robot.geometry.base_radius_in, self.noise,
                             self.rng, self.clock_s, preset=preset, movers=self.physics.movers.outlines())

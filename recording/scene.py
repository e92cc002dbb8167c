"""Our values as Foxglove's well-known messages: poses, paths, sonar rays, images, the
map and objects. Inches and degrees become metres and quaternions (Foxglove's units);
times are nanoseconds of robot time."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from foxglove.messages import (ArrowPrimitive, Color, CylinderPrimitive, FrameTransform, Grid, KeyValuePair,
                               LaserScan, LinePrimitive, LinePrimitiveLineType, PackedElementField,
                               PackedElementFieldNumericType, Point3, Pose, PoseInFrame, Quaternion, RawImage,
                               SceneEntity, SceneUpdate, TextPrimitive, Timestamp, Vector2, Vector3)

from camera_model.image import CameraImage
from recording.topics import BASE_FRAME, METRES_PER_INCH, WORLD_FRAME
from hero_driver.interface import Pose as RobotPose
from planner.image import undistorted
from robot_profile.model import RobotGeometry

OUTCOME_COLOURS = {"grasped": (0.17, 0.63, 0.17), "left": (0.12, 0.47, 0.71), "failed": (0.84, 0.15, 0.16)}
_PATH = (1.0, 0.5, 0.05)
_CONTACT = (0.84, 0.15, 0.16)
_LOCATED = (0.6, 0.6, 0.6)
_TEXT = (1.0, 1.0, 1.0)


def colour(rgb: tuple[float, float, float], alpha: float = 1.0) -> Color:
    return Color(r=rgb[0], g=rgb[1], b=rgb[2], a=alpha)


def stamp(ns: int) -> Timestamp:
    return Timestamp(sec=ns // 1_000_000_000, nsec=ns % 1_000_000_000)


def metres(inches: float) -> float:
    return inches * METRES_PER_INCH


def heading(deg: float) -> Quaternion:
    """A rotation about +z (counter-clockwise from +x, as docs/conventions.md)."""
    half = math.radians(deg) / 2
    return Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half))


def floor_pose(x_in: float, y_in: float, heading_deg: float = 0.0, z_in: float = 0.0) -> Pose:
    return Pose(position=Vector3(x=metres(x_in), y=metres(y_in), z=metres(z_in)), orientation=heading(heading_deg))


def base_transform(pose: RobotPose, ns: int) -> FrameTransform:
    return FrameTransform(timestamp=stamp(ns), parent_frame_id=WORLD_FRAME, child_frame_id=BASE_FRAME,
                          translation=Vector3(x=metres(pose.x_in), y=metres(pose.y_in), z=0.0),
                          rotation=heading(pose.heading_deg))


def base_pose(pose: RobotPose, ns: int) -> PoseInFrame:
    return PoseInFrame(timestamp=stamp(ns), frame_id=WORLD_FRAME,
                       pose=floor_pose(pose.x_in, pose.y_in, pose.heading_deg))


def body(geometry: RobotGeometry, ns: int) -> SceneUpdate:
    """The base as a disc and its heading as an arrow, drawn in ``base_link`` so they
    follow every transform."""
    r = metres(geometry.base_radius_in)
    return SceneUpdate(entities=[SceneEntity(
        timestamp=stamp(ns), frame_id=BASE_FRAME, id="robot", frame_locked=True,
        cylinders=[CylinderPrimitive(pose=floor_pose(0.0, 0.0, z_in=1.0), size=Vector3(x=2 * r, y=2 * r, z=metres(2.0)),
                                     bottom_scale=1.0, top_scale=1.0, color=Color(r=0.8, g=0.8, b=0.8, a=0.6))],
        arrows=[ArrowPrimitive(pose=floor_pose(0.0, 0.0, z_in=2.5), shaft_length=r, shaft_diameter=r / 8,
                               head_length=r / 3, head_diameter=r / 4, color=colour(_PATH))])])


def planned_path(number: int, origin: RobotPose, waypoints: Sequence[RobotPose], stop: RobotPose, collided: bool,
                 geometry: RobotGeometry, ns: int) -> SceneUpdate:
    """One move: the line from where it began through the planner's waypoints, its order
    number and the base's footprint at the stop (red when it stopped on contact)."""
    rgb = _CONTACT if collided else _PATH
    line = [origin, *waypoints]
    r = metres(geometry.base_radius_in)
    return SceneUpdate(entities=[SceneEntity(
        timestamp=stamp(ns), frame_id=WORLD_FRAME, id=f"move/{number}",
        metadata=[KeyValuePair(key="move", value=str(number)),
                  KeyValuePair(key="collided", value=str(collided).lower()),
                  KeyValuePair(key="waypoints", value=str(len(waypoints)))],
        lines=[LinePrimitive(thickness=2.0, scale_invariant=True, color=colour(rgb),
                             points=[Point3(x=metres(p.x_in), y=metres(p.y_in), z=0.01) for p in line])],
        cylinders=[CylinderPrimitive(pose=floor_pose(stop.x_in, stop.y_in, stop.heading_deg),
                                     size=Vector3(x=2 * r, y=2 * r, z=0.002), bottom_scale=1.0, top_scale=1.0,
                                     color=colour(rgb, 0.15))],
        arrows=[ArrowPrimitive(pose=floor_pose(stop.x_in, stop.y_in, stop.heading_deg, z_in=0.5), shaft_length=r,
                               shaft_diameter=r / 10, head_length=r / 4, head_diameter=r / 5, color=colour(rgb))],
        texts=[TextPrimitive(pose=floor_pose(stop.x_in, stop.y_in, z_in=4.0), billboard=True, font_size=14.0,
                             scale_invariant=True, color=colour(_TEXT), text=str(number))])])


def sonar_ray(pose: RobotPose, distance_in: float, geometry: RobotGeometry, ns: int) -> LaserScan:
    """A one-beam scan from the wrist sonar, ``sensor_offset_in`` ahead of the base
    centre along the heading, at ``sensor_height_in`` (docs/conventions.md)."""
    h = math.radians(pose.heading_deg)
    x = pose.x_in + geometry.sensor_offset_in * math.cos(h)
    y = pose.y_in + geometry.sensor_offset_in * math.sin(h)
    return LaserScan(timestamp=stamp(ns), frame_id=WORLD_FRAME,
                     pose=floor_pose(x, y, pose.heading_deg, z_in=geometry.sensor_height_in),
                     start_angle=0.0, end_angle=0.0, ranges=[metres(distance_in)], intensities=[1.0])


def raw_image(image: CameraImage, ns: int) -> RawImage:
    pixels = np.ascontiguousarray(image.pixels, dtype=np.uint8)
    h, w = pixels.shape
    return RawImage(timestamp=stamp(ns), frame_id="overhead_camera", width=w, height=h, encoding="mono8", step=w,
                    data=pixels.tobytes())


def floor_map(image: CameraImage, ns: int) -> Grid:
    """The overhead image, undistorted, as a grid on the floor: the grid's first row is
    its low-y edge, the image's last row (docs/conventions.md)."""
    flat = undistorted(image)
    pixels = np.ascontiguousarray(np.flipud(flat.pixels), dtype=np.uint8)
    h, w = pixels.shape
    corner = floor_pose(image.origin_x_in, image.origin_y_in - h * image.inches_per_pixel)
    cell = metres(image.inches_per_pixel)
    return Grid(timestamp=stamp(ns), frame_id=WORLD_FRAME, pose=corner, column_count=w,
                cell_size=Vector2(x=cell, y=cell), row_stride=w, cell_stride=1,
                fields=[PackedElementField(name="intensity", offset=0, type=PackedElementFieldNumericType.Uint8)],
                data=pixels.tobytes())


def located(regions: Sequence[dict], ns: int) -> SceneUpdate:
    """A grey marker at each region the camera found (the ``located`` event's centroids)."""
    return SceneUpdate(entities=[SceneEntity(
        timestamp=stamp(ns), frame_id=WORLD_FRAME, id=f"located/{k}",
        cylinders=[CylinderPrimitive(pose=floor_pose(*region["centroid"]), size=Vector3(x=0.05, y=0.05, z=0.01),
                                     bottom_scale=1.0, top_scale=1.0, color=colour(_LOCATED, 0.8))])
        for k, region in enumerate(regions)])


def handled(index: int, polygon: Sequence[tuple[float, float]], label: str, grasp: str | None, outcome: str | None,
            ns: int) -> SceneUpdate:
    """An object once handled: its outline coloured by outcome, and a label."""
    drawn = colour(OUTCOME_COLOURS.get(outcome or "", (0.5, 0.5, 0.5)))
    cx = sum(p[0] for p in polygon) / len(polygon)
    cy = sum(p[1] for p in polygon) / len(polygon)
    return SceneUpdate(entities=[SceneEntity(
        timestamp=stamp(ns), frame_id=WORLD_FRAME, id=f"object/{index}",
        metadata=[KeyValuePair(key="object", value=str(index)), KeyValuePair(key="label", value=label),
                  KeyValuePair(key="grasp", value=grasp or "-"), KeyValuePair(key="outcome", value=outcome or "")],
        lines=[LinePrimitive(type=LinePrimitiveLineType.LineLoop, thickness=3.0, scale_invariant=True, color=drawn,
                             points=[Point3(x=metres(x), y=metres(y), z=0.02) for x, y in polygon])],
        texts=[TextPrimitive(pose=floor_pose(cx, cy, z_in=6.0), billboard=True, font_size=12.0, scale_invariant=True,
                             color=drawn, text=f"{index}: {label} → {grasp or '-'} ({outcome})")])])

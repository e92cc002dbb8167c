"""A home to explore (docs/simulator.md, "Homes"): interior walls with doorways, named
rooms, tables the base cannot enter but a planar sensor sees only the legs of, no
ceiling camera, heading drift; the shipped apartments load and every object in them
can be reached; and the true occupancy map the mapping work is scored against."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
import zenoh
from scipy import ndimage

from hero_driver.interface import NO_CAMERA, DriverError, Pose
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.home import DOORWAY_MARGIN_IN
from hero_driver.sim.noise import NOISE_PRESETS, NoiseConfig
from hero_driver.sim.odometry import Drift
from hero_driver.sim.truth_map import truth_map, write_png
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import WorldSpec, load_world, parse_world
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.node import DriverNode
from tests.hero_driver.test_zenoh_node import REPLY_S, error_of
from tests.hero_driver.test_zenoh_support import DriverProcess

PROFILE, CATALOGUE = profile_and_catalogue(None)
RADIUS = PROFILE.robot.geometry.base_radius_in
APARTMENTS = ("apartment", "apartment-2")


def world(**fields: Any) -> dict[str, Any]:
    """A 100x50 in room with the robot near its lower-left corner, plus ``fields``."""
    return {"room": {"width_in": 100, "depth_in": 50}, "robot": {"x_in": 15, "y_in": 15, "heading_deg": 0}, **fields}


def spec(data: dict[str, Any], source: str = "home.json") -> WorldSpec:
    return parse_world(data, source, CATALOGUE)


def refusal(data: dict[str, Any], in_sim: bool = False) -> str:
    """The one-line error a world is refused with (by the loader, or when a robot is put in it)."""
    with pytest.raises(ValueError) as caught:
        SimWorld(spec(data)) if in_sim else spec(data)
    text = str(caught.value)
    assert "\n" not in text and text.startswith("home.json: ")
    return text


# ---------------------------------------------------------------- the world file


def test_a_lab_world_has_no_home_fields_and_a_camera() -> None:
    lab = load_world("lab", CATALOGUE)
    assert lab.home.walls == () and lab.home.rooms == ()
    assert lab.home.ceiling_camera and not lab.home.heading_drift
    assert all(f.kind == "solid" for f in lab.furniture)


def test_a_doorway_cuts_a_wall_into_pieces() -> None:
    wall = {"from": [50, 0], "to": [50, 50], "thickness_in": 2, "doors": [{"at_in": 25, "width_in": 30}]}
    home = spec(world(walls=[wall]))
    pieces = home.home.walls[0].pieces()
    # 0-10 and 40-50 along the wall, from y=0 up: centres at y=5 and y=45, 10 in long
    assert [(p.x_in, p.y_in, p.length_in) for p in pieces] == [(50, 5, 10), (50, 45, 10)]
    assert sorted(home.wall_outlines()[0]) == [(49, 0), (49, 10), (51, 0), (51, 10)]


def test_a_doorway_narrower_than_the_base_and_its_margin_is_refused() -> None:
    need = 2 * RADIUS + DOORWAY_MARGIN_IN
    narrow = {"from": [50, 0], "to": [50, 50], "doors": [{"at_in": 25, "width_in": need - 1}]}
    text = refusal(world(walls=[narrow]), in_sim=True)
    assert "walls[0].doors[0]: field 'width_in'" in text and f"{need:g} in" in text
    wide = {"from": [50, 0], "to": [50, 50], "doors": [{"at_in": 25, "width_in": need}]}
    SimWorld(spec(world(walls=[wide])))


@pytest.mark.parametrize("wall, field", [
    ({"from": [50, 0], "to": [50, 60]}, "'to'"),  # beyond the room
    ({"from": [10 ** 400, 0], "to": [50, 50]}, "'from'"),  # an integer with no float
    ({"from": [50, 0], "to": [50, float("nan")]}, "'to'"),
    ({"from": [50, 0], "to": [50, 50], "doors": [{"at_in": 40, "width_in": 30}]}, "'at_in'"),  # past its end
    ({"from": [50, 0], "to": [50, 50], "doors": [{"at_in": 12, "width_in": 24}, {"at_in": 30, "width_in": 24}]},
     "doors[1]: field 'at_in'"),  # two doorways over each other
    ({"from": [50, 0], "to": [50, 50], "height_in": 90}, "'height_in'"),  # unknown field
])
def test_a_bad_wall_is_one_line_naming_its_field(wall: dict[str, Any], field: str) -> None:
    assert field in refusal(world(walls=[wall]))


def test_objects_and_furniture_through_a_wall_are_refused() -> None:
    wall = {"from": [50, 0], "to": [50, 50], "thickness_in": 4}
    box = {"id": "closed-box-2x2x2/upright", "x_in": 51, "y_in": 25}
    through = refusal(world(walls=[wall], objects=[box]))
    assert through.endswith("objects[0] 'closed-box-2x2x2/upright': overlaps walls[0]")
    sofa = {"name": "sofa", "x_in": 60, "y_in": 25, "width_in": 20, "depth_in": 10}
    assert refusal(world(walls=[wall], furniture=[sofa])).endswith("furniture 'sofa': overlaps walls[0]")
    flush = {"name": "sofa", "x_in": 62, "y_in": 25, "width_in": 20, "depth_in": 10}  # x from 52: touching
    spec(world(walls=[wall], furniture=[flush]))


def test_an_object_may_lie_under_a_table_but_not_in_its_leg() -> None:
    table = {"name": "table", "kind": "table", "leg_in": 2, "x_in": 70, "y_in": 25, "width_in": 40, "depth_in": 20}
    under = {"id": "closed-box-2x2x2/upright", "x_in": 70, "y_in": 25}
    assert spec(world(furniture=[table], objects=[under])).furniture[0].kind == "table"
    in_leg = {"id": "closed-box-2x2x2/upright", "x_in": 51, "y_in": 16}  # the leg spans x 50-52, y 15-17
    assert refusal(world(furniture=[table], objects=[in_leg])).endswith("overlaps furniture 'table' leg 2")
    assert "'leg_in'" in refusal(world(furniture=[{**table, "kind": "solid"}]))  # legs are for tables
    assert "'kind'" in refusal(world(furniture=[{**table, "kind": "chair"}]))


def test_named_rooms_say_where_a_point_is() -> None:
    rooms = [{"name": "kitchen", "outline": [[0, 0], [50, 0], [50, 50], [0, 50]]},
             {"name": "hall", "outline": [[50, 0], [100, 0], [100, 50]]}]  # a triangle below the diagonal
    home = spec(world(rooms=rooms)).home
    assert (home.room_at(10, 10), home.room_at(90, 10), home.room_at(60, 40)) == ("kitchen", "hall", None)
    assert "'name'" in refusal(world(rooms=[rooms[0], {**rooms[1], "name": "kitchen"}]))
    assert "'outline'" in refusal(world(rooms=[{"name": "hall", "outline": [[0, 0], [10, 0]]}]))


# ---------------------------------------------------------------- physics


def test_a_table_is_legs_to_a_ray_and_a_top_to_the_base() -> None:
    table = {"name": "table", "kind": "table", "leg_in": 2, "x_in": 70, "y_in": 25, "width_in": 40, "depth_in": 20}
    sim = SimWorld(spec(world(furniture=[table], robot={"x_in": 15, "y_in": 25})), noise=NoiseConfig.off())
    # a ray along y=25 passes between the legs and under the top to the far wall at x=100
    assert sim.physics.ray((20, 25), (120, 25)).point.x == pytest.approx(100)
    # a ray along y=16 meets the near leg's face at x=50
    assert sim.physics.ray((20, 16), (120, 16)).point.x == pytest.approx(50)
    # the base (radius 9) driving along y=25 stops short of the top's edge at x=50
    moved = sim.move([Pose(80, 25, 0)], None)
    assert moved.collided and moved.pose.x_in == pytest.approx(50 - RADIUS - 0.1)


def test_a_base_stops_at_a_tables_top_on_a_leg_that_ends_short_of_it() -> None:
    """The top spans x 50-90. A waypoint at x 40.5, 0.5 in short of where the base
    (radius 9) would meet the top at x 41: the leg does not reach it, the next one does,
    and the base stops 0.1 in short, at x 40.9, whatever the legs. The thin segment of
    the second leg alone lies outside the top's box: with a second top in the home
    (a stool), pymunk's own query with a radius missed the table's then, and the base
    went on under it."""
    table = {"name": "table", "kind": "table", "leg_in": 2, "x_in": 70, "y_in": 25, "width_in": 40, "depth_in": 20}
    stool = {"name": "stool", "kind": "table", "leg_in": 1, "x_in": 20, "y_in": 40, "width_in": 8, "depth_in": 8}
    sim = SimWorld(spec(world(furniture=[table, stool], robot={"x_in": 15, "y_in": 25})), noise=NoiseConfig.off())
    assert sim.physics.sweep_circle((30.0, 25.0), (40.5, 25.0), RADIUS) is None
    assert sim.physics.sweep_circle((40.5, 25.0), (45.0, 25.0), RADIUS) == pytest.approx(0.5 / 4.5)
    moved = sim.move([Pose(40.5, 25, 0), Pose(45, 25, 0), Pose(80, 25, 0)], None)
    assert moved.collided and moved.pose.x_in == pytest.approx(50 - RADIUS - 0.1)


def test_a_home_without_a_ceiling_camera_answers_no_camera() -> None:
    sim = SimWorld("apartment", noise=NoiseConfig.off())
    with pytest.raises(DriverError) as caught:
        sim.camera()
    assert caught.value.code == NO_CAMERA and "'apartment' has no ceiling camera" in caught.value.message
    assert SimWorld("lab").camera().pixels.size > 0


# ---------------------------------------------------------------- heading drift


def test_a_turned_frame_keeps_the_robot_where_it_believes_it_is() -> None:
    drift = Drift().turned(90.0, (10.0, 0.0))
    assert drift.to_true((10.0, 0.0)) == pytest.approx((10.0, 0.0))
    assert drift.to_true((20.0, 0.0)) == pytest.approx((10.0, 10.0))  # 10 in east in belief: truly 10 in north
    assert drift.to_reckoned((10.0, 10.0)) == pytest.approx((20.0, 0.0))


def test_the_heading_drifts_only_in_a_world_that_asks() -> None:
    lab = SimWorld("lab", seed=3, noise=NOISE_PRESETS["harsh"])
    lab.move([Pose(120, 30, 0), Pose(120, 90, 90)], None)
    assert lab.drift.dheading_deg == 0.0 and lab.reported_pose().heading_deg == lab.pose.heading_deg
    assert NOISE_PRESETS["clean"].heading_drift_turn == NOISE_PRESETS["mild"].heading_drift_turn == 0.0


def test_a_heading_error_turns_later_moves_about_where_it_happened() -> None:
    noise = dataclasses.replace(NoiseConfig.off(), heading_drift_turn=1.0)
    sim = SimWorld(spec(world(heading_drift=True, room={"width_in": 200, "depth_in": 200},
                              robot={"x_in": 50, "y_in": 50, "heading_deg": 0})), seed=1, noise=noise)
    sim.move([Pose(100, 50, 90)], None)  # no turn on the way, a 90° turn at the end: one error drawn
    error = sim.drift.dheading_deg
    assert error != 0.0
    assert sim.pose.heading_deg == pytest.approx(90.0)  # it truly faces where it turned to ...
    assert sim.reported_pose().heading_deg == pytest.approx((90.0 - error) % 360)  # ... and believes it is off
    moved = sim.move([Pose(100, 100, 90)], None)
    assert (moved.pose.x_in, moved.pose.y_in) == pytest.approx((100, 100))  # where it believes it went
    truly = (sim.pose.x_in, sim.pose.y_in)
    assert math.dist(truly, (100, 50)) == pytest.approx(50)  # 50 in from where the error happened ...
    assert math.dist(truly, (100, 100)) == pytest.approx(100 * math.sin(math.radians(abs(error)) / 2))  # ... turned


# ---------------------------------------------------------------- the apartments


@pytest.mark.parametrize("name", APARTMENTS)
def test_the_apartments_are_homes_of_named_rooms(name: str) -> None:
    home = load_world(name, CATALOGUE)
    assert 3 <= len(home.home.rooms) <= 5 and 10 <= len(home.objects) <= 20
    assert not home.home.ceiling_camera and home.home.heading_drift and home.dock is not None
    assert any(f.kind == "table" for f in home.furniture) and any(f.kind == "solid" for f in home.furniture)
    assert all(home.home.room_at(p.x_in, p.y_in) is not None for p in home.objects)


def reachable_cells(home: WorldSpec) -> tuple[np.ndarray, Any]:
    """The cells (1 in) a base centre can reach from the start: free of every wall,
    furniture footprint (a table's whole top) and object by more than the base's
    radius (plus a cell's half-diagonal, so the grid never cuts a corner), and joined
    to the start's cell by 8-connected moves."""
    grid = truth_map(home, CATALOGUE, 1.0, layer="footprint", objects=True)
    clearance = ndimage.distance_transform_edt(~grid.occupied)
    free = clearance > RADIUS + 1.0
    labels, _ = ndimage.label(free, structure=np.ones((3, 3)))
    start = grid.cell_of(home.robot[0], home.robot[1])
    assert free[start], "the start pose is not clear of everything"
    return labels == labels[start], grid


@pytest.mark.parametrize("name", APARTMENTS)
def test_every_object_in_the_apartment_can_be_reached(name: str) -> None:
    """For each object a base pose exists, joined to the start by a collision-free
    path, from which the sonar (``sensor_offset_in`` ahead of the base) turned to the
    object is within 12 in of its footprint: the middle of the procedures' ranges."""
    home = load_world(name, CATALOGUE)
    reach, grid = reachable_cells(home)
    rows, cols = np.indices(reach.shape)
    xs, ys = grid.x0_in + cols + 0.5, grid.y0_in + rows + 0.5
    for i, p in enumerate(home.objects):
        fp = CATALOGUE[p.entry_id].footprint
        extent = fp.radius_in if fp.shape == "circle" else math.hypot(fp.length_in, fp.width_in) / 2
        near = np.hypot(xs - p.x_in, ys - p.y_in) <= extent + PROFILE.robot.geometry.sensor_offset_in + 12.0
        assert (reach & near).any(), f"{name}: objects[{i}] {p.entry_id} cannot be reached"


def test_a_doorway_blocked_by_furniture_is_found_unreachable() -> None:
    """The reachability check can fail: a cabinet across the hall's doorway to the
    living room cuts that room (and the bedroom beyond it) off."""
    home = load_world("apartment", CATALOGUE)
    cabinet = dataclasses.replace(home.furniture[0], name="cabinet", x_in=100, y_in=215, width_in=40, depth_in=20)
    blocked = dataclasses.replace(home, furniture=(*home.furniture, cabinet))
    reach, grid = reachable_cells(blocked)
    assert reach[grid.cell_of(100, 100)] and not reach[grid.cell_of(100, 300)]


# ---------------------------------------------------------------- the truth map


def test_the_truth_map_of_a_room_with_one_wall_counts_its_cells() -> None:
    """100x50 in, a 2 in wall at x=50 along the whole depth (x 49-51), 1 in cells: the
    wall covers the columns of x 49-50 and 50-51 over 50 rows, 100 cells (the columns
    it only touches, 48-49 and 51-52, are free); with the 6 in outer walls around the
    room the grid is 112x62 cells, the walls a 6-cell ring. With 5 in cells the wall
    covers part of the columns 45-50 and 50-55: 2 x 10 cells."""
    home = spec(world(walls=[{"from": [50, 0], "to": [50, 50], "thickness_in": 2}], robot={"x_in": 15, "y_in": 15}))
    inside = truth_map(home, CATALOGUE, 1.0, margin_in=0.0)
    assert inside.occupied.shape == (50, 100) and inside.occupied.sum() == 100
    assert inside.occupied[:, 49:51].all() and inside.extent == (0.0, 0.0, 100.0, 50.0)
    whole = truth_map(home, CATALOGUE, 1.0)
    assert whole.occupied.shape == (62, 112) and whole.occupied.sum() == 112 * 62 - 100 * 50 + 100
    coarse = truth_map(home, CATALOGUE, 5.0, margin_in=0.0)
    assert coarse.occupied.shape == (10, 20) and coarse.occupied.sum() == 20 and coarse.occupied[:, 9:11].all()


def test_the_truth_map_sees_a_table_as_legs_at_the_scan_plane_and_a_top_in_its_footprint() -> None:
    table = {"name": "table", "kind": "table", "leg_in": 2, "x_in": 70, "y_in": 25, "width_in": 40, "depth_in": 20}
    box = {"id": "closed-box-2x2x2/upright", "x_in": 20, "y_in": 40}
    home = spec(world(furniture=[table], objects=[box]))
    assert truth_map(home, CATALOGUE, 1.0, margin_in=0.0).occupied.sum() == 4 * 4  # four 2x2 in legs
    assert truth_map(home, CATALOGUE, 1.0, margin_in=0.0, layer="footprint").occupied.sum() == 40 * 20
    assert truth_map(home, CATALOGUE, 1.0, margin_in=0.0, objects=True).occupied.sum() == 4 * 4 + 2 * 2


def test_the_truth_map_png_has_north_up(tmp_path: Path) -> None:
    home = spec(world(walls=[{"from": [0, 40], "to": [100, 40], "thickness_in": 2}], rooms=[
        {"name": "hall", "outline": [[0, 0], [100, 0], [100, 39], [0, 39]]}]))
    grid = truth_map(home, CATALOGUE, 1.0, margin_in=0.0)
    image = cv2.imread(str(write_png(tmp_path / "map.png", grid, home, pixels_per_cell=2)), cv2.IMREAD_GRAYSCALE)
    assert image.shape == (100, 200)
    assert (image[2 * (50 - 41):2 * (50 - 39)] == 0).all()  # the wall at y 39-41 is 9-11 cells from the top
    assert (image[0:2 * (50 - 41)] == 255).all()  # above it, nothing but floor


def test_the_executive_stops_at_its_first_look_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A run in a home with the ceiling camera's perception (the default) stops before
    the robot moves with one line saying what to add (exit status 2, bad usage)."""
    from csl_cli.main import main

    assert main(["run", "--world", "apartment", "--no-plots", "--out", str(tmp_path),
                 "--library", str(tmp_path / "lib.sqlite")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["csl: error: world 'apartment' has no ceiling camera: add --perception onboard (the robot "
                   "explores it with its own range scans)"]


# ---------------------------------------------------------------- over zenoh


@pytest.mark.zenoh
def test_a_driver_node_resets_to_the_apartment_and_answers_no_camera(server: zenoh.Session, endpoint: str) -> None:
    node = DriverNode(SimulatedHero("home1", noise=NoiseConfig.off()), server)
    client = ZenohDriver("home1", connect=[endpoint], discover_s=5.0)
    with node, client:
        assert client.wait_ready(5.0)
        assert client.reset(world="apartment", seed=0).result(REPLY_S).pose == Pose(50, 50, 0)
        refused = error_of(client.camera())
        assert refused.code == NO_CAMERA and "no ceiling camera" in refused.message
        moved = client.move([Pose(80, 50, 0)]).result(REPLY_S)  # the node serves on
        assert (moved.pose.x_in, moved.pose.y_in) == pytest.approx((80, 50))
        assert client.reset(world="lab").result(REPLY_S).pose == Pose(30, 30, 0)
        assert client.camera().result(REPLY_S).pixels.size > 0


@pytest.mark.zenoh
def test_csl_driver_sim_serves_the_apartment(endpoint: str) -> None:
    argv = ["-m", "csl_cli", "driver", "sim", "--robot", "home2", "--world", "apartment", "--listen", endpoint]
    with DriverProcess(argv) as process:
        process.ready()
        with ZenohDriver("home2", connect=[endpoint], discover_s=5.0) as client:
            assert client.wait_ready(5.0)
            assert client.state().pose == Pose(50, 50, 0)
            assert error_of(client.camera()).code == NO_CAMERA
            assert client.reset(world="apartment-2").result(REPLY_S).pose == Pose(40, 210, 0)
        assert process.stop() == 0


@pytest.mark.parametrize("name", ["apartment", "apartment-2"])
def test_a_lidar_scan_in_the_apartment_ends_where_the_true_map_is_occupied(name: str) -> None:
    """The scan (ray casting in pymunk) and the true map (drawn from the world file) are
    two readings of one home: every echo of a noise-free lidar scan from the start pose
    ends within a cell of an occupied cell of the scan-plane map with objects, and the
    beam is free 3 in before it ends; a beam with no echo (out through a doorway) meets
    no occupied cell within the lidar's 480 in."""
    home = load_world(name, CATALOGUE)
    truth = truth_map(home, CATALOGUE, 1.0, objects=True)
    scan = SimWorld(home, 0, PROFILE, NoiseConfig.off()).scan()
    occupied = ndimage.binary_dilation(truth.occupied, iterations=1)
    echoes = 0
    for angle, r in zip(scan.angles_deg, scan.ranges_in):
        heading = math.radians(scan.pose.heading_deg + angle)
        if not math.isfinite(r):  # no echo within 480 in: the beam's way out is free that far
            x0, y0, x1, y1 = truth.extent
            way = [(scan.pose.x_in + d * math.cos(heading), scan.pose.y_in + d * math.sin(heading))
                   for d in np.arange(1.0, scan.range_max_in - 2.0, 1.0)]
            assert not any(truth.occupied[truth.cell_of(x, y)] for x, y in way if x0 <= x < x1 and y0 <= y < y1)
            continue
        echoes += 1
        end = (scan.pose.x_in + r * math.cos(heading), scan.pose.y_in + r * math.sin(heading))
        before = (scan.pose.x_in + (r - 3.0) * math.cos(heading), scan.pose.y_in + (r - 3.0) * math.sin(heading))
        assert occupied[truth.cell_of(*end)], (angle, r)
        assert not truth.occupied[truth.cell_of(*before)], (angle, r)
    assert echoes > 0.9 * len(scan.ranges_in)  # the hall's walls: most beams end within 480 in

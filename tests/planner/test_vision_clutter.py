"""Vision on cluttered floors (docs/planner.md "Clutter"): objects 1-3 in apart are
separate regions, touching ones are cut at their pinch, and a lone object is never cut."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camera_model.board import load_board
from hero_driver.sim.render_board import board_path
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import WORLDS_DIR, load_world, parse_world
from planner.segmentation import calibrated_camera
from planner.vision import Region, look
from tests.planner.drawing import Canvas

CATALOGUE = profile_and_catalogue()[1]
# vision's usual centroid error by preset: BENCHMARKS.md "Vision error by camera preset"
# (max 0.34 in simple; test_vision_realistic.py bounds the realistic max at 0.7 in)
CENTROID_ERROR_IN = {"simple": 0.5, "realistic": 0.7}


def floor(*objects: tuple[str, float, float, float]) -> object:
    data = {"name": "clutter-test", "board": "lab-board.json", "room": {"width_in": 240, "depth_in": 180},
            "robot": {"x_in": 30, "y_in": 30, "heading_deg": 0},
            "objects": [{"id": i, "x_in": x, "y_in": y, "yaw_deg": yaw} for i, x, y, yaw in objects]}
    return parse_world(data, str(WORLDS_DIR / "clutter-test.json"), CATALOGUE)  # the board beside the shipped ones


def regions(world: object, preset: str) -> tuple[Region, ...]:
    """The regions vision finds on the world's first image; a realistic one through a
    camera calibrated on that same image (its empty floor painted from it), as an
    episode without a calibration file does."""
    image = SimWorld(world, 0, camera=preset).camera()
    camera = calibrated_camera(image.pixels, load_board(board_path("lab"))) if preset == "realistic" else None
    return look(image, camera).regions


def assert_found_once_each(found: tuple[Region, ...], placed: list[tuple[float, float]], preset: str) -> None:
    assert len(found) == len(placed)
    for x, y in placed:
        assert min(math.hypot(r.centroid[0] - x, r.centroid[1] - y) for r in found) < CENTROID_ERROR_IN[preset]


@pytest.mark.parametrize("preset", ["simple", "realistic"])
def test_the_clutter_world_is_six_regions_where_the_file_puts_them(preset: str) -> None:
    spec = load_world("clutter", CATALOGUE)
    assert_found_once_each(regions(spec, preset), [(p.x_in, p.y_in) for p in spec.objects], preset)


# a tumbler beside a bottle, a 2 in box against the magazine box's side, a tumbler at
# the 10 in box's corner: edge-to-edge gaps in inches
PAIRS = {
    "round pair": lambda g: [("tumbler-20oz/upright", 70, 60, 0), ("soda-bottle-16oz/upright", 70 + 3.2 + g, 60, 0)],
    "small box on a side": lambda g: [("magazine-box-9x4x7/upright", 130, 110, 0),
                                      ("closed-box-2x2x2/upright", 130, 113 + g, 0)],
    "tumbler at a big box": lambda g: [("closed-box-10x10x10/upright", 180, 80, 0),
                                       ("tumbler-20oz/upright", 186.85 + g, 83, 0)],
}


@pytest.mark.parametrize("preset", ["simple", "realistic"])
@pytest.mark.parametrize("pair", sorted(PAIRS))
@pytest.mark.parametrize("gap_in", [1.0, 2.0, 3.0])
def test_two_objects_one_to_three_inches_apart_are_two_regions(preset: str, pair: str, gap_in: float) -> None:
    objects = PAIRS[pair](gap_in)
    assert_found_once_each(regions(floor(*objects), preset), [(x, y) for _, x, y, _ in objects], preset)


@pytest.mark.parametrize("pair", sorted(PAIRS))
def test_touching_objects_are_cut_at_their_pinch(pair: str) -> None:
    # half an inch apart: on band images they merge into one blob, which is cut in two
    objects = PAIRS[pair](0.5)
    assert_found_once_each(regions(floor(*objects), "simple"), [(x, y) for _, x, y, _ in objects], "simple")


@settings(max_examples=25, deadline=None)
@given(entry=st.sampled_from(sorted(e for e in CATALOGUE if e.endswith(("upright", "lying")))),
       yaw=st.floats(0.0, 360.0), dx=st.floats(-0.4, 0.4), dy=st.floats(-0.4, 0.4))
def test_a_lone_object_is_never_cut(entry: str, yaw: float, dx: float, dy: float) -> None:
    found = regions(floor((entry, 120 + dx, 90 + dy, yaw)), "simple")
    assert len(found) == 1 and not found[0].cluster


def test_a_blob_far_from_convex_is_one_region_reported_as_a_cluster() -> None:
    # an L of two 16 x 3.2 in bars meeting at a corner: 92.2 in² over a hull of 174.1
    # (the 16 in square less the corner triangle beyond the bars' ends, 12.8² / 2): it
    # fills 0.53 of its hull, far below any lone object (planner/vision.py)
    canvas = Canvas().rect(108.0, 81.6, 16.0, 3.2, 0.0).rect(101.6, 88.0, 3.2, 16.0, 0.0)
    found = look(canvas.image()).regions
    assert len(found) == 1 and found[0].cluster


def test_two_boxes_in_an_l_are_one_region_one_image_cannot_call_a_cluster() -> None:
    # two 9 x 4 in boxes in an L, 0.2 in apart: one blob with no pinch to cut at that
    # fills 0.80 of its hull, as much as a lone box seen through the fish-eye camera
    # can; seen apart the image before, it is one (tests/planner/test_merging.py)
    found = regions(floor(("magazine-box-9x4x7/upright", 100, 90, 0),
                          ("magazine-box-9x4x7/upright", 106.7, 92.5, 90)), "simple")
    assert len(found) == 1 and not found[0].cluster

"""Disturbances in the simulator (hero_driver.sim.events): a world file's scheduled
nudges, removals and swaps by robot step or robot time, the ``--disturb`` presets, and
the one-line errors for a bad ``events`` entry or flag value.

The scene: a 10 in closed box at (80, 20), the robot at (20, 20) facing it; a move to
(58, 20) puts the sonar 6 in from the box (as in test_sim_battery).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.interface import NO_TARGET, DriverError, Pose
from hero_driver.sim.disturber import area
from hero_driver.sim.events import DisturbPreset, parse_disturb
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import parse_world

BOX = "closed-box-10x10x10/upright"
BOTTLE = "soda-bottle-16oz/upright"


def spec(events: list[object], objects: list[dict[str, object]] | None = None) -> object:
    data = {"name": "events", "room": {"width_in": 160, "depth_in": 100},
            "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0},
            "objects": objects or [{"id": BOX, "x_in": 80, "y_in": 20}], "events": events}
    return data


def world(events: list[object], disturb: DisturbPreset = DisturbPreset(), **kw: object) -> SimWorld:
    _, catalogue = profile_and_catalogue()
    return SimWorld(parse_world(spec(events, **kw), "<events>", catalogue), seed=0,  # type: ignore[arg-type]
                    noise=NoiseConfig.preset("clean"), disturb=disturb)


def object_pixels(sim: SimWorld) -> int:
    """Pixels of the camera image in the objects' band (220, docs/conventions.md)."""
    pixels = sim.camera().pixels
    return int(((pixels >= 205) & (pixels <= 235)).sum())


def approach_and_sense(sim: SimWorld) -> None:
    sim.move([Pose(58.0, 20.0, 0.0)], (80.0, 20.0))  # step 1
    sim.sense("H-Sweep-5°")  # step 2


def test_a_nudge_at_a_step_moves_the_object_after_that_verb() -> None:
    sim = world([{"at_step": 2, "object": 0, "do": "nudge", "dx_in": 0, "dy_in": 30, "dyaw_deg": 15}])
    sim.move([Pose(58.0, 20.0, 0.0)], (80.0, 20.0))
    assert (sim.truth()[0].x_in, sim.truth()[0].y_in) == (80.0, 20.0)
    sim.sense("H-Sweep-5°")  # measured in place; the nudge comes as it ends
    [truth] = sim.truth()
    assert (truth.x_in, truth.y_in, truth.yaw_deg) == pytest.approx((80.0, 50.0, 15.0))
    [happened] = sim.disturbances
    assert (happened.step, happened.object, happened.do) == (2, 0, "nudge")
    assert happened.detail == "moved 30.0 in, turned +15 deg"
    with pytest.raises(DriverError) as gone:  # nothing in front of the sonar any more
        sim.sense("H-Sweep-5°")
    assert gone.value.code == NO_TARGET


def test_a_removal_by_robot_time_takes_the_object_off_the_floor_and_the_image() -> None:
    sim = world([{"at_s": 1.0, "object": BOX, "do": "remove"}])
    pixels_before = object_pixels(sim)
    sim.move([Pose(58.0, 20.0, 0.0)], (80.0, 20.0))  # its end is past 1 s: removed then
    assert [h.step for h in sim.disturbances] == [1] and sim.disturbances[0].do == "remove"
    assert not [o for o in sim.physics.objects if o.status == "floor"]
    assert pixels_before > 100 and object_pixels(sim) == 0


def test_a_replacement_swaps_the_entry_in_place() -> None:
    sim = world([{"at_step": 1, "object": 0, "do": "replace", "entry": BOTTLE}])
    sim.move([Pose(58.0, 20.0, 0.0)], (80.0, 20.0))
    [truth] = sim.truth()
    assert (truth.entry_id, truth.x_in, truth.y_in, truth.index) == (BOTTLE, 80.0, 20.0, 0)
    assert sim.disturbances[0].detail == f"{BOX} -> {BOTTLE}"


def test_events_fire_once_and_reset_restores_them() -> None:
    sim = world([{"at_step": 1, "object": 0, "do": "nudge", "dx_in": 5}])
    approach_and_sense(sim)
    assert len(sim.disturbances) == 1 and sim.truth()[0].x_in == pytest.approx(85.0)
    sim.load(sim.spec, 0)
    assert sim.disturbances == [] and sim.truth()[0].x_in == 80.0


def test_an_object_in_the_hand_is_not_disturbed() -> None:
    # the bottle's face where the box's was (75 in): the sonar 6 in from it after the move
    sim = world([{"at_step": 3, "object": 0, "do": "remove"}], objects=[{"id": BOTTLE, "x_in": 76.35, "y_in": 20}])
    approach_and_sense(sim)
    assert sim.grasp("Front-Wrap").success  # step 3: lifted, so nothing to take away
    assert sim.disturbances == [] and sim.truth()[0].held


@pytest.mark.parametrize(("event", "message"), [
    ({"object": 0, "do": "remove"}, "field 'at_step' or 'at_s' must be given"),
    ({"at_step": 1, "at_s": 2, "object": 0, "do": "remove"}, "field 'at_step' or 'at_s' must be given"),
    ({"at_step": 1.5, "object": 0, "do": "remove"}, "field 'at_step' must be a whole number"),
    ({"at_step": 1, "object": 3, "do": "remove"}, "field 'object' must be an index into objects (0-0)"),
    ({"at_step": 1, "object": "no-such/entry", "do": "remove"}, "field 'object' must be an index"),
    ({"at_step": 1, "object": 0, "do": "explode"}, "field 'do' must be one of"),
    ({"at_step": 1, "object": 0, "do": "remove", "dx_in": 3}, "field 'dx_in' does not apply to do 'remove'"),
    ({"at_step": 1, "object": 0, "do": "replace", "entry": "nothing"}, "field 'entry' names unknown catalogue"),
    ({"at_step": 1, "object": 0, "do": "nudge", "dx_in": "far"}, "field 'dx_in' must be a number"),
    ({"at_step": 1, "object": 0, "do": "nudge", "when": 3}, "field 'when' is unknown"),
])
def test_a_bad_event_is_one_line_naming_it(event: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError) as caught:
        world([event])
    text = str(caught.value)
    assert "\n" not in text and text.startswith("<events>: events[0]: ") and message in text


def test_events_must_be_an_array() -> None:
    _, catalogue = profile_and_catalogue()
    with pytest.raises(ValueError, match="field 'events' must be an array"):
        parse_world({**spec([]), "events": {"at_step": 1}}, "<events>", catalogue)  # type: ignore[dict-item]


# -- presets ----------------------------------------------------------------------------


def test_parse_disturb() -> None:
    assert parse_disturb("nudge:0.2").rates == (("nudge", 0.2),)
    assert parse_disturb("remove:0.1, replace:0.3").rates == (("remove", 0.1), ("replace", 0.3))
    assert not parse_disturb("nudge:0").active
    for bad, message in (("push:0.2", "KIND one of nudge, remove, replace"), ("nudge:x", "a number from 0 to 1"),
                         ("nudge:1.5", "a number from 0 to 1"), ("nudge:0.6,remove:0.6", "sum to 1.2"),
                         ("nudge:0.1,nudge:0.2", "nudge is given twice")):
        with pytest.raises(ValueError, match=message) as caught:
            parse_disturb(bad)
        assert str(caught.value).startswith("--disturb: ")


def test_a_certain_preset_removes_each_object_right_after_its_first_measurement() -> None:
    sim = world([], disturb=parse_disturb("remove:1"))
    sim.move([Pose(58.0, 20.0, 0.0)], (80.0, 20.0))
    assert sim.disturbances == []  # moving near it is not sensing it
    sim.sense("H-Sweep-5°")
    assert [(h.step, h.do) for h in sim.disturbances] == [(2, "remove")]


def test_a_preset_swap_is_for_an_entry_the_camera_can_tell_apart() -> None:
    sim = world([], disturb=parse_disturb("replace:1"))
    approach_and_sense(sim)
    _, catalogue = profile_and_catalogue()
    [truth] = sim.truth()
    ratio = area(catalogue[truth.entry_id].footprint) / area(catalogue[BOX].footprint)
    assert truth.entry_id != BOX and (ratio >= 2.0 or ratio <= 0.5)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**16))
def test_a_preset_nudge_is_seeded_and_leaves_the_object_clear_of_the_robot(seed: int) -> None:
    def run() -> tuple[object, ...]:
        sim = world([], disturb=parse_disturb("nudge:1"))
        sim.load(sim.spec, seed)
        approach_and_sense(sim)
        return tuple(sim.disturbances), sim.truth()[0], sim.pose

    first, again = run(), run()
    assert first == again
    happened, truth, pose = first
    assert len(happened) <= 1  # type: ignore[arg-type]
    # the base's centre in the 10 in box's own frame; its distance to the box's outline
    yaw = math.radians(truth.yaw_deg)  # type: ignore[attr-defined]
    dx, dy = pose.x_in - truth.x_in, pose.y_in - truth.y_in  # type: ignore[attr-defined]
    lx, ly = dx * math.cos(yaw) + dy * math.sin(yaw), -dx * math.sin(yaw) + dy * math.cos(yaw)
    gap = math.hypot(max(abs(lx) - 5.0, 0.0), max(abs(ly) - 5.0, 0.0))
    assert gap >= profile_and_catalogue()[0].robot.geometry.base_radius_in + 1.0 - 1e-6


def test_without_a_preset_or_events_nothing_happens() -> None:
    sim = world([])
    approach_and_sense(sim)
    assert sim.disturbances == [] and sim.truth()[0].x_in == 80.0

"""The map draws every move as planned: the log carries each move's waypoints, and the
plot joins them to the stop before (a straight line between stops once cut through a
box the planner went round)."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st
import matplotlib.image
import numpy as np
import pytest

from camera_model.image import CameraImage
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from reporting.plots import Leg, legs, plot_map
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner

EVENTS = [
    {"tick": 1, "event": "located", "regions": []},
    {"tick": 1, "event": "move", "object": 0, "pose": [50.2, 61.0, 90.0], "collided": False,
     "path": [[50.0, 30.0, 0.0], [50.0, 60.0, 90.0]]},
    {"tick": 2, "event": "sense", "object": 0, "procedure": "D-Scan-0.3"},
    {"tick": 3, "event": "move", "object": 0, "pose": [64.0, 61.0, 0.0], "collided": True,
     "path": [[70.0, 61.0, 0.0]]},
]


def test_each_leg_starts_where_the_last_move_stopped() -> None:
    assert legs(EVENTS, (30.0, 30.0)) == [
        Leg(1, (30.0, 30.0), ((50.0, 30.0), (50.0, 60.0)), (50.2, 61.0, 90.0), False),
        Leg(2, (50.2, 61.0), ((70.0, 61.0),), (64.0, 61.0, 0.0), True),
    ]


def test_without_a_start_the_first_leg_begins_at_its_first_waypoint() -> None:
    assert legs(EVENTS[:2], None)[0].origin is None


def test_the_map_is_drawn_with_paths_and_footprints(tmp_path) -> None:  # noqa: ANN001
    pixels = np.full((100, 120), 30, np.uint8)
    image = CameraImage(pixels, 0.8, 0.0, 80.0)
    out = tmp_path / "map.png"
    plot_map(out, image, [], EVENTS, [], (30.0, 30.0), base_radius_in=8.0)
    drawn = matplotlib.image.imread(out)
    assert drawn.shape[0] > 400 and drawn.shape[1] > 400


@pytest.mark.slow
def test_a_simulated_episode_logs_every_moves_waypoints(tmp_path) -> None:  # noqa: ANN001
    learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    executive = Executive(SimulatedHero("r1", world="lab", seed=0), learner)
    try:
        executive.run()
    finally:
        executive.shutdown()
        learner.close()
    moves = [e for e in executive.log.events if e["event"] == "move"]
    assert moves
    for move in moves:
        assert move["path"], "a move is logged with the waypoints it was sent"
        # the base stops near the goal: within odometry and sonar-centring distance of it
        assert math.dist(move["path"][-1][:2], move["pose"][:2]) < 6.0
        assert all(len(p) == 3 for p in move["path"])


_xy = st.floats(-500, 500, allow_nan=False)
_move = st.fixed_dictionaries({
    "event": st.just("move"), "collided": st.booleans(),
    "pose": st.tuples(_xy, _xy, st.floats(-180, 180)).map(list),
    "path": st.lists(st.tuples(_xy, _xy, st.floats(-180, 180)).map(list), min_size=1, max_size=5)})


@given(st.lists(st.one_of(_move, st.just({"event": "sense"})), max_size=12), st.tuples(_xy, _xy))
def test_legs_chain_every_move_to_the_stop_before_it(events, start) -> None:  # noqa: ANN001
    drawn = legs(events, start)
    moves = [e for e in events if e["event"] == "move"]
    assert [leg.number for leg in drawn] == list(range(1, len(moves) + 1))
    stops = [tuple(m["pose"]) for m in moves]
    assert [leg.origin for leg in drawn] == ([start] + [s[:2] for s in stops])[:len(moves)]
    assert [leg.stop for leg in drawn] == stops
    assert [leg.waypoints for leg in drawn] == [tuple(tuple(p[:2]) for p in m["path"]) for m in moves]

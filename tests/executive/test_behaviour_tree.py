"""Snapshots of the behaviour tree: its shape, and tick-by-tick traces of scripted
episodes, one per control strategy (method.md §5)."""

from __future__ import annotations

import py_trees
import pytest
from syrupy.extensions.single_file import SingleFileSnapshotExtension, WriteMode

from behaviours.context import Params
from executive.tree_shape import shape_tree
from tests.executive.scenarios import one, run, transcript, upright_tumbler_description, world
from learner.service.local import LocalLearner


class TextSnapshot(SingleFileSnapshotExtension):
    _write_mode = WriteMode.TEXT
    file_extension = "txt"


@pytest.fixture
def snap(snapshot):  # noqa: ANN001, ANN201
    return snapshot.use_extension(TextSnapshot)


def test_tree_shape(snap) -> None:  # noqa: ANN001
    assert py_trees.display.unicode_tree(shape_tree()) == snap


def _one_object(entry: str, seed: int, params: Params = Params()):  # noqa: ANN202
    scenario = run(one(entry), seed, params=params)
    assert scenario.result.status == "SUCCESS"
    (obj,) = scenario.result.objects
    return scenario, obj


def test_clean_recognition(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("cup-8oz/upright", 1)
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert not obj.ledger.recoveries
    assert transcript(scenario) == snap


def test_value_between_ranges_reselects(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("cup-8oz/upright", 0)
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert obj.ledger.recoveries["reselect"] >= 1 and obj.ledger.recoveries["backtrack"] == 0
    assert any(e["event"] == "unreliable" for e in scenario.executive.log.events)
    assert transcript(scenario) == snap


def test_repeated_unreliable_tests_backtrack(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("closed-box-10x10x10/upright", 0)
    assert obj.ledger.recoveries["backtrack"] >= 1
    assert (obj.outcome, obj.grasp) == ("left", "No-Grab")  # never seen, and correctly left
    assert transcript(scenario) == snap


def test_everything_failing_ends_in_nearest_neighbour(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("closed-box-10x10x10/upright", 0, Params(nearest_after=1))
    events = [e["event"] for e in scenario.executive.log.events]
    assert "nearest" in events and obj.ledger.recoveries["nearest neighbour"] >= 1
    assert events.index("nearest") < events.index("backtrack") if "backtrack" in events else True
    assert transcript(scenario) == snap


def test_ambiguous_leaf_tries_grasps_as_features(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("tumbler-20oz/upside-down", 1)
    assert obj.ledger.recoveries["ambiguous leaf"] >= 1
    assert (obj.outcome, obj.grasp) == ("grasped", "Top-Vert-Grip")
    assert transcript(scenario) == snap


def test_failed_grasp_without_side_effects_drops_its_class(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("tumbler-20oz/upside-down", 3)
    drops = [e for e in scenario.executive.log.events if e["event"] == "drop_grasp"]
    assert drops and all(e["event"] != "start_over" for e in scenario.executive.log.events)
    assert drops[0]["grasp"] not in drops[0]["candidates"]
    assert transcript(scenario) == snap


def test_knocked_over_object_starts_over(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("soda-bottle-16oz/upright", 2)
    assert obj.ledger.recoveries["start over (changed)"] == 1
    effects = [e for e in scenario.executive.log.events if e["event"] == "side_effect"]
    assert effects[0]["effect"] == "changed"
    assert (obj.outcome, obj.grasp) == ("grasped", "Top-Vert-Grip")  # it lies now: a top grip
    assert transcript(scenario) == snap


def test_upside_down_tumbler_jams_recovers_and_is_told_apart_next_time(snap, tmp_path) -> None:  # noqa: ANN001
    """The paper's characteristic failure: Top-Pinch jams the fingers on the upside-down
    20 oz tumbler, recovery finds Top-Vert-Grip, and the description learned (with its
    closed top, Top-Hole? = 0) tells it from the upright tumbler next time."""
    store = tmp_path / "library.sqlite"
    first = run(one("tumbler-20oz/upside-down"), 0, store=store)
    grasps = [(e["grasp"], e["success"]) for e in first.executive.log.events if e["event"] == "grasp"]
    assert ("Top-Pinch", False) in grasps and grasps[-1] == ("Top-Vert-Grip", True)
    jam = grasps.index(("Top-Pinch", False))
    effects = [e["effect"] for e in first.executive.log.events if e["event"] == "side_effect"]
    assert effects[jam] == "none"  # jammed fingers: nothing moved
    learned = next(e for e in first.executive.log.events if e["event"] == "learn")
    assert "Top-Pinch" in learned["wrong"]
    described = {d.object_id: d for d in first.learner.library().descriptions}[learned["id"]]
    assert any(o.feature == "Top-Hole?" and o.value == 0 for o in described.observations)

    with LocalLearner(store) as learner:  # the team also teaches it the upright tumbler
        learner.learn(upright_tumbler_description())
    second = run(one("tumbler-20oz/upside-down"), 1, store=store)
    (again,) = second.result.objects
    tests = [e["test"] for e in second.executive.log.events if e["event"] == "branch"]
    assert tests == ["Height(6,0)", "Top-Hole?(6,0)"]  # same height; the closed top decides
    assert (again.outcome, again.grasp) == ("grasped", "Top-Vert-Grip") and not again.ledger.recoveries
    assert transcript(first) + "# --- next encounter ---\n" + transcript(second) == snap

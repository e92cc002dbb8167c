"""Snapshots of the behaviour tree: its shape, and tick-by-tick traces of scripted
episodes, one per control strategy (docs/method.md §5)."""

from __future__ import annotations

import py_trees
import pytest
from syrupy.extensions.single_file import SingleFileSnapshotExtension, WriteMode

from behaviours.services import Params
from executive.behaviour_tree import build_tree
from hero_driver.sim.noise import NoiseConfig
from learner.criteria import criterion
from tests.executive.scenarios import NOISE, NOISY_SONAR, one, run, transcript, tumbler_story_library

PAPER = criterion("cs-id3")  # the paper's rule, for the stories the paper tells


class TextSnapshot(SingleFileSnapshotExtension):
    _write_mode = WriteMode.TEXT
    file_extension = "txt"


@pytest.fixture
def snap(snapshot):  # noqa: ANN001, ANN201
    return snapshot.use_extension(TextSnapshot)


def test_tree_shape(snap) -> None:  # noqa: ANN001
    assert py_trees.display.unicode_tree(build_tree()) == snap


def _one_object(entry: str, seed: int, params: Params = Params(), noise: NoiseConfig = NOISE):  # noqa: ANN202
    scenario = run(one(entry), seed, params=params, noise=noise)
    assert scenario.result.status == "SUCCESS"
    (obj,) = scenario.result.objects
    return scenario, obj


def _events(scenario, kind: str) -> list[dict]:  # noqa: ANN001
    return [e for e in scenario.executive.log.events if e["event"] == kind]


def test_clean_recognition(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("cup-8oz/upright", 0)
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert not obj.ledger.recoveries and not _events(scenario, "unreliable")
    assert transcript(scenario) == snap


def test_value_between_ranges_reselects(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("magazine-box-9x4x7/upright", 4)
    assert (obj.outcome, obj.grasp) == ("grasped", "Top-Pinch")
    unreliable = _events(scenario, "unreliable")[0]
    value, ranges = unreliable["value"], unreliable["ranges"]
    assert not any(lo <= value <= hi for lo, hi in ranges)  # between (or beyond) the branches
    assert obj.ledger.recoveries["reselect"] >= 1 and obj.ledger.recoveries["backtrack"] == 0
    assert [e["how"] for e in _events(scenario, "choose")][:2] == ["best", "reselect"]
    assert transcript(scenario) == snap


def test_repeated_unreliable_tests_backtrack(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("cup-8oz/upright", 0, Params(max_alternatives=1), NOISY_SONAR)
    backtrack = _events(scenario, "backtrack")
    assert backtrack and obj.ledger.recoveries["backtrack"] >= 1
    events = scenario.executive.log.events
    at = events.index(backtrack[0])
    assert events[at - 1]["event"] == "unreliable" and backtrack[0]["depth"] == 0  # popped from below the root
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert transcript(scenario) == snap


def test_everything_failing_ends_in_nearest_neighbour(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("cup-8oz/upright", 4)
    nearest = _events(scenario, "nearest")
    assert nearest and obj.ledger.recoveries["nearest neighbour"] >= 1
    first_nearest = scenario.executive.log.events.index(nearest[0])
    before = [e["event"] for e in scenario.executive.log.events[:first_nearest]]
    assert "unreliable" in before  # only after reselection had nothing reliable left
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert transcript(scenario) == snap


def test_ambiguous_leaf_tries_grasps_as_features(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("soda-can-12oz/upright", 0, noise=NOISY_SONAR)
    assert obj.ledger.recoveries["ambiguous leaf"] >= 1
    ambiguous = [e for e in _events(scenario, "choose_grasp") if e["how"] == "ambiguous"]
    assert ambiguous and len(ambiguous[0]["candidates"]) > 1  # several grasps left: try them
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert transcript(scenario) == snap


def test_failed_grasp_without_side_effects_drops_its_class(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("magazine-box-9x4x7/upright", 1)
    (drop,) = _events(scenario, "drop_grasp")
    assert drop["grasp"] == "Front-Pinch" and _events(scenario, "side_effect")[0]["effect"] == "none"
    assert not _events(scenario, "start_over")
    assert (obj.outcome, obj.grasp) == ("grasped", "Top-Pinch")  # rebuilt without Front-Pinch
    assert transcript(scenario) == snap


def test_knocked_over_object_starts_over(snap) -> None:  # noqa: ANN001
    scenario, obj = _one_object("tumbler-16oz/upright", 0)
    assert obj.ledger.recoveries["start over (changed)"] == 1
    assert _events(scenario, "side_effect")[0]["effect"] == "changed"
    assert _events(scenario, "start_over")[0]["changed"] is True
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Pinch")  # it lies now: a lying tumbler's grasp
    assert transcript(scenario) == snap


def test_upside_down_tumbler_jams_recovers_and_is_told_apart_next_time(snap, tmp_path) -> None:  # noqa: ANN001
    """The paper's characteristic failure, under the paper's rule (cs-id3): the upside-down
    20 oz tumbler looks like the upright one, Top-Pinch jams the fingers, recovery finds
    Top-Vert-Grip, and the description learned (closed top: Top-Hole? = 0) tells the two
    apart next time."""
    store = tmp_path / "library.sqlite"
    first = run(one("tumbler-20oz/upside-down"), 0, store=store, library=tumbler_story_library(), criterion=PAPER)
    grasps = [(e["grasp"], e["success"]) for e in _events(first, "grasp")]
    assert grasps == [("Top-Pinch", False), ("Top-Vert-Grip", True)]
    assert _events(first, "side_effect")[0]["effect"] == "none"  # jammed fingers: nothing moved
    (learned,) = _events(first, "learn")
    assert learned["wrong"] == ["Top-Pinch"]
    described = {d.object_id: d for d in first.learner.library().descriptions}[learned["id"]]
    assert any(o.feature == "Top-Hole?" and o.value == 0 for o in described.observations)

    second = run(one("tumbler-20oz/upside-down"), 1, store=store, criterion=PAPER)
    (again,) = second.result.objects
    tests = [e["test"] for e in _events(second, "branch")]
    assert "Top-Hole?(6,*)" in tests  # as tall as the upright one: the closed top decides
    assert [(e["grasp"], e["success"]) for e in _events(second, "grasp")] == [("Top-Vert-Grip", True)]
    assert not again.ledger.recoveries
    assert transcript(first) + "# --- next encounter ---\n" + transcript(second) == snap


def test_upside_down_tumbler_next_time_under_the_default_rule(tmp_path) -> None:  # noqa: ANN001
    """The default rule prices a grasp tried as a feature by its failure share. On the
    second encounter the learned description (Top-Vert-Grip) and the upright tumbler's
    (Top-Pinch) remain; Top-Vert-Grip tried as a feature is paid only if it fails, which
    is cheaper than sensing the top's hole first: it is tried at once and holds, so the
    object is right the first time, with no recovery."""
    store = tmp_path / "library.sqlite"
    run(one("tumbler-20oz/upside-down"), 0, store=store, library=tumbler_story_library())
    second = run(one("tumbler-20oz/upside-down"), 1, store=store)
    (again,) = second.result.objects
    assert [(e["grasp"], e["as_feature"], e["success"]) for e in _events(second, "grasp")] == [
        ("Top-Vert-Grip", True, True)]
    assert not _events(second, "sense") and not again.ledger.recoveries

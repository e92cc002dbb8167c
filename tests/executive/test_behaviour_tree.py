"""Snapshots of the behaviour tree: its shape, and tick-by-tick traces of scripted
episodes, one per control strategy (docs/method.md §5), written on the installed
testing API (csl_testing and its pytest plugin, docs/snapshot-testing.md)."""

from __future__ import annotations

from behaviours.services import Params
from csl_testing import ScenarioFactory, ScenarioResult, encounters, tree_display
from hero_driver.sim.noise import NoiseConfig
from learner.choosing.criteria import criterion
from tests.executive.scenarios import NOISE, NOISY_SONAR, tumbler_story_library

PAPER = criterion("cs-id3")  # the paper's rule, for the stories the paper tells
# The paper's robot sensed with the arm only: each story pins one control strategy on the
# sensing it takes, so the camera's appearance (on by default) is off here.
ARM_ONLY = Params(use_appearance=False)


def test_tree_shape(csl_snapshot) -> None:  # noqa: ANN001
    assert tree_display() == csl_snapshot


def _one_object(csl_scenario: ScenarioFactory, entry: str, seed: int, params: Params = ARM_ONLY,
                noise: NoiseConfig = NOISE) -> ScenarioResult:
    result = csl_scenario.one_object(entry, seed=seed, params=params, noise=noise).run()
    assert result.status == "SUCCESS"
    return result


def test_clean_recognition(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "cup-8oz/upright", 0)
    obj = result.object
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert not obj.ledger.recoveries and not result.events_of("unreliable")
    assert result.transcript() == csl_snapshot


def test_appearance_recognition(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    """The default executive on the same cup: the camera's appearance (round, its area and
    elongation) leaves candidates that share one grasp, so the cup is grasped with nothing
    sensed (docs/method.md, the appearance); the arm-only story above senses first."""
    result = _one_object(csl_scenario, "cup-8oz/upright", 0, Params())
    obj = result.object
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert not result.events_of("sense") and not obj.ledger.recoveries
    assert result.transcript() == csl_snapshot


def test_value_between_ranges_reselects(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "magazine-box-9x4x7/upright", 4)
    obj = result.object
    assert (obj.outcome, obj.grasp) == ("grasped", "Top-Pinch")
    unreliable = result.events_of("unreliable")[0]
    value, ranges = unreliable["value"], unreliable["ranges"]
    assert not any(lo <= value <= hi for lo, hi in ranges)  # between (or beyond) the branches
    assert obj.ledger.recoveries["reselect"] >= 1 and obj.ledger.recoveries["backtrack"] == 0
    assert [e["how"] for e in result.events_of("choose")][:2] == ["best", "reselect"]
    assert result.transcript() == csl_snapshot


def test_repeated_unreliable_tests_backtrack(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "cup-8oz/upright", 0, Params(max_alternatives=1, use_appearance=False), NOISY_SONAR)
    obj = result.object
    backtrack = result.events_of("backtrack")
    assert backtrack and obj.ledger.recoveries["backtrack"] >= 1
    at = result.events.index(backtrack[0])
    assert result.events[at - 1]["event"] == "unreliable" and backtrack[0]["depth"] == 0  # popped from below the root
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert result.transcript() == csl_snapshot


def test_everything_failing_ends_in_nearest_neighbour(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "cup-8oz/upright", 4)
    obj = result.object
    nearest = result.events_of("nearest")
    assert nearest and obj.ledger.recoveries["nearest neighbour"] >= 1
    before = [e["event"] for e in result.events[:result.events.index(nearest[0])]]
    assert "unreliable" in before  # only after reselection had nothing reliable left
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert result.transcript() == csl_snapshot


def test_ambiguous_leaf_tries_grasps_as_features(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "soda-can-12oz/upright", 0, noise=NOISY_SONAR)
    obj = result.object
    assert obj.ledger.recoveries["ambiguous leaf"] >= 1
    ambiguous = [e for e in result.events_of("choose_grasp") if e["how"] == "ambiguous"]
    assert ambiguous and len(ambiguous[0]["candidates"]) > 1  # several grasps left: try them
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Wrap")
    assert result.transcript() == csl_snapshot


def test_failed_grasp_without_side_effects_drops_its_class(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "magazine-box-9x4x7/upright", 1)
    obj = result.object
    (drop,) = result.events_of("drop_grasp")
    assert drop["grasp"] == "Front-Pinch" and result.events_of("side_effect")[0]["effect"] == "none"
    assert not result.events_of("start_over")
    assert (obj.outcome, obj.grasp) == ("grasped", "Top-Pinch")  # rebuilt without Front-Pinch
    assert result.transcript() == csl_snapshot


def test_knocked_over_object_starts_over(csl_scenario, csl_snapshot) -> None:  # noqa: ANN001
    result = _one_object(csl_scenario, "tumbler-16oz/upright", 0)
    obj = result.object
    assert obj.ledger.recoveries["start over (changed)"] == 1
    assert result.events_of("side_effect")[0]["effect"] == "changed"
    assert result.events_of("start_over")[0]["changed"] is True
    assert (obj.outcome, obj.grasp) == ("grasped", "Front-Pinch")  # it lies now: a lying tumbler's grasp
    assert result.transcript() == csl_snapshot


def test_upside_down_tumbler_jams_recovers_and_is_told_apart_next_time(csl_scenario, csl_snapshot,  # noqa: ANN001
                                                                        tmp_path) -> None:  # noqa: ANN001
    """The paper's characteristic failure, under the paper's rule (cs-id3): the upside-down
    20 oz tumbler looks like the upright one, Top-Pinch jams the fingers, recovery finds
    Top-Vert-Grip, and the description learned (closed top: Top-Hole? = 0) tells the two
    apart next time."""
    story = csl_scenario.one_object("tumbler-20oz/upside-down", seed=0, store=tmp_path / "library.sqlite",
                                    library=tumbler_story_library(), criterion=PAPER, params=ARM_ONLY)
    first = story.run()
    grasps = [(e["grasp"], e["success"]) for e in first.events_of("grasp")]
    assert grasps == [("Top-Pinch", False), ("Top-Vert-Grip", True)]
    assert first.events_of("side_effect")[0]["effect"] == "none"  # jammed fingers: nothing moved
    (learned,) = first.events_of("learn")
    assert learned["wrong"] == ["Top-Pinch"]
    described = {d.object_id: d for d in first.library}[learned["id"]]
    assert any(o.feature == "Top-Hole?" and o.value == 0 for o in described.observations)

    second = story.but(seed=1, library=None).run()  # the same store: what was learned stays
    tests = [e["test"] for e in second.events_of("branch")]
    assert "Top-Hole?(6,*)" in tests  # as tall as the upright one: the closed top decides
    assert [(e["grasp"], e["success"]) for e in second.events_of("grasp")] == [("Top-Vert-Grip", True)]
    assert not second.object.ledger.recoveries
    assert encounters(first.transcript(), second.transcript()) == csl_snapshot


def test_upside_down_tumbler_next_time_under_the_default_rule(csl_scenario, tmp_path) -> None:  # noqa: ANN001
    """The default rule prices a grasp tried as a feature by its failure share. On the
    second encounter the learned description (Top-Vert-Grip) and the upright tumbler's
    (Top-Pinch) remain; Top-Vert-Grip tried as a feature is paid only if it fails, which
    is cheaper than sensing the top's hole first: it is tried at once and holds, so the
    object is right the first time, with no recovery."""
    story = csl_scenario.one_object("tumbler-20oz/upside-down", seed=0, store=tmp_path / "library.sqlite",
                                    library=tumbler_story_library())
    story.run()
    second = story.but(seed=1, library=None).run()
    assert [(e["grasp"], e["as_feature"], e["success"]) for e in second.events_of("grasp")] == [
        ("Top-Vert-Grip", True, True)]
    assert not second.events_of("sense") and not second.object.ledger.recoveries

"""The execution stage step by step: each control strategy of docs/method.md §5."""

from __future__ import annotations

from dataclasses import replace

import pytest

from learner.appearance import Appearance
from learner.choosing.criteria import criterion
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf
from learner.choosing.node import ScoredTest
from learner.costs import ModelMoveCost
from learner.runtime import Exhausted, Matched, RecognitionSession, Unreliable
from tests.learner.fixtures import P, desc, four_objects, hero


def session(library=None, n: int = 3, start=P(60, 0)) -> RecognitionSession:  # noqa: ANN001
    k = hero()
    return RecognitionSession.for_library(library or four_objects(), k, criterion("cs-id3"), ModelMoveCost(k.move), start,
                              max_alternatives=n)


def test_clean_recognition_follows_one_path_and_learns_what_it_measured() -> None:
    s = session()
    sweep = s.decide()
    assert isinstance(sweep, ScoredTest) and str(sweep.test) == "Width-Degree-1°(24,0)"
    assert s.observe(sweep, {"Width-Degree-1°": 8.5}, sweep.target) == Matched(0, (8, 9), 8.5)
    assert s.candidates == ("cup", "tumbler")
    height = s.decide()
    assert str(height.test) == "Height(6,*)" and height.target == P(6, 0)
    assert height.move_cost == pytest.approx(18 * 2)
    s.observe(height, {"Height": 3.4, "Depth": 3.0, "Top-Hole?": 1.0}, height.target)
    leaf = s.decide()
    assert isinstance(leaf, GraspLeaf) and leaf.grasp == "Front-Wrap" and leaf.position == P(6, 0)
    learned = s.description("cup#2", "Front-Wrap", P(6, None))
    assert [str(o) for o in learned.observations] == [
        "(Depth(6,0), 3)", "(Height(6,0), 3.4)", "(Top-Hole?(6,0), 1)", "(Width-Degree-1°(24,0), 8.5)"]


def test_a_value_between_ranges_is_unreliable_and_reselection_picks_the_next_best() -> None:
    s = session()
    sweep = s.decide()
    # [8,9] widens to [5,12], [18,18] to [15,21]: 13.5 lies in neither
    assert s.observe(sweep, {"Width-Degree-1°": 13.5}, sweep.target) == Unreliable(13.5)
    nxt = s.decide()
    assert isinstance(nxt, ScoredTest) and str(nxt.test) == "Height(6,*)"
    assert s.depth == 0


def test_a_dropout_is_unreliable() -> None:
    s = session()
    sweep = s.decide()
    assert s.observe(sweep, {"Width-Degree-1°": None}, sweep.target) == Unreliable(None)


def test_after_n_alternatives_the_node_is_exhausted_and_backtracking_invalidates_the_parent() -> None:
    s = session(n=1)
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 8.5}, sweep.target)
    height = s.decide()
    # Height 4.8: [3.5] widens to [3,4], [6] to [5.5,6.5]: unreliable
    assert isinstance(s.observe(height, {"Height": 4.8}, height.target), Unreliable)
    assert s.decide() == Exhausted(1)
    assert s.backtrack()
    assert s.depth == 0 and ("Width-Degree-1°", P(24, 0)) not in s.measurements
    assert ("Height", P(6, 0)) in s.measurements  # the child's value was not the parent's
    assert s.decide() == Exhausted(1)  # N = 1: the root's one alternative is used up too
    assert not s.backtrack()  # nothing left to undo at the root


def test_backtracking_chooses_a_different_test_at_the_parent() -> None:
    s = session(n=2)
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 8.5}, sweep.target)
    height = s.decide()
    s.observe(height, {"Height": 4.8}, height.target)
    assert s.backtrack()
    again = s.decide()
    assert isinstance(again, ScoredTest) and str(again.test) == "Height(6,*)"  # measured: free
    assert again.cost == 0


def test_nearest_neighbour_follows_the_closest_branch() -> None:
    s = session()
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 13.0}, sweep.target)
    assert s.follow_nearest() == Matched(0, (8, 9), 13.0)  # 4 from [8,9], 5 from [18]
    assert s.candidates == ("cup", "tumbler")


def test_a_guess_does_not_leave_the_object_while_a_confirmable_grasp_is_untried() -> None:
    s = session()
    sweep = s.decide()
    # 25 is in neither [15,21] nor [27,33]: nearest is the closed box's 30 (5 away, 7 from 18)
    assert s.observe(sweep, {"Width-Degree-1°": 25.0}, sweep.target) == Unreliable(25.0)
    assert s.follow_nearest() == Matched(2, (30, 30), 25.0)
    assert s.candidates == ("closed",)
    offered = s.decide()  # not the closed box's No-Grab leaf: the guess's node's grasps, No-Grab last
    assert isinstance(offered, AmbiguousLeaf)
    assert set(offered.object_ids) == {"cup", "box", "tumbler", "closed"}
    assert [o.grasp for o in offered.options][-1] == "No-Grab"
    assert {o.grasp for o in offered.options[:-1]} == {"Front-Wrap", "Front-Pinch", "Top-Pinch"}


def test_a_measured_no_grab_leaf_leaves_and_a_guessed_one_only_when_nothing_else_holds() -> None:
    s = session()
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 31.0}, sweep.target)  # within [27,33]: measured, not guessed
    assert isinstance(s.decide(), GraspLeaf) and s.decide().grasp == "No-Grab"
    s = session()
    for grasp in ("Front-Wrap", "Front-Pinch"):
        s.grasp_failed(grasp, side_effects=False)
    sweep = s.decide()  # the tumbler (9) against the closed box (30)
    s.observe(sweep, {"Width-Degree-1°": 25.0}, sweep.target)
    s.follow_nearest()  # 5 from 30, 16 from 9
    offered = s.decide()
    assert isinstance(offered, AmbiguousLeaf) and [o.grasp for o in offered.options] == ["Top-Pinch", "No-Grab"]
    s.grasp_failed("Top-Pinch", side_effects=False)
    leaf = s.decide()  # every confirmable grasp has failed: leaving is all that is left
    assert isinstance(leaf, GraspLeaf) and leaf.grasp == "No-Grab"


def test_a_no_grab_leaf_the_camera_rules_out_does_not_leave_the_object() -> None:
    looks = {"cup": Appearance(True, 7.0, 1.0), "box": Appearance(False, 45.0, 1.8),
             "tumbler": Appearance(True, 10.0, 1.0), "closed": Appearance(False, 99.0, 1.2)}
    lib = [replace(d, appearance=looks[d.object_id]) for d in four_objects()]
    k = hero()
    seen = Appearance(False, 22.4, 2.3)  # a lying bottle: like none of the four
    s = RecognitionSession.for_library(lib, k, criterion("cs-id3"), ModelMoveCost(k.move), P(60, 0),
                                       appearance=seen)
    assert s.appearance_ignored and set(s.candidates) == {"cup", "box", "tumbler", "closed"}
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 31.0}, sweep.target)  # the closed box's branch, measured
    offered = s.decide()
    assert isinstance(offered, AmbiguousLeaf) and offered.options[-1].grasp == "No-Grab"
    assert {o.grasp for o in offered.options[:-1]} == {"Front-Wrap", "Front-Pinch", "Top-Pinch"}
    like = Appearance(False, 99.0, 1.2)  # looks like the closed box: its leaf is believed
    s = RecognitionSession.for_library(lib, k, criterion("cs-id3"), ModelMoveCost(k.move), P(60, 0), appearance=like)
    assert s.candidates == ("closed",) and s.decide().grasp == "No-Grab"


def test_an_ambiguous_leaf_offers_its_grasps_cheapest_first() -> None:
    lib = [desc("a", "Front-Wrap", ("Width", P(6, 0), 3)), desc("b", "Top-Pinch", ("Width", P(6, 0), 3.2))]
    k = hero()
    s = RecognitionSession.for_library(lib, k, criterion("cs-id3"), ModelMoveCost(k.move), P(6, 0), grasps_as_features=False)
    leaf = s.decide()
    assert isinstance(leaf, AmbiguousLeaf)
    assert [o.grasp for o in leaf.options] == ["Front-Wrap", "Top-Pinch"]


def test_a_grasp_tried_as_a_feature_follows_its_failure_branch() -> None:
    lib = [desc("a", "Front-Wrap", ("Width", P(6, 0), 3)), desc("b", "Top-Pinch", ("Width", P(6, 0), 3.2))]
    s = session(lib, start=P(6, 0))
    grasp = s.decide()
    assert isinstance(grasp, ScoredTest) and grasp.test.is_grasp and grasp.test.feature == "Front-Wrap"
    assert s.grasp_as_feature(grasp, False, grasp.target) == Matched(0, (0, 0), 0.0)
    leaf = s.decide()
    assert isinstance(leaf, GraspLeaf) and leaf.grasp == "Top-Pinch"
    assert s.wrong_predictions == ["Front-Wrap"]
    assert "Front-Wrap" in s.dropped_grasps  # a rebuild after a later failure keeps it out


def test_a_failed_grasp_without_side_effects_drops_its_class_and_rebuilds_from_here() -> None:
    s = session()
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 8.5}, sweep.target)
    height = s.decide()
    s.observe(height, {"Height": 3.6}, height.target)
    assert s.decide().grasp == "Front-Wrap"
    s.grasp_failed("Front-Wrap", side_effects=False)
    assert "cup" not in s.candidates and s.depth == 0
    # the sweep value is still known: re-testing it is free and comes first
    redo = s.decide()
    assert redo.cost == 0 and str(redo.test) == "Width-Degree-1°(24,0)"
    s.observe(redo, {}, s.position)
    assert s.candidates == ("tumbler",)
    assert s.decide().grasp == "Top-Pinch"


def test_a_push_keeps_what_is_known_and_a_change_restores_everything() -> None:
    s = session()
    sweep = s.decide()
    s.observe(sweep, {"Width-Degree-1°": 8.5}, sweep.target)
    s.grasp_failed("Front-Wrap", side_effects=False)
    s.grasp_failed("Top-Pinch", side_effects=True, position=P(30, 10))  # pushed: same object
    assert set(s.candidates) == {"box", "tumbler", "closed"}  # the push may be why Top-Pinch failed
    assert s.measurements and s.position == P(30, 10)
    s.grasp_failed("Top-Pinch", side_effects=True)  # pushed again by the same grasp: now it is dropped
    assert set(s.candidates) == {"box", "closed"}
    assert s.wrong_predictions == ["Front-Wrap"]  # the clean failure only: a push says nothing of the class
    s.grasp_failed("Front-Pinch", side_effects=True, changed=True)  # knocked over: a new object
    assert set(s.candidates) == {"cup", "box", "tumbler", "closed"}
    assert not s.measurements
    assert s.wrong_predictions == []  # Front-Wrap failed on the object before it fell: no lesson about this one


def test_discriminating_test_for_a_wrong_prediction_is_the_cheapest_the_other_class_has() -> None:
    s = session(start=P(6, 0))
    disc = s.discriminating_test("Top-Pinch")
    # the tumbler (Top-Pinch) has Width-Degree-1°(24,0), Height(6,*) and Top-Hole?(6,*);
    # from (6,0): D-Scan here (84 s) beats the sweep (100 s + the move to 24 in)
    assert disc is not None and disc.test.procedure == "D-Scan-0.3" and disc.move_cost == 0


def test_every_grasp_failing_is_reported() -> None:
    lib = [desc("a", "Front-Wrap", ("Width", P(6, 0), 3))]
    s = session(lib)
    with pytest.raises(ValueError, match="every grasp in the library has failed"):
        s.grasp_failed("Front-Wrap", side_effects=False)

"""The incremental study's upside-down-tumbler count, on chains made by hand.

The paper's story: an object misclassified once, and then learned as itself, is
classified right the next time. An encounter that ends with the tumbler knocked over and
held as the lying tumbler teaches nothing about it upside down, so it is counted apart.
"""

from __future__ import annotations

from experiments.episodes import EpisodeRow
from experiments.study_incremental import TUMBLER, Tally, TumblerStory, later_knock_overs, own_grasps, strict, tumbler_story

OWN = frozenset({"Top-Vert-Grip"})


def _row(episode: int, grasp: str, wrong_grasps: int, success: bool = True, obj: str = TUMBLER,
         failed_features: int = 0, knocked_over: bool = False) -> EpisodeRow:
    return EpisodeRow("incremental", "chain of 4", "cs-id3-failure", "paper", 1.0, "on", 1.0, 1.0, "trained", "test",
                      0, episode, 14 + episode, obj, "grasped" if success else "failed", grasp, success, 300.0,
                      45.0, 120.0, 135.0, 5.0, 1, 6.0, 0, wrong_grasps, "-", failed_features, knocked_over)


def test_own_grasps_come_from_the_simulator_catalogue() -> None:
    assert own_grasps(TUMBLER) == OWN


def test_a_lesson_learned_as_itself_then_right_counts_in_both_tallies() -> None:
    chain = [_row(0, "Top-Vert-Grip", 1), _row(1, "Top-Vert-Grip", 0)]
    assert tumbler_story([chain], OWN) == TumblerStory(Tally(1, 1), Tally(1, 1))


def test_knocked_over_and_held_lying_is_not_a_lesson_about_it_upside_down() -> None:
    # episode 0: a wrong grasp knocked it over, held as lying (Front-Pinch); episode 1 wrong again
    chain = [_row(0, "Front-Pinch", 1), _row(1, "Front-Pinch", 1), _row(2, "Top-Vert-Grip", 1), _row(3, "Top-Vert-Grip", 0)]
    # misclassified with a next encounter: 0 (->1 wrong), 1 (->2 wrong), 2 (->3 right); learned as itself: only 2
    assert tumbler_story([chain], OWN) == TumblerStory(Tally(1, 1), Tally(1, 3))


def test_not_handled_is_misclassified_and_teaches_nothing() -> None:
    chain = [_row(0, "-", 0, success=False), _row(1, "Top-Vert-Grip", 0)]
    assert tumbler_story([chain], OWN) == TumblerStory(Tally(0, 0), Tally(1, 1))


def test_the_last_encounter_and_other_objects_and_chains_are_apart() -> None:
    first = [_row(2, "Top-Vert-Grip", 1), _row(0, "Top-Vert-Grip", 0), _row(1, "Front-Wrap", 1, obj="cup")]
    second = [_row(0, "Top-Vert-Grip", 2), _row(3, "Top-Vert-Grip", 1)]
    # first chain: episode 0 right, episode 2 wrong but last; the cup is not the tumbler.
    # second: episode 0 wrong and learned, its next encounter (episode 3) wrong again.
    assert tumbler_story([first, second], OWN) == TumblerStory(Tally(0, 1), Tally(0, 1))


def test_the_strict_reading_counts_a_failed_feature_grasp_and_a_knock_over() -> None:
    # episode 0: right at the leaf but a grasp tried as a feature failed; episode 1: right at the
    # leaf but knocked over; episode 2: clean. Lenient: never misclassified; strict: 0 -> 1 wrong, 1 -> 2 right.
    chain = [_row(0, "Top-Vert-Grip", 0, failed_features=1), _row(1, "Top-Vert-Grip", 0, knocked_over=True),
             _row(2, "Top-Vert-Grip", 0)]
    assert tumbler_story([chain], OWN) == TumblerStory(Tally(0, 0), Tally(0, 0))
    assert tumbler_story([chain], OWN, wrong=strict) == TumblerStory(Tally(1, 2), Tally(1, 2))
    assert [r.misclassified_strict for r in chain] == [True, True, False]


def test_knock_overs_after_the_first_encounter_are_counted_per_chain() -> None:
    first = [_row(0, "Top-Vert-Grip", 1, knocked_over=True), _row(1, "Top-Vert-Grip", 0, knocked_over=True),
             _row(2, "Top-Vert-Grip", 0)]
    second = [_row(0, "Top-Vert-Grip", 0), _row(1, "Front-Wrap", 0, obj="cup", knocked_over=True)]
    assert later_knock_overs([first, second]) == Tally(1, 2)  # first chain's episodes 1 and 2; the cup is apart

"""A lesson with nothing sensed is kept, a chain of floors in the simulator
(docs/method.md §5.8, "A lesson with nothing sensed"): the incremental study's chain of
seed 3 with noise off, six floors of the unseen test objects on one learner store. On its
second floor the upside-down tumbler fails grasps tried as features until Top-Vert-Grip
holds, with no value sensed on it: it is saved by its appearance and that grasp (before,
nothing was saved and later floors failed the same grasps at a leaf). Every other
object held with nothing sensed was picked right at once by its appearance and is not
saved."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

import experiments.episodes as episodes
from experiments.episodes import EpisodeRow, EpisodeSpec
from experiments.worker import install_worker
from reporting.report import match_truth
from robot_profile import load_profile
from tests.executive.floors import trained

TUMBLER = "tumbler-20oz/upside-down"


@pytest.fixture(scope="module")
def chain() -> Iterator[tuple[list[EpisodeRow], list[list[dict[str, object]]]]]:
    """The chain's rows and, per floor, its learn events tagged with the true object."""
    install_worker({"trained": trained()}, load_profile())
    learns: list[list[dict[str, object]]] = []
    play = episodes.play

    def watched(hero, executive):  # noqa: ANN001, ANN202
        played = play(hero, executive)
        truths = played.truths()
        names = {r.index: getattr(match_truth(r, truths), "name", None) for r in played.result.objects}
        learns.append([{**e, "truth": names.get(e.get("object"))}
                       for e in played.events if e["event"] == "learn"])
        return played

    episodes.play = watched
    try:
        rows = episodes.run_job(EpisodeSpec("incremental", "chain", 3, noise="off", episodes=6))
    finally:
        episodes.play = play
    yield rows, learns


@pytest.mark.slow
def test_the_tumbler_held_with_nothing_sensed_is_saved_as_a_lesson(chain) -> None:  # noqa: ANN001
    rows, learns = chain
    (lesson,) = [e for e in learns[1] if e["truth"] == TUMBLER]
    assert lesson["grasp"] == "Top-Vert-Grip" and lesson["features"] == 0
    assert lesson["id"] is not None and lesson["wrong"]  # the grasps tried as features that failed first
    later = [r for r in rows if r.object == TUMBLER and r.episode > 1]
    assert later and all(r.success and r.wrong_grasps == 0 for r in later)  # never a grasp failed at a leaf


@pytest.mark.slow
def test_only_lessons_are_saved_without_a_value(chain) -> None:  # noqa: ANN001
    _, learns = chain
    # saved with no value, or not saved because nothing was measured (clusters aside)
    unsensed = [e for floor in learns for e in floor
                if (e["features"] == 0 and "reason" not in e) or e.get("reason", "").startswith("nothing was measured")]
    assert len(unsensed) >= 10
    for e in unsensed:
        assert (e["id"] is not None) == bool(e.get("wrong")), e

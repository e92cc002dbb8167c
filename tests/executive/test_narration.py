"""The executive's story on Python's ``logging`` (``csl -v``): each event told from the
episode log, each robot verb with its reply time, each object's outcome; the bulky
fields, the tests ranked and the paths planned only at DEBUG (``-vv``)."""

from __future__ import annotations

import logging
from concurrent.futures import Future

import pytest

from executive.episode_log import EpisodeLog
from executive.verb_log import VerbLog
from hero_driver.interface import DriverError, GraspResult, Pose, SenseResult

STORY = "executive.narration"


def _lines(caplog: pytest.LogCaptureFixture, name: str, level: int | None = None) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == name and (level is None or r.levelno == level)]


def test_a_test_chosen_is_told_with_its_cost(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.INFO, logger=STORY):
        log = EpisodeLog()
        log.tick = 16
        log.event("choose", object=0, behaviour="Reselect", how="reselect", test="Top-Vert-Grip(6,0)", at=[6, 0],
                  gain=1.0, move_s=135.8, sense_s=110.0)
    assert _lines(caplog, STORY) == [
        "tick 16, object 0: choose Top-Vert-Grip(6,0) (reselect), cost 245.8 s (move 135.8 s + sense 110 s), "
        "at (6, 0), gain 1"]


def test_a_recovery_says_so_and_bulky_fields_wait_for_debug(caplog: pytest.LogCaptureFixture) -> None:
    candidates = [f"description-{i}" for i in range(8)]
    with caplog.at_level(logging.INFO, logger=STORY):
        log = EpisodeLog()
        log.tick = 3
        log.event("drop_grasp", object=2, behaviour="DropFailedGrasp", grasp="Front-Wrap", candidates=candidates)
        log.event("located", behaviour="LocateObjects", regions=[])
    assert _lines(caplog, STORY) == ["tick 3, object 2: recovery drop_grasp: grasp Front-Wrap, candidates (8)",
                                     "tick 3: located: regions []"]
    caplog.clear()
    with caplog.at_level(logging.DEBUG, logger=STORY):
        EpisodeLog().event("drop_grasp", object=2, grasp="Front-Wrap", candidates=candidates)
    assert _lines(caplog, STORY, logging.DEBUG) == [
        "tick 0, object 2: drop_grasp detail: candidates [" + ", ".join(candidates) + "]"]


def test_quiet_below_info(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING, logger=STORY):
        EpisodeLog().event("choose", object=0, how="best", test="Height(6,*)", move_s=1.0, sense_s=2.0)
    assert _lines(caplog, STORY) == []


class _Robot:
    """A driver whose verbs answer from a script (a future each, settled or not)."""

    robot = "r7"

    def __init__(self) -> None:
        self.pending: Future[SenseResult] = Future()

    def sense(self, procedure: str) -> Future[SenseResult]:
        return self.pending

    def grasp(self, procedure: str) -> Future[GraspResult]:
        raise DriverError("busy", "another verb is still executing")

    def move(self, waypoints: list[Pose], face: tuple[float, float] | None = None) -> Future[object]:
        done: Future[object] = Future()
        done.set_exception(DriverError("out_of_range", "no path"))
        return done

    def state(self) -> object:
        return "a state"


def test_each_verb_is_told_when_answered_with_its_reply_time(caplog: pytest.LogCaptureFixture) -> None:
    ticks = iter([10.0, 10.25, 15.0, 20.0, 21.5])  # a clock read as each verb is sent and answered
    robot = _Robot()
    driver = VerbLog(robot, clock=lambda: next(ticks))  # type: ignore[arg-type]
    with caplog.at_level(logging.DEBUG, logger="executive.verb_log"):
        future = driver.sense("V-Sweep-5°")
        assert _lines(caplog, "executive.verb_log", logging.INFO) == []  # not answered yet
        robot.pending.set_result(SenseResult("V-Sweep-5°", {"Height-Degree-5°": 30.0, "Width": None}, 42.0, 6.0))
        assert future.result().duration_s == 42.0  # the driver's own future, untouched
        with pytest.raises(DriverError):
            driver.grasp("Front-Wrap")
        driver.move([Pose(1.04, 2.0, 90.0), Pose(57.46, 47.12, 45.96)], face=(70.0, 60.0))
        assert driver.state() == "a state"  # answered at once: not told
    assert _lines(caplog, "executive.verb_log") == [
        "r7: sense (procedure V-Sweep-5°) sent",
        "r7: sense (procedure V-Sweep-5°) answered in 0.250 s: 42.0 robot s, Height-Degree-5° 30, Width none",
        "r7: grasp (procedure Front-Wrap) sent",
        "r7: grasp (procedure Front-Wrap) refused at once: busy: another verb is still executing",
        "r7: move (waypoints 2 to (57.5, 47.1, 46.0°), face (70.0, 60.0)) sent",
        "r7: move (waypoints 2 to (57.5, 47.1, 46.0°), face (70.0, 60.0)) failed after 1.500 s: out_of_range: "
        "no path",
    ]


def test_an_episode_tells_its_story(csl_scenario, caplog: pytest.LogCaptureFixture) -> None:  # noqa: ANN001
    # the cup's episode of tests/executive/__snapshots__/test_behaviour_tree/test_appearance_recognition.txt:
    # one test chosen (a grasp tried as a feature) priced 181.7 s away and 90 s to try; it holds
    with caplog.at_level(logging.INFO):
        result = csl_scenario.one_object("cup-8oz/upright", seed=0).run()
    assert result.status == "SUCCESS"
    story = _lines(caplog, STORY)
    assert story[:3] == [
        "tick 1: located: regions (1)",  # the region whole at DEBUG
        "tick 1, object 0: object: centroid (110, 80), pixels 16, start (83.5, 215.9), "
        "appearance {round true, area_in2 10.24, elongation 1.209}, ruled_out 8",
        "tick 1, object 0: choose Front-Wrap(6,*) (best), cost 271.7 s (move 181.7 s + sense 90 s), "
        "at (6, 215.9), gain 1"]
    assert "object 0: outcome grasped with Front-Wrap, 4.0 robot min" in story  # moved 178.6 s, grasped 60 s
    verbs = _lines(caplog, "executive.verb_log")
    assert any(v.startswith("r1: grasp (procedure Front-Wrap) answered in ") and v.endswith(", held") for v in verbs)
    assert not [r for r in caplog.records if r.levelno < logging.INFO]
    caplog.clear()
    with caplog.at_level(logging.DEBUG):
        csl_scenario.one_object("cup-8oz/upright", seed=0).run()
    ranked = _lines(caplog, "learner.runtime", logging.DEBUG)
    assert ranked and "tests ranked at" in ranked[0] and "Front-Wrap(6,*) score" in ranked[0]
    assert any(p.startswith("path (") for p in _lines(caplog, "planner.navigator", logging.DEBUG))
    assert any(" move detail: path [(" in line for line in _lines(caplog, STORY, logging.DEBUG))

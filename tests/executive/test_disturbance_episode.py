"""Objects disturbed during sensing, whole episodes in the simulator: a nudged object is
re-located and still grasped with what was measured kept; a removed one is reported
gone and the run goes on (``csl run`` exits 0: gone is not a failure); a swapped one is
started over; and no description is ever saved from a disturbed attempt while the
check is on (with it off, the same floors save some: the count can fail).

The floor: a soda bottle (Front-Wrap) and a closed box (No-Grab) the example library
handles; each event comes right after the bottle's first sensing (robot step 2: the
move there, then the sensing).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from behaviours.services import Params
from executive import defaults
from csl_cli.main import main
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from executive.exit_status import ALL_HANDLED, SOME_FAILED, episode_status
from experiments.disturbed import saved_from_disturbed, unnoticed
from hero_driver.sim.events import DisturbPreset, parse_disturb
from hero_driver.sim.world import ObjectTruth
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner

BOTTLE = {"id": "soda-bottle-16oz/upright", "x_in": 70, "y_in": 30}
BOX = {"id": "closed-box-10x10x10/upright", "x_in": 85, "y_in": 70, "yaw_deg": 15}


def floor(tmp_path: Path, events: list[dict[str, object]]) -> Path:
    data = {"name": "disturbed", "room": {"width_in": 120, "depth_in": 100},
            "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0}, "objects": [BOTTLE, BOX], "events": events}
    path = tmp_path / "disturbed.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def episode(tmp_path: Path, world: Path, *, check: bool = True, disturb: DisturbPreset = DisturbPreset(),
            seed: int = 0) -> tuple[EpisodeResult, EpisodeLog, SimulatedHero, list[ObjectTruth], LocalLearner]:
    driver = SimulatedHero("r1", world=world, seed=seed, disturb=disturb)
    start = driver.truth()
    learner = LocalLearner(tmp_path / f"library-{seed}-{check}.sqlite",
                           seed_library=read_library_json(defaults.EXAMPLE_LIBRARY))
    log = EpisodeLog()
    executive = Executive(driver, learner, log=log, params=Params(check_in_place=check, use_appearance=False))  # the stories pin sensing
    try:
        return executive.run(), log, driver, start, learner
    finally:
        executive.shutdown()


def kinds(log: EpisodeLog, index: int) -> list[str]:
    return [str(e["event"]) for e in log.events if e.get("object") == index]


def test_a_nudged_object_is_relocated_and_grasped_with_its_values_kept(tmp_path: Path) -> None:
    world = floor(tmp_path, [{"at_step": 2, "object": 0, "do": "nudge", "dx_in": -6, "dy_in": 8, "dyaw_deg": 0}])
    result, log, driver, start, learner = episode(tmp_path, world)
    [happened] = driver.disturbances()
    assert (happened.step, happened.do) == (2, "nudge")
    bottle = kinds(log, 0)
    assert bottle.index("sense") < bottle.index("disturbance") < bottle.index("relocate") < bottle.index("grasp")
    [relocate] = [e for e in log.events if e["event"] == "relocate"]
    assert relocate["at"] == [64.0, 38.0] and relocate["kept"] >= 1  # 70 - 6, 30 + 8: the first value kept
    assert [r.outcome for r in result.objects] == ["grasped", "left"]
    assert result.objects[0].grasp == "Front-Wrap" and driver.truth()[0].binned
    assert saved_from_disturbed(result.objects, log.events, driver.disturbances(), start) == 0
    learner.close()


def test_a_removed_object_is_reported_gone_and_the_run_goes_on(tmp_path: Path) -> None:
    world = floor(tmp_path, [{"at_step": 2, "object": 0, "do": "remove"}])
    result, log, driver, _, learner = episode(tmp_path, world)
    assert [r.outcome for r in result.objects] == ["gone", "left"]
    bottle = kinds(log, 0)
    assert bottle[-2:] == ["disturbance", "gone"] and "learn" not in bottle and "grasp" not in bottle
    assert result.objects[1].learned_id is None and "object" in kinds(log, 1)  # on to the box, left
    assert result.status == "SUCCESS"
    learner.close()


def test_csl_run_exits_0_when_an_object_was_taken_away(tmp_path: Path) -> None:
    world = floor(tmp_path, [{"at_step": 2, "object": 0, "do": "remove"}])
    out = tmp_path / "out"
    assert main(["run", "--world", str(world), "--no-plots", "--out", str(out), "--no-appearance",  # sensed to step 2
                 "--library", str(tmp_path / "lib.sqlite")]) == 0
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    assert [e["object"] for e in events if e["event"] == "gone"] == [0]


def test_gone_is_not_a_failure_but_is_said() -> None:
    assert episode_status(["gone", "left"]) == (ALL_HANDLED, "1 of 2 objects were handled, 1 gone (taken away)")
    assert episode_status(["gone", "failed"]) == (SOME_FAILED, "1 of 2 objects were not handled")
    assert episode_status(["grasped", "left"]) == (ALL_HANDLED, "all 2 objects were handled")


def test_a_swapped_object_is_started_over_and_learned_as_what_it_is_now(tmp_path: Path) -> None:
    tumbler = "tumbler-32oz/lying"  # 7 x 4 in lying where a 2.7 in bottle stood: the camera sees the change
    world = floor(tmp_path, [{"at_step": 2, "object": 0, "do": "replace", "entry": tumbler}])
    result, log, driver, start, learner = episode(tmp_path, world)
    bottle = kinds(log, 0)
    afresh = bottle.index("start_afresh")
    assert bottle.index("sense") < afresh and bottle.count("object") == 1
    [truth] = [t for t in driver.truth() if t.index == 0]
    assert truth.entry_id == tumbler
    record = result.objects[0]
    if record.outcome == "grasped":  # what it learned is the tumbler's grasp, from values measured after the swap
        assert record.grasp in {g.procedure for g in truth.grasps}
    assert saved_from_disturbed(result.objects, log.events, driver.disturbances(), start) == 0
    learner.close()


@pytest.mark.slow
def test_no_description_is_saved_from_a_disturbed_attempt_with_the_check_on(tmp_path: Path) -> None:
    """Swaps and nudges after the first sensing of every object, on three floors: with
    the check off some disturbed attempts are learned (the count is real); with it on,
    none."""
    world = floor(tmp_path, [])
    saved = {True: 0, False: 0}
    for check in (True, False):
        for seed in range(3):
            result, log, driver, start, learner = episode(tmp_path, world, check=check, seed=seed,
                                                          disturb=parse_disturb("replace:0.5,nudge:0.5"))
            assert driver.disturbances()  # every floor was disturbed
            if check:
                assert unnoticed(result.objects, log.events, driver.disturbances(), start) == []
            saved[check] += saved_from_disturbed(result.objects, log.events, driver.disturbances(), start)
            learner.close()
    assert saved[True] == 0 and saved[False] > 0


def test_a_bad_disturb_preset_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["driver", "sim", "--disturb", "push:0.2"]) == 2
    err = capsys.readouterr().err
    assert "argument --disturb: 'push:0.2': expected KIND:P with KIND one of nudge, remove, replace" in err

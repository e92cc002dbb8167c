"""Low battery in the simulator, whole episodes: with the guard on, a
robot that starts just above the threshold docks once, charges and still handles every
object, resuming the one it was on; with the guard off it runs flat and the objects
left fail (``csl run`` exits non-zero)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from behaviours.services import Params
from executive import defaults
from csl_cli.main import main
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from executive.exit_status import episode_status
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner

HANDLED = {"grasped", "left"}


def small_world(tmp_path: Path, battery: float, dock: bool = True) -> Path:
    """Two objects the example library handles, a dock by the west wall."""
    data: dict[str, object] = {
        "name": "dock-test", "room": {"width_in": 120, "depth_in": 100},
        "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0}, "battery": battery,
        "objects": [{"id": "soda-bottle-16oz/upright", "x_in": 70, "y_in": 30},
                    {"id": "closed-box-10x10x10/upright", "x_in": 85, "y_in": 70, "yaw_deg": 15}]}
    if dock:
        data["dock"] = {"x_in": 20, "y_in": 75, "heading_deg": 180}
    path = tmp_path / "dock-test.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def episode(tmp_path: Path, battery: float, threshold: float) -> tuple[EpisodeResult, EpisodeLog, SimulatedHero]:
    driver = SimulatedHero("r1", world=small_world(tmp_path, battery), seed=0)
    learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(defaults.EXAMPLE_LIBRARY))
    log = EpisodeLog()
    executive = Executive(driver, learner, log=log, params=Params(battery_low=threshold, use_appearance=False))  # pins the sensing route
    try:
        return executive.run(), log, driver
    finally:
        executive.shutdown()
        learner.close()


def test_the_guard_docks_once_charges_and_every_object_is_still_handled(tmp_path: Path) -> None:
    result, log, driver = episode(tmp_path, battery=0.2005, threshold=0.2)
    charges = [e for e in log.events if e["event"] == "charge"]
    assert len(charges) == 1
    [charge] = charges
    assert charge["level_before"] < 0.2 and charge["level"] == 1.0 and charge["dock"][:2] == [20.0, 75.0]
    # what was left on arrival (the level when it set off less the drive at 1/18000 per
    # second) filled at 1/1800 per second; level_before is logged to a thousandth
    arrived = charge["level_before"] - charge["moving_s"] / 18000.0
    assert charge["charging_s"] == pytest.approx((1.0 - arrived) * 1800.0, abs=1.0)
    # it happened while object 0 was under way, and object 0 went on from there
    kinds = [(e["event"], e.get("object")) for e in log.events]
    at = kinds.index(("charge", 0))
    assert ("sense", 0) in kinds[:at] and ("choose", 0) in kinds[at:] and ("object", 0) not in kinds[at:]
    assert [r.outcome for r in result.objects] == ["grasped", "left"]
    assert result.status == "SUCCESS" and driver.state().battery > 0.9


def test_without_the_guard_the_robot_runs_flat_and_objects_fail(tmp_path: Path) -> None:
    result, log, driver = episode(tmp_path, battery=0.005, threshold=0.0)
    assert not [e for e in log.events if e["event"] == "charge"]
    assert driver.state().battery == 0.0
    assert {e["code"] for e in log.events if e["event"] == "driver_error"} == {"battery_empty"}
    outcomes = [r.outcome for r in result.objects]
    assert "failed" in outcomes and set(outcomes) <= HANDLED | {"failed"}
    assert episode_status(outcomes)[0] != 0


def test_csl_run_exits_non_zero_when_the_robot_runs_flat(tmp_path: Path) -> None:
    world = small_world(tmp_path, battery=0.005)
    argv = ["run", "--world", str(world), "--no-plots", "--library", str(tmp_path / "lib.sqlite")]
    assert main([*argv, "--battery-low", "0", "--out", str(tmp_path / "off")]) == 1
    events = [json.loads(line) for line in (tmp_path / "off" / "episode.jsonl").read_text().splitlines()]
    assert not [e for e in events if e["event"] == "charge"]


def test_csl_run_says_in_one_line_when_the_guard_is_off(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    world = small_world(tmp_path, battery=1.0, dock=False)
    assert main(["run", "--world", str(world), "--no-plots", "--out", str(tmp_path / "o"),
                 "--library", str(tmp_path / "lib.sqlite")]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "low-battery guard" in line]
    assert lines == ["battery: driver r1 has no battery feature (no charging dock): the low-battery guard is off"]


@pytest.mark.parametrize(("value", "message"), [("1.5", "must be a battery level from 0 to 1"),
                                                ("low", "expected a battery level from 0 to 1")])
def test_a_bad_battery_low_is_a_usage_error(tmp_path: Path, value: str, message: str,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--battery-low", value, "--out", str(tmp_path)]) == 2
    assert f"argument --battery-low: {message}" in capsys.readouterr().err

"""Moving obstacles on the everyday commands: ``csl run`` says in one
line when the driver lacks the ``blocked_moves`` feature, and ``--movers N[:SPEED]``
puts people and carts into the in-process simulator as ``csl driver sim --movers``
does."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from behaviours.blocked import branch_off_notice
from behaviours.services import Params
from csl_cli.main import main
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.node import DriverNode
from robot_profile import load_profile, profile_stamp
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

NOTICE = ("blocked moves: driver r1 has no blocked_moves feature: the blocked-move branch is off "
          "(a move into a person or cart ends collided)")


def _run(tmp_path: Path, *extra: str) -> tuple[int, list[dict[str, object]]]:
    out = tmp_path / "out"
    status = main(["run", "--no-plots", "--out", str(out), "--library", str(tmp_path / "lib.sqlite"), *extra])
    return status, [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]


def _notices(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("blocked moves:")]


def test_the_notice_is_the_branchs_own_line() -> None:
    assert branch_off_notice(SimulatedHero("r1", world="lab", stop_for_movers=False), Params().blocked_tries) == NOTICE


@pytest.mark.slow
def test_a_run_without_movers_has_the_branch_and_says_nothing(tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    """The lab has no movers, yet the simulator's safety stop is on: no notice, no blocked move."""
    status, events = _run(tmp_path, "--driver", "sim", "--seed", "0")
    assert status in (0, 1) and events[-1]["event"] == "episode_end"
    assert _notices(capsys.readouterr().err) == []
    assert not [e for e in events if e.get("blocked")]


@pytest.mark.slow
def test_movers_on_csl_run_reach_the_simulator(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Two preset movers in the lab: the feature is on (no notice), moves stop short of
    them (``blocked`` moves in the log: the lab alone has none) and nothing collides."""
    status, events = _run(tmp_path, "--driver", "sim", "--movers", "2", "--seed", "0")
    assert status in (0, 1) and events[-1]["event"] == "episode_end"
    assert _notices(capsys.readouterr().err) == []
    moves = [e for e in events if e["event"] == "move"]
    assert [e for e in moves if e.get("blocked")], "no move met a mover: --movers did not reach the simulator"
    assert not [e for e in moves if e["collided"]]


@pytest.mark.parametrize(("value", "message"), [
    ("two", "'two': expected N or N:SPEED with N a whole number"),
    ("21", "'21': N must be from 0 to 20"),
    ("2:fast", "'2:fast': SPEED must be a number of inches per second"),
    ("2:0", "'2:0': SPEED must be above 0 and at most 200 in/s"),
])
@pytest.mark.parametrize("command", ["run", "demo"])
def test_a_bad_movers_value_names_the_flag(command: str, value: str, message: str, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    assert main([command, "--movers", value, "--out", str(tmp_path)]) == 2
    assert f"argument --movers: {message}" in capsys.readouterr().err


@pytest.mark.zenoh
@pytest.mark.parametrize("stops", [False, True])
def test_a_zenoh_driver_without_the_feature_is_named_in_one_line(
        stops: bool, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A driver process whose hello lacks ``blocked_moves`` (a simulator that ignores
    its movers) gets the line; the same world served with the feature gets none."""
    endpoint = free_endpoint()
    hero = SimulatedHero("r1", world="crossing", stop_for_movers=stops)
    with open_session(listen=[endpoint]) as session, DriverNode(hero, session, profile=profile_stamp(load_profile())):
        status, events = _run(tmp_path, "--driver", "zenoh", "--connect", endpoint)
    assert status in (0, 1) and events[-1]["event"] == "episode_end"
    assert _notices(capsys.readouterr().err) == ([] if stops else [NOTICE])

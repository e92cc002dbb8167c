"""``--verb-timeout VERB=SECONDS``: parsed and checked before anything
connects, and a verb the driver never answers ends its object as not handled, in one
line, with a non-zero exit status. The hung driver is a real process."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from csl_cli.args import add_verb_timeout_option, verb_timeout
from csl_cli.main import build_parser
from csl_cli.commands.episode import _unanswered, _verb_timeouts, run_run
from executive.episode_log import read_log
from executive.exit_status import SOME_FAILED
from hero_driver.zenoh_link.client import VerbTimeouts
from hero_driver.zenoh_link.verbs import BY_NAME
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint


def parsed(*flags: str) -> list[tuple[str, float]]:
    parser = argparse.ArgumentParser()
    add_verb_timeout_option(parser)
    return parser.parse_args(list(flags)).verb_timeout


def test_the_flag_repeats_and_pairs_verbs_with_seconds() -> None:
    assert parsed("--verb-timeout", "sense=1.5", "--verb-timeout", "move=600") == [("sense", 1.5), ("move", 600.0)]
    assert parsed() is None


@pytest.mark.parametrize(("text", "says"), [
    ("sense", "expected VERB=SECONDS"), ("=3", "expected VERB=SECONDS"), ("sense=soon", "expected a number"),
    ("sense=0", "positive"), ("sense=-2", "positive"), ("sense=nan", "positive"), ("sense=inf", "positive"),
])
def test_bad_values_are_refused_in_one_line(text: str, says: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError, match=says):
        verb_timeout(text)


@given(st.sampled_from(sorted(BY_NAME)), st.floats(min_value=1e-3, max_value=1e6))
def test_any_verb_and_positive_seconds_become_that_verbs_timeout(verb: str, seconds: float) -> None:
    name, value = verb_timeout(f"{verb}={seconds!r}")
    timeouts = VerbTimeouts.of_verbs([(name, value)])
    assert timeouts.of(verb) == seconds
    assert all(timeouts.of(other) == BY_NAME[other].timeout_s for other in BY_NAME if other != verb)


def run_args(*argv: str, timeouts: list[tuple[str, float]] | None) -> argparse.Namespace:
    args = build_parser().parse_args(["run", *argv])
    args.verb_timeout = timeouts  # what add_verb_timeout_option gives csl run
    return args


@pytest.mark.parametrize(("argv", "timeouts", "says"), [
    (("--driver", "zenoh"), [("fly", 1.0)], "--verb-timeout: 'fly' is not a verb"),
    (("--driver", "zenoh"), [("sense", 1.0), ("sense", 2.0)], "--verb-timeout: sense is given twice"),
])
def test_bad_verbs_are_refused_before_anything_connects(argv: tuple[str, ...], timeouts: list[tuple[str, float]],
                                                        says: str) -> None:
    with pytest.raises(ValueError, match=f"^{says}"):
        _verb_timeouts(run_args(*argv, timeouts=timeouts))


def test_only_timeouts_count_as_unanswered() -> None:
    events = [{"event": "driver_error", "object": 2, "code": "busy", "message": "sense: busy"},
              {"event": "driver_error", "object": 2, "code": "timeout", "message": "sense: no reply within 1 s"},
              {"event": "driver_error", "object": 2, "code": "timeout", "message": "move: no reply within 9 s"},
              {"event": "driver_error", "object": 4, "code": "timeout", "message": "grasp: overran"},
              {"event": "move", "object": 5, "code": "timeout"}]
    assert _unanswered(events) == {2: "sense: no reply within 1 s", 4: "grasp: overran"}


def hanging_sim(endpoint: str, sense_bound_s: float) -> DriverProcess:
    """The simulator whose first sense never answers, holding the robot busy on it for
    ``sense_bound_s`` (the node's bound) before it frees the robot."""
    return DriverProcess(["-m", "tests.hero_driver.test_zenoh_support", "sim-hang", "r1", endpoint,
                          str(sense_bound_s)])


@pytest.mark.slow
@pytest.mark.zenoh
def test_a_sense_the_driver_never_answers_fails_its_object_only(tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    """The client gives up on the sense after 1 s; the driver keeps the robot busy on it
    until its 3 s bound. Object 0 is given up in one line; the next object waits for
    the robot instead of being refused ``busy``, and every later object is worked on."""
    endpoint = free_endpoint()
    with hanging_sim(endpoint, 3.0) as driver:
        driver.ready()
        args = run_args("--driver", "zenoh", "--connect", endpoint, "--out", str(tmp_path / "out"), "--no-plots",
                        "--library", str(tmp_path / "library.sqlite"), timeouts=[("sense", 1.0)])
        status = run_run(args)
    said = capsys.readouterr()
    assert status == SOME_FAILED
    [reason] = [line for line in said.err.splitlines() if "did not answer" in line]
    assert reason == "csl: object 0 not handled: the robot did not answer in time (sense: no reply within 1 s)"
    events = read_log(tmp_path / "out" / "episode.jsonl")
    errors = [e for e in events if e["event"] == "driver_error"]
    assert [(e["object"], e["code"]) for e in errors] == [(0, "timeout")]  # nothing refused busy
    [gave_up] = [e for e in events if e["event"] == "gave_up"]
    assert gave_up["object"] == 0
    assert gave_up["reason"] == "the robot did not answer in time (sense: no reply within 1 s)"
    after = [e for e in events if e.get("object") == 0 and e["tick"] > gave_up["tick"]]
    assert after == []  # object 0's step ended there: nothing more was decided or sent for it
    objects = [e["object"] for e in events if e["event"] == "object"]
    assert objects == list(range(7))
    # object 1 was worked on, sensed or (the camera's appearance may leave one grasp) grasped: the robot came back
    assert [e for e in events if e["event"] in ("sense", "grasp") and e["object"] == 1]
    assert "exit status 1: " in said.out

"""``--verb-timeout VERB=SECONDS``: parsed and checked before anything
connects, and a verb the driver never answers ends its object as not handled, in one
line, with a non-zero exit status. The hung driver is a real process."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from executive.args import add_verb_timeout_option, verb_timeout
from executive.cli import build_parser
from executive.commands.episode import _unanswered, _verb_timeouts, run_run
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
    ((), [("sense", 1.0)], "--verb-timeout goes with --driver zenoh"),
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


@pytest.mark.zenoh
def test_a_sense_the_driver_never_answers_fails_its_object_and_the_run(tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("sim-hang", endpoint) as driver:  # its first sense never answers
        driver.ready()
        args = run_args("--driver", "zenoh", "--connect", endpoint, "--out", str(tmp_path / "out"), "--no-plots",
                        "--library", str(tmp_path / "library.sqlite"), timeouts=[("sense", 1.0)])
        status = run_run(args)
    said = capsys.readouterr()
    assert status == SOME_FAILED
    [reason] = [line for line in said.err.splitlines() if "did not answer" in line]
    assert reason == "csl: object 0 not handled: the robot did not answer in time (sense: no reply within 1 s)"
    assert "exit status 1: " in said.out

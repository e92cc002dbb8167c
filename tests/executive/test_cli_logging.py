"""``-v``/``--log-level`` on ``csl`` and on every command, through ``logging``; the
default stays quiet (warnings only)."""

from __future__ import annotations

import argparse
import logging

import pytest

from csl_cli.main import build_parser, log_level, main


@pytest.mark.parametrize(
    ("options", "level"),
    [
        ([], logging.WARNING),
        (["-v"], logging.INFO),
        (["-vv"], logging.DEBUG),
        (["-v", "-v", "-v"], logging.DEBUG),  # there is nothing below debug
        (["--log-level", "error"], logging.ERROR),
        (["--log-level", "ERROR", "-vv"], logging.ERROR),  # the named level wins over -v
        (["--verbose"], logging.INFO),
    ],
)
def test_the_level_the_options_name(options: list[str], level: int) -> None:
    parser = build_parser()
    assert log_level(parser.parse_args([*options, "bt"])) == level  # before the command
    assert log_level(parser.parse_args(["bt", *options])) == level  # or after it
    assert log_level(parser.parse_args(["library", *options, "show"])) == level  # or after a group


def _commands(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    found = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in action.choices.values():
                found += [child, *_commands(child)]
    return found


def test_every_command_takes_the_options() -> None:
    commands = _commands(build_parser())
    names = {p.prog for p in commands}
    assert {"csl demo", "csl run", "csl library show", "csl driver sim", "csl driver state",
            "csl learner serve"} <= names
    for command in commands:
        assert {"-v", "--verbose", "--log-level"} <= set(command._option_string_actions), command.prog


def test_quiet_by_default_and_info_with_v(capsys) -> None:  # noqa: ANN001
    probe = logging.getLogger("csl.test-probe")
    assert main(["bt"]) == 0
    probe.info("an info line")
    probe.warning("a warning line")
    err = capsys.readouterr().err
    assert "an info line" not in err and "WARNING csl.test-probe: a warning line" in err
    assert main(["bt", "-v"]) == 0
    probe.info("an info line")
    probe.debug("a debug line")
    err = capsys.readouterr().err
    assert "INFO csl.test-probe: an info line" in err and "a debug line" not in err
    assert main(["--log-level", "debug", "bt"]) == 0
    probe.debug("a debug line")
    assert capsys.readouterr().err.count("a debug line") == 1  # one handler, however often main runs
    main(["bt"])  # leave the process as quiet as it was


def test_a_bad_level_is_one_line(capsys) -> None:  # noqa: ANN001
    assert main(["bt", "--log-level", "loud"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--log-level: invalid choice: 'loud'" in err[0]

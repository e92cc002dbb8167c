"""Help that reads well in an 80-column terminal and lists what the code has."""

from __future__ import annotations

import pytest

from csl_cli.main import _commands, build_parser, main


def test_driver_call_lists_every_verb_of_the_table(capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """Read from the verb table when printed: a verb added there is in the help, as
    charge (the battery feature) and wait (blocked moves) were not."""
    from hero_driver.zenoh_link.verbs import NAMES

    monkeypatch.setenv("COLUMNS", "1000")  # one line to search, whatever the terminal
    assert main(["driver", "call", "--help"]) == 0
    verb_line = next(line for line in capsys.readouterr().out.splitlines() if line.lstrip().startswith("VERB "))
    assert f"the verb: {', '.join(NAMES)} (" in verb_line
    assert {"charge", "wait", "noop", "hello"} <= set(NAMES)


def test_no_usage_or_help_line_is_wider_than_the_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    """argparse wraps at the terminal's width but cannot break one item: an option
    whose choices are spelled in its usage item (``--criterion {cs-id3,id3,...}`` was
    ~300 characters) overflows, so such options show a metavar and list their
    choices in their help."""
    monkeypatch.setenv("COLUMNS", "80")
    parser = build_parser()
    wide = [f"{command.prog}: {line}" for command in (parser, *_commands(parser))
            for line in (command.format_usage() + command.format_help()).splitlines() if len(line) > 80]
    assert wide == []

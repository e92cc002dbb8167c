"""``csl run`` refuses every option given out of its mode (a simulator option with
``--driver zenoh``, a library with ``--learner zenoh``...) with one line and exit 2
(csl_cli/commands/modes.py), before anything connects."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from csl_cli.main import build_parser, main
from csl_cli.commands import modes

# A valid value for the simulator-only options that take one and offer no choices.
GIVEN = {"--world": "lab", "--seed": "0", "--disturb": "nudge:0.2", "--movers": "2"}
KNOWN = {"--world", "--seed", "--noise", "--camera", "--disturb", "--movers"}


def _run_parser() -> argparse.ArgumentParser:
    subparsers = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return subparsers.choices["run"]


def _given(action: argparse.Action) -> list[str]:
    """The option as typed with a valid value (not its default)."""
    flag = max(action.option_strings, key=len)
    if action.nargs == 0:  # a switch
        return [flag]
    if action.choices:
        return [flag, next(str(c) for c in action.choices if c != action.default)]
    assert flag in GIVEN, f"{flag} is simulator-only: give it a valid value in GIVEN"
    return [flag, GIVEN[flag]]


def _groups(mode: modes.Mode) -> list[argparse.Action]:
    """The options of ``csl run`` declared with ``mode``."""
    groups = _run_parser().get_default("mode_groups")
    return [a for g in groups if g.mode == mode for a in g.actions]


MARKED = {max(a.option_strings, key=len): _given(a) for a in _groups(modes.SIMULATOR)}


def test_the_simulators_options_are_marked() -> None:
    """These six at least are simulator-only (the mark cannot silently drop off one)."""
    assert KNOWN <= set(MARKED)


@pytest.mark.parametrize("flag", sorted(MARKED))
def test_a_sim_only_option_with_a_zenoh_driver_is_one_line_and_exit_2(flag: str, tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    # port 9 (discard): were the option let through, the run would try to connect and exit 3
    argv = ["run", "--driver", "zenoh", "--connect", "tcp/127.0.0.1:9", *MARKED[flag], "--out", str(tmp_path)]
    assert main(argv) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        f"csl: error: {flag} goes with --driver sim: with --driver zenoh any simulator runs in the driver's own "
        f"process, so give {flag} there (csl driver sim {flag} ...)"]


SIM = modes.Mode(("driver",), "sim", "--driver sim", lambda flag, args: f": with --driver {args.driver}, not here")


def _toy(handled: list[argparse.Namespace]) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser()
    parser.add_argument("--driver", default="sim")
    parser.add_argument("--robot", default="r1", help="robot name")
    parser.set_defaults(handler=lambda args: handled.append(args) or 0)
    sim = modes.ModeGroup(parser, "toy simulator", SIM)
    sim.add_argument("--world", default=None, help="a world")
    modes.guarded(parser)
    sim.add_argument("--quiet", action="store_true", help="say less")  # added after the guard: refused too
    return parser


@pytest.mark.parametrize(("argv", "refused"), [
    (["--driver", "zenoh", "--robot", "r2"], None),  # options of no mode pass
    (["--driver", "sim", "--world", "w", "--quiet"], None),  # the mode's own go with it
    (["--driver", "zenoh", "--quiet"], "--quiet"),  # a flag is refused too
    (["--driver", "zenoh", "--world", "w"], "--world"),
])
def test_the_guard_runs_the_handler_only_when_nothing_is_refused(argv: list[str], refused: str | None) -> None:
    handled: list[argparse.Namespace] = []
    parser = _toy(handled)
    args = parser.parse_args(argv)
    if refused is None:
        assert args.handler(args) == 0 and handled == [args]
    else:
        with pytest.raises(ValueError, match=f"^{refused} goes with --driver sim: with --driver zenoh, not here$"):
            args.handler(args)
        assert handled == []
        with pytest.raises(ValueError):
            modes.refuse_out_of_mode(args)


def test_the_help_names_each_group_with_its_mode() -> None:
    text = _run_parser().format_help()
    for title in ("the simulator in this process (with --driver sim)", "a driver over zenoh (with --driver zenoh)",
                  "the learner in this process (with --learner local)",
                  "a shared learner service (with --learner zenoh)", "any zenoh session (with --driver or --learner zenoh)"):
        assert title + ":" in text


@pytest.mark.parametrize(("argv", "line"), [
    (["--connect", "tcp/127.0.0.1:9"], "--connect goes with --driver zenoh"),
    (["--wait-driver", "5"], "--wait-driver goes with --driver zenoh"),
    (["--verb-timeout", "sense=60"], "--verb-timeout goes with --driver zenoh"),
    (["--learner-name", "x"], "--learner-name goes with --learner zenoh"),
    (["--outbox", "o.sqlite"], "--outbox goes with --learner zenoh"),
    (["--learner", "zenoh", "--library", "l.sqlite"], "--library goes with --learner local"),
    (["--zenoh-config", "z.json5"], "--zenoh-config goes with --driver or --learner zenoh"),
])
def test_each_modes_options_are_refused_in_the_other(argv: list[str], line: str, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", *argv, "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [f"csl: error: {line}"]

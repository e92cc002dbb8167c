"""``csl run --driver zenoh`` refuses every simulator-only option with one line and
exit 2 (executive/commands/sim_only.py), before anything connects."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from executive.cli import build_parser, main
from executive.commands.sim_only import guarded, refuse_sim_only, sim_only_options

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


MARKED = {max(a.option_strings, key=len): _given(a) for a in sim_only_options(_run_parser())}


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


def _toy(handled: list[argparse.Namespace]) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser()
    parser.add_argument("--driver", default="sim")
    parser.add_argument("--world", default=None, help="a world (with --driver sim; default: the lab)")
    parser.add_argument("--quiet", action="store_true", help="say less (with --driver sim)")
    parser.add_argument("--robot", default="r1", help="robot name")
    parser.set_defaults(handler=lambda args: handled.append(args) or 0)
    guarded(parser)
    return parser


@pytest.mark.parametrize(("argv", "refused"), [
    (["--driver", "zenoh", "--robot", "r2"], None),  # unmarked options pass
    (["--driver", "sim", "--world", "w", "--quiet"], None),  # marked ones go with the simulator
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
        with pytest.raises(ValueError, match=f"^{refused} goes with --driver sim: with --driver zenoh"):
            args.handler(args)
        assert handled == []
        with pytest.raises(ValueError):
            refuse_sim_only(parser, args)

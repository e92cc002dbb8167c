"""``csl run``'s simulator-only options are refused with a driver over zenoh.

With ``--driver zenoh`` the simulator (if there is one at all) runs in the driver's own
process, set up by that process's options (``csl driver sim --world ... --disturb
...``); a ``--world`` or ``--disturb`` given to ``csl run`` would silently do nothing,
and a run that looks disturbed or seeded but is not misleads whoever reads its results.

Which options are simulator-only is what ``csl run --help`` says of them: their help
reads "with --driver sim" (:data:`SIM_ONLY_MARK`). Reading the parser itself, when the
command runs, keeps the list and the help from drifting apart, also for an option added
after the guard was placed.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

SIM_ONLY_MARK = "with --driver sim"
"""The words in an option's help that make it simulator-only."""

Handler = Callable[[argparse.Namespace], int]


def sim_only_options(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    """The options of ``parser`` whose help marks them simulator-only."""
    return [action for action in parser._actions  # argparse keeps no public list of a parser's options
            if action.option_strings and action.help and SIM_ONLY_MARK in action.help]


def refuse_sim_only(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Raise a one-line ``ValueError`` naming the first simulator-only option given
    (set away from its default) when ``args`` chose a driver other than the simulator."""
    if args.driver == "sim":
        return
    for action in sim_only_options(parser):
        if getattr(args, action.dest) != action.default:
            flag = max(action.option_strings, key=len)
            raise ValueError(f"{flag} goes with --driver sim: with --driver {args.driver} any simulator runs in "
                             f"the driver's own process, so give {flag} there (csl driver sim {flag} ...)")


def guarded(parser: argparse.ArgumentParser) -> None:
    """Make ``parser``'s handler refuse simulator-only options first (call once its
    ``handler`` default is set); before any file is read or anything connects."""
    handler: Handler = parser.get_default("handler")

    def handle(args: argparse.Namespace) -> int:
        refuse_sim_only(parser, args)
        return handler(args)

    parser.set_defaults(handler=handle)

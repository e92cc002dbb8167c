"""Options that go with one mode of a command, declared once by the group they sit in.

``csl run`` has modes: the driver in this process or over zenoh, the learner in this
process or a shared service. An option of one mode given in another would silently do
nothing (a ``--world`` for a simulator that runs in the driver's own process, a
``--library`` for a learner that keeps its own), and a run that looks seeded or
disturbed but is not misleads whoever reads its results. So each such option is added
to a :class:`ModeGroup`, an argument group whose title names its mode in ``csl run
--help``, and :func:`guarded` refuses it, in one line naming the option and its mode,
before the handler reads a file or connects. The declaration is the list: an option
added to the group later is refused too, with no second list to keep in step.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

Handler = Callable[[argparse.Namespace], int]
Reason = Callable[[str, argparse.Namespace], str]


@dataclass(frozen=True)
class Mode:
    """The mode an option goes with: ``dest`` (any of them) set to ``value``, said as
    ``said`` (``--driver sim``), with ``reason`` to add after a colon or in brackets."""

    dests: tuple[str, ...]
    value: str
    said: str
    reason: Reason | None = None

    def active(self, args: argparse.Namespace) -> bool:
        return any(getattr(args, dest) == self.value for dest in self.dests)

    def refusal(self, flag: str, args: argparse.Namespace) -> str:
        line = f"{flag} goes with {self.said}"
        return line if self.reason is None else line + self.reason(flag, args)


class ModeGroup:
    """An argument group of ``parser`` whose options go with ``mode``; use it where a
    parser is expected (``add_argument``)."""

    def __init__(self, parser: argparse.ArgumentParser, title: str, mode: Mode) -> None:
        self.mode = mode
        self.actions: list[argparse.Action] = []
        self._group = parser.add_argument_group(f"{title} (with {mode.said})")
        groups: list[ModeGroup] = parser.get_default("mode_groups") or []
        parser.set_defaults(mode_groups=[*groups, self])

    def add_argument(self, *names: str, **kwargs: Any) -> argparse.Action:
        action = self._group.add_argument(*names, **kwargs)
        self.actions.append(action)
        return action


def refuse_out_of_mode(args: argparse.Namespace) -> None:
    """Raise a one-line ``ValueError`` for the first option given (set away from its
    default) whose mode ``args`` did not choose."""
    for group in getattr(args, "mode_groups", None) or ():
        if group.mode.active(args):
            continue
        for action in group.actions:
            if getattr(args, action.dest) != action.default:
                raise ValueError(group.mode.refusal(max(action.option_strings, key=len), args))


def guarded(parser: argparse.ArgumentParser) -> None:
    """Make ``parser``'s handler refuse options out of their mode first (call once its
    ``handler`` default is set)."""
    handler: Handler = parser.get_default("handler")

    def handle(args: argparse.Namespace) -> int:
        refuse_out_of_mode(args)
        return handler(args)

    parser.set_defaults(handler=handle)


def _elsewhere(flag: str, args: argparse.Namespace) -> str:
    return (f": with --driver {args.driver} any simulator runs in the driver's own process, so give {flag} there "
            f"(csl driver sim {flag} ...)")


SIMULATOR = Mode(("driver",), "sim", "--driver sim", _elsewhere)
"""The in-process simulator's options."""
ZENOH_DRIVER = Mode(("driver",), "zenoh", "--driver zenoh")
"""A driver over zenoh's options."""
LOCAL_LEARNER = Mode(("learner",), "local", "--learner local")
"""The in-process learner's options."""
SHARED_LEARNER = Mode(("learner",), "zenoh", "--learner zenoh")
"""A learner service over zenoh's options."""
ANY_ZENOH = Mode(("driver", "learner"), "zenoh", "--driver or --learner zenoh")
"""Options of every zenoh session."""

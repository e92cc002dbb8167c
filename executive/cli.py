"""The ``csl`` command: one entry point, one module per group of subcommands.

Each command module exposes ``register(subparsers)``, adding its parser(s) with a
``handler`` default: a function taking the parsed namespace and returning an exit
status (``executive/exit_status.py``). Bad input anywhere (files, arguments) is raised
as ``ValueError`` or ``OSError`` with a one-line message naming what is wrong; ``main``
prints it as ``csl: error: ...`` and exits 2, never with a traceback (set
``CSL_DEBUG=1`` to see one). A robot or learner service that cannot be reached or
vanishes mid-run stops it with ``csl: robot error: ...`` or ``csl: learner error: ...``,
exit 3.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import os
import sys
from collections.abc import Sequence
from typing import NoReturn

from executive import commands
from executive.exit_status import BAD_INPUT, LOST
from hero_driver.interface import DriverError
from learner.service.interface import LearnerUnavailable


class _Parser(argparse.ArgumentParser):
    """argparse, but a bad argument is one line (and where to read more), exit 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(BAD_INPUT, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def build_parser() -> argparse.ArgumentParser:
    """The full ``csl`` parser with every subcommand registered."""
    parser = _Parser(
        prog="csl",
        description=(
            "csl-executive: cost-sensitive approach-and-recognize (CSL, Tan & Schlimmer "
            "1991) as a py_trees executive. A robot finds objects on a floor, learns which "
            "grasp picks each one up, and senses as cheaply as it can."
        ),
        epilog="Run 'csl COMMAND --help' for a command's options.",
    )
    parser.add_argument("--version", action="version", version=f"csl-executive {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in commands.MODULES:
        module.register(sub)
    return parser


def _version() -> str:
    try:
        return importlib.metadata.version("csl-executive")
    except importlib.metadata.PackageNotFoundError:
        return "(not installed)"


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``csl``; returns the process exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a bad argument (already reported)
        return int(exc.code or 0)
    try:
        return int(args.handler(args) or 0)
    except BrokenPipeError:  # the reader went away (csl ... | head): stop quietly, as Unix tools do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except LearnerUnavailable as exc:  # the learner service could not be reached or vanished
        if os.environ.get("CSL_DEBUG"):
            raise
        print(f"csl: learner error: {_one_line(exc)}", file=sys.stderr)
        return LOST
    except (ValueError, OSError, KeyError) as exc:
        if os.environ.get("CSL_DEBUG"):
            raise
        print(f"csl: error: {_one_line(exc)}", file=sys.stderr)
        return BAD_INPUT
    except DriverError as exc:  # the robot refused or vanished while the executive ran
        if os.environ.get("CSL_DEBUG"):
            raise
        print(f"csl: robot error: {exc}", file=sys.stderr)
        return LOST
    except KeyboardInterrupt:
        print("csl: interrupted", file=sys.stderr)
        return 130


def _one_line(exc: BaseException) -> str:
    """The first line of an error, naming the file for an OS error."""
    if isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        return f"{exc.filename}: {exc.strerror.lower()}"
    if isinstance(exc, KeyError) and exc.args:
        text = str(exc.args[0])
    else:
        text = str(exc)
    text = text.strip()
    return text.splitlines()[0] if text else type(exc).__name__


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

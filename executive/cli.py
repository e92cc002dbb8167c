"""The ``csl`` command: one entry point, one module per group of subcommands.

Each command module exposes ``register(subparsers)``, adding its parser(s) with a
``handler`` default: a function taking the parsed namespace and returning an exit
status. Bad input anywhere (files, arguments) is raised as ``ValueError`` or
``OSError`` with a one-line message naming what is wrong; ``main`` prints it as
``csl: error: ...`` and exits 2, never with a traceback (set ``CSL_DEBUG=1`` to see
one). A robot that vanishes mid-run stops it with ``csl: robot error: ...``, exit 1.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from executive import commands
from hero_driver.interface import DriverError

USAGE_ERROR = 2


def build_parser() -> argparse.ArgumentParser:
    """The full ``csl`` parser with every subcommand registered."""
    parser = argparse.ArgumentParser(
        prog="csl",
        description=(
            "csl-executive: cost-sensitive approach-and-recognize (CSL, Tan & Schlimmer "
            "1991) as a py_trees executive. A robot finds objects on a floor, learns which "
            "grasp picks each one up, and senses as cheaply as it can."
        ),
        epilog="Run 'csl COMMAND --help' for a command's options.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in commands.MODULES:
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``csl``; returns the process exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except BrokenPipeError:  # the reader went away (csl ... | head): stop quietly, as Unix tools do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except (ValueError, OSError, KeyError) as exc:
        if os.environ.get("CSL_DEBUG"):
            raise
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        print(f"csl: error: {message}", file=sys.stderr)
        return USAGE_ERROR
    except DriverError as exc:  # the robot refused or vanished while the executive ran
        if os.environ.get("CSL_DEBUG"):
            raise
        print(f"csl: robot error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("csl: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

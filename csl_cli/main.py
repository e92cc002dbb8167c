# PYTHON_ARGCOMPLETE_OK  (argcomplete's global completion looks for this mark in an entry point's module)
"""The ``csl`` command: one entry point, one module per group of subcommands.

Each command module exposes ``register(subparsers)``, adding its parser(s) with a
``handler`` default: a function taking the parsed namespace and returning an exit
status (``executive/exit_status.py``). Bad input anywhere (files, arguments) is raised
as ``ValueError`` or ``OSError`` with a one-line message naming what is wrong; ``main``
prints it as ``csl: error: ...`` and exits 2, never with a traceback (set
``CSL_DEBUG=1`` to see one). A robot or learner service that cannot be reached or
vanishes mid-run stops it with ``csl: robot error: ...`` or ``csl: learner error: ...``,
exit 3.

``-v``/``--log-level`` is accepted by ``csl`` and by every command (before or after its
name) and sets the level of Python's ``logging``; the default, warnings only, keeps a
run quiet. ``-v`` and ``-vv`` show our packages' lines (the executive's story is told by
``executive/narration.py`` and ``executive/verb_log.py``), other libraries' only from
``-vvv``; ``--log-level`` applies to all alike.

Shell completion is argcomplete's (README): commands and options, and, on every
``--world``, the shipped worlds (an unknown name is refused listing them), on every
``--knowledge`` and ``--profile`` the shipped robot profiles, on every ``--robot`` (and
``ROBOT``) the robots alive on the driver endpoint, and on ``csl library show`` the
library's description ids (``csl_cli/completion.py``). Completion runs only when
the shell's hook sets ``_ARGCOMPLETE``; otherwise argcomplete is not even imported.

Only the module of the command named is imported (``csl_cli/commands/__init__.py``):
``csl --help`` imports argparse and that table, and a command's stack (numpy, the
learner, the transport) waits for the command that uses it.
"""

from __future__ import annotations

import argparse
import logging
import os
import shlex
import signal
import sys
from collections.abc import Sequence
from typing import NoReturn, TextIO

from csl_cli.commands import COMMANDS, NAMES
from csl_cli.interrupt import INTERRUPTED, LINE, exit_quietly, leave


class _Parser(argparse.ArgumentParser):
    """argparse, but a bad argument is one line (and where to read more), exit 2."""

    def error(self, message: str) -> NoReturn:
        """One line even when the message quotes an argument holding a newline (argparse
        names unrecognised arguments as they are): control characters are escaped."""
        from executive.exit_status import BAD_INPUT

        line = "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)
        self.exit(BAD_INPUT, f"{self.prog}: error: {line} (see '{self.prog} --help')\n")


class _Version(argparse.Action):
    """``--version``: the installed distribution's version, read only when asked
    (importlib.metadata is a noticeable share of a bare start)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS,
                 default: str = argparse.SUPPRESS, help: str = "show the version and exit") -> None:  # noqa: A002
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> NoReturn:
        sys.stdout.write(f"csl-executive {_version()}\n")
        parser.exit()


ALL = "*"
"""``build_parser``'s default: every command's own parser (tests, documentation)."""


def build_parser(command: str | None = ALL) -> argparse.ArgumentParser:
    """The ``csl`` parser. Every command is listed; the parsers of ``command``'s module
    are built in full (of every module with :data:`ALL`; of none with None, enough for
    ``csl --help``, ``--version`` and an unknown command), the others are a name and
    a help line."""
    parser = _Parser(
        prog="csl",
        description=(
            "csl-executive: cost-sensitive approach-and-recognize (CSL, Tan & Schlimmer "
            "1991) as a py_trees executive. A robot finds objects on a floor, learns which "
            "grasp picks each one up, and senses as cheaply as it can."
        ),
        epilog="Run 'csl COMMAND --help' for a command's options.",
    )
    parser.add_argument("--version", action=_Version)
    _add_log_options(parser, default=None)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    wanted = {c.module for c in COMMANDS if command in (ALL, c.name)}
    registered: set[str] = set()
    for entry in COMMANDS:
        if entry.module not in wanted:
            sub.add_parser(entry.name, help=entry.help)
        elif entry.module not in registered:  # its commands, in its order (the table's)
            registered.add(entry.module)
            entry.load().register(sub)
    for each in _commands(parser):
        _add_log_options(each, default=argparse.SUPPRESS)
        _add_completers(each)
    return parser


def named_command(argv: Sequence[str]) -> str | None:
    """The command ``argv`` names: its first word that is one (what precedes it are
    ``csl``'s own options, whose values are never command names); None when there is
    none (``csl --help``, ``csl --version``, a mistyped command)."""
    return next((word for word in argv if word in NAMES), None)


def _completed_command() -> str | None:
    """The command on the line the shell is completing, as :func:`named_command` finds
    it (all of them when the line cannot be split, half-typed quotes and all)."""
    line = os.environ.get("COMP_LINE", "")
    try:
        return named_command(shlex.split(line[:int(os.environ.get("COMP_POINT", len(line)))])[1:])
    except ValueError:
        return ALL


LOG_LEVELS = ("debug", "info", "warning", "error", "critical")


def _add_log_options(parser: argparse.ArgumentParser, default: object) -> None:
    """``-v`` (repeatable) and ``--log-level``; a command's copy defaults to SUPPRESS so
    that ``csl -v demo`` is not undone by the command's own default."""
    parser.add_argument("-v", "--verbose", action="count", default=0 if default is None else default,
                        help="log more on standard error: -v tells the run (each test chosen with its cost, each "
                             "robot verb and its reply time, each recovery, each object's outcome, each request "
                             "a service serves), -vv adds detail (tests ranked, paths planned, every event field), "
                             "-vvv adds other libraries' debug output")
    parser.add_argument("--log-level", choices=LOG_LEVELS, type=str.lower, default=default, metavar="LEVEL",
                        help=f"logging level, one of {', '.join(LOG_LEVELS)}, for csl and the libraries it uses "
                             "alike (default: warning; overrides -v)")


def _commands(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    """Every command and sub-command parser below ``parser``, each once."""
    found: list[argparse.ArgumentParser] = []
    for action in parser._actions:  # noqa: SLF001 - argparse has no public walk of its subparsers
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            for child in dict.fromkeys(action.choices.values()):
                found += [child, *_commands(child)]
    return found


def _add_completers(command: argparse.ArgumentParser) -> None:
    """World, robot-profile and robot-name arguments, wherever a command declares them,
    check and complete the same way (``action.completer`` is argcomplete's hook)."""
    for action in command._actions:  # noqa: SLF001
        options = set(action.option_strings)
        if "--world" in options:
            from csl_cli.args import world_argument

            action.type = world_argument
            action.completer = complete_world  # type: ignore[attr-defined]
        elif options & {"--knowledge", "--profile"}:
            action.completer = complete_profile  # type: ignore[attr-defined]
        elif "--robot" in options or (not options and action.dest == "robot"):
            from csl_cli.completion import complete_robot  # the robots alive, else r1

            action.completer = complete_robot  # type: ignore[attr-defined]


def complete_world(prefix: str, **_kwargs: object) -> list[str]:
    """The shipped worlds' names, then world files, that start with ``prefix``."""
    from hero_driver.shipped import shipped_worlds

    return [w for w in shipped_worlds() if w.startswith(prefix)] + _files(prefix, ".json")


def complete_profile(prefix: str, **_kwargs: object) -> list[str]:
    """The shipped robot profiles (``hero_driver/profiles/*.toml``), then TOML files,
    that start with ``prefix``."""
    from executive import defaults

    shipped = [str(p) for p in sorted(defaults.PROFILES.glob("*.toml"))]
    return [p for p in shipped if p.startswith(prefix)] + [f for f in _files(prefix, ".toml") if f not in shipped]


def _files(prefix: str, suffix: str) -> list[str]:
    """Folders and ``*.suffix`` files that start with ``prefix`` (argcomplete's own file
    completer; imported only while completing)."""
    from argcomplete.completers import FilesCompleter

    return list(FilesCompleter(allowednames=(suffix.lstrip("."),), directories=True)(prefix))


def log_level(args: argparse.Namespace) -> int:
    """The ``logging`` level the options ask for: --log-level, else one step per -v
    below warning."""
    if args.log_level is not None:
        return logging.getLevelNamesMapping()[args.log_level.upper()]
    return max(logging.WARNING - 10 * args.verbose, logging.DEBUG)


OUR_PACKAGES = frozenset({"executive", "behaviours", "learner", "planner", "mapping", "hero_driver", "robot_profile",
                          "zenoh_rpc", "camera_model", "reporting", "recording", "experiments", "csl_cli",
                          "csl_testing"})
"""The top-level packages whose log lines ``-v`` and ``-vv`` show (pyproject.toml's)."""
OTHERS_AT = 3
"""The count of ``-v`` from which other libraries' records below warning are shown too:
their debug output (pydot, matplotlib, PIL, asyncio...) would drown the run's story."""


def others_level(args: argparse.Namespace) -> int:
    """The level other libraries' records must reach to be shown: --log-level's, else
    warning until ``-vvv``."""
    if args.log_level is not None or args.verbose >= OTHERS_AT:
        return log_level(args)
    return logging.WARNING


class _OthersFilter(logging.Filter):
    """Passes our packages' records, and other libraries' from ``level`` up."""

    def __init__(self, level: int) -> None:
        super().__init__()
        self.level = level

    def filter(self, record: logging.LogRecord) -> bool:
        return record.levelno >= self.level or record.name.partition(".")[0] in OUR_PACKAGES


class _StderrHandler(logging.StreamHandler):  # type: ignore[type-arg]
    """Writes to whatever ``sys.stderr`` is when a record comes (a redirected or captured
    stream), not to the one there was when ``csl`` started."""

    @property  # type: ignore[override]
    def stream(self) -> TextIO:
        return sys.stderr

    @stream.setter
    def stream(self, _value: object) -> None:
        pass


def configure_logging(level: int, others: int = logging.WARNING) -> None:
    """Set the process's logging level, with one handler writing to standard error
    (added once: ``main`` may run many times in one process, as in the tests) that shows
    other libraries' records only from ``others`` up. The filter sits on the handler, so
    no library's own logger level is changed behind its back."""
    root = logging.getLogger()
    root.setLevel(level)
    handler = next((h for h in root.handlers if isinstance(h, _StderrHandler)), None)
    if handler is None:
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
        root.addHandler(handler)
    handler.filters = [_OthersFilter(others)]


def _version() -> str:
    import importlib.metadata

    try:
        return importlib.metadata.version("csl-executive")
    except importlib.metadata.PackageNotFoundError:
        return "(not installed)"


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``csl``; returns the process exit status. A Ctrl-C at any moment is status 130
    and one line (csl_cli/interrupt.py): inside the command a ``KeyboardInterrupt``, so
    that its clean-ups run; while it starts or after it returned, a quiet exit."""
    quiet = signal.getsignal(signal.SIGINT) is exit_quietly  # started as the csl command
    try:
        if quiet:
            signal.signal(signal.SIGINT, signal.default_int_handler)
        return _main(sys.argv[1:] if argv is None else list(argv))
    except KeyboardInterrupt:
        print(LINE, file=sys.stderr)
        if quiet:
            leave(INTERRUPTED)
        return INTERRUPTED
    finally:
        if quiet:
            signal.signal(signal.SIGINT, exit_quietly)  # the interpreter's shutdown: threads, atexit


def _main(argv: list[str]) -> int:
    if "_ARGCOMPLETE" in os.environ:  # the shell asks for completions: print them and exit
        import argcomplete

        argcomplete.autocomplete(build_parser(_completed_command()))
    parser = build_parser(named_command(argv))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a bad argument (already reported)
        return int(exc.code or 0)
    configure_logging(log_level(args), others_level(args))
    try:
        return int(args.handler(args) or 0)
    except BrokenPipeError:  # the reader went away (csl ... | head): stop quietly, as Unix tools do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except KeyboardInterrupt:  # before the next clause, which imports what it names
        raise
    except _expected() as exc:
        if os.environ.get("CSL_DEBUG"):
            raise
        line, status = _error(exc)
        print(line, file=sys.stderr)
        return status


def _expected() -> tuple[type[Exception], ...]:
    """The errors ``csl`` reports in one line (imported once a command has failed:
    the driver interface brings numpy)."""
    from hero_driver.interface import DriverError
    from learner.service.interface import LearnerUnavailable

    return LearnerUnavailable, DriverError, ValueError, OSError, KeyError


def _error(exc: Exception) -> tuple[str, int]:
    """The one line for an error ``csl`` expects, and its exit status: a learner service
    or robot lost is exit 3, anything else a bad input (exit 2)."""
    from executive.exit_status import BAD_INPUT, LOST
    from hero_driver.interface import DriverError
    from learner.service.interface import LearnerTimedOut, LearnerUnavailable

    if isinstance(exc, LearnerTimedOut):  # there, but slower than it was given: the line says how to give more
        return f"csl: learner error: {_one_line(exc)}", LOST
    if isinstance(exc, LearnerUnavailable):  # the learner service could not be reached or vanished
        return f"csl: learner error: {_one_line(exc)} (is one serving? start it with 'csl learner serve')", LOST
    if isinstance(exc, DriverError):  # the robot refused or vanished while the executive ran
        return f"csl: robot error: {exc}", LOST
    return f"csl: error: {_one_line(exc)}", BAD_INPUT


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

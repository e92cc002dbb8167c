"""Ctrl-C at any moment ends ``csl`` with exit status 130 and one line, ``csl:
interrupted``, never a traceback.

Inside :func:`csl_cli.main.main` an interrupt is Python's ``KeyboardInterrupt``: the
command's ``finally`` clauses run (a failed start takes back what it made, a driver
process is stopped, a recording closed) and ``main`` prints the line. Before ``main``
runs (the imports of ``csl_cli.main`` and the command's module, the parser being built)
and after it has returned (the interpreter's shutdown: threads, atexit handlers), there
is nothing of the command's to clean up and a ``KeyboardInterrupt`` would only print a
traceback from wherever it landed; :func:`exit_quietly` is the handler for those
moments. The interpreter's own start-up, before any of our code runs, is Python's: a
Ctrl-C then ends the process by the signal, silently.
"""

from __future__ import annotations

import logging
import os
import signal
import sys
from pathlib import Path
from types import FrameType

INTERRUPTED = 130
"""128 + SIGINT, the status a shell gives a process that a Ctrl-C ended (README, "Exit
status"; not in executive/exit_status.py, which a start-up must not import: numpy)."""
LINE = "csl: interrupted"


def exit_quietly(_signum: int, _frame: FrameType | None) -> None:
    """Leave at once with :data:`INTERRUPTED` and :data:`LINE`: for the moments when
    nothing needs cleaning up (see the module's docstring)."""
    os.write(2, f"{LINE}\n".encode())
    os._exit(INTERRUPTED)


def leave(status: int) -> None:
    """End the ``csl`` process now with ``status``, once the interrupted command's
    clean-ups have run: log handlers and standard streams flushed, no interpreter
    shutdown. CPython 3.11 marks a ``KeyboardInterrupt`` raised inside code compiled
    from a string (a dataclass's generated methods, any ``exec`` or ``eval``, common
    while a command imports its stack) as unhandled even once caught, and at exit kills
    itself with SIGINT: the status was then -2, not 130 (seen while a command imported
    its stack)."""
    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing more can be said
            pass
    os._exit(status)


def started_as_command() -> bool:
    """True while ``csl`` (the console script) or ``python -m csl_cli`` is starting:
    Python sets ``sys.argv[0]`` to ``-m`` while it locates a ``-m`` module. Imported by
    a test or another program, the package leaves the process's Ctrl-C alone."""
    return sys.argv[:1] == ["-m"] or Path(sys.argv[0] if sys.argv else "").name == "csl"


def guard_start() -> None:
    """Install :func:`exit_quietly` for ``csl``'s start-up (the package's import)."""
    if started_as_command() and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, exit_quietly)

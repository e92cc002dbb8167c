"""The ``csl`` command line: one entry point (:mod:`csl_cli.main`), one module per group
of subcommands (:mod:`csl_cli.commands`), and the argument checks they share
(:mod:`csl_cli.args`). It composes the executive, the reports and the recording; nothing
below it imports it."""

from csl_cli.interrupt import guard_start

guard_start()  # Ctrl-C while csl starts: one line, status 130 (csl_cli/interrupt.py)

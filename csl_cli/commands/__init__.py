"""The ``csl`` subcommand modules, in the order ``csl --help`` lists them.

Each module has ``register(subparsers)``; add a new group here.
"""

from __future__ import annotations

from types import ModuleType

from csl_cli.commands import camera, experiment, learner_cmd, library, log, offline, run
from hero_driver import cli as driver

MODULES: list[ModuleType] = [run, experiment, log, offline, library, learner_cmd, driver, camera]

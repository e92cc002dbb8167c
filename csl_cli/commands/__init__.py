"""The ``csl`` commands, in the order ``csl --help`` lists them, and the module that
registers each.

Each module has ``register(subparsers)``, adding its parsers with a ``handler``
default. A module is imported only for its own commands (run, asked for help, or
completed by the shell): ``csl --help`` lists the commands from this table alone, so
it does not wait for numpy and the rest of every command's stack. A command added to
a module is added here too, with the same help line
(``tests/executive/test_cli_startup.py`` holds the two equal).
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import import_module
from types import ModuleType


@dataclass(frozen=True)
class Command:
    """One ``csl`` command: its name, the module that registers it, and its line in
    ``csl --help``."""

    name: str
    module: str
    help: str

    def load(self) -> ModuleType:
        return import_module(self.module)


COMMANDS: tuple[Command, ...] = (
    Command("demo", "csl_cli.commands.run",
            "the main job: train in the simulated lab, then retrieve the test objects"),
    Command("run", "csl_cli.commands.run",
            "run the executive against any driver (simulated in-process, or over zenoh)"),
    Command("bt", "csl_cli.commands.run", "show the behaviour tree"),
    Command("experiment", "csl_cli.commands.experiment",
            "measure the method against the paper's figures, baselines and the optimum"),
    Command("log", "csl_cli.commands.log",
            "replay an episode log: what was decided, measured and paid, object by object"),
    Command("view", "csl_cli.commands.view", "replay an episode in a browser, from one HTML page"),
    Command("tree", "csl_cli.commands.offline", "print the decision tree the learner grows from a pose"),
    Command("train", "csl_cli.commands.offline",
            "run the training stage, in the simulator (--sim) or on recorded measurements"),
    Command("library", "csl_cli.commands.library",
            "show, import, export or summarise the persistent library; the learning history"),
    Command("learner", "csl_cli.commands.learner_cmd",
            "serve the shared library over zenoh so several robots learn into it"),
    Command("driver", "hero_driver.cli", "serve the simulated robot over zenoh, or check a driver process"),
    Command("camera", "csl_cli.commands.camera", "the overhead camera: calibrate it from the printed marker board"),
)

NAMES: frozenset[str] = frozenset(c.name for c in COMMANDS)

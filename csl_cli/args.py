"""Argument checks shared by the commands: fail at once, naming the argument, before
any long work (a training run must not end in 'cannot write the output')."""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable
from pathlib import Path

from executive import defaults
from hero_driver.shipped import shipped_worlds
from learner.choosing.criteria import CRITERIA, DEFAULT_CRITERION, Criterion, CriterionSpec, Parameter
from zenoh_rpc.argtypes import non_negative_int
from zenoh_rpc.endpoints import check_endpoint


def endpoint(text: str) -> str:
    """argparse type: a zenoh endpoint such as tcp/127.0.0.1:7447."""
    try:
        return check_endpoint(text)
    except (ValueError, OSError) as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def verb_timeout(text: str) -> tuple[str, float]:
    """argparse type for ``--verb-timeout VERB=SECONDS``: a positive, finite number of
    seconds (the verb itself is checked against the protocol's verbs when the driver
    client is built, so ``csl --help`` need not import the driver link)."""
    verb, equals, seconds = text.partition("=")
    if not equals or not verb:
        raise argparse.ArgumentTypeError(f"expected VERB=SECONDS, such as sense=60, got {text!r}")
    try:
        value = float(seconds)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{verb}: expected a number of seconds, got {seconds!r}") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{verb}: must be a positive number of seconds, got {seconds}")
    return verb, value


def add_verb_timeout_option(p: argparse.ArgumentParser) -> None:
    """Add ``--verb-timeout VERB=SECONDS`` (repeatable) to a command that drives a
    robot over zenoh."""
    p.add_argument("--verb-timeout", type=verb_timeout, action="append", default=None, metavar="VERB=SECONDS",
                   help="with --driver zenoh: how long to wait for one verb's reply before the object it "
                        "serves is given up (repeatable, e.g. --verb-timeout sense=60 --verb-timeout move=600; "
                        "defaults in docs/driver-protocol.md, Verbs)")


def world_argument(text: str) -> str:
    """argparse type for ``--world``: a world file, or the name of a shipped world; an
    unknown name is refused while parsing, listing the shipped ones. A name the
    system refuses (over 255 bytes) is not a file, not an OSError inside argparse."""
    try:
        is_file = Path(text).is_file()
    except OSError:
        is_file = False
    if is_file or text in shipped_worlds():
        return text
    raise argparse.ArgumentTypeError(f"{text!r} is neither a world file nor a shipped world "
                                     f"(shipped: {', '.join(shipped_worlds())})")


def writable_file(path: Path, option: str) -> Path:
    """Check that ``path`` can be written (its folder exists and is writable, it is not
    a folder, the file itself can be made) before the work that produces it starts.

    A new file is made and removed again: permissions alone do not tell (root passes
    every ``os.access`` check, yet cannot create a file under ``/proc`` or one whose
    name is too long), and the writer that fails later says only "No such file or
    directory", naming neither the option nor the file."""
    try:
        if path.is_dir():
            raise ValueError(f"{option}: {path} is a folder, not a file")
        folder = path.parent if str(path.parent) else Path(".")
        if not folder.is_dir():
            raise ValueError(f"{option}: folder {folder} does not exist")
        if not os.access(folder, os.W_OK):
            raise ValueError(f"{option}: cannot write into {folder}")
        if path.exists():  # a file (or a device such as /dev/stdout): opening it could block or truncate
            if not os.access(path, os.W_OK):
                raise ValueError(f"{option}: cannot write {path}: permission denied")
            return path
        path.open("xb").close()
    except OSError as exc:  # a name too long, a folder such as /proc that takes no new files...
        raise ValueError(f"{option}: cannot create {path}: {(exc.strerror or str(exc)).lower()}") from None
    path.unlink()
    return path


def library_path(path: Path | None, option: str) -> Path:
    """The library database ``option`` names, or the user's default one.

    A folder the user named is never created behind their back (a typo would start an
    empty library somewhere unexpected): a missing one is a one-line error. Only the
    default's folder, ``$CSL_HOME``, is created when the store is opened."""
    if path is None:
        return defaults.library_db()
    if path.is_dir():
        raise ValueError(f"{option}: {path} is a folder, not a library database")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"{option}: folder {folder} does not exist (create it first, or choose another path)")
    return path


def add_retrain_option(p: argparse.ArgumentParser) -> None:
    """Add ``--retrain`` to ``csl demo``: train even when a library trained on the same
    inputs is stored (csl_cli/demo_library.py)."""
    p.add_argument("--retrain", action="store_true",
                   help="train on the Table 3 objects even when a library trained on the same knowledge, "
                        "world, seed and code is stored ($CSL_HOME/trained/)")


CEILING, ONBOARD = "ceiling", "onboard"
PERCEPTIONS = (CEILING, ONBOARD)
"""``--perception``'s choices: ``executive.executive.PERCEPTIONS``, named here so that
parsing the command line does not import the executive (``csl --help`` stays light;
``tests/executive/test_cli_onboard.py`` holds the two equal)."""


def add_perception_option(p: argparse.ArgumentParser, help: str) -> None:  # noqa: A002
    """Add ``--perception {ceiling,onboard}`` (default ceiling), with ``help`` saying
    what it changes for the command."""
    p.add_argument("--perception", choices=PERCEPTIONS, default=CEILING, help=help)


def output_folder(path: Path, option: str) -> Path:
    """Create the output folder, or say in one line why it cannot be."""
    if path.exists() and not path.is_dir():
        raise ValueError(f"{option}: {path} exists and is not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"{option}: cannot create folder {path}: {exc.strerror}") from None
    if not os.access(path, os.W_OK):
        raise ValueError(f"{option}: cannot write into {path}")
    return path


def _parameter_option(spec: CriterionSpec, parameter: Parameter) -> str:
    """The option naming one criterion's parameter: eg2's ``w`` is ``--eg2-w``."""
    return f"--{spec.name}-{parameter.name}"


def _parameter_dest(spec: CriterionSpec, parameter: Parameter) -> str:
    return _parameter_option(spec, parameter)[2:].replace("-", "_")


def _parameter_type(parameter: Parameter) -> Callable[[str], float]:
    """argparse type for a criterion parameter: a bad value is refused while parsing,
    as one line naming the option, before any training or robot time."""

    def parse(text: str) -> float:
        value = _float(text, "a number")
        try:
            return parameter.check(value)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return parse


def add_criterion_options(p: argparse.ArgumentParser) -> None:
    """Add ``--criterion`` (each entry's formula and help in the help text) and one
    option per criterion parameter, all from the registry."""
    listing = "; ".join(f"{s.name} = {s.formula} ({s.help})" for s in CRITERIA.values())
    p.add_argument("--criterion", choices=CRITERIA, default=DEFAULT_CRITERION, metavar="NAME",
                   help=f"evaluation function of a test's gain I (bits) and cost C (s): {listing}; "
                        f"default {DEFAULT_CRITERION}")
    for spec in CRITERIA.values():
        for parameter in spec.parameters:
            p.add_argument(_parameter_option(spec, parameter), type=_parameter_type(parameter), default=None,
                           metavar=parameter.name.upper(),
                           help=f"with --criterion {spec.name}: its {parameter.name}, {parameter.help}; "
                                f"finite, >= {parameter.minimum:g} (default {parameter.default:g})")


def criterion_from_args(args: argparse.Namespace) -> Criterion:
    """The criterion the parsed options name, with its parameters; a parameter of a
    criterion not chosen is a mistake worth a line (ValueError), not something to ignore."""
    chosen = CRITERIA[args.criterion]
    given: dict[str, float] = {}
    for spec in CRITERIA.values():
        for parameter in spec.parameters:
            value = getattr(args, _parameter_dest(spec, parameter))
            if value is None:
                continue
            if spec is not chosen:
                raise ValueError(f"{_parameter_option(spec, parameter)} goes with --criterion {spec.name}")
            given[parameter.name] = value
    return chosen.build(**given)


def port(text: str) -> int:
    """argparse type: a TCP port, 0 for any free one."""
    value = non_negative_int(text)
    if value > 65535:
        raise argparse.ArgumentTypeError(f"a port is at most 65535, got {value}")
    return value


def _float(text: str, what: str) -> float:
    """``text`` as a number, or the argparse error 'expected WHAT, got TEXT'."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None


def non_negative_seconds(text: str) -> float:
    """argparse type: a finite number of seconds >= 0."""
    value = _float(text, "a number of seconds")
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"must be a finite number of seconds >= 0, got {text}")
    return value


def battery_level(text: str) -> float:
    """argparse type: a battery level from 0 (empty) to 1 (full)."""
    value = _float(text, "a battery level from 0 to 1")
    if not 0.0 <= value <= 1.0:  # NaN fails this too
        raise argparse.ArgumentTypeError(f"must be a battery level from 0 to 1, got {text}")
    return value


def add_recording_options(p: argparse.ArgumentParser) -> None:
    """Add ``--record``, ``--live``, ``--live-port``, ``--live-pace`` and ``--show-status``
    (docs/recording.md): watching an episode in Foxglove or on the terminal."""
    p.add_argument("--record", type=Path, default=None, metavar="FILE.mcap",
                   help="record the episode as MCAP with Foxglove's schemas: robot pose, planned paths, sonar rays, "
                        "camera, map, objects, the tree's status per tick (docs/recording.md)")
    p.add_argument("--live", action="store_true",
                   help="serve the same channels live to Foxglove or Lichtblick on 127.0.0.1 (subprotocol "
                        "foxglove.sdk.v1 or foxglove.websocket.v1); the episode starts when a client subscribes")
    p.add_argument("--live-port", type=port, default=None, metavar="N",
                   help="with --live: the port (default 8765, Foxglove's; 0 for any free one)")
    p.add_argument("--live-pace", type=non_negative_seconds, default=None, metavar="SECONDS",
                   help="with --live: wall seconds between ticks, so an in-process simulator is watchable "
                        "(default 0.2; 0 runs flat out)")
    p.add_argument("--show-status", action="store_true",
                   help="print py_trees' tree with every behaviour's status after each object (colour on a terminal)")


def add_learned_grasp_costs_option(p: argparse.ArgumentParser) -> None:
    """Add ``--learned-grasp-costs`` / ``--no-learned-grasp-costs``. On by default: a
    default changes only for a gain beyond twice its standard error, and the study of
    docs/method.md §5.7 measures one where the knowledge file's grasp prices are wrong
    and none lost where they are right (docs/results.md has the figures). So a robot
    prices its grasps by what they cost, the file's prices the prior;
    ``--no-learned-grasp-costs`` keeps the file's prices for ever (the paper's behaviour)."""
    p.add_argument("--learned-grasp-costs", action=argparse.BooleanOptionalAction, default=True,
                   help="record each object's grasp costs in the library store and price later choices by them, "
                        "the knowledge file's costs the prior (docs/method.md §5.7; default: on, for what it saved in "
                        "docs/results.md; --no-learned-grasp-costs prices grasps by the file alone, as the paper did)")

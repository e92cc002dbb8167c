"""Argument checks shared by the commands: fail at once, naming the argument, before
any long work (a training run must not end in 'cannot write the output')."""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable
from pathlib import Path

from learner.criteria import CRITERIA, DEFAULT_CRITERION, Criterion, CriterionSpec, Parameter
from zenoh_rpc.endpoints import check_endpoint


def non_negative_int(text: str) -> int:
    """argparse type: an integer >= 0 (a seed, a count)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must not be negative, got {value}")
    return value


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    value = non_negative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def endpoint(text: str) -> str:
    """argparse type: a zenoh endpoint such as tcp/127.0.0.1:7447."""
    try:
        return check_endpoint(text)
    except (ValueError, OSError) as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def writable_file(path: Path, option: str) -> Path:
    """Check that ``path`` can be written (its folder exists and is writable, it is not
    a folder) before the work that produces it starts."""
    if path.is_dir():
        raise ValueError(f"{option}: {path} is a folder, not a file")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"{option}: folder {folder} does not exist")
    if not os.access(folder, os.W_OK):
        raise ValueError(f"{option}: cannot write into {folder}")
    return path


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
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        try:
            return parameter.check(value)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return parse


def add_criterion_options(p: argparse.ArgumentParser) -> None:
    """Add ``--criterion`` (each entry's formula and help in the help text) and one
    option per criterion parameter, all from the registry."""
    listing = "; ".join(f"{s.name} = {s.formula} ({s.help})" for s in CRITERIA.values())
    p.add_argument("--criterion", choices=CRITERIA, default=DEFAULT_CRITERION,
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

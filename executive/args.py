"""Argument checks shared by the commands: fail at once, naming the argument, before
any long work (a training run must not end in 'cannot write the output')."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from hero_driver.zenoh_link.config import check_endpoint


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

"""Where the built-in files live, so every command has a sensible default."""

from __future__ import annotations

import os
from pathlib import Path

import hero_driver
from robot_profile import DEFAULT_PROFILE

PROFILES = Path(hero_driver.__file__).resolve().parent / "profiles"
KNOWLEDGE = DEFAULT_PROFILE
EXAMPLE_LIBRARY = PROFILES / "hero2000-library.json"


def library_db() -> Path:
    """The user's persistent library: ``$CSL_HOME/library.sqlite`` (``~/.local/share/csl``)."""
    home = os.environ.get("CSL_HOME") or str(Path.home() / ".local" / "share" / "csl")
    return Path(home) / "library.sqlite"

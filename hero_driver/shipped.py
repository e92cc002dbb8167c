"""The worlds shipped with the simulator, found without loading it: ``csl --help``,
argument checks and shell completion list them, and none of those should import the
physics."""

from __future__ import annotations

import json
from pathlib import Path

WORLDS_DIR = Path(__file__).resolve().parent / "worlds"
"""Where the shipped world files, the catalogue and the marker boards live."""


def shipped_worlds() -> list[str]:
    """The names of the shipped worlds: the files in :data:`WORLDS_DIR` that place
    objects (not the catalogue, not the calibration board)."""
    names = []
    for path in sorted(WORLDS_DIR.glob("*.json"), key=lambda p: p.stem):  # "apartment" before "apartment-2"
        try:
            document = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(document, dict) and "objects" in document:
            names.append(path.stem)
    return names

"""The raw results: one CSV row per object per episode, every condition in its columns,
so a user can re-plot anything without re-running."""

from __future__ import annotations

import csv
from collections.abc import Iterable
from dataclasses import astuple
from pathlib import Path

from experiments.episodes import EpisodeRow


def write_episodes(path: Path, rows: Iterable[EpisodeRow]) -> int:
    """Write ``rows`` (header first; empty cells for None); returns the rows written."""
    count = 0
    with path.open("w", encoding="utf-8", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(EpisodeRow.columns())
        for row in rows:
            writer.writerow(["" if v is None else v for v in astuple(row)])
            count += 1
    return count


def read_episodes(path: Path) -> list[dict[str, str]]:
    """The CSV back as dictionaries of strings (for checks and quick re-plots)."""
    with path.open(encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))

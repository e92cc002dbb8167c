"""How big a run is: seeds, sweep points and chain lengths, full or ``--quick``.

One place decides every study's size, so ``--quick`` shrinks all of them together; what
a run cost (episodes, wall and CPU time) is in the header of the page it wrote
(docs/results.md).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from learner.position import Position

FULL_SEEDS = 20
QUICK_SEEDS = 2
MAX_SEEDS = 10_000  # more seeds than any run would want: a typo, not a plan


def parse_seeds(text: str) -> tuple[int, ...]:
    """The seeds a ``--seeds`` value names: ``N`` (the first N, 0 to N-1), a range
    ``A-B`` (both ends included) or a list ``A,B,C``; each seed lays a floor out, so
    other seeds than the page's are other floors (ValueError: what is wrong, one line)."""
    text = text.strip()
    if re.fullmatch(r"\d+", text):
        count = int(text)
        if not 1 <= count <= MAX_SEEDS:
            raise ValueError(f"a count of seeds must be 1 to {MAX_SEEDS}, got {count}")
        return tuple(range(count))
    if match := re.fullmatch(r"(\d+)\s*-\s*(\d+)", text):
        first, last = int(match[1]), int(match[2])
        if last < first or last - first >= MAX_SEEDS:
            raise ValueError(f"a range of seeds goes from low to high, at most {MAX_SEEDS} of them: got {text!r}")
        return tuple(range(first, last + 1))
    if re.fullmatch(r"\d+(\s*,\s*\d+)+", text):
        seeds = tuple(int(part) for part in text.split(","))
        if len(set(seeds)) != len(seeds):
            raise ValueError(f"a seed is named twice in {text!r}")
        return seeds
    raise ValueError(f"expected a count (20), a range (100-109) or a list (1,5,9) of seeds, got {text!r}")


@dataclass(frozen=True)
class ExperimentConfig:
    """The run's size and where it writes. ``command`` is how it was invoked (for the
    page's header)."""

    quick: bool
    seeds: tuple[int, ...]  # the floors every condition runs on (the page's: 0 to N-1)
    jobs: int
    out: Path
    command: str

    @property
    def seed_list(self) -> list[int]:
        return list(self.seeds)

    @property
    def few_seeds(self) -> list[int]:
        """For sweeps, whose many points already average over objects."""
        return self.seed_list[: 1 if self.quick else max(1, len(self.seeds) // 2)]

    @property
    def cost_multipliers(self) -> list[float]:
        return [0.25, 1.0, 4.0] if self.quick else [0.25, 0.5, 1.0, 2.0, 4.0]

    @property
    def noise_factors(self) -> list[float]:
        return [0.0, 1.0, 2.0] if self.quick else [0.0, 0.5, 1.0, 2.0, 3.0]

    @property
    def chain_length(self) -> int:
        """Episodes in one incremental-learning chain."""
        return 3 if self.quick else 6

    @property
    def chain_seeds(self) -> list[int]:
        return self.seed_list[: 1 if self.quick else len(self.seeds)]

    @property
    def start_poses(self) -> list[Position]:
        """Where the robot stands when the optimum and the policies start."""
        poses = [Position(24.0, 0.0), Position(60.0, 90.0), Position(100.0, 180.0)]
        return poses[:2] if self.quick else poses

    @property
    def shipped_descriptions(self) -> int | None:
        """How much of the shipped library the optimum searches (None: all 14). The
        search grows exponentially with descriptions: all 14 take minutes per start,
        the first 10 about a second."""
        return 10 if self.quick else None

    @property
    def synthetic_objects(self) -> int:
        return 8 if self.quick else 12


def seeds_text(seeds: tuple[int, ...]) -> str:
    """How a page names its seeds: ``0 to 19``, ``100 to 109``, or the list."""
    if len(seeds) > 1 and seeds == tuple(range(seeds[0], seeds[-1] + 1)):
        return f"{len(seeds)} ({seeds[0]} to {seeds[-1]})"
    return f"{len(seeds)} ({', '.join(map(str, seeds))})"

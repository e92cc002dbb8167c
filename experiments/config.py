"""How big a run is: seeds, sweep points and chain lengths, full or ``--quick``.

One place decides every study's size, so ``--quick`` shrinks all of them together and
the full run's cost can be read off here: 620 episodes and 6 optimum searches at the
default 20 seeds, about 8 CPU minutes (30 episodes and 4 small searches with ``--quick``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from learner.position import Position

FULL_SEEDS = 20
QUICK_SEEDS = 2


@dataclass(frozen=True)
class ExperimentConfig:
    """The run's size and where it writes. ``command`` is how it was invoked (for the
    page's header)."""

    quick: bool
    seeds: int
    jobs: int
    out: Path
    command: str

    @property
    def seed_list(self) -> list[int]:
        return list(range(self.seeds))

    @property
    def few_seeds(self) -> list[int]:
        """For sweeps, whose many points already average over objects."""
        return self.seed_list[: 1 if self.quick else max(1, self.seeds // 2)]

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
        return self.seed_list[: 1 if self.quick else self.seeds]

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

"""The robot's knowledge: sensing and grasping procedures, their costs, and moving.

This is the learner's only view of a robot, so another robot is other knowledge. The
learner reads no files and imports nothing of ours, so these types are its own: the
robot profile reader (``robot_profile``) builds them directly from the validated file
(one definition, nothing translated), and tests build them by hand.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property


@dataclass(frozen=True)
class FeatureSpec:
    """A feature a sensing procedure yields, with the noise the learner must tolerate."""

    name: str
    error: float  # expected error, in the feature's unit: values this close are one branch
    unit: str
    binary: bool  # 0/1 features (holes); their domain is {0, 1}
    span: tuple[float, float]  # the values the feature can take, for the "unknown" subset
    angular_of: str | None = None  # the linear feature whose angular size this is (training distances)

    def covered_by(self, ranges: list[tuple[float, float]]) -> bool:
        """True when the observed ranges, widened by the error, cover the feature's domain.

        When they do not, a value outside them is possible, so scoring adds an "unknown"
        subset (docs/method.md §3, missing values).
        """
        if self.binary:
            return all(any(lo - self.error <= v <= hi + self.error for lo, hi in ranges) for v in (0.0, 1.0))
        reach = self.span[0]
        for lo, hi in sorted(ranges):
            if lo - self.error > reach:
                return False
            reach = max(reach, hi + self.error)
        return reach >= self.span[1]


@dataclass(frozen=True)
class SensingProcedure:
    """An arm motion with the wrist sonar; one application yields all its features."""

    name: str
    time_s: float
    range_in: tuple[float, float]
    features: tuple[FeatureSpec, ...]

    def applicable_at(self, distance_in: float) -> bool:
        return self.range_in[0] - 1e-9 <= distance_in <= self.range_in[1] + 1e-9


@dataclass(frozen=True)
class GraspingProcedure:
    """A grasp; tried as a binary feature its cost is time plus the side-effect penalty,
    priced with its failure harm.

    ``side_effect_penalty_s`` is robot time (the recovery a failure causes, which
    learned grasp costs replace by what failures really cost); ``failure_harm_s`` is not
    time at all but the price of what a failure does beyond it (a tumbler knocked over,
    an object pushed, an arm strained), which no measured seconds can learn away, so it
    stays as the profile sets it (0: none, the paper's pricing)."""

    name: str
    time_s: float
    range_in: tuple[float, float]
    side_effect_penalty_s: float
    verifiable: bool  # the finger sensor can confirm success; else never tried as a feature
    failure_harm_s: float = 0.0

    @property
    def failure_time_s(self) -> float:
        """The robot seconds a failed attempt costs: its time and its side-effect penalty."""
        return self.time_s + self.side_effect_penalty_s

    @property
    def feature_cost_s(self) -> float:
        """What a failed attempt is *priced* at wherever a choice weighs one (a grasp
        tried as a feature, an ambiguous leaf's order, a wrong leaf grasp in a search):
        its seconds plus its harm. A decision price, never robot time spent."""
        return self.failure_time_s + self.failure_harm_s

    def applicable_at(self, distance_in: float) -> bool:
        return self.range_in[0] - 1e-9 <= distance_in <= self.range_in[1] + 1e-9


@dataclass(frozen=True)
class MoveModel:
    """The default move-cost model, used until a planner prices moves on a map."""

    seconds_per_inch: float
    seconds_per_degree: float
    overhead_s: float


@dataclass(frozen=True)
class Knowledge:
    """Everything the learner knows about the robot it serves.

    Built from a validated profile, so it assumes what the reader checked: names are
    unique and each feature comes from exactly one sensing procedure.
    """

    sensing: tuple[SensingProcedure, ...]
    grasping: tuple[GraspingProcedure, ...]
    move: MoveModel
    source: str = "<knowledge>"

    def feature(self, name: str) -> FeatureSpec:
        return self._features[name][0]

    def procedure_for(self, feature: str) -> SensingProcedure:
        """The procedure that yields ``feature`` (each feature has exactly one)."""
        return self._features[feature][1]

    def grasp(self, name: str) -> GraspingProcedure:
        try:
            return self._grasps[name]
        except KeyError:
            raise KeyError(f"{self.source}: unknown grasping procedure {name!r}") from None

    def has_feature(self, name: str) -> bool:
        return name in self._features

    def has_grasp(self, name: str) -> bool:
        return name in self._grasps

    @cached_property
    def _features(self) -> dict[str, tuple[FeatureSpec, SensingProcedure]]:
        return {f.name: (f, p) for p in self.sensing for f in p.features}

    @cached_property
    def _grasps(self) -> dict[str, GraspingProcedure]:  # grasp() is asked per candidate test
        return {g.name: g for g in self.grasping}

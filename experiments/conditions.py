"""The conditions an episode runs under: how noisy the robot is, how dear moving and
sensing are, and which control strategies the executive may use.

Each is a small value a job carries to its worker process, turned there into what the
simulator and the executive take (a ``NoiseConfig``, a ``RobotProfile``, ``Params``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from behaviours.services import Params
from hero_driver.sim import noise as sim_noise
from robot_profile import RobotProfile

DEFAULT_NOISE = "default"  # the simulator's own default (mild: clipped sonar, 2% outliers)
NO_NOISE = "off"  # exact values everywhere
EXECUTION_NOISE = "paper"  # the preset the paper's experiment runs under (docs/simulator.md)


def noise_names() -> list[str]:
    """Every noise a job may name: the two built in here, and the simulator's presets."""
    names = [DEFAULT_NOISE, NO_NOISE]
    return names + [n for n in sim_noise.NOISE_PRESETS if n not in names]


def noise_config(name: str, factor: float = 1.0) -> sim_noise.NoiseConfig:
    """The simulator's noise called ``name``, its rates scaled by ``factor`` (presets only:
    the built-in default and ``off`` have no scale)."""
    if name == NO_NOISE:
        return sim_noise.NoiseConfig.off()
    if name == DEFAULT_NOISE:
        if factor != 1.0:
            raise ValueError("the default noise cannot be scaled; name a preset")
        return sim_noise.NoiseConfig()
    if name not in sim_noise.NOISE_PRESETS:
        raise ValueError(f"unknown noise {name!r} (choose from: {', '.join(noise_names())})")
    config = sim_noise.NoiseConfig.preset(name)
    return config if factor == 1.0 else config.scaled(factor)


@dataclass(frozen=True)
class Control:
    """The control strategies for noise (docs/method.md §5) as the executive's knobs.

    ``alternatives``: the paper's N, tests tried at a node before backtracking.
    ``nearest_after``: unreliable values before following the nearest branch (None:
    only as the last resort; 0: at once, which switches reselection and backtracking
    off, since the executive then trusts the nearest branch of every value; where no
    value was had, a dropout or an unreachable test, there is nothing to be near to and
    the executive still backtracks: docs/method.md, "Findings").
    ``appearance``: rule candidates out by what the camera saw (``Params.use_appearance``).
    """

    alternatives: int = 3
    nearest_after: int | None = None
    appearance: bool = True

    @property
    def label(self) -> str:
        camera = "" if self.appearance else ", no appearance"
        if self.nearest_after == 0:
            return "off" + camera
        nearest = "last" if self.nearest_after is None else f"after {self.nearest_after}"
        return f"N={self.alternatives}, nearest {nearest}{camera}"

    def params(self) -> Params:
        return Params(max_alternatives=self.alternatives, nearest_after=self.nearest_after,
                      use_appearance=self.appearance)


STRATEGIES_ON = Control()
STRATEGIES_OFF = Control(alternatives=1, nearest_after=0)


@dataclass(frozen=True)
class CostScale:
    """Multipliers on the robot's time: ``move`` on everything a move costs (driving,
    turning, vision, centring, and the learner's move model), ``sense`` on every sensing
    procedure. The simulator and the learner see the same scaled robot, so what the
    learner expects is what the robot pays."""

    move: float = 1.0
    sense: float = 1.0

    def apply(self, profile: RobotProfile) -> RobotProfile:
        if (self.move, self.sense) == (1.0, 1.0):
            return profile
        if self.move <= 0 or self.sense <= 0:
            raise ValueError(f"cost multipliers must be > 0, got move x{self.move:g}, sense x{self.sense:g}")
        m = profile.robot.motion
        motion = replace(m, speed_in_per_s=m.speed_in_per_s / self.move, turn_deg_per_s=m.turn_deg_per_s / self.move,
                         vision_s=m.vision_s * self.move, centring_s=m.centring_s * self.move)
        mv = profile.move
        move = replace(mv, seconds_per_inch=mv.seconds_per_inch * self.move,
                       seconds_per_degree=mv.seconds_per_degree * self.move, overhead_s=mv.overhead_s * self.move)
        sensing = tuple(replace(p, time_s=p.time_s * self.sense) for p in profile.sensing)
        return replace(profile, robot=replace(profile.robot, motion=motion), move=move, sensing=sensing,
                       source=f"{profile.source} (move x{self.move:g}, sense x{self.sense:g})")


@dataclass(frozen=True)
class Conditions:
    """Whose robot a comparison with the paper runs on. The paper's camera located objects
    but could not tell them apart, so in *the paper's conditions* the executive does not
    rule candidates out by their appearance (``Params.use_appearance`` off); everything
    else is as the paper ran it already (its strategies, N = 3, its costs). *Our
    defaults* add the camera's appearance. A row measured both ways shows what
    reproduces and what our additions buy (docs/results.md's two columns)."""

    name: str
    appearance: bool

    def control(self, base: Control = STRATEGIES_ON) -> Control:
        """``base`` (the strategies on, by default) in these conditions."""
        return replace(base, appearance=self.appearance)


PAPERS = Conditions("paper's conditions", appearance=False)
OURS = Conditions("our defaults", appearance=True)
BOTH = (PAPERS, OURS)

"""One job of the experiment: an episode (or a chain of episodes sharing what was
learned) run in a worker process, reported as one row per object.

A job is a frozen value (:class:`EpisodeSpec`) so it can cross to a worker process,
be deduplicated when two studies want the same run, and name its own conditions in
the CSV. The worker builds its own simulator, learner store and executive: nothing is
shared between episodes except, within a chain, the library on disk.
"""

from __future__ import annotations

import tempfile
from collections import Counter, defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

from executive.executive import Executive
from experiments.ablations import criterion
from experiments.conditions import DEFAULT_NOISE, STRATEGIES_ON, Control, CostScale, noise_config
from experiments.floor import play
from experiments.table import mean
from experiments.worker import installed_library, installed_profile
from experiments.worlds import write_floor
from executive.exit_status import HANDLED_OUTCOMES
from reporting.report import Row, Truth, match_truth, rows
from hero_driver.sim_driver import SimulatedHero
from learner.choosing.criteria import DEFAULT_CRITERION
from learner.service.local import LocalLearner
from robot_profile import RobotProfile

@dataclass(frozen=True)
class EpisodeSpec:
    """What to run: which objects, under which conditions, with which learner.

    ``episodes`` > 1 is a chain: the same learner store runs ``episodes`` floors one
    after the other (each laid out anew), so later episodes use what earlier ones
    learned. ``library`` names a seed library given to :func:`install_libraries`.
    """

    study: str = field(compare=False)  # labels only: two studies wanting the same run share it
    variant: str = field(compare=False)
    seed: int = 0
    objects: str = "test"
    criterion: str = DEFAULT_CRITERION  # a name in experiments.ablations.MEASURED
    noise: str = DEFAULT_NOISE
    noise_factor: float = 1.0
    control: Control = STRATEGIES_ON
    cost: CostScale = CostScale()
    library: str = "trained"
    episodes: int = 1

    def run(self) -> list[EpisodeRow]:
        return run_job(self)

    def floor_seed(self, episode: int) -> int:
        """The layout (and simulator) seed of the chain's ``episode``-th floor."""
        return self.seed * 1000 + episode


@dataclass(frozen=True)
class EpisodeRow:
    """One object of one episode, as the CSV keeps it (docs: one row per object)."""

    study: str
    variant: str
    criterion: str
    noise: str
    noise_factor: float
    strategies: str
    move_mult: float
    sense_mult: float
    library: str
    objects: str
    seed: int
    episode: int
    library_size: int
    object: str
    outcome: str
    grasp: str
    success: bool
    robot_s: float
    sensing_s: float
    moving_s: float
    grasping_s: float
    computing_ms: float
    tests: int  # applied to recognize it: paid sensing, grasps tried as features (records.Ledger.tests)
    sense_distance_in: float | None  # mean distance of the sensing tests paid for (None: none)
    grasps_as_features: int  # grasps tried as binary features
    wrong_grasps: int  # grasps executed at a leaf that failed (a misclassification)
    recoveries: str = field(default="-")
    failed_features: int = 0  # grasps tried as binary features that failed
    knocked_over: bool = False  # the simulator's truth: it ended the episode in another pose (a grasp tipped it)

    @property
    def misclassified(self) -> bool:
        """The lenient reading: a grasp executed at a leaf failed, or not handled."""
        return self.wrong_grasps > 0 or not self.success

    @property
    def misclassified_strict(self) -> bool:
        """The strict reading: any grasp failed, at a leaf or tried as a feature, or the
        object was knocked over, or not handled (what a person watching would call a
        mistake)."""
        return self.misclassified or self.failed_features > 0 or self.knocked_over

    @staticmethod
    def columns() -> list[str]:
        return [f.name for f in fields(EpisodeRow)]


Results = Mapping[EpisodeSpec, Sequence[EpisodeRow]]  # every job's rows, as a study's summary reads them


def success_rate(rows: Iterable[EpisodeRow]) -> float:
    """The share of the objects grasped."""
    return mean(float(r.success) for r in rows)


def robot_minutes(rows: Iterable[EpisodeRow]) -> float:
    """Robot minutes per object."""
    return mean(r.robot_s for r in rows) / 60.0


def run_job(spec: EpisodeSpec) -> list[EpisodeRow]:
    """Run ``spec`` here (in a worker process) and return its rows, object by object."""
    profile = spec.cost.apply(installed_profile())
    seed_library = installed_library(spec.library)
    out: list[EpisodeRow] = []
    with tempfile.TemporaryDirectory(prefix="csl-experiment-") as tmp:
        folder = Path(tmp)
        learner = LocalLearner(folder / "library.sqlite", seed_library=list(seed_library))
        try:
            for episode in range(spec.episodes):
                out += _episode(spec, episode, profile, learner, folder)
        finally:
            learner.close()
    return out




def _episode(spec: EpisodeSpec, episode: int, profile: RobotProfile, learner: LocalLearner,
             folder: Path) -> list[EpisodeRow]:
    """One floor: run the executive to the end and report every object on it, those the
    robot never found included (as failures: the paper's success counts them)."""
    world = write_floor(folder, spec.objects, spec.floor_seed(episode))
    hero = SimulatedHero("experiment", world=world, seed=spec.floor_seed(episode), profile=profile,
                         noise=noise_config(spec.noise, spec.noise_factor))
    size = len(learner.library().descriptions)
    executive = Executive(hero, learner, profile=profile, params=spec.control.params(),
                          criterion=criterion(spec.criterion))
    played = play(hero, executive)
    result, truths = played.result, played.truths()
    stats = _object_stats(executive.log.events)

    def row(name: str, outcome: str, grasp: str, success: bool, robot: tuple[float, float, float],
            computing_ms: float = 0.0, tests: int = 0, indices: Sequence[int] = (), recoveries: str = "-",
            knocked: bool = False) -> EpisodeRow:
        folded = [stats.get(i, ([], 0, 0, 0)) for i in indices]
        distances = [d for ds, _, _, _ in folded for d in ds]
        as_features, wrong, failed = (sum(f[k] for f in folded) for k in (1, 2, 3))
        moving, sensing, grasping = robot
        return EpisodeRow(
            spec.study, spec.variant, spec.criterion, spec.noise, spec.noise_factor, spec.control.label,
            spec.cost.move, spec.cost.sense, spec.library, spec.objects, spec.seed, episode, size, name, outcome,
            grasp, success, round(moving + sensing + grasping, 2), round(sensing, 2), round(moving, 2),
            round(grasping, 2), round(computing_ms, 1), tests,
            round(sum(distances) / len(distances), 2) if distances else None, as_features, wrong, recoveries,
            failed, knocked)

    tipped = {id(t) for t, before, after in zip(truths, played.start, played.now) if before.entry_id != after.entry_id}
    matched = [(match_truth(record, truths), r) for record, r in zip(result.objects, rows(result.objects, truths))]
    found = {id(t) for t, _ in matched}
    knocked = {r.index for t, r in matched if id(t) in tipped}
    out = [row(r.object, r.outcome, r.grasp, bool(r.correct), (r.moving_s, r.sensing_s, r.grasping_s),
               r.computing_ms, r.tests, indices, r.recoveries, any(i in knocked for i in indices))
           for r, indices in one_row_per_object(matched)]
    out += [row(t.name, "not found", "-", False, (0.0, 0.0, 0.0), knocked=id(t) in tipped)
            for t in truths if id(t) not in found]
    return out


def one_row_per_object(matched: Sequence[tuple[Truth | None, Row]]) -> list[tuple[Row, tuple[int, ...]]]:
    """One row per true object, whatever the robot's records of it.

    The robot may record one object twice (seen again after it was knocked over and
    rolled, or its region split): each record is matched to the nearest true object, so
    two records can name the same one, and the CSV must still hold one row per object on
    the floor. The robot time, computation, tests and recoveries of all its records add
    up (the robot spent them on this object); the verdict is the last record's that
    handled it (grasped or left), else the last record's. Records matched to no truth
    (no simulator) stay rows of their own. Returns each row with the record indices it
    folds, in the order the objects were first seen.
    """
    groups: dict[int, list[Row]] = {}
    for truth, r in matched:
        groups.setdefault(id(truth) if truth is not None else -1 - r.index, []).append(r)
    out = []
    for records in groups.values():
        handled = [r for r in records if r.outcome in HANDLED_OUTCOMES]
        verdict = (handled or records)[-1]
        counts: Counter[str] = Counter()
        for r in records:
            counts.update(dict(r.recovery_counts))
        kinds = tuple(sorted(counts.items()))
        out.append((replace(verdict, moving_s=sum(r.moving_s for r in records),
                            sensing_s=sum(r.sensing_s for r in records),
                            grasping_s=sum(r.grasping_s for r in records),
                            computing_ms=sum(r.computing_ms for r in records), tests=sum(r.tests for r in records),
                            recoveries=", ".join(f"{k} ×{v}" for k, v in kinds) or "-", recovery_counts=kinds),
                    tuple(r.index for r in records)))
    return out


def _object_stats(events: Sequence[Mapping[str, object]]) -> dict[int, tuple[list[float], int, int, int]]:
    """Per object index: the distance of each paid sensing test (the position of the
    latest ``choose`` before its ``sense``), grasps tried as features, grasps executed
    at a leaf that failed, and grasps tried as features that failed, read from the
    episode's events in one pass."""
    chosen_at: dict[int, float] = {}
    distances: dict[int, list[float]] = defaultdict(list)
    as_features: dict[int, int] = defaultdict(int)
    wrong: dict[int, int] = defaultdict(int)
    failed: dict[int, int] = defaultdict(int)
    for event in events:
        index = event.get("object")
        if not isinstance(index, int):
            continue
        kind = event.get("event")
        if kind == "choose":
            where = event.get("at")
            if isinstance(where, list) and where and isinstance(where[0], (int, float)):
                chosen_at[index] = float(where[0])
        elif kind == "sense" and index in chosen_at:
            distances[index].append(chosen_at[index])
        elif kind == "grasp":
            if event.get("as_feature"):
                as_features[index] += 1
                failed[index] += event.get("success") is False
            elif event.get("success") is False:
                wrong[index] += 1
    return {i: (distances[i], as_features[i], wrong[i], failed[i])
            for i in set(distances) | set(as_features) | set(wrong)}

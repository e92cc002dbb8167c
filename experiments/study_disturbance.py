"""Study: disturbances — success and cost against the disturbance rate, with the
camera check before sensing and grasping on and off.

Beyond the paper: CSL "can not handle ... the disappearance of an object during
sensing". Each floor of unseen test objects runs under the simulator's ``--disturb``
preset at rate r: every object, when first sensed, is nudged with probability r/2,
swapped for another object with r/4 and taken away with r/4 (docs/simulator.md,
"Disturbances"). The same floors and seeds run with the check on and off, the
camera's appearance off: with it most objects are grasped without the sonar ever
measuring them (tests per object: docs/results.md), so a disturbance, which happens at
an object's first sensing, would come to few of them and the sweep would hardly
exercise the check (BENCHMARKS.md, "Disturbances").

Measured per rate and setting: the success rate over the objects still on the floor
at the end (a removed object cannot be retrieved by anyone; with the check off the
executive does not know it is gone and fails it), robot minutes per object, objects
reported gone, and descriptions saved from disturbed attempts (ground truth:
:mod:`experiments.disturbed`), which must be 0 with the check on.

Run: ``csl experiment disturbance [--quick] [--seeds N] [--jobs J]``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from behaviours.services import Params
from experiments.floor import play_floor
from experiments.disturbed import saved_from_disturbed, sim_index
from experiments.config import ExperimentConfig
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, mean, num, percent
from experiments.worlds import write_floor
from hero_driver.sim.events import DisturbPreset

TITLE = "Disturbances: success and cost vs the disturbance rate, camera check on and off"
QUICK_RATES = (0.0, 0.3, 0.6)
FULL_RATES = (0.0, 0.1, 0.2, 0.4, 0.6, 0.8)

def preset(rate: float) -> DisturbPreset:
    """The mix at rate ``rate``: half nudges, a quarter swaps, a quarter removals."""
    return DisturbPreset((("nudge", rate / 2), ("replace", rate / 4), ("remove", rate / 4)))


@dataclass(frozen=True)
class DisturbanceJob:
    """One floor (``seed``) at disturbance rate ``rate`` with the check on or off."""

    rate: float
    check: bool
    seed: int
    study: str = field(default="disturbance", compare=False)

    def run(self) -> list[ObjectRow]:
        return run_job(self)


@dataclass(frozen=True)
class ObjectRow:
    """One object of one episode."""

    rate: float
    check: bool
    seed: int
    object: str
    outcome: str
    correct: bool
    removed: bool  # taken away by the simulator (ground truth)
    disturbed: bool  # nudged, swapped or removed (ground truth)
    robot_s: float
    saved_disturbed: bool  # its description was saved from a disturbed attempt


def run_job(job: DisturbanceJob) -> list[ObjectRow]:
    """Run one floor here (in a worker process) and report it object by object."""
    played = play_floor(lambda folder: write_floor(folder, "test", job.seed), job.seed,
                        Params(check_in_place=job.check, use_appearance=False), disturb=preset(job.rate))
    start, happened = played.start, played.disturbances
    removed = {h.object for h in happened if h.do == "remove"}
    disturbed = {h.object for h in happened}
    saved = {r.index for r in played.result.objects if saved_from_disturbed([r], played.events, happened, start)}
    out = []
    for record, row in played.rows():
        index = sim_index(record, start)
        out.append(ObjectRow(job.rate, job.check, job.seed, row.object, row.outcome, bool(row.correct),
                             index in removed, index in disturbed, round(row.robot_s, 1), record.index in saved))
    return out


def plan(rates: Sequence[float], seeds: Sequence[int]) -> list[DisturbanceJob]:
    return [DisturbanceJob(r, c, s) for r in rates for c in (True, False) for s in seeds]


@dataclass(frozen=True)
class Cell:
    """One rate and setting, over its seeds."""

    success: float  # over the objects still on the floor
    minutes: float  # robot minutes per object
    gone: int  # objects reported gone
    removed: int  # objects taken away
    saved_disturbed: int
    objects: int


def cell(found: Sequence[ObjectRow]) -> Cell:
    present = [r for r in found if not r.removed]
    return Cell(mean(float(r.correct) for r in present), mean(r.robot_s for r in found) / 60.0,
                sum(r.outcome == "gone" for r in found), sum(r.removed for r in found),
                sum(r.saved_disturbed for r in found), len(found))


def summarise(results: Mapping[DisturbanceJob, Sequence[ObjectRow]], rates: Sequence[float]) -> StudyResult:
    cells = {(r, c): cell([row for job, found in results.items() if job.rate == r and job.check == c
                           for row in found]) for r in rates for c in (True, False)}
    table = tuple(
        (f"{r:g}", *(f"{percent(cells[(r, c)].success)}, {num(cells[(r, c)].minutes)} min, "
                     f"{cells[(r, c)].gone}/{cells[(r, c)].removed} gone, {cells[(r, c)].saved_disturbed} bad"
                     for c in (True, False)))
        for r in rates)
    on = sum(c.saved_disturbed for (_, check), c in cells.items() if check)
    off = sum(c.saved_disturbed for (_, check), c in cells.items() if not check)
    top = max(rates)
    result_rows = (
        ResultRow("descriptions saved from disturbed attempts, check on (must be 0)", "-", str(on)),
        ResultRow("descriptions saved from disturbed attempts, check off", "-", str(off)),
        ResultRow(f"success at rate {top:g}: check on / off", "not handled",
                  f"{percent(cells[(top, True)].success)} / {percent(cells[(top, False)].success)}"),
        ResultRow(f"robot min per object at rate {top:g}: check on / off", "-",
                  f"{num(cells[(top, True)].minutes)} / {num(cells[(top, False)].minutes)}"),
    )
    notes = ("Each cell: success over the objects still on the floor, robot minutes per object, objects "
             "reported gone / taken away, descriptions saved from disturbed attempts ('bad').",)
    return StudyResult(TITLE, result_rows, notes,
                       details=((("rate", "check on", "check off"), table),))



def rates(config: ExperimentConfig) -> tuple[float, ...]:
    return QUICK_RATES if config.quick else FULL_RATES


STUDY = Study("disturbance", lambda config: plan(rates(config), config.seed_list),
              lambda context, results: summarise(results, rates(context.config)), floors=(2, 6))
"""Every rate with the check on and off (``csl experiment disturbance``)."""

"""Study: moving obstacles — success, cost and contacts against the number and speed of
people and carts crossing the floor, with the driver's safety stop and the executive's
blocked-move branch on and off.

Beyond the paper: CSL "can not handle ... moving obstacles". Each floor of unseen test
objects runs under the simulator's ``--movers N:SPEED`` preset: N movers (people and
carts in turn) crossing the room wall to wall on lines drawn from the floor's seed
(docs/simulator.md, "Moving obstacles"). The same floors and seeds run twice:

- **on**: the simulator's ``blocked_moves`` feature stops a move short of a mover ahead
  and the executive's branch looks again, re-plans around it or waits, and gives the
  object up after ``Params.blocked_tries`` rounds (``behaviours.blocked``);
- **off**: a driver that ignores movers (the base drives into them; the bumper stops
  it, as against any obstacle) and the branch off: a move that met a mover fails as
  a collision did before.

Measured per setting: the success rate, robot minutes per object, contacts between the
base and anything (ground truth; must be 0 with the stop on), blocked moves and
objects given up by the branch.

Run: ``csl experiment obstacles [--quick] [--seeds N] [--jobs J]``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from behaviours.services import Params
from experiments.floor import play_floor
from experiments.config import ExperimentConfig
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, mean, num, percent
from experiments.worlds import write_floor
from hero_driver.sim.movers import MoverPreset

TITLE = "Moving obstacles: success, cost and contacts vs movers, safety stop and branch on and off"
QUICK_SWEEP = ((0, 12.0), (3, 12.0))
FULL_SWEEP = ((0, 12.0), (2, 12.0), (4, 12.0), (6, 12.0), (4, 6.0), (4, 24.0))

@dataclass(frozen=True)
class ObstaclesJob:
    """One floor (``seed``) with ``movers`` movers at ``speed`` in/s, the stop and branch ``on`` or off."""

    movers: int
    speed: float
    on: bool
    seed: int
    study: str = field(default="obstacles", compare=False)

    def run(self) -> Floor:
        return run_job(self)


@dataclass(frozen=True)
class Floor:
    """One episode: its objects' outcomes and robot seconds, and what the movers did."""

    correct: tuple[bool, ...]
    robot_s: tuple[float, ...]
    contacts: int
    blocked_moves: int
    given_up: int  # objects the blocked-move branch gave up


def run_job(job: ObstaclesJob) -> Floor:
    """Run one floor here (in a worker process)."""
    played = play_floor(lambda folder: write_floor(folder, "test", job.seed), job.seed,
                        Params() if job.on else Params(blocked_tries=0),
                        movers=MoverPreset(job.movers, job.speed), stop_for_movers=job.on)
    found = [row for _, row in played.rows()]
    events = played.events
    return Floor(tuple(bool(r.correct) for r in found), tuple(round(r.robot_s, 1) for r in found), played.contacts,
                 sum(1 for e in events if e["event"] == "move" and "blocked" in e),
                 sum(1 for e in events if e["event"] == "gave_up" and e.get("behaviour") == "Blocked?"))


def plan(sweep: Sequence[tuple[int, float]], seeds: Sequence[int]) -> list[ObstaclesJob]:
    return [ObstaclesJob(n, v, on, s) for n, v in sweep for on in (True, False) for s in seeds]


@dataclass(frozen=True)
class Cell:
    """One sweep point and setting, over its seeds."""

    success: float
    minutes: float  # robot minutes per object
    contacts: int
    blocked: int
    given_up: int


def cell(floors: Sequence[Floor]) -> Cell:
    return Cell(mean(float(c) for f in floors for c in f.correct), mean(s for f in floors for s in f.robot_s) / 60.0,
                sum(f.contacts for f in floors), sum(f.blocked_moves for f in floors),
                sum(f.given_up for f in floors))


def summarise(results: Mapping[ObstaclesJob, Floor], sweep: Sequence[tuple[int, float]]) -> StudyResult:
    cells = {(n, v, on): cell([f for job, f in results.items() if (job.movers, job.speed, job.on) == (n, v, on)])
             for n, v in sweep for on in (True, False)}

    def show(c: Cell, on: bool) -> str:
        extra = f", {c.blocked} blocked, {c.given_up} given up" if on else ""
        return f"{percent(c.success)}, {num(c.minutes)} min, {c.contacts} contacts{extra}"

    table = tuple((str(n), f"{v:g}", show(cells[(n, v, True)], True), show(cells[(n, v, False)], False))
                  for n, v in sweep)
    busiest = max(sweep)
    on = sum(c.contacts for (_, _, setting), c in cells.items() if setting)
    off = sum(c.contacts for (_, _, setting), c in cells.items() if not setting)
    result_rows = (
        ResultRow("contacts with anything, stop and branch on (must be 0)", "-", str(on)),
        ResultRow("contacts with anything, stop and branch off", "-", str(off)),
        ResultRow(f"success with {busiest[0]} movers at {busiest[1]:g} in/s: on / off", "not handled",
                  f"{percent(cells[(*busiest, True)].success)} / {percent(cells[(*busiest, False)].success)}"),
        ResultRow(f"robot min per object with {busiest[0]} movers at {busiest[1]:g} in/s: on / off", "-",
                  f"{num(cells[(*busiest, True)].minutes)} / {num(cells[(*busiest, False)].minutes)}"),
    )
    notes = ("Each cell: success over the floor's objects, robot minutes per object, contacts between the base and "
             "anything over the floors (walls, furniture and objects included), and with the branch on the moves "
             "a mover blocked and the objects the branch gave up.",)
    return StudyResult(TITLE, result_rows, notes,
                       details=((("movers", "speed in/s", "stop and branch on", "off"), table),))


def sweep(config: ExperimentConfig) -> tuple[tuple[int, float], ...]:
    return QUICK_SWEEP if config.quick else FULL_SWEEP


STUDY = Study("obstacles", lambda config: plan(sweep(config), config.seed_list),
              lambda context, results: summarise(results, sweep(context.config)), floors=(2, 6))
"""Every sweep point with the stop and branch on and off (``csl experiment obstacles``)."""

"""Per-object results as a table a person reads, with the simulator's truth when known."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from behaviours.records import ObjectRecord
from executive.exit_status import HANDLED_OUTCOMES


@dataclass(frozen=True)
class Truth:
    """What the object really was (only a simulator knows)."""

    name: str
    grasps: tuple[str, ...]
    x_in: float
    y_in: float


@dataclass(frozen=True)
class Row:
    object: str
    grasp: str
    outcome: str
    correct: bool | None
    moving_s: float
    sensing_s: float
    grasping_s: float
    computing_ms: float
    tests: int
    recoveries: str

    @property
    def robot_s(self) -> float:
        return self.moving_s + self.sensing_s + self.grasping_s


def match_truth(record: ObjectRecord, truths: Sequence[Truth]) -> Truth | None:
    """The true object nearest the region where the object was first seen."""
    if not truths:
        return None
    x, y = (record.first_region or record.region).centroid
    return min(truths, key=lambda t: math.hypot(t.x_in - x, t.y_in - y))


def rows(records: Sequence[ObjectRecord], truths: Sequence[Truth] = ()) -> list[Row]:
    out = []
    for r in records:
        truth = match_truth(r, truths)
        seen = (r.first_region or r.region).centroid
        name = truth.name if truth else f"object {r.index} at ({seen[0]:.0f}, {seen[1]:.0f})"
        correct = None
        if truth is not None and r.outcome in HANDLED_OUTCOMES:
            correct = (r.grasp in truth.grasps) if r.outcome == "grasped" else ("No-Grab" in truth.grasps)
        elif truth is not None:
            correct = False
        recov = ", ".join(f"{k} ×{v}" for k, v in sorted(r.ledger.recoveries.items())) or "-"
        out.append(Row(name, r.grasp or "-", r.outcome or "unfinished", correct, r.ledger.moving_s,
                       r.ledger.sensing_s, r.ledger.grasping_s, r.ledger.computing_s * 1000.0,
                       len(r.ledger.tests), recov))
    return out


HEADERS = ["object", "grasp", "outcome", "ok", "cost s", "min", "cpu ms", "tests", "recoveries"]
CAPTION = ("cost s: robot seconds moving/sensing/grasping; min: robot minutes in all; "
           "cpu ms: learner + planner computation")


def table_cells(row: Row) -> list[str]:
    ok = {True: "yes", False: "NO", None: "?"}[row.correct]
    cost = f"{row.moving_s:.0f}/{row.sensing_s:.0f}/{row.grasping_s:.0f}"
    return [row.object, row.grasp, row.outcome, ok, cost, f"{row.robot_s / 60:.1f}", f"{row.computing_ms:.0f}",
            str(row.tests), row.recoveries]


def summary(table: Sequence[Row]) -> str:
    judged = [r for r in table if r.correct is not None]
    ok = sum(bool(r.correct) for r in judged)
    mean_min = sum(r.robot_s for r in table) / max(len(table), 1) / 60
    mean_ms = sum(r.computing_ms for r in table) / max(len(table), 1)
    rate = f"{ok}/{len(judged)} handled correctly ({100 * ok / len(judged):.0f}%)" if judged else "no truth to judge by"
    return (f"{len(table)} objects: {rate}; {mean_min:.1f} robot minutes and "
            f"{mean_ms:.0f} ms of computation per object (paper: ~12 min, ~20 s)")

"""Per-object results as a table a person reads (and a JSON document a script reads),
with the simulator's truth when known."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from behaviours.records import ObjectRecord
from executive.exit_status import HANDLED_OUTCOMES
from reporting.tables import Column, print_paragraph, print_table


@dataclass(frozen=True)
class Truth:
    """What the object really was (only a simulator knows)."""

    name: str
    grasps: tuple[str, ...]
    x_in: float
    y_in: float
    ended_as: str | None = None  # the entry it became when knocked over or turned (None: unchanged)


@dataclass(frozen=True)
class Row:
    object: str  # the object as the robot found it
    grasp: str
    outcome: str
    correct: bool | None
    moving_s: float
    sensing_s: float
    grasping_s: float
    computing_ms: float
    tests: int
    recoveries: str
    index: int  # the object's number in the episode (``csl log --object N``)
    recovery_counts: tuple[tuple[str, int], ...]  # ``recoveries`` by kind, for --json
    ended_as: str | None = None  # what it became during the episode (knocked over), when it changed

    @property
    def robot_s(self) -> float:
        return self.moving_s + self.sensing_s + self.grasping_s


def match_truth(record: ObjectRecord, truths: Sequence[Truth]) -> Truth | None:
    """The true object nearest the region where the object was first seen."""
    if not truths:
        return None
    x, y = (record.first_region or record.region).centroid
    return min(truths, key=lambda t: math.hypot(t.x_in - x, t.y_in - y))


FOUND_WITHIN_IN = 12.0
"""A record first seen this near the true object it is matched to found it: more than an
object's size (the largest is 11 in) away, it located something else."""


def found_truth(record: ObjectRecord, truths: Sequence[Truth]) -> Truth | None:
    """The true object ``record`` found: the one it is matched to (:func:`match_truth`),
    when it was first seen within :data:`FOUND_WITHIN_IN` of it; else None."""
    truth = match_truth(record, truths)
    if truth is None:
        return None
    x, y = (record.first_region or record.region).centroid
    return truth if math.hypot(truth.x_in - x, truth.y_in - y) <= FOUND_WITHIN_IN else None


def rows(records: Sequence[ObjectRecord], truths: Sequence[Truth] = ()) -> list[Row]:
    out = []
    for r in records:
        truth = match_truth(r, truths)
        seen = (r.first_region or r.region).centroid
        name = truth.name if truth else f"object {r.index} at ({seen[0]:.0f}, {seen[1]:.0f})"
        correct = None
        if truth is not None and r.outcome in HANDLED_OUTCOMES:
            correct = (r.grasp in truth.grasps) if r.outcome == "grasped" else ("No-Grab" in truth.grasps)
        elif truth is not None and r.outcome != "gone":  # taken away: nothing left to judge
            correct = False
        counts = tuple(sorted(r.ledger.recoveries.items()))
        recov = ", ".join(f"{k} ×{v}" for k, v in counts) or "-"
        out.append(Row(name, r.grasp or "-", r.outcome or "unfinished", correct, r.ledger.moving_s,
                       r.ledger.sensing_s, r.ledger.grasping_s, r.ledger.computing_s * 1000.0,
                       len(r.ledger.tests), recov, r.index, counts, truth.ended_as if truth else None))
    return out


TITLE = "approach and recognize: one row per object"
COLUMNS = (Column("#", numeric=True), Column("object", fold=True), Column("grasp"), Column("outcome"),
           Column("ok"), Column("min", numeric=True), Column("ms", numeric=True),
           Column("tests", numeric=True))
"""Fits 80 columns with the longest catalogue name: the seconds moving, sensing and
grasping go to the summary (per object in ``--json``), the recoveries below the table."""
CAPTION = ("min: robot minutes moving, sensing, grasping; ms: learner + planner computation\n"
           "tests: sensing procedures applied, grasps tried as features (not a leaf's grasp)")
"""Each line within 80 columns. ``tests`` is :attr:`behaviours.records.Ledger.tests`."""


def table_cells(row: Row) -> list[str]:
    ok = "-" if row.outcome == "gone" else {True: "yes", False: "NO", None: "?"}[row.correct]
    return [str(row.index), row.object + ("*" if row.ended_as else ""), row.grasp, row.outcome, ok, f"{row.robot_s / 60:.1f}",
            f"{row.computing_ms:.0f}", str(row.tests)]


def recovery_lines(table: Sequence[Row]) -> list[str]:
    """One line per object that needed a recovery, by its number in the table."""
    return [f"  {r.index} {r.object}" + (f" (ended as {r.ended_as})" if r.ended_as else "") + f": {r.recoveries}"
            for r in table if r.recovery_counts or r.ended_as]


def print_report(table: Sequence[Row]) -> None:
    """The per-object table, its recoveries and the summary, on standard output."""
    changed = "; *: it changed during the episode (knocked over: below)" if any(r.ended_as for r in table) else ""
    print_table(COLUMNS, [table_cells(r) for r in table], title=TITLE, caption=CAPTION + changed)
    lines = recovery_lines(table)
    if lines:
        print("recoveries:")
        for line in lines:
            print_paragraph(line, indent=4)
    print_paragraph(summary(table))
    print_paragraph(time_split(table))


def _totals(table: Sequence[Row]) -> tuple[int, int, float, float]:
    """Objects judged against the truth, those handled correctly, and the mean robot
    seconds and computing milliseconds per object."""
    judged = [r for r in table if r.correct is not None]
    n = max(len(table), 1)
    return (len(judged), sum(bool(r.correct) for r in judged), sum(r.robot_s for r in table) / n,
            sum(r.computing_ms for r in table) / n)


def summary(table: Sequence[Row]) -> str:
    judged, ok, mean_s, mean_ms = _totals(table)
    gone = sum(r.outcome == "gone" for r in table)
    rate = (f"{ok}/{judged} handled correctly ({100 * ok / judged:.0f}%)" if judged
            else "none left to judge" if gone else "no truth to judge by")
    rate += f", {gone} taken away" if gone else ""
    return (f"{len(table)} objects: {rate}; {mean_s / 60:.1f} robot minutes and "
            f"{mean_ms:.0f} ms of computation per object (paper: ~12 min, ~20 s)")


def time_split(table: Sequence[Row]) -> str:
    """Where the robot's time went, over the whole episode."""
    moving, sensing, grasping = (sum(getattr(r, f) for r in table) / 60
                                 for f in ("moving_s", "sensing_s", "grasping_s"))
    return (f"robot time: {moving + sensing + grasping:.1f} min in all, {moving:.1f} moving, "
            f"{sensing:.1f} sensing, {grasping:.1f} grasping")


def row_json(row: Row) -> dict[str, object]:
    """One object for ``--json``: seconds unrounded, recoveries by kind."""
    return {"index": row.index, "object": row.object, "ended_as": row.ended_as, "grasp": None if row.grasp == "-" else row.grasp,
            "outcome": row.outcome, "correct": row.correct, "robot_s": row.robot_s, "moving_s": row.moving_s,
            "sensing_s": row.sensing_s, "grasping_s": row.grasping_s, "computing_ms": row.computing_ms,
            "tests": row.tests, "recoveries": dict(row.recovery_counts)}


def summary_json(table: Sequence[Row]) -> dict[str, object]:
    """The summary line's numbers for ``--json``."""
    judged, ok, mean_s, mean_ms = _totals(table)
    return {"objects": len(table), "judged": judged, "correct": ok, "mean_robot_s": mean_s,
            "mean_computing_ms": mean_ms}


def episode_json(table: Sequence[Row], *, ticks: int, wall_s: float, out: Path, plots: bool, library: Path | None,
                 library_created: bool, status: int, why: str) -> dict[str, object]:
    """``csl demo/run --json``: everything the human report says, as one document."""
    drawn = ([out / "map.png", *(out / f"tree-{r.index}.png" for r in table), out / "behaviour-tree.png"]
             if plots else [])
    return {"objects": [row_json(r) for r in table], "summary": summary_json(table),
            "episode": {"ticks": ticks, "wall_s": wall_s, "log": str(out / "episode.jsonl")},
            "plots": [str(p) for p in drawn], "library": None if library is None else str(library),
            "library_created": library_created, "exit_status": status, "why": why}

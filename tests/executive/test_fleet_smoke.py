"""The fleet benchmark's accounting, on a small fleet of real processes and by hand.

``bench/bench_fleet.py`` runs a router, a learner service, simulated drivers and
executives as separate processes. Here two robots run one episode each through it, and
the test re-derives from the files it left (each episode's JSON report and log, the
SQLite library read through ``learner.library.store``) that every object located came out
handled or failed and that the library gained exactly one row per learned description.
The accounting itself is checked on hand-made cases, so a bench that stopped counting
lost or duplicated rows would fail here too.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from executive import defaults
from learner.library.format import read_library_json
from learner.library.store import load_library

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "bench" / "bench_fleet.py"


def _bench():  # noqa: ANN202 - a script, loaded by path: bench/ is not a package
    spec = importlib.util.spec_from_file_location("bench_fleet", BENCH)
    module = importlib.util.module_from_spec(spec)
    sys.modules["bench_fleet"] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


fleet = _bench()


def _episode(robot: str, ids: tuple[str, ...]):  # noqa: ANN202
    return fleet.Episode(robot, 0, 0, 0, 1.0, len(ids), len(ids), ("grasped",) * len(ids), ids, 0, 0, ())


def _row(id_: str, value: float) -> dict:
    return {"id": id_, "grasp": "Top-Pinch", "grasp_position": [6, "*"],
            "features": [{"feature": "Height", "position": [6, "*"], "value": value}]}


SEED = [_row("seed", 1.0)]


def test_accounting_holds_when_each_learned_id_is_one_new_row() -> None:
    books = fleet.account([_episode("r1", ("a",)), _episode("r2", ("a#2",))], SEED,
                          [*SEED, _row("a", 2.0), _row("a#2", 3.0)])
    assert (books.learned, books.stored, books.holds) == (2, 2, True)


def test_accounting_finds_lost_unclaimed_and_twice_claimed_rows() -> None:
    lost = fleet.account([_episode("r1", ("a", "b"))], SEED, [*SEED, _row("a", 2.0)])
    assert (lost.lost, lost.holds) == (("b",), False)
    # A retried learn stored twice: the client was told one id, the library holds two rows.
    retried = fleet.account([_episode("r1", ("a",))], SEED, [*SEED, _row("a", 2.0), _row("a#2", 2.0)])
    assert (retried.unclaimed, retried.identical, retried.holds) == (("a#2",), 1, False)
    twice = fleet.account([_episode("r1", ("a",)), _episode("r2", ("a",))], SEED, [*SEED, _row("a", 2.0)])
    assert (twice.claimed_twice, twice.holds) == (("a",), False)
    # The same object met twice and measured alike: two learns, two rows, nothing lost.
    again = fleet.account([_episode("r1", ("a",)), _episode("r2", ("a#2",))], SEED,
                          [*SEED, _row("a", 2.0), _row("a#2", 2.0)])
    assert (again.identical, again.holds) == (1, True)
    queued = fleet.account([_episode("r1", ("queued:k1",))], SEED, SEED)
    assert (queued.queued, queued.holds) == (1, False)


def test_percentiles_are_nearest_rank() -> None:
    values = list(range(1, 101))  # 1..100: the p-th percentile is p itself
    assert (fleet.percentile(values, 50), fleet.percentile(values, 99)) == (50, 99)
    assert fleet.percentile([7.0], 99) == 7.0
    assert fleet.percentile([], 50) is None


@pytest.mark.zenoh
@pytest.mark.slow
def test_two_robots_through_one_router_lose_and_duplicate_nothing(tmp_path: Path) -> None:
    out = tmp_path / "fleet"
    bench = subprocess.run([sys.executable, str(BENCH), "--robots", "2", "--episodes", "1", "--minutes", "1",
                            "--out", str(out)], capture_output=True, text=True, timeout=120, check=False)
    assert bench.returncode == 0, bench.stdout + bench.stderr

    learned: list[str] = []
    for robot in ("r1", "r2"):
        episode = out / robot / "ep0000"
        report = json.loads((episode / "run.json").read_text())
        events = [json.loads(line) for line in (episode / "episode.jsonl").read_text().splitlines()]
        located = next(len(e["regions"]) for e in events if e["event"] == "located")
        outcomes = [o["outcome"] for o in report["objects"]]
        assert located == len(outcomes) == 7  # the lab's seven, each reported
        assert set(outcomes) <= {"grasped", "left", "failed"}
        learns = [e for e in events if e["event"] == "learn"]
        # One learn event per grasped object; a grasp needing no test stores nothing.
        assert sorted(e["object"] for e in learns) == [o["index"] for o in report["objects"]
                                                        if o["outcome"] == "grasped"]
        learned += [e["id"] for e in learns if e["id"] is not None]

    assert learned and not any(i.startswith("queued:") for i in learned)
    seed_ids = {d.object_id for d in read_library_json(defaults.EXAMPLE_LIBRARY)}
    stored = [d for d in load_library(out / "library.sqlite") if d.object_id not in seed_ids]
    assert Counter(d.object_id for d in stored) == Counter(learned)  # none lost, none twice
    figures = json.loads((out / "fleet.json").read_text())
    assert figures["accounting"]["stored"] == len(stored)
    assert figures["node_exit_statuses"] == {"driver-r2": 0, "driver-r1": 0, "learner": 0, "router": 0}


def test_an_episode_that_left_no_report_leaves_every_object_unaccounted(tmp_path: Path) -> None:
    # A csl run that died at start (seen: a module mid-edit raised SyntaxError) wrote
    # neither log nor report: its seven objects were never attempted.
    episode = fleet._read_episode("r1", 0, 0, tmp_path, 1, 1.0, "", "", "SyntaxError: unterminated string")
    assert fleet.PLACED == 7  # the lab's objects
    assert (episode.located, episode.outcomes, episode.unaccounted) == (None, (), 7)
    assert episode.error == "no JSON report: SyntaxError: unterminated string"

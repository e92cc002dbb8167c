"""The moving-obstacles study's arithmetic (experiments.study_obstacles) on
hand-made floors, and one real floor run in this process."""

from __future__ import annotations

import pytest

from executive import defaults
from experiments.worker import install_worker
from experiments.study_obstacles import Floor, ObstaclesJob, cell, plan, run_job, summarise
from learner.library.format import read_library_json
from robot_profile import load_profile


def test_the_plan_runs_every_point_on_and_off_on_the_same_seeds() -> None:
    jobs = plan([(0, 12.0), (3, 6.0)], [0, 1])
    assert len(jobs) == 8 and ObstaclesJob(3, 6.0, False, 1) in jobs and ObstaclesJob(0, 12.0, True, 0) in jobs


def test_a_cell_pools_the_objects_of_its_floors() -> None:
    floors = [Floor((True, False), (60.0, 180.0), 0, 3, 1), Floor((True, True, True, False), (120.0,) * 4, 2, 5, 0)]
    c = cell(floors)
    # 4 of 6 objects right; (60 + 180 + 4 x 120) / 6 = 120 s = 2 min
    assert c.success == pytest.approx(4 / 6) and c.minutes == pytest.approx(2.0)
    assert (c.contacts, c.blocked, c.given_up) == (2, 8, 1)


def test_the_summary_names_contacts_on_and_off_and_the_busiest_point() -> None:
    sweep = [(0, 12.0), (2, 12.0)]
    results = {ObstaclesJob(n, v, on, 0): Floor((on or n == 0, True), (60.0, 60.0), 0 if on else n, n if on else 0, 0)
               for n, v in sweep for on in (True, False)}
    study = summarise(results, sweep)
    assert study.rows[0].ours == "0" and study.rows[1].ours == "2"
    assert study.rows[2].measured == "success with 2 movers at 12 in/s: on / off"
    assert study.rows[2].ours == "100% / 50%"
    (_, table), = study.details
    assert table[1][:2] == ("2", "12") and "2 blocked, 0 given up" in table[1][2] and "2 contacts" in table[1][3]


@pytest.mark.slow
def test_one_floor_with_movers_runs_with_no_contact_when_on() -> None:
    install_worker({"trained": read_library_json(defaults.EXAMPLE_LIBRARY)}, load_profile())
    floor = run_job(ObstaclesJob(2, 12.0, True, 0))
    assert floor.contacts == 0 and len(floor.correct) == len(floor.robot_s) > 0

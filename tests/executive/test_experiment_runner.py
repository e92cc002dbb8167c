"""The experiment's job runner: parallel workers, results in the jobs' order."""

from __future__ import annotations

import time

from experiments.runner import run_all


def slow_square(n: int) -> int:
    """A job that takes longer the larger ``n``: finishing order is the reverse of size."""
    time.sleep(0.2 * n)
    return n * n


def test_results_come_in_the_jobs_order_not_the_finishing_order() -> None:
    jobs = [3, 0, 2, 1, 0]  # 0 twice: equal jobs run once
    results = run_all(jobs, slow_square, workers=2, group=lambda _: "squares")
    assert list(results) == [3, 0, 2, 1]
    assert results == {3: 9, 0: 0, 2: 4, 1: 1}


def test_one_worker_runs_in_this_process_in_order() -> None:
    assert list(run_all([2, 1], slow_square, workers=1, group=lambda _: "squares").items()) == [(2, 4), (1, 1)]

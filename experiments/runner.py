"""Independent jobs in parallel worker processes, with one progress bar per study.

Episodes share nothing, so they spread over processes (``--jobs``; the simulator and
learner are pure Python and hold the GIL). Workers are *spawned*, not forked: each
imports its own simulator, planner and learner, and inherits no thread, lock or open
store from the parent. Jobs equal as values run once, so two studies that need the
same episode (the execution study's and the baselines' default-criterion runs) share it.
"""

from __future__ import annotations

import multiprocessing
from collections import Counter
from collections.abc import Callable, Hashable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import TypeVar

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

J = TypeVar("J", bound=Hashable)
R = TypeVar("R")


def run_all(jobs: Sequence[J], work: Callable[[J], R], *, workers: int, group: Callable[[J], str],
            initializer: Callable[..., None] | None = None, initargs: tuple[object, ...] = (),
            console: Console | None = None) -> dict[J, R]:
    """``work(job)`` for every distinct job, on ``workers`` processes (1: in this process).

    The results come in the jobs' order however the workers finished, so every page and
    table made from them reads the same from one run to the next.
    ``group`` names a job's study for its progress bar. A job that raises stops the run
    with that error: a broken episode is a bug to see, not a row to average over.
    """
    unique = list(dict.fromkeys(jobs))
    totals = Counter(group(j) for j in unique)
    results: dict[J, R] = {}
    with Progress(TextColumn("{task.description:<22}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console or Console(stderr=True), transient=False) as progress:
        bars = {name: progress.add_task(name, total=total) for name, total in totals.items()}
        if workers <= 1:
            if initializer is not None:
                initializer(*initargs)
            for job in unique:
                results[job] = work(job)
                progress.advance(bars[group(job)])
            return results
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=initializer,
                                 initargs=initargs) as pool:
            pending: dict[Future[R], J] = {pool.submit(work, job): job for job in unique}
            try:
                while pending:
                    done, _ = wait(pending, return_when=FIRST_COMPLETED)
                    for future in done:
                        job = pending.pop(future)
                        results[job] = future.result()
                        progress.advance(bars[group(job)])
            except BaseException:
                for future in pending:
                    future.cancel()
                raise
    return {job: results[job] for job in unique}  # the jobs' order, not their finishing order

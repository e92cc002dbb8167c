"""The one study framework (experiments/study.py): every study's jobs run once in one
pool, each study is summarised from the results in the order the studies planned
them, and the sections come in the studies' order."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from experiments.config import ExperimentConfig
from experiments.situation import markdown
from experiments.study import TRAINING, Context, Results, Study, longest_first, run_studies
from experiments.table import ResultRow, StudyResult

RAN: list[int] = []  # what the jobs ran, in order (workers=1: this process)


@dataclass(frozen=True)
class Square:
    n: int
    study: str = field(default="squares", compare=False)

    def run(self) -> list[int]:
        RAN.append(self.n)
        return [self.n * self.n]


@dataclass(frozen=True)
class Chain:
    n: int
    episodes: int
    study: str = field(default="chains", compare=False)

    def run(self) -> list[int]:
        RAN.append(self.n)
        return [self.n] * self.episodes


def _sum_of(jobs: Sequence[object]) -> object:
    def summarise(context: Context, results: Results) -> StudyResult:
        total = sum(sum(results[job]) for job in jobs)
        return StudyResult(f"seeds {context.config.seeds}", (ResultRow("total", "-", str(total)),))
    return summarise


def test_jobs_two_studies_share_run_once_and_each_study_reads_its_own(tmp_path: Path) -> None:
    RAN.clear()
    first, second = [Square(2), Square(3)], [Square(3), Square(4)]  # Square(3) in both
    studies = [Study("a", lambda config: first, _sum_of(first)), Study("b", lambda config: second, _sum_of(second)),
               TRAINING]
    ran = run_studies(studies, ExperimentConfig(True, (3, 4), 1, tmp_path, "test"))
    assert sorted(RAN) == [2, 3, 4]  # 3 once
    assert list(ran.results) == [Square(2), Square(3), Square(4)]  # the studies' order
    assert [s.rows[0].ours for s in ran.sections[:2]] == ["13", "25"]  # 4 + 9, 9 + 16
    assert ran.sections[0].title == "seeds (3, 4)"
    assert ran.sections[2] is ran.trained.study  # training's own section, from the run's training


def test_searches_go_first_then_the_longest_chains() -> None:
    jobs = [Chain(1, 2), Square(5), Chain(2, 6), Chain(3, 2)]
    assert longest_first(jobs) == [Square(5), Chain(2, 6), Chain(1, 2), Chain(3, 2)]


def test_a_changing_world_section_is_headed_by_its_command() -> None:
    section = markdown(StudyResult("Clutter", (ResultRow("success", "-", "90%"),), ("a note",),
                                   details=((("gap", "on"), (("2", "a|b"),)),)), "csl experiment clutter --quick", 12.4)
    assert section.splitlines() == [
        "### Clutter", "", "`csl experiment clutter --quick` (12 s wall)", "",
        "| measured | paper | ours |", "| --- | --- | --- |", "| success | - | 90% |", "",
        "| gap | on |", "| --- | --- |", "| 2 | a\\|b |", "", "a note"]

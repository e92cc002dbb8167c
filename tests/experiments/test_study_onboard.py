"""``csl experiment onboard`` (experiments.study_onboard and its page) without playing
an episode: the plan, the table and the goals from episodes made up by hand, the page's
header, and the command line's refusals. One ``--quick`` run end to end is marked slow."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from csl_cli.main import main
from experiments.config import ExperimentConfig
from experiments.onboard_page import PAGE, page_lines
from experiments.onboard_truth import Found, Localisation, MapAccuracy
from experiments.study_onboard import (HEADERS, HOMES, LAB, PRESETS, Episode, OnboardJob, goals, plan, pooled,
                                       summarise, table_row)
from mapping import LocalisationError


def located(errors: tuple[float, ...], odometry: tuple[float, ...]) -> Localisation:
    stamps = tuple(float(i) for i in range(len(errors)))
    return Localisation(LocalisationError(stamps, errors, (0.0,) * len(errors)),
                        LocalisationError(stamps, odometry, (0.0,) * len(errors)))


def onboard(seed: int, found: Found, explore_s: float, surface: float, errors: tuple[float, ...],
            odometry: tuple[float, ...], preset: str = "paper") -> tuple[OnboardJob, Episode]:
    """An apartment episode: 10 objects present, 1800 robot s on them."""
    return (OnboardJob("apartment", preset, seed),
            Episode("apartment", preset, seed, 10, found, explore_s, 1800.0, MapAccuracy(0.4, surface, 0.9),
                    located(errors, odometry), 100.0))


def lab(seed: int, objects_s: float, preset: str = "paper") -> tuple[OnboardJob, Episode]:
    """A lab episode: 5 objects present, no exploration, no map."""
    return OnboardJob(LAB, preset, seed), Episode(LAB, preset, seed, 5, Found(5, 5, 0), 0.0, objects_s, None, None,
                                                  30.0)


RESULTS = dict([
    # seed 0: 10 min exploring + 30 on objects = 40 min over 10 objects: 4 per object
    onboard(0, Found(9, 9, 1), 600.0, 0.875, (1.0, 2.0, 3.0), (5.0, 9.0, 1.0)),
    # seed 1: 20 + 30 = 50 min over 10: 5 per object
    onboard(1, Found(10, 9, 0), 1200.0, 0.9375, (1.0, 1.0, 7.0), (20.0, 3.0, 2.0)),
    onboard(0, Found(10, 10, 0), 300.0, 0.96, (0.5,), (0.5,), preset="clean"),
    lab(0, 900.0), lab(1, 1200.0),  # 3 and 4 min per object: 3.5 on the mean
    lab(0, 600.0, preset="clean"),  # 2 min per object
])


def test_the_plan_is_every_home_preset_and_seed_with_the_lab_beside_and_one_map(tmp_path: Path) -> None:
    jobs = plan(HOMES, PRESETS, [0, 1], tmp_path / "map.png")
    assert len(jobs) == 2 * 3 * 2 + 3 * 2
    assert {(j.world, j.preset) for j in jobs if j.world == LAB} == {(LAB, p) for p in PRESETS}
    assert [(j.world, j.preset, j.seed) for j in jobs if j.map_png is not None] == [("apartment", "paper", 0)]
    quick = plan(("apartment",), ("paper",), [3])
    assert quick == [OnboardJob("apartment", "paper", 3), OnboardJob(LAB, "paper", 3)]


def test_a_row_is_the_means_over_its_seeds_against_the_labs_on_the_same_preset() -> None:
    paper, clean = pooled(RESULTS, ["apartment"], ["paper", "clean"])
    cells = dict(zip(HEADERS, table_row(paper)))
    assert cells["seeds"] == "0, 1" and cells["episodes"] == "2" and cells["present"] == "10"
    assert cells["found"] == "95% (19/20)" and cells["right of found"] == "95% (18/19)"
    assert cells["false records"] == "0.5" and cells["exploration min"] == "15.0"
    assert cells["robot min / object present"] == "4.50"  # (4 + 5) / 2
    assert cells["x lab (lab min / object)"] == "1.29 (3.50)"  # 4.5 / 3.5
    assert cells["surface IoU"] == "0.91"  # (0.875 + 0.9375) / 2
    # the medians 2 and 1 on the mean; the largest of either episode
    assert (cells["localisation median in"], cells["localisation max in"], cells["odometry max in"]) == (
        "1.5", "7.0", "20.0")
    one = dict(zip(HEADERS, table_row(clean)))  # (5 + 30) min over 10 objects against the lab's 2
    assert one["seeds"] == "0 (1 seed: a smoke value, not a result)"
    assert one["x lab (lab min / object)"] == "1.75 (2.00)"


def test_the_goals_under_paper_say_met_or_missed_each_one() -> None:
    found, right, time, surface = goals(pooled(RESULTS, ["apartment"], PRESETS))  # only paper's: clean has none
    assert (found.met, right.met, time.met, surface.met) == (True, False, True, True)  # 18/19 is under 95%
    assert right.line == "goal MISSED: apartment under paper: handled right of found 95% (18/19) (at least 95%)"
    assert time.text == "apartment under paper: robot time per object present 1.29x the lab's (at most 1.5x)"
    # a home that did not run under paper (or had no lab beside it) meets none of its goals
    missing = goals(pooled({}, ["apartment-2"], ["paper"]))
    assert [g.met for g in missing] == [False] * 4 and missing[0].shown == "-"
    assert [g.what for g in goals(pooled(RESULTS, ["apartment"], ["paper"]), objects=False)] == ["surface IoU"]


def test_the_summary_puts_the_goals_first_and_the_table_and_map_after() -> None:
    drawn = dict(RESULTS)
    first = OnboardJob("apartment", "paper", 0)
    drawn[first] = dataclasses.replace(RESULTS[first], drawn="onboard-map.png")
    study = summarise(drawn, ["apartment"], ["paper"])
    assert [r.ours for r in study.rows] == ["95% (19/20): met", "95% (18/19): NOT met", "1.29x the lab's: met",
                                            "0.91: met"]
    [(headers, body)] = study.details
    assert headers == HEADERS and [row[:2] for row in body] == [("apartment", "paper")]
    assert study.plots == ("onboard-map.png",)


def test_the_page_says_how_it_was_made(tmp_path: Path) -> None:
    config = ExperimentConfig(True, (0,), 1, tmp_path, "csl experiment onboard --quick --jobs 1")
    lines = page_lines(config, summarise(RESULTS, ["apartment"], ["paper"]), 2, 123.4, 200.0)
    text = "\n".join(lines)
    assert "*Generated by `csl experiment onboard --quick --jobs 1`; do not edit by hand" in text
    assert "wall time 123 s, 200 CPU seconds" in text and "- episodes: 2 (onboard and lab)" in text
    assert "- homes: apartment; noise presets: paper;" in text  # --quick's
    assert "## 1. Without a ceiling camera" in text and "apartment under paper: handled right of found" in text


@pytest.mark.parametrize("argv, message", [
    (["--seeds", "0"], "--seeds: a count of seeds must be 1 to 10000, got 0"),
    (["--jobs", "two"], "--jobs: expected a whole number"),
])
def test_bad_flags_are_one_line_and_exit_2(argv: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["experiment", "onboard", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_an_out_that_is_a_file_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "f").write_text("x")
    assert main(["experiment", "onboard", "--quick", "--out", str(tmp_path / "f")]) == 2
    assert "--out" in capsys.readouterr().err and not (tmp_path / PAGE).exists()


def test_a_lab_episode_is_measured_without_a_map() -> None:
    """The baseline's job played for real (the lab's seven objects, a second or two; an
    onboard episode takes minutes and is left to ``csl experiment onboard --quick``)."""
    from experiments.study_onboard import run_job
    from experiments.worker import install_worker
    from robot_profile import load_profile

    install_worker({}, load_profile())
    episode = run_job(OnboardJob(LAB, "paper", 0))
    # the ceiling camera sees all seven objects where they are: each found once, none false
    assert (episode.present, episode.found.found, episode.found.false) == (7, 7, 0)
    assert episode.explore_s == 0.0 and episode.objects_s > 0
    assert episode.map is None and episode.located is None and episode.drawn is None

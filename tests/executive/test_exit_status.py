"""The exit status a script reads after ``csl run`` (executive/exit_status.py)."""

from __future__ import annotations

from executive.exit_status import ALL_HANDLED, SOME_FAILED, episode_status


def test_all_grasped_or_left_is_success() -> None:
    assert episode_status(["grasped", "left", "grasped"]) == (ALL_HANDLED, "all 3 objects were handled")


def test_one_failed_or_unfinished_object_fails_the_run() -> None:
    assert episode_status(["grasped", "failed", None]) == (SOME_FAILED, "2 of 3 objects were not handled")


def test_no_object_located_is_a_failure_not_a_success() -> None:
    status, why = episode_status([])
    assert status == SOME_FAILED and "no object was located" in why

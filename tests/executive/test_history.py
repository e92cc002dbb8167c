"""The learning history: one row per run, read back exactly, bad rows refused in one
line naming file, line and field, and the learning curve's numbers worked by hand."""

from __future__ import annotations

import dataclasses
import json
import uuid
from datetime import datetime, timedelta, timezone
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
import pytest

from reporting.history import (_KINDS, CurvePoint, Run, append_run, default_history, episode_run, learning_curve,
                               read_history, wrong_grasps)

EVENTS = [
    {"event": "grasp", "object": 0, "as_feature": False, "success": False},  # a wrong prediction
    {"event": "grasp", "object": 0, "as_feature": True, "success": False},  # a grasp tried as a test
    {"event": "grasp", "object": 0, "as_feature": False, "success": True},
    {"event": "grasp", "object": 1, "as_feature": False, "success": False},  # another
    {"event": "sense", "object": 1, "success": False},
]


def _run(**changes: object) -> Run:
    base = Run(date="2026-01-02T03:04:05+00:00", command="run", robot="r1", world="lab", seed=3,
               criterion="cs-id3", objects=4, handled=3, failed=1, errors=2, robot_min_per_object=10.0,
               library_size=20, library="/tmp/lib.sqlite")
    return dataclasses.replace(base, **changes)  # type: ignore[arg-type]


def test_the_field_checks_cover_every_field_of_a_run() -> None:
    assert set(_KINDS) == {f.name for f in dataclasses.fields(Run)}


def test_errors_are_the_leaf_grasps_that_did_not_hold() -> None:
    assert wrong_grasps(EVENTS) == 2


def test_an_episodes_row_counts_outcomes_errors_and_minutes(tmp_path: Path) -> None:
    eastern = timezone(timedelta(hours=-5))
    row = episode_run(command="demo", robot="r1", world="lab", seed=0, criterion="cs-id3-failure",
                      outcomes=["grasped", "left", "failed", None], robot_s=480.0, events=EVENTS, library_size=17,
                      library=tmp_path / "library.sqlite", now=datetime(2026, 1, 1, 22, 4, 5, 999, tzinfo=eastern))
    assert row == Run(date="2026-01-02T03:04:05+00:00", command="demo", robot="r1", world="lab", seed=0,
                      criterion="cs-id3-failure", objects=4, handled=2, failed=2, errors=2,
                      robot_min_per_object=2.0,  # 480 s / 60 / 4 objects
                      library_size=17, library=str((tmp_path / "library.sqlite").resolve()))


def test_a_run_that_saw_nothing_has_no_minutes_per_object() -> None:
    row = episode_run(command="run", robot="r2", world=None, seed=None, criterion="id3", outcomes=[], robot_s=0.0,
                      events=[], library_size=0, library=None)
    assert (row.objects, row.handled, row.failed, row.robot_min_per_object, row.library) == (0, 0, 0, None, None)


def test_the_default_history_lives_in_csl_home(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("CSL_HOME", str(tmp_path / "home"))
    assert default_history() == tmp_path / "home" / "history.jsonl"


_text = st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=12)
_count = st.integers(0, 50)
_dates = st.datetimes(timezones=st.just(timezone.utc)).map(lambda t: t.replace(microsecond=0).isoformat())
_runs = st.builds(
    lambda handled, failed, **kw: Run(handled=handled, failed=failed, objects=handled + failed, **kw),
    handled=_count, failed=_count, date=_dates, command=st.sampled_from(["demo", "run"]), robot=_text,
    world=st.none() | _text, seed=st.none() | _count, criterion=_text, errors=_count,
    robot_min_per_object=st.none() | st.floats(0, 1e6, allow_nan=False), library_size=_count,
    library=st.none() | _text)


@pytest.mark.slow
@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=40)
@given(st.lists(_runs, max_size=6))
def test_rows_read_back_as_appended_oldest_first(tmp_path: Path, runs: list[Run]) -> None:
    path = tmp_path / uuid.uuid4().hex / "history.jsonl"  # the folder is made, as $CSL_HOME is
    path.parent.mkdir()
    path.touch()
    for run in runs:
        append_run(path, run)
    assert read_history(path) == runs


def test_appending_makes_the_missing_folder_of_the_default_file(tmp_path: Path) -> None:
    path = tmp_path / "home" / "history.jsonl"
    append_run(path, _run())
    append_run(path, _run(seed=4))
    assert [r.seed for r in read_history(path)] == [3, 4]


def _line(**changes: object) -> str:
    document = dataclasses.asdict(_run())
    document.update(changes)
    return json.dumps(document)


@pytest.mark.parametrize(("text", "says"), [
    ("{not json\n", ":1: not a JSON row: "),
    ("[1, 2]\n", ":1: expected a JSON object, got list"),
    (_line() + "\n" + json.dumps({k: v for k, v in dataclasses.asdict(_run()).items() if k != "errors"}),
     ":2: field 'errors' missing"),
    (_line(seed="3"), ":1: field 'seed': unexpected value '3'"),
    (_line(date="yesterday"), ":1: field 'date': expected an ISO 8601 time, got 'yesterday'"),
    (_line(objects=True), ":1: field 'objects': unexpected value True"),
    (_line(errors=-1), ":1: field 'errors': expected a number >= 0, got -1"),
    (_line(handled=4), ":1: handled + failed (4 + 1) is not objects (4)"),
])
def test_a_bad_row_is_one_line_naming_file_line_and_field(tmp_path: Path, text: str, says: str) -> None:
    path = tmp_path / "history.jsonl"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ValueError) as caught:
        read_history(path)
    message = str(caught.value)
    assert message.startswith(f"{path}{says}") and "\n" not in message


def test_a_missing_history_or_a_folder_says_so(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="no history file there"):
        read_history(tmp_path / "nothing.jsonl")
    with pytest.raises(ValueError, match="is a folder"):
        read_history(tmp_path)


def test_blank_lines_are_skipped(tmp_path: Path) -> None:
    path = tmp_path / "history.jsonl"
    path.write_text("\n" + _line() + "\n\n", encoding="utf-8")
    assert read_history(path) == [_run()]


def test_the_learning_curve_is_per_object_and_numbers_runs_as_read() -> None:
    runs = [_run(objects=4, handled=3, failed=1, errors=2, robot_min_per_object=10.0),
            _run(objects=0, handled=0, failed=0, errors=0, robot_min_per_object=None),  # nothing seen: no point
            _run(objects=5, handled=5, failed=0, errors=1, robot_min_per_object=8.0)]
    assert learning_curve(runs) == [CurvePoint(1, 10.0, 0.5, 0.25), CurvePoint(3, 8.0, 0.2, 0.0)]

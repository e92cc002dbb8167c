"""The episode log's vocabulary is written once (behaviours/events.py); the docs, the
log and ``csl log`` take it from there."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from behaviours.events import RECOVERIES, Event
from csl_cli.commands.log import EVENT_KINDS
from executive.episode_log import EpisodeLog

DOC = Path(__file__).resolve().parents[2] / "docs" / "executive.md"


def test_the_docs_list_every_event_kind_with_its_reading() -> None:
    rows = dict(re.findall(r"^\| `([a-z_]+)` \| (.+) \|$", DOC.read_text(encoding="utf-8"), re.MULTILINE))
    assert rows == {e.value: e.reading for e in Event}


def test_csl_log_offers_exactly_the_event_kinds() -> None:
    assert EVENT_KINDS == tuple(e.value for e in Event)


def test_the_log_refuses_an_unknown_kind_and_writes_nothing() -> None:
    log = EpisodeLog()
    with pytest.raises(ValueError, match="unknown episode event kind 'chose'"):
        log.event("chose", object=0)
    assert log.events == []
    log.event(Event.CHOOSE, object=0)
    log.event("branch", object=0)
    assert [e["event"] for e in log.events] == ["choose", "branch"]


def test_recoveries_are_plain_strings_as_the_log_holds_them() -> None:
    assert "backtrack" in RECOVERIES and "other_end" in RECOVERIES and "choose" not in RECOVERIES

"""Transcripts show what the robot decided and nothing that differs between runs."""

from __future__ import annotations

import uuid

from hypothesis import given
from hypothesis import strategies as st

from csl_testing.transcript import encounters, event_line, masked, transcript_text


def test_an_event_line_is_its_tick_kind_and_fields_in_logged_order() -> None:
    event = {"tick": 3, "event": "grasp", "object": 0, "behaviour": "Grasp", "grasp": "Front-Wrap",
             "success": True, "seconds": 60.0}
    assert event_line(event) == "   3 grasp: object=0, grasp=Front-Wrap, success=True, seconds=60.0"


def test_a_moves_duration_and_path_are_left_out_but_where_it_ended_stays() -> None:
    event = {"tick": 12, "event": "move", "object": 1, "to": [6, 182], "seconds": 31.7,
             "path": [[30.0, 30.0], [91.5, 79.4]], "pose": [91.5, 79.4, 2.0]}
    assert event_line(event) == "  12 move: object=1, to=[6, 182], pose=[91.5, 79.4, 2.0]"


def test_transcript_layout() -> None:
    text = transcript_text(["   1 LocateObjects:S"], [{"tick": 1, "event": "episode_end", "status": "SUCCESS"}])
    assert text == ("# ticks: every behaviour ticked this tick, with its status (S/F/R)\n"
                    "   1 LocateObjects:S\n"
                    "# events\n"
                    "   1 episode_end: status=SUCCESS\n")
    assert encounters("a\n", "b\n") == "a\n# --- next encounter ---\nb\n"


@given(st.integers(0, 2**128 - 1), st.integers(0x100000, 2**64 - 1))
def test_uuids_and_addresses_are_masked(number: int, address: int) -> None:
    text = f"<Grasp at {hex(address)}> id={uuid.UUID(int=number)} value=0x1f"
    assert masked(text) == "<Grasp at 0x…> id=<uuid> value=0x1f"  # a short hex number is a value, kept


def test_masking_reaches_trace_lines_and_event_fields() -> None:
    trace = ["   1 Probe <object at 0x7f3a2b1c9d00>:S"]
    events = [{"tick": 1, "event": "learn", "key": "5a2b9c1e-0d4f-4e6a-9b7c-1234567890ab"}]
    assert transcript_text(trace, events).splitlines()[1:] == [
        "   1 Probe <object at 0x…>:S", "# events", "   1 learn: key=<uuid>"]

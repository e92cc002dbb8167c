"""The verb table against ``docs/driver-protocol.md``: every verb of the table is
documented (key, section, fields, timeout, driver's bound) as the table has it, and the page names no
verb the table lacks. Fields are read off the wire: each verb encodes a hand-made
value of its request's and its reply's message shapes, and the JSON keys are compared
with the page's."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from camera_model.image import CameraImage
from hero_driver.interface import GraspResult, Hello, MoveResult, Pose, RangeScan, RobotState, SenseResult
from hero_driver.zenoh_link.codec import EmptyRequest, MoveRequest, ProcedureRequest, ResetRequest, WaitRequest
from hero_driver.zenoh_link.verbs import BY_NAME, NAMES, VERBS
from hero_driver.zenoh_link.versions import Greeting

DOC = (Path(__file__).resolve().parents[2] / "docs" / "driver-protocol.md").read_text(encoding="utf-8")
HERE = Pose(30.0, 30.0, 0.0)
STATE = RobotState(HERE, 0.0, 1.0)
# One hand-made value per message shape (codec.Message.value), so a verb that sends
# and answers known shapes has its examples already.
REQUESTS: dict[type, object] = {
    MoveRequest: MoveRequest((HERE,), (60.0, 30.0)),
    ProcedureRequest: ProcedureRequest("H-Sweep-5°"),
    EmptyRequest: EmptyRequest(),
    ResetRequest: ResetRequest("lab", 3),
    WaitRequest: WaitRequest(20.0),
}
REPLIES: dict[type, object] = {
    MoveResult: MoveResult(HERE, 2.0, False, True),
    SenseResult: SenseResult("H-Sweep-5°", {"Width-Degree-5°": 31.5}, 45.0, 20.0),
    GraspResult: GraspResult("Front-Pinch", True, 45.0),
    RobotState: STATE,
    CameraImage: CameraImage(np.zeros((2, 3), dtype=np.uint8), 0.8, 0.0, 1.6),
    type(None): None,
    Greeting: Greeting(Hello((1,), ("an-optional-feature",))),
    RangeScan: RangeScan(HERE, 0.2, (-90.0, 0.0, 90.0), (30.0, 210.0, float("inf")), 0.5, 480.0),
}
EXAMPLES: dict[str, tuple[object, object]] = {
    verb.name: (REQUESTS.get(verb.request.value), REPLIES.get(verb.reply.value)) for verb in VERBS}
"""Each verb's request and reply, by its shapes."""


def names_in(cell: str) -> set[str]:
    """The backticked field names of a table cell (``none`` for no field)."""
    return set(re.findall(r"`(\w+)`", cell))


def summary() -> dict[str, list[str]]:
    """The verb table of the page: verb -> [request fields, reply fields, timeout, bound]."""
    rows = re.findall(r"^\| `(\w+)` \| (.*?) \| (.*?) \| ([\d.]+) s \| ([\d.]+ s|none) \|$", DOC, re.MULTILINE)
    return {verb: [request, reply, timeout, bound] for verb, request, reply, timeout, bound in rows}


def sections() -> dict[str, str]:
    """Each ``#### `verb`: ...`` section's text, up to the next heading."""
    parts = re.split(r"^#### `(\w+)`:.*$", DOC, flags=re.MULTILINE)
    return {verb: re.split(r"^#", text, flags=re.MULTILINE)[0] for verb, text in zip(parts[1::2], parts[2::2])}


def wire_fields(body: bytes) -> set[str]:
    return set(json.loads(body)) - {"v"}


def test_every_shape_of_the_table_has_an_example() -> None:
    assert {verb.request.value for verb in VERBS} <= set(REQUESTS)
    assert {verb.reply.value for verb in VERBS} <= set(REPLIES)
    assert all(isinstance(example, shape) for shape, example in (REQUESTS | REPLIES).items())


def test_the_page_names_exactly_the_verbs_of_the_table() -> None:
    assert tuple(summary()) == NAMES
    assert tuple(sections()) == NAMES
    [served] = re.findall(r"^\| `hero/<robot>/rpc/<verb>` \|.*\| (.*) \|$", DOC, re.MULTILINE)
    assert re.findall(r"`(\w+)`", served) == list(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_each_verb_is_documented_as_the_table_has_it(name: str) -> None:
    verb = BY_NAME[name]
    request_cell, reply_cell, timeout, bound = summary()[name]
    assert float(timeout) == verb.timeout_s
    assert bound == ("none" if verb.bound_s is None else f"{verb.bound_s:g} s")
    request, result = EXAMPLES[name]
    assert names_in(request_cell) == wire_fields(verb.encode_request(request))
    assert names_in(reply_cell) == wire_fields(verb.encode_result(result))


@pytest.mark.parametrize("name", NAMES)
def test_each_section_states_the_same_fields(name: str) -> None:
    """Where a section spells fields out (a field table, an example request), they
    are the verb table's."""
    text = sections()[name]
    request_cell, reply_cell, _, _ = summary()[name]
    for heading, cell in (("request field", request_cell), ("reply field", reply_cell)):
        table = re.search(rf"^\| {heading} \|.*\n\|[-|]+\|\n((?:\|.*\n)+)", text, re.MULTILINE)
        if table:
            rows = re.findall(r"^\| (.*?) \|", table.group(1), re.MULTILINE)
            assert set().union(*map(names_in, rows)) == names_in(cell), heading
    for example in re.findall(r"Request:? `(\{.*?\})`", text):
        assert set(json.loads(example)) - {"v"} == names_in(request_cell)

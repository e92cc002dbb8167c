"""The behaviour tree as data (``/behaviour_tree/nodes``) and the ``csl-run`` metadata
record: a recorded lab episode read back with ``mcap``'s own reader, every message
checked against the channel's JSON Schema, and the pieces on small trees worked by hand."""

from __future__ import annotations

import dataclasses
import enum
import json
from collections.abc import Iterator
from pathlib import Path

import mcap
import numpy as np
import py_trees
import py_trees.version
import pytest
from jsonschema import Draft202012Validator
from mcap.reader import make_reader
from py_trees.common import Access, Status

from executive.behaviour_tree import build_tree
from recording import topics
from recording.run_metadata import DISTRIBUTIONS, RUN_METADATA, describe_run
from recording.tree_nodes import MAX_DEPTH, MAX_ITEMS, SCHEMA, BlackboardChanges, json_value, tree_message, tree_nodes
from robot_profile import load_profile, profile_stamp
from tests.executive.test_recording import record_episode

STATUSES = {"SUCCESS", "FAILURE", "RUNNING", "INVALID"}
KEYS = {f"/csl/r1/{key}" for key in ("objects", "results", "object", "step", "pose", "driver_lost", "driver_back",
                                      "blocked", "disturbance")}


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, object]:
    folder = tmp_path_factory.mktemp("tree")
    run = describe_run("r1", load_profile(), "eg2", 7)
    result, log, recording = record_episode(folder, before_run=lambda r: r.describe_run(run), mcap=folder / "e.mcap")
    recording.close()
    with (folder / "e.mcap").open("rb") as f:
        reader = make_reader(f)
        messages = list(reader.iter_messages(topics=[topics.NODES.name, topics.STATUS.name], log_time_order=True))
        f.seek(0)
        metadata = [(m.name, m.metadata) for m in make_reader(f).iter_metadata()]
    on = {name: [(s, m) for s, c, m in messages if c.topic == name] for name in (topics.NODES.name, topics.STATUS.name)}
    return {"result": result, "log": log, "nodes": on[topics.NODES.name], "status": on[topics.STATUS.name],
            "metadata": metadata}


def test_every_message_validates_against_the_channels_schema(recorded) -> None:  # noqa: ANN001
    Draft202012Validator.check_schema(SCHEMA)
    validator = Draft202012Validator(SCHEMA)
    schema, _ = recorded["nodes"][0]
    assert (schema.name, schema.encoding) == ("csl.BehaviourTreeNodes", "jsonschema")
    assert json.loads(schema.data) == SCHEMA
    for _, message in recorded["nodes"]:
        tick = json.loads(message.data)
        assert validator.is_valid(tick), [e.message for e in validator.iter_errors(tick)][:3]


def test_one_message_a_tick_stamped_as_the_text_tree(recorded) -> None:  # noqa: ANN001
    ticks = [json.loads(m.data) for _, m in recorded["nodes"]]
    texts = [json.loads(m.data) for _, m in recorded["status"]]
    assert [t["tick"] for t in ticks] == list(range(1, recorded["result"].ticks + 1))
    assert [m.log_time for _, m in recorded["nodes"]] == [m.log_time for _, m in recorded["status"]]
    for tick, text in zip(ticks, texts):
        assert tick["nodes"][0]["status"] == text["status"]  # the root's
        position = 0  # py_trees' own display lists the nodes in the same depth-first order
        for node in tick["nodes"]:
            position = text["tree"].index(node["name"], position)
    assert ticks[-1]["nodes"][0]["status"] == recorded["result"].status == "SUCCESS"


def test_node_ids_are_the_same_every_tick_and_in_a_tree_built_again(recorded) -> None:  # noqa: ANN001
    ticks = [json.loads(m.data) for _, m in recorded["nodes"]]
    shapes = [[(n["id"], n["parent"], n["name"], n["kind"], n["family"]) for n in t["nodes"]] for t in ticks]
    assert all(shape == shapes[0] for shape in shapes)
    again = build_tree("r1")  # other py_trees uuids, the same ids
    assert [(n["id"], n["parent"], n["name"], n["kind"], n["family"]) for n in tree_nodes(again)] == shapes[0]
    assert [node_id for node_id, *_ in shapes[0]] == list(range(len(shapes[0])))
    assert [node_id for node_id, parent, *_ in shapes[0] if parent is None] == [0]  # one root, first
    assert all(parent < node_id for node_id, parent, *_ in shapes[0][1:])  # a parent before its children
    assert shapes[0][0][1:] == (None, "driver check", "Selector", "Selector")


def test_statuses_are_py_trees_four_and_the_tree_ran(recorded) -> None:  # noqa: ANN001
    seen = {n["status"] for _, m in recorded["nodes"] for n in json.loads(m.data)["nodes"]}
    assert seen == STATUSES  # each occurs: never-ticked branches stay INVALID, failures recover
    first = {n["name"]: n for n in json.loads(recorded["nodes"][0][1].data)["nodes"]}
    assert (first["LocateObjects"]["status"], first["LocateObjects"]["feedback"]) == ("SUCCESS", "7 objects")


def test_the_blackboard_keys_that_changed_each_tick(recorded) -> None:  # noqa: ANN001
    ticks = {t["tick"]: t for t in (json.loads(m.data) for _, m in recorded["nodes"])}
    changes = {tick: {b["key"]: b["value"] for b in t["blackboard"]} for tick, t in ticks.items()}
    assert set(changes[1]) == KEYS  # the first tick: every key of the robot's namespace
    located = next(e for e in recorded["log"].events if e["event"] == "located")
    assert len(located["regions"]) == 7
    # RememberAppearance takes the next object off the list and writes it as the one under
    # way: both keys change on that tick, and only then does the list change
    starts = [e for e in recorded["log"].events if e["event"] == "object"]
    assert [e["object"] for e in starts] == list(range(7))
    for start in starts:
        written = changes[start["tick"]]["/csl/r1/object"]
        assert written["index"] == start["object"]
        assert written["first_region"]["centroid"] == pytest.approx(start["centroid"], abs=0.05)  # logged to 0.1 in
        assert len(changes[start["tick"]]["/csl/r1/objects"]) == 7 - (start["object"] + 1)
    assert [tick for tick, changed in changes.items() if "/csl/r1/objects" in changed] == [e["tick"] for e in starts]


def test_the_run_metadata_record_reads_back(recorded) -> None:  # noqa: ANN001
    profile = load_profile()
    ((name, record),) = recorded["metadata"]
    assert name == RUN_METADATA == "csl-run"
    assert {k: record[k] for k in ("robot", "profile", "profile_name", "profile_sha256", "criterion", "seed")} == {
        "robot": "r1", "profile": profile.source, "profile_name": "hero2000",
        "profile_sha256": profile_stamp(profile).sha256, "criterion": "eg2", "seed": "7"}
    versions = {k.removeprefix("version."): v for k, v in record.items() if k.startswith("version.")}
    assert set(versions) == set(DISTRIBUTIONS)  # all installed here
    assert (versions["py-trees"], versions["mcap"]) == (py_trees.version.__version__, mcap.__version__)


def test_a_node_kind_and_family_on_a_tree_worked_by_hand() -> None:
    class Wait(py_trees.behaviours.Running):
        pass

    root = py_trees.composites.Sequence("root", memory=True, children=[
        py_trees.behaviours.Success("a"),
        py_trees.decorators.Inverter("not", child=py_trees.behaviours.Failure("b")),
        py_trees.composites.Selector("pick", memory=False, children=[Wait("c")]),
        py_trees.composites.Parallel("both", policy=py_trees.common.ParallelPolicy.SuccessOnAll(), children=[])])
    root.tick_once()
    assert [(n["id"], n["parent"], n["name"], n["kind"], n["family"], n["status"]) for n in tree_nodes(root)] == [
        (0, None, "root", "Sequence", "Sequence", "RUNNING"),
        (1, 0, "a", "Success", "Action", "SUCCESS"),
        (2, 0, "not", "Inverter", "Decorator", "SUCCESS"),
        (3, 2, "b", "Failure", "Action", "FAILURE"),
        (4, 0, "pick", "Selector", "Selector", "RUNNING"),
        (5, 4, "c", "Wait", "Action", "RUNNING"),
        (6, 0, "both", "Parallel", "Parallel", "INVALID")]


@pytest.fixture
def blackboard() -> Iterator[None]:
    py_trees.blackboard.Blackboard.clear()
    yield
    py_trees.blackboard.Blackboard.clear()


def test_a_key_written_by_a_behaviour_is_sent_once_then_not_until_it_changes(blackboard) -> None:  # noqa: ANN001
    class Count(py_trees.behaviour.Behaviour):
        def __init__(self) -> None:
            super().__init__("Count")
            self.bb = self.attach_blackboard_client(namespace="/csl/t")
            self.bb.register_key("count", access=Access.WRITE)

        def update(self) -> Status:
            self.bb.count = 2
            return Status.RUNNING

    py_trees.blackboard.Blackboard.set("/elsewhere/x", 1)  # another robot's key: not this robot's
    root = Count()
    changes = BlackboardChanges("/csl/t/")
    sent = []
    for tick in (1, 2, 3):
        root.tick_once()
        sent.append(tree_message(tick, root, changes)["blackboard"])
    assert sent == [[{"key": "/csl/t/count", "value": 2}], [], []]  # written every tick, changed once
    py_trees.blackboard.Blackboard.unset("/csl/t/count")
    assert changes.since_last() == [{"key": "/csl/t/count", "value": None, "removed": True}]


def test_a_value_changed_in_place_is_seen(blackboard) -> None:  # noqa: ANN001
    record = {"outcome": None}
    py_trees.blackboard.Blackboard.set("/csl/t/object", record)
    changes = BlackboardChanges("/csl/t/")
    assert changes.since_last() == [{"key": "/csl/t/object", "value": {"outcome": None}}]
    record["outcome"] = "grasped"
    assert changes.since_last() == [{"key": "/csl/t/object", "value": {"outcome": "grasped"}}]


class Colour(enum.Enum):
    RED = "red"


@dataclasses.dataclass(frozen=True)
class Point:
    x: float
    y: float
    hidden: str = dataclasses.field(default="not shown", repr=False)


class Opaque:
    pass


def test_values_as_json() -> None:
    assert json_value(Point(1.5, float("nan"))) == {"x": 1.5, "y": "nan"}
    assert json_value({"tags": frozenset({"b", "a"}), 3: (Colour.RED, None)}) == {"tags": ["a", "b"],
                                                                                  "3": ["red", None]}
    assert json_value([np.float64(0.25), np.int64(4), True, float("-inf")]) == [0.25, 4, True, "-inf"]
    assert json_value(Opaque()) == "<Opaque>" and json_value(b"\x00") == "<bytes>"
    deep: object = 1
    for _ in range(MAX_DEPTH + 1):
        deep = [deep]
    assert json.dumps(json_value(deep)) == "[" * MAX_DEPTH + '"<list>"' + "]" * MAX_DEPTH
    assert json_value(list(range(MAX_ITEMS + 3))) == [*range(MAX_ITEMS), "... 3 more"]


@pytest.mark.slow
def test_csl_run_record_writes_the_run_metadata(tmp_path: Path) -> None:
    from tests.executive.test_recording_cli import _run_args

    args = _run_args(tmp_path, record=tmp_path / "run.mcap")
    args.seed, args.criterion = 3, "eg2"
    assert args.handler(args) == 0
    with (tmp_path / "run.mcap").open("rb") as f:
        (record,) = [m.metadata for m in make_reader(f).iter_metadata() if m.name == "csl-run"]
    assert (record["robot"], record["criterion"], record["seed"]) == (args.robot, "eg2", "3")
    assert record["profile_sha256"] == profile_stamp(load_profile()).sha256


def test_a_live_client_is_offered_the_channel_with_its_schema_and_gets_each_tick() -> None:
    import struct

    from recording.session import Recording
    from tests.executive.ws_client import MESSAGE_DATA, FoxgloveClient

    recording = Recording(load_profile().robot.geometry, live_port=0)
    try:
        client = FoxgloveClient(recording.live_port)  # type: ignore[arg-type]
        channels: dict[str, dict] = {}
        while topics.NODES.name not in channels:
            message = client.receive()
            if isinstance(message, str) and json.loads(message)["op"] == "advertise":
                channels.update({c["topic"]: c for c in json.loads(message)["channels"]})
        offered = channels[topics.NODES.name]
        assert (offered["encoding"], offered["schemaName"], json.loads(offered["schema"])) == (
            "json", "csl.BehaviourTreeNodes", SCHEMA)
        client.send_json({"op": "subscribe", "subscriptions": [{"id": 1, "channelId": offered["id"]}]})
        assert recording.wait_for_viewer(10.0)
        tree = build_tree("r1")
        recording.tick(1, tree)
        while not isinstance(message := client.receive(), bytes) or message[0] != MESSAGE_DATA:
            pass
        assert struct.unpack_from("<I", message, 1) == (1,)
        tick = json.loads(message[13:])
        assert tick["tick"] == 1 and [n["name"] for n in tick["nodes"]] == [n.name for n in _preorder(tree)]
        client.close()
    finally:
        recording.close()


def _preorder(node: py_trees.behaviour.Behaviour) -> list[py_trees.behaviour.Behaviour]:
    return [node, *(n for child in node.children for n in _preorder(child))]

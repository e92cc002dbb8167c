"""docs/foxglove-layout.json is a Foxglove layout that shows a recording of ours: valid
JSON, every panel placed, the panels the docs promise, and every topic and message path
it names one a recording has (paths resolved through the channels' schemas: our JSON
Schemas, Foxglove's protobuf descriptors)."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import foxglove.messages
import pytest

from executive.behaviour_tree import build_tree
from recording import topics
from recording.recorder import EVENT_SCHEMA, STATUS_SCHEMA
from recording.tree_nodes import SCHEMA as NODES_SCHEMA
from recording.tree_nodes import tree_nodes
from tests.executive.foxglove_wire import fields

LAYOUT = Path(__file__).resolve().parents[2] / "docs" / "foxglove-layout.json"
JSON_SCHEMAS = {topics.STATUS.name: STATUS_SCHEMA, topics.NODES.name: NODES_SCHEMA, topics.EVENTS.name: EVENT_SCHEMA}
TOPICS = {t.name: t for t in topics.ALL}
PROTO_NUMBERS = {1, 2, 3, 4, 5, 6, 7, 13, 15, 16, 17, 18}  # double, float, int64, ... sint64: plottable
REPEATED, MESSAGE = 3, 11  # FieldDescriptorProto label and type


@pytest.fixture(scope="module")
def layout() -> dict[str, Any]:
    return json.loads(LAYOUT.read_text(encoding="utf-8"))


def _leaves(mosaic: object) -> Iterator[str]:
    if isinstance(mosaic, str):
        yield mosaic
    else:
        assert isinstance(mosaic, dict) and mosaic["direction"] in ("row", "column"), mosaic
        yield from _leaves(mosaic["first"])
        yield from _leaves(mosaic["second"])


def _message_paths(config: dict[str, Any]) -> list[str]:
    paths = [path["value"] for path in config.get("paths", [])]
    return paths + ([config["topicPath"]] if "topicPath" in config else [])


def test_every_panel_is_placed_once_and_the_promised_ones_are_there(layout) -> None:  # noqa: ANN001
    placed = list(_leaves(layout["layout"]))
    assert sorted(placed) == sorted(layout["configById"]) and len(set(placed)) == len(placed)
    kinds = {panel.split("!")[0] for panel in placed}
    assert {"3D", "Image", "RawMessages", "StateTransitions", "Plot"} <= kinds
    configs = layout["configById"]
    assert configs["Image!overhead"]["imageMode"]["imageTopic"] == topics.CAMERA.name
    assert {c.get("topicPath") for c in configs.values()} >= {topics.NODES.name, topics.EVENTS.name}
    assert all(path["enabled"] for c in configs.values() for path in c.get("paths", []))  # else Foxglove draws nothing


def test_every_topic_named_is_a_channel_of_a_recording(layout) -> None:  # noqa: ANN001
    named = []
    for config in layout["configById"].values():
        named += list(config.get("topics", {}))
        named += [config["imageMode"]["imageTopic"]] if "imageMode" in config else []
        named += [re.match(r"/[^.\[{]*", path).group() for path in _message_paths(config)]  # type: ignore[union-attr]
    assert named and set(named) <= set(TOPICS), set(named) - set(TOPICS)
    three_d = layout["configById"]["3D!floor"]
    assert all(t["visible"] for t in three_d["topics"].values()) and three_d["followTf"] == topics.WORLD_FRAME


def _steps(path: str) -> list[tuple[str, bool]]:
    """The fields of a message path after its topic, each with whether it is indexed."""
    rest = path[len(re.match(r"/[^.\[{]*", path).group()):]  # type: ignore[union-attr]
    return [(m.group(1), m.group(2) is not None) for m in re.finditer(r"\.(\w+)(\[\d+\])?", rest)]


def _json_leaf(schema: dict[str, Any], steps: list[tuple[str, bool]]) -> dict[str, Any]:
    for name, indexed in steps:
        schema = schema["properties"][name]
        if indexed:
            assert schema["type"] == "array", name
            schema = schema["items"]
    return schema


def _descriptors(schema: bytes) -> dict[str, dict[str, tuple[int, int, str]]]:
    """Each message of a FileDescriptorSet: field name to (label, type, type name)."""
    out = {}
    for file in fields(schema)[1]:
        for described in fields(file).get(4, []):  # type: ignore[arg-type]
            d = fields(described)  # type: ignore[arg-type]
            out[d[1][0].decode()] = {  # type: ignore[union-attr]
                f[1][0].decode(): (f[4][0], f[5][0], f.get(6, [b""])[0].decode().split(".")[-1])  # type: ignore
                for f in map(fields, d.get(2, []))}  # type: ignore[arg-type]
    return out


def _proto_leaf(schema_name: str, steps: list[tuple[str, bool]]) -> int:
    message = schema_name.split(".")[1]
    described = _descriptors(getattr(foxglove.messages, message).get_schema().data)
    kind = MESSAGE
    for name, indexed in steps:
        assert kind == MESSAGE, f"{name} below a scalar"
        label, kind, message = described[message][name]
        assert (label == REPEATED) == indexed, f"{name}: indexed {indexed}, repeated {label == REPEATED}"
    return kind


def test_every_message_path_resolves_to_a_value_the_panel_can_show(layout) -> None:  # noqa: ANN001
    for panel, config in layout["configById"].items():
        for path in _message_paths(config):
            topic = re.match(r"/[^.\[{]*", path).group()  # type: ignore[union-attr]
            steps = _steps(path)
            if topic in JSON_SCHEMAS:
                leaf = _json_leaf(JSON_SCHEMAS[topic], steps)
                scalar = leaf.get("type") in ("integer", "number", "string") or "enum" in leaf
            else:
                scalar = _proto_leaf(TOPICS[topic].schema, steps) in PROTO_NUMBERS
            if panel.startswith(("Plot", "StateTransitions")):
                assert scalar, f"{panel}: {path} is not a single value"


def test_the_statuses_panel_names_the_nodes_it_shows(layout) -> None:  # noqa: ANN001
    """Nodes are addressed by their depth-first id: a tree changed is a layout to change."""
    nodes = tree_nodes(build_tree("r1"))
    paths = layout["configById"]["StateTransitions!statuses"]["paths"]
    for path in paths:
        found = re.fullmatch(r"/behaviour_tree/nodes\.nodes\[(\d+)\]\.status", path["value"])
        assert found, path["value"]
        index = int(found.group(1))
        assert nodes[index]["name"] == path["label"], (
            f"{LAYOUT.name}: {path['value']} is {nodes[index]['name']!r}, labelled {path['label']!r}: the tree "
            "changed shape; give the layout the node's new id")
    assert paths[0]["value"].endswith("nodes[0].status")  # the root


def test_the_floor_is_seen_from_above_centred_on_the_lab(layout) -> None:  # noqa: ANN001
    """Foxglove's camera: phi 0 looks straight down, theta 0 puts world +x right and +y up
    (docs/conventions.md), ``targetOffset`` is the point looked at, in metres."""
    room = json.loads((LAYOUT.parents[1] / "hero_driver" / "worlds" / "lab.json").read_text(encoding="utf-8"))["room"]
    camera = layout["configById"]["3D!floor"]["cameraState"]
    assert (camera["perspective"], camera["phi"], camera["thetaOffset"]) == (False, 0, 0)
    centre = [room["width_in"] / 2 * topics.METRES_PER_INCH, room["depth_in"] / 2 * topics.METRES_PER_INCH, 0.0]
    assert camera["targetOffset"] == pytest.approx(centre, abs=0.005)

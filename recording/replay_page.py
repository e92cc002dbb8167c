"""The replay page of ``csl view``: one episode, read from a ``--record`` MCAP file or an
out folder, as one self-contained HTML file (the script, the style and the data inside
it; no server, no network) with a slider over the ticks. At each tick it shows the
behaviour tree coloured by status, the floor with the robot, its paths and the objects,
and each object's tests, grasps and outcome.

Where the tree's statuses come from: a recording has them for every node and tick
(``/behaviour_tree/nodes``). An out folder holds only the episode log, so its tree is
the executive's own (``executive.behaviour_tree.build_tree``, the same node ids) with
every status unknown, except the nodes an event names at a tick (marked ``active``)
and the root at the last tick (the episode's end status): a status guessed from the
log would look as certain as a recorded one.
"""

from __future__ import annotations

import base64
import json
import math
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mcap.reader import make_reader

from executive.behaviour_tree import build_tree
from executive.episode_log import IsRecording, read_log
from recording.reader import read_recorded_events
from recording.topics import MAP, METRES_PER_INCH, NODES, POSE
from recording.tree_nodes import tree_nodes
from recording.replay_template import TEMPLATE
from robot_profile import load_profile

UNKNOWN = "UNKNOWN"
"""A node's status where the source does not say it (an out folder without a recording)."""
ACTIVE = "ACTIVE"
"""A node an episode event names at that tick, in an out folder without a recording."""


@dataclass(frozen=True)
class Floor:
    """The overhead image laid on the floor, as the recording's first ``/map`` grid: row 0
    is the low-y edge; positions in inches."""

    x_in: float
    y_in: float
    cell_in: float
    columns: int
    rows: int
    pixels: bytes  # intensity, one byte a cell, row after row


@dataclass(frozen=True)
class Replay:
    """Everything the page draws, tick by tick; tick 0 is before the first tick."""

    source: str
    ticks: int
    tree_source: str  # "recording" or "rebuilt"
    nodes: tuple[dict[str, Any], ...]  # id, parent, name, kind, family
    statuses: tuple[tuple[str, ...], ...]  # [tick][node id]
    feedback: tuple[tuple[str, ...], ...]  # [tick][node id]
    poses: tuple[tuple[float, float, float] | None, ...]  # [tick]: x_in, y_in, heading_deg at the tick's end
    moves: tuple[dict[str, Any], ...]
    objects: tuple[dict[str, Any], ...]
    events: tuple[dict[str, Any], ...]
    floor: Floor | None
    base_radius_in: float
    images: dict[int, str]  # object index -> its decision-tree picture as a data: URI

    def status(self, tick: int, name: str) -> str:
        """The status of the first node called ``name`` at ``tick``."""
        node = next(n for n in self.nodes if n["name"] == name)
        return self.statuses[tick][node["id"]]


def load_replay(run: Path) -> Replay:
    """The episode of ``run``: a ``.mcap`` recording, or an out folder (its one
    recording when it holds one, else its ``episode.jsonl``). Bad input is a
    ``ValueError`` naming the file and what is wrong."""
    if not run.exists():
        raise ValueError(f"{run}: no such file or folder")
    folder = run if run.is_dir() else run.parent
    if run.is_dir():
        recordings = sorted(run.glob("*.mcap"))
        if len(recordings) == 1:
            run = recordings[0]
        elif (run / "episode.jsonl").is_file():
            run = run / "episode.jsonl"
        else:
            raise ValueError(f"{run}: not an out folder of csl run/demo (no episode.jsonl, no .mcap recording)")
    images = _tree_images(folder) if (folder / "episode.jsonl").is_file() else {}
    try:
        events = read_log(run)
        return replay(events, None, str(run), images=images)
    except IsRecording:
        pass
    events = read_recorded_events(run)
    ticks, floor, start, profile = _read_recording(run)
    return replay(events, ticks, str(run), floor=floor, start=start, images=images,
                  base_radius_in=_base_radius(profile))


def replay(events: Sequence[dict[str, Any]], tree_ticks: Sequence[dict[str, Any]] | None, source: str, *,
           floor: Floor | None = None, start: tuple[float, float, float] | None = None,
           images: dict[int, str] | None = None, base_radius_in: float | None = None) -> Replay:
    """The replay of an episode's events and, when recorded, its ``/behaviour_tree/nodes``
    messages (else the tree is rebuilt and its statuses are unknown). ``start``: the
    base's pose before the first tick, which a recording has (its first ``/robot/pose``)
    and the episode log does not."""
    if not events:
        raise ValueError(f"{source}: no episode in it (no events)")
    for n, e in enumerate(events, 1):
        if not isinstance(e, dict) or not isinstance(e.get("event"), str):
            raise ValueError(f"{source}: event {n} is not an episode event (an object with an 'event' name)")
    _check_tree(tree_ticks or (), source)
    last = max([_tick(e) for e in events] + [t["tick"] for t in tree_ticks or ()])
    if tree_ticks:
        nodes, statuses, feedback = _recorded_tree(tree_ticks, last, source)
        tree_source = "recording"
    else:
        nodes, statuses, feedback = _rebuilt_tree(events, last)
        tree_source = "rebuilt"
    moves = tuple(_move(e, source) for e in events if e.get("event") == "move")
    return Replay(source=source, ticks=last, tree_source=tree_source, nodes=nodes, statuses=statuses,
                  feedback=feedback, poses=_poses(moves, last, start), moves=moves, objects=objects(events, last),
                  events=tuple(events), floor=floor,
                  base_radius_in=_base_radius(None) if base_radius_in is None else base_radius_in,
                  images=images or {})


def _move(e: dict[str, Any], source: str) -> dict[str, Any]:
    """A ``move`` event as the map draws it, checked: ``pose`` is x, y, heading and
    ``path`` waypoints of x, y (and heading)."""
    def point(value: object, size: int) -> bool:
        return (isinstance(value, list) and len(value) >= size
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value[:size]))

    path = e.get("path", [])
    if not point(e.get("pose"), 3):
        raise ValueError(f"{source}: the move at tick {_tick(e)} has no 'pose' of x, y and heading")
    if not isinstance(path, list) or not all(point(p, 2) for p in path):
        raise ValueError(f"{source}: the move at tick {_tick(e)} has a 'path' that is not a list of x, y points")
    return {"tick": _tick(e), "object": e.get("object"), "path": [p[:2] for p in path], "pose": e["pose"][:3],
            "collided": bool(e.get("collided"))}


def _tick(event: dict[str, Any]) -> int:
    tick = event.get("tick", 0)
    return tick if isinstance(tick, int) and not isinstance(tick, bool) else 0


def _recorded_tree(tree_ticks: Sequence[dict[str, Any]], last: int, source: str
                   ) -> tuple[tuple[dict[str, Any], ...], tuple[tuple[str, ...], ...], tuple[tuple[str, ...], ...]]:
    """Statuses per tick as recorded; tick 0 all INVALID (nothing ticked yet); a tick
    with no message (none should be missing) keeps the tick before's."""
    first = tree_ticks[0]["nodes"]
    nodes = tuple({k: n[k] for k in ("id", "parent", "name", "kind", "family")} for n in first)
    by_tick = {t["tick"]: t["nodes"] for t in tree_ticks}
    statuses = [tuple("INVALID" for _ in nodes)]
    feedback = [tuple("" for _ in nodes)]
    for tick in range(1, last + 1):
        if tick in by_tick:
            if len(by_tick[tick]) != len(nodes):
                raise ValueError(f"{source}: {NODES.name} at tick {tick} has {len(by_tick[tick])} nodes, "
                                 f"the first tick {len(nodes)}")
            statuses.append(tuple(n["status"] for n in by_tick[tick]))
            feedback.append(tuple(n["feedback"] for n in by_tick[tick]))
        else:
            statuses.append(statuses[-1])
            feedback.append(feedback[-1])
    return nodes, tuple(statuses), tuple(feedback)


_NODE_KEYS = {"id", "parent", "name", "kind", "family", "status", "feedback"}


def _check_tree(tree_ticks: Sequence[object], source: str) -> None:
    for n, tick in enumerate(tree_ticks, 1):
        if not (isinstance(tick, dict) and isinstance(tick.get("tick"), int) and isinstance(tick.get("nodes"), list)
                and tick["nodes"] and all(isinstance(node, dict) and _NODE_KEYS <= node.keys()
                                          for node in tick["nodes"])):
            raise ValueError(f"{source}: message {n} on {NODES.name} is not a tick of nodes "
                             f"(keys {', '.join(sorted(_NODE_KEYS))})")


def _rebuilt_tree(events: Sequence[dict[str, Any]], last: int
                  ) -> tuple[tuple[dict[str, Any], ...], tuple[tuple[str, ...], ...], tuple[tuple[str, ...], ...]]:
    """The executive's tree as ``build_tree`` makes it (the same ids as a recording's) with
    what the log says of it: ACTIVE where an event names a node, the root's end status."""
    nodes = tuple({k: n[k] for k in ("id", "parent", "name", "kind", "family")} for n in tree_nodes(build_tree("r1")))
    named: dict[int, set[str]] = {}
    end = None
    for e in events:
        if isinstance(e.get("behaviour"), str):
            named.setdefault(_tick(e), set()).add(e["behaviour"])
        if e.get("event") == "episode_end" and isinstance(e.get("status"), str):
            end = e["status"]
    statuses = [tuple("INVALID" for _ in nodes)]
    for tick in range(1, last + 1):
        here = named.get(tick, set())
        row = [ACTIVE if n["name"] in here else UNKNOWN for n in nodes]
        if tick == last and end is not None:
            row[0] = end
        statuses.append(tuple(row))
    return nodes, tuple(statuses), tuple(tuple("" for _ in nodes) for _ in statuses)


def _poses(moves: Sequence[dict[str, Any]], last: int, start: tuple[float, float, float] | None
           ) -> tuple[tuple[float, float, float] | None, ...]:
    """Where the base is at the end of each tick: where the tick's last move stopped, else
    where it was; before the first move, at ``start`` (None when unknown: a move's
    ``path`` leaves out the pose it began at)."""
    pose = start
    out = [pose]
    stops = {m["tick"]: m["pose"] for m in moves}  # the last move of each tick wins
    for tick in range(1, last + 1):
        if tick in stops:
            pose = tuple(float(v) for v in stops[tick][:3])  # type: ignore[assignment]
        out.append(pose)
    return tuple(out)


def objects(events: Sequence[dict[str, Any]], last: int) -> tuple[dict[str, Any], ...]:
    """Each object as the map and its panel show it: where it was seen, the tick its turn
    began and ended, the grasp and outcome (grasped when a grasp succeeded, as a grasp
    or tried as a test; left when the tree chose not to grasp; failed when its turn ended
    without either), and its steps (the tests chosen, measured values, grasps)."""
    out: dict[int, dict[str, Any]] = {}
    regions = next((e.get("regions") for e in events if e.get("event") == "located"), None)
    regions = [r if isinstance(r, dict) else {} for r in regions] if isinstance(regions, list) else []
    for e in events:
        index = e.get("object")
        if not isinstance(index, int) or isinstance(index, bool):
            continue
        if index not in out:
            region = regions[index] if index < len(regions) else {}
            out[index] = {"index": index, "centroid": _xy(e.get("centroid")) or _xy(region.get("centroid")),
                          "pixels": _number(e.get("pixels")) or _number(region.get("pixels")), "start_tick": _tick(e),
                          "end_tick": None, "outcome": None, "grasp": None, "steps": []}
        record = out[index]
        if record["centroid"] is None:
            record["centroid"] = _xy(e.get("centroid"))
        if e.get("event") in _STEPS:
            record["steps"].append({"tick": _tick(e), "text": _step(e)})
        if record["outcome"] is None:
            if e.get("event") == "grasp" and e.get("success") is True:
                record.update(outcome="grasped", grasp=e.get("grasp"), end_tick=_tick(e))
            elif e.get("event") == "leave":
                record.update(outcome="left", grasp=e.get("grasp"), end_tick=_tick(e))
    ordered = sorted(out.values(), key=lambda r: r["start_tick"])
    for record, following in zip(ordered, [*ordered[1:], None]):
        if record["outcome"] is None:
            ended = following["start_tick"] if following else last
            ended_at_all = following is not None or any(e.get("event") == "episode_end" for e in events)
            if ended_at_all:
                record.update(outcome="failed", end_tick=ended)
    return tuple(sorted(out.values(), key=lambda r: r["index"]))


def _number(value: object) -> float | None:
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def _xy(value: object) -> list[float] | None:
    """A point on the floor as the log writes it, ``[x_in, y_in]``; None for anything else."""
    if isinstance(value, list) and len(value) == 2 and all(_number(v) is not None for v in value):
        return value
    return None


_STEPS = ("choose", "choose_grasp", "sense", "branch", "unreliable", "grasp", "discriminate", "start_over",
          "side_effect", "leave", "learn")


def _step(e: dict[str, Any]) -> str:
    """One line of an object's story (the fields ``csl log`` prints, shorter)."""
    kind = e.get("event")
    if kind == "choose":
        return f"test {e.get('test')} ({e.get('how')}, gain {e.get('gain')})"
    if kind == "choose_grasp":
        return f"grasp chosen: {e.get('grasp')} ({e.get('how')})"
    if kind in ("sense", "discriminate"):
        measured = e.get("values")
        values = ", ".join(f"{k} = {v}" for k, v in measured.items()) if isinstance(measured, dict) else ""
        return f"{'sensed' if kind == 'sense' else 'discriminate'}: {values}"
    if kind == "branch":
        return f"branch {e.get('test')} = {e.get('value')} in {e.get('range')}"
    if kind == "unreliable":
        return f"unreliable {e.get('test')} = {e.get('value')}"
    if kind == "grasp":
        how = "tried as a test" if e.get("as_feature") else "grasp"
        return f"{how}: {e.get('grasp')} {'succeeded' if e.get('success') else 'failed'}"
    if kind == "side_effect":
        return f"side effect: {e.get('effect')} (moved {e.get('shift_in')} in)"
    if kind == "start_over":
        return "start over"
    if kind == "leave":
        return f"left ({e.get('grasp')})"
    if kind == "learn":
        return f"learned {e.get('id')}" if e.get("id") else f"nothing learned ({e.get('reason', '')})"
    return str(kind)


def _tree_images(folder: Path) -> dict[int, str]:
    """The out folder's decision-tree pictures (``tree-N.png``, drawn by the demo), as
    data URIs so the page needs no file beside it."""
    images = {}
    for path in folder.glob("tree-*.png"):
        stem = path.stem.removeprefix("tree-")
        if stem.isdigit():
            images[int(stem)] = "data:image/png;base64," + base64.b64encode(path.read_bytes()).decode("ascii")
    return images


def _base_radius(profile: str | None) -> float:
    """The footprint drawn: the recording's robot profile when it can be read here (the
    path it was recorded with), else the default profile's."""
    if profile:
        try:
            return load_profile(profile).robot.geometry.base_radius_in
        except (OSError, ValueError):
            pass
    return load_profile().robot.geometry.base_radius_in


def _read_recording(path: Path
                    ) -> tuple[list[dict[str, Any]], Floor | None, tuple[float, float, float] | None, str | None]:
    """The recording's tree messages, its first floor map, the base's first pose and its
    robot profile's path."""
    ticks: list[dict[str, Any]] = []
    floor = start = None
    profile = None
    with path.open("rb") as f:
        reader = make_reader(f)
        for _, channel, message in reader.iter_messages(topics=[NODES.name, MAP.name, POSE.name],
                                                        log_time_order=True):
            if channel.topic == NODES.name:
                try:
                    ticks.append(json.loads(message.data))
                except ValueError:
                    raise ValueError(f"{path}: message {message.sequence} on {NODES.name} is not JSON") from None
            elif channel.topic == MAP.name and floor is None:
                floor = _floor(message.data)
            elif channel.topic == POSE.name and start is None:
                start = _pose(message.data)
        f.seek(0)
        for record in make_reader(f).iter_metadata():
            if record.name == "csl-run":
                profile = record.metadata.get("profile")
    return ticks, floor, start, profile


def _pose(data: bytes) -> tuple[float, float, float] | None:
    """A ``foxglove.PoseInFrame`` on the floor (pose 3: position 1, orientation 2) as
    x_in, y_in, heading_deg, read from its protobuf bytes by hand."""
    try:
        pose = _protobuf(_protobuf(data)[3][0])
        position, orientation = (_protobuf(pose.get(k, [b""])[0]) for k in (1, 2))
        x, y = (_double(position, k) for k in (1, 2))
        z, w = (_double(orientation, k) for k in (3, 4))
    except (KeyError, IndexError, struct.error, TypeError):
        return None
    return x / METRES_PER_INCH, y / METRES_PER_INCH, math.degrees(2 * math.atan2(z, w)) % 360


def _double(fields: dict[int, list[Any]], number: int) -> float:
    """A double field, 0 when absent (protobuf leaves zeros out)."""
    return struct.unpack("<d", fields.get(number, [b"\0" * 8])[0])[0]


def _floor(data: bytes) -> Floor | None:
    """A ``foxglove.Grid`` of one uint8 field, read from its protobuf bytes by hand (the
    few fields we write: pose 3, column_count 4, cell_size 5, row_stride 6, data 9); a
    grid of another shape is not drawn."""
    try:
        grid = _protobuf(data)
        position = _protobuf(_protobuf(grid[3][0])[1][0])
        cell = _protobuf(grid[5][0])
        x, y = (_double(position, k) for k in (1, 2))
        cell_x = _double(cell, 1)
        columns = grid[4][0]
        stride = grid.get(6, [columns])[0]
        pixels = grid[9][0]
    except (KeyError, IndexError, struct.error, TypeError):
        return None
    if not columns or stride != columns or len(pixels) % columns or not math.isfinite(cell_x) or cell_x <= 0:
        return None
    inch = METRES_PER_INCH
    return Floor(x / inch, y / inch, cell_x / inch, columns, len(pixels) // columns, pixels)


def _protobuf(data: bytes) -> dict[int, list[Any]]:
    """The fields of one protobuf message: varints and fixed32 as integers, fixed64 and
    length-delimited as bytes."""
    fields: dict[int, list[Any]] = {}
    i = 0
    while i < len(data):
        key, i = _varint(data, i)
        number, wire = key >> 3, key & 7
        if wire == 0:
            value, i = _varint(data, i)
        elif wire == 1:
            value, i = data[i:i + 8], i + 8
        elif wire == 2:
            size, i = _varint(data, i)
            value, i = data[i:i + size], i + size
        elif wire == 5:
            value, i = struct.unpack_from("<I", data, i)[0], i + 4
        else:
            raise TypeError(f"wire type {wire}")
        fields.setdefault(number, []).append(value)
    return fields


def _varint(data: bytes, i: int) -> tuple[int, int]:
    value = shift = 0
    while True:
        byte = data[i]
        value |= (byte & 0x7F) << shift
        i += 1
        if not byte & 0x80:
            return value, i
        shift += 7


def page_data(replay: Replay) -> dict[str, Any]:
    """What the page's script reads, as JSON."""
    floor = None
    if replay.floor is not None:
        f = replay.floor
        floor = {"x": f.x_in, "y": f.y_in, "cell": f.cell_in, "columns": f.columns, "rows": f.rows,
                 "pixels": base64.b64encode(f.pixels).decode("ascii")}
    return {"source": replay.source, "ticks": replay.ticks, "tree_source": replay.tree_source,
            "nodes": list(replay.nodes), "statuses": [list(s) for s in replay.statuses],
            "feedback": [list(s) for s in replay.feedback], "poses": list(replay.poses), "moves": list(replay.moves),
            "objects": list(replay.objects), "events": list(replay.events), "floor": floor,
            "base_radius": replay.base_radius_in, "images": {str(k): v for k, v in replay.images.items()}}


def page(replay: Replay) -> str:
    """The HTML page: the template with the data inside a ``<script type=application/json>``
    (``<`` escaped so no text in the data can end the element)."""
    data = json.dumps(page_data(replay), ensure_ascii=False, separators=(",", ":")).replace("<", "\\u003c")
    return TEMPLATE.replace("/*DATA*/", data).replace("<!--TITLE-->", _html(Path(replay.source).name))


def _html(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def write_page(replay: Replay, path: Path) -> None:
    """Write the page to ``path`` (its folder must exist)."""
    path.write_text(page(replay), encoding="utf-8")

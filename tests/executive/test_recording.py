"""An episode recorded as MCAP with Foxglove's schemas, read back with ``mcap``'s own
reader: the channels and schemas, and values checked against the episode itself."""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable
from pathlib import Path

import pytest
from mcap.reader import make_reader

from executive.defaults import EXAMPLE_LIBRARY
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from recording import topics
from recording.session import Recording
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from robot_profile import load_profile
from tests.executive.foxglove_wire import doubles, fields, named, vector

M = topics.METRES_PER_INCH


def record_episode(folder: Path, before_run: Callable[[Recording], None] | None = None,
                   **sinks: object) -> tuple[EpisodeResult, EpisodeLog, Recording]:
    """One lab episode of the in-process simulator, recorded (``mcap=``, ``live_port=``);
    ``before_run`` is called once the recording's channels exist (a live client joins)."""
    profile = load_profile()
    recording = Recording(profile.robot.geometry, **sinks)  # type: ignore[arg-type]
    log = EpisodeLog()
    learner = LocalLearner(folder / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    driver = recording.attach(SimulatedHero("r1", world="lab", seed=0, profile=profile), log)
    executive = Executive(driver, learner, profile=profile, log=log, on_tick=recording.tick)
    if before_run is not None:
        before_run(recording)
    driver.camera().result()
    try:
        result = executive.run(on_object=lambda record: recording.handled(record, f"thing {record.index}"))
    finally:
        executive.shutdown()
        learner.close()
    return result, log, recording


@pytest.fixture(scope="module")
def episode(tmp_path_factory: pytest.TempPathFactory) -> tuple[EpisodeResult, EpisodeLog, dict[str, list]]:
    folder = tmp_path_factory.mktemp("recording")
    result, log, recording = record_episode(folder, mcap=folder / "episode.mcap")
    recording.close()
    by_topic: dict[str, list] = {}
    with (folder / "episode.mcap").open("rb") as f:
        for schema, channel, message in make_reader(f).iter_messages(log_time_order=True):
            by_topic.setdefault(channel.topic, []).append((schema, channel, message))
    return result, log, by_topic


def test_every_channel_has_its_well_known_schema(episode) -> None:  # noqa: ANN001
    _, _, by_topic = episode
    assert set(by_topic) == {t.name for t in topics.ALL}
    for topic in topics.ALL:
        schema, channel, _ = by_topic[topic.name][0]
        assert schema.name == topic.schema
        ours = topic.schema.startswith("csl.")
        assert (channel.message_encoding, schema.encoding) == (("json", "jsonschema") if ours else
                                                               ("protobuf", "protobuf"))


def test_the_events_channel_is_the_episode_log(episode) -> None:  # noqa: ANN001
    _, log, by_topic = episode
    assert [json.loads(m.data) for _, _, m in by_topic[topics.EVENTS.name]] == log.events


def test_one_status_per_tick_in_py_trees_own_words(episode) -> None:  # noqa: ANN001
    result, _, by_topic = episode
    statuses = [json.loads(m.data) for _, _, m in by_topic[topics.STATUS.name]]
    assert [s["tick"] for s in statuses] == list(range(1, result.ticks + 1))
    assert statuses[-1]["status"] == result.status == "SUCCESS"
    first = statuses[0]["tree"]
    assert "{-} retrieve objects [" in first and "--> LocateObjects [✓] -- 7 objects" in first
    uuid = re.compile(r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}")
    assert not any(uuid.search(s["tree"]) or "\x1b" in s["tree"] for s in statuses)


def test_one_planned_path_per_move_from_where_the_last_stopped(episode) -> None:  # noqa: ANN001
    _, log, by_topic = episode
    moves = [e for e in log.events if e["event"] == "move"]
    paths = by_topic[topics.PATHS.name]
    assert len(paths) == len(moves) > 0
    for k, ((schema, _, message), move) in enumerate(zip(paths, moves), 1):
        (entity,) = named(message.data, schema.data, "SceneUpdate")["entities"]
        entity_fields = named(entity, schema.data, "SceneEntity")
        assert entity_fields["id"] == [f"move/{k}".encode()]
        (line,) = entity_fields["lines"]
        points = [vector(p) for p in named(line, schema.data, "LinePrimitive")["points"]]
        assert len(points) == len(move["path"]) + 1  # from where the move began
        for point, waypoint in zip(points[1:], move["path"]):
            assert math.isclose(point[0], waypoint[0] * M, abs_tol=0.1 * M)
            assert math.isclose(point[1], waypoint[1] * M, abs_tol=0.1 * M)


def test_the_pose_over_time_ends_where_the_last_move_stopped(episode) -> None:  # noqa: ANN001
    _, log, by_topic = episode
    transforms = by_topic[topics.TF.name]
    times = [m.log_time for _, _, m in transforms]
    assert times == sorted(times) and len(set(times)) == len(times)
    schema, _, message = transforms[-1]
    last = named(message.data, schema.data, "FrameTransform")
    assert (last["parent_frame_id"], last["child_frame_id"]) == ([b"world"], [b"base_link"])
    x, y, _ = vector(last["translation"][0])
    final = [e for e in log.events if e["event"] == "move"][-1]["pose"]
    assert math.isclose(x, final[0] * M, abs_tol=0.06 * M) and math.isclose(y, final[1] * M, abs_tol=0.06 * M)
    assert len(by_topic[topics.POSE.name]) == len(transforms)


def test_a_sonar_ray_per_sensing_procedure(episode) -> None:  # noqa: ANN001
    _, log, by_topic = episode
    senses = [e for e in log.events  # ApplyTest's and Discriminate's readings
              if e["event"] in ("sense", "discriminate") and "procedure" in e]
    rays = by_topic[topics.SONAR.name]
    assert len(rays) == len(senses) > 0
    for schema, _, message in rays:
        (ranges,) = named(message.data, schema.data, "LaserScan")["ranges"]
        (distance,) = doubles(ranges)  # type: ignore[arg-type]
        assert 0.0 < distance < 40 * M  # a sonar reading in front of an object, inches to metres


def test_the_camera_and_the_map_carry_the_overhead_image(episode) -> None:  # noqa: ANN001
    _, _, by_topic = episode
    schema, _, message = by_topic[topics.CAMERA.name][0]
    image = named(message.data, schema.data, "RawImage")
    width, height, encoding, step, data = (image[n][0] for n in ("width", "height", "encoding", "step", "data"))
    assert encoding == b"mono8" and step == width and len(data) == width * height  # type: ignore[arg-type,operator]
    schema, _, message = by_topic[topics.MAP.name][0]
    grid = named(message.data, schema.data, "Grid")
    assert grid["column_count"] == [width] and grid["row_stride"] == [width]
    (cells,) = grid["data"]
    assert len(cells) == width * height  # type: ignore[arg-type,operator]  # one uint8 intensity a cell
    assert cells[:width] == data[-width:]  # type: ignore[index]  # the grid's first row is the image's last (low y)


def test_each_object_ends_with_its_outcome(episode) -> None:  # noqa: ANN001
    result, _, by_topic = episode
    handled = []
    for schema, _, message in by_topic[topics.OBJECTS.name]:
        for entity in named(message.data, schema.data, "SceneUpdate")["entities"]:
            f = named(entity, schema.data, "SceneEntity")  # type: ignore[arg-type]
            if f["id"][0].startswith(b"object/"):  # type: ignore[union-attr]
                pairs = [fields(kv) for kv in f["metadata"]]  # type: ignore[arg-type]
                meta = {p[1][0].decode(): p[2][0].decode() for p in pairs}  # type: ignore[union-attr]
                handled.append((int(meta["object"]), meta["outcome"], meta["grasp"]))
    assert handled == [(r.index, r.outcome, r.grasp or "-") for r in result.objects]


def test_a_driver_without_a_state_does_not_stop_the_recording(tmp_path: Path) -> None:
    """Over zenoh a driver may have published nothing yet, or be gone: the episode says
    so in its own words; the recording carries on at the last robot time it knew."""
    from executive.behaviour_tree import build_tree
    from hero_driver.interface import UNAVAILABLE, DriverError

    class Gone:
        robot = "r1"

        def state(self) -> None:
            raise DriverError(UNAVAILABLE, "no driver alive")

    recording = Recording(load_profile().robot.geometry, mcap=tmp_path / "gone.mcap")
    log = EpisodeLog()
    recording.attach(Gone(), log)  # type: ignore[arg-type]
    recording.tick(1, build_tree())
    log.event("episode_end", status="INVALID", ticks=1)
    recording.close()
    with (tmp_path / "gone.mcap").open("rb") as f:
        topics_seen = [channel.topic for _, channel, _ in make_reader(f).iter_messages()]
    assert topics_seen == [topics.STATUS.name, topics.NODES.name, topics.EVENTS.name]

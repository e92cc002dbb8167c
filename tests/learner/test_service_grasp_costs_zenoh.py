"""Grasp costs over zenoh (docs/learner-protocol.md, ``record_grasps`` and
``grasp_costs``): a robot records its attempts to ``csl learner serve`` in its own
process and reads the totals back, a retried record counts once, bad records are
refused whole, the outbox client keeps deciding when the service is gone, and
``csl run --learner zenoh --learned-grasp-costs`` records every attempt of its episode.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Iterator
from pathlib import Path

import pytest

from csl_cli.main import main
from executive.grasp_attempts import attempt_costs
from learner.costs import GraspCostRecord
from learner.library.format import write_library_json
from learner.service.interface import MAX_GRASP_ATTEMPTS
from learner.service.outbox import Outbox, OutboxLearner
from learner.service.protocol import learner_keys
from tests.learner.fixtures import four_objects
from tests.learner.test_service_zenoh import ServiceProcess, robot
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh


@pytest.fixture
def service(tmp_path: Path) -> Iterator[ServiceProcess]:
    seed = tmp_path / "seed.json"
    write_library_json(seed, four_objects())
    process = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed)
    try:
        process.ready()
        yield process
    finally:
        process.close()


def test_attempts_recorded_by_one_robot_are_the_totals_another_reads(service: ServiceProcess) -> None:
    with robot(service) as r1, robot(service) as r2:
        assert r2.grasp_costs() == []  # a store that never recorded a grasp
        r1.record_grasp_attempts([("Front-Wrap", 240.0, True), ("Front-Wrap", 300.0, False)], key="ep/0")
        r1.record_grasp_attempts([("Top-Pinch", 63.0, True), ("Front-Wrap", 240.0, True)], key="ep/1")
        r1.record_grasp_attempts([("Top-Pinch", 63.0, True), ("Front-Wrap", 240.0, True)], key="ep/1")  # a retry
        assert r2.grasp_costs() == [GraspCostRecord("Front-Wrap", 2, 480.0, 1, 300.0),
                                    GraspCostRecord("Top-Pinch", 1, 63.0, 0, 0.0)]
        assert r2.version() == 1  # the descriptions did not change


def test_a_record_named_by_its_robot_is_that_robots_and_a_wildcard_name_is_refused(service: ServiceProcess,
                                                                                    tmp_path: Path) -> None:
    """``record_grasps/<robot>``: the name in the key says whose attempts they are (the
    store keeps each robot's weight apart); a wildcard in that place is refused with
    ``bad_request``, not run."""
    with robot(service) as r1:
        r1.record_grasp_attempts([("Front-Wrap", 240.0, True)], key="ep/0", robot="r1")
        r1.record_grasp_attempts([("Front-Wrap", 60.0, True)], key="ep/1")  # unnamed
        assert r1.grasp_costs() == [GraspCostRecord("Front-Wrap", 2, 300.0, 0, 0.0)]
    session = open_session(connect=[service.endpoint], connect_timeout_s=3.0)
    try:
        keys = learner_keys(service.name)
        request = b'{"v": 1, "key": "k", "attempts": [["Front-Wrap", 60, true]]}'
        [reply] = list(session.get(keys.rpc("record_grasps/*"), payload=request, timeout=5.0))
        assert reply.ok is None and b"bad_request" in reply.err.payload.to_bytes()
    finally:
        session.close()
    db = sqlite3.connect(tmp_path / "lib.sqlite")
    try:
        assert db.execute("SELECT robot, successes FROM grasp_costs_by_robot ORDER BY robot").fetchall() == [
            ("", 1), ("r1", 1)]
    finally:
        db.close()


BAD_RECORDS = [
    (b'{"v": 1, "key": "k"}', "missing field 'attempts'"),
    (b'{"v": 1, "attempts": [["Front-Wrap", 60, true]]}', "missing field 'key'"),  # a replay must count once
    (b'{"v": 1, "key": "k", "attempts": {}}', "attempts: must be a list"),
    (b'{"v": 1, "key": "k", "attempts": [["Front-Wrap", 60]]}', "attempts[0]: must be [grasp, seconds, success]"),
    (b'{"v": 1, "key": "k", "attempts": [["Front-Wrap", -1, true]]}',
     "attempts[0]: seconds must be a number from 0 to 86400"),
    (b'{"v": 1, "key": "k", "attempts": [["Front-Wrap", 1e999, true]]}', "seconds must be a number from 0 to 86400"),
    (b'{"v": 1, "key": "k", "attempts": [["Front-Wrap", "60", true]]}', "seconds must be a number from 0 to 86400"),
    (b'{"v": 1, "key": "k", "attempts": [["Front-Wrap", 60, 1]]}', "success must be true or false"),
    (b'{"v": 1, "key": "k", "attempts": [["Top-Pinch", 63, true], ["Juggle", 5, true]]}',
     "grasp 'Juggle' is not in the knowledge file"),
    (json.dumps({"v": 1, "key": "k", "attempts": [["Front-Wrap", 60, True]] * (MAX_GRASP_ATTEMPTS + 1)}).encode(),
     f"at most {MAX_GRASP_ATTEMPTS} in one record"),
    (b'{"v": 1, "attempts": [], "key": ""}', "key: an idempotency key is 1 to 100"),
    (b'{"v": 1, "key": "k", "attempts": [], "grasp": "Front-Wrap"}', "unknown field 'grasp'"),
]


def test_a_bad_record_is_refused_whole_and_the_node_keeps_serving(service: ServiceProcess) -> None:
    session = open_session(connect=[service.endpoint], connect_timeout_s=3.0)
    try:
        for payload, message in BAD_RECORDS:
            replies = list(session.get(learner_keys(service.name).rpc("record_grasps"), payload=payload, timeout=3.0))
            assert len(replies) == 1 and replies[0].err is not None, payload[:80]
            body = json.loads(replies[0].err.payload.to_bytes())
            assert body["code"] == "bad_request" and message in body["message"], body
            assert "\n" not in body["message"]
        replies = list(session.get(learner_keys(service.name).rpc("grasp_costs"), payload=b'{"v": 1, "x": 1}',
                                   timeout=3.0))
        assert "unknown field 'x'" in json.loads(replies[0].err.payload.to_bytes())["message"]
    finally:
        session.close()
    with robot(service) as r1:
        assert r1.grasp_costs() == []  # the good Top-Pinch beside the unknown grasp was not counted either
        with pytest.raises(ValueError, match="bad_request: .*seconds must be a number from 0 to 86400") as err:
            r1.record_grasp_attempts([("Front-Wrap", -5.0, False)])
        assert "\n" not in str(err.value)


def test_the_outbox_client_passes_records_and_keeps_the_last_costs_when_the_service_is_gone(
        service: ServiceProcess, tmp_path: Path) -> None:
    client = OutboxLearner(robot(service), Outbox(tmp_path / "outbox.sqlite"), service.name)
    try:
        client.record_grasp_attempts([("Front-Wrap", 240.0, True)], key="ep/0")
        assert client.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 240.0, 0, 0.0)]
        assert service.terminate() == 0
        client.record_grasp_attempts([("Front-Wrap", 300.0, False)], key="ep/1")  # dropped, counted
        assert client.grasp_records_lost == 1
        assert client.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 240.0, 0, 0.0)]  # the last received
    finally:
        client.close()


def test_csl_run_records_each_objects_grasps_with_the_zenoh_learner(service: ServiceProcess, tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert main(["run", "--learner", "zenoh", "--learner-name", service.name, "--learner-connect", service.endpoint,
                 "--outbox", str(tmp_path / "outbox.sqlite"), "--out", str(out), "--no-plots",
                 "--learned-grasp-costs"]) == 0
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    attempts = attempt_costs(events)
    with robot(service) as r1:
        recorded = r1.grasp_costs()
    assert recorded and sum(r.attempts for r in recorded) == len(attempts)  # every attempt, each once
    assert sum(r.success_s + r.failure_s for r in recorded) == pytest.approx(sum(a.seconds for a in attempts))


def test_a_robot_records_unnamed_to_a_service_from_before_named_records(tmp_path: Path,
                                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    """A service that serves only ``rpc/record_grasps`` answers the named key with
    ``'record_grasps/r1' is not a verb``: the client sends the record unnamed, once, and
    from then on unnamed."""
    import functools

    from learner.service import zenoh_node
    from learner.service.local import LocalLearner
    from learner.service.zenoh_client import ZenohLearner

    class OldServer(zenoh_node.RpcServer):
        def __init__(self, *args: object, **kwargs: object) -> None:
            kwargs.pop("named", None)
            super().__init__(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(zenoh_node, "RpcServer", OldServer)
    endpoint = free_endpoint()
    with LocalLearner(tmp_path / "old.sqlite", four_objects()) as service, \
            open_session(listen=[endpoint]) as session, zenoh_node.LearnerNode(service, session, "old"), \
            ZenohLearner("old", connect=[endpoint], timeout_s=3.0) as client:
        sent = functools.partial(client.record_grasp_attempts, robot="r1")
        sent([("Front-Wrap", 240.0, True)], key="ep/0")
        assert client._named_records is False
        sent([("Front-Wrap", 60.0, True)], key="ep/1")
        assert client.grasp_costs() == [GraspCostRecord("Front-Wrap", 2, 300.0, 0, 0.0)]

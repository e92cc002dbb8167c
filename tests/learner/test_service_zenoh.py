"""The learner service over zenoh: ``csl learner serve`` in its own process, robots as
``ZenohLearner`` clients, malformed requests, and a service that is not there.

Every service runs as a child process on a free 127.0.0.1 port with a temporary
database, and is killed when its test ends, pass or fail.
"""

from __future__ import annotations

import json
import os
import select
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from csl_cli.main import main
from learner.description import ObjectDescription
from learner.library.backup import check_file
from learner.library.checks import check_library
from learner.library.format import descriptions_to_json, write_library_json
from learner.library.store import LibraryStore, load_library
from learner.service.protocol import (MAX_REQUEST_BYTES, encode_learn_request, encode_record_grasps_request,
                                       learner_keys)
from learner.service.zenoh_client import ZenohLearner
from tests.learner.fixtures import P, desc, four_objects, hero
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.serving import HEADER_ROOM
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

REPO = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 20.0  # a cold interpreter importing numpy and zenoh on a busy box
# Fits the HERO 2000 profile the service checks against by default.
MUG = desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 10), ("Front-Hole?", P(6, None), 1))


class ServiceProcess:
    """``csl learner serve`` as a child process; :meth:`close` always ends it."""

    def __init__(self, db: Path, endpoint: str, seed: Path, name: str = "test", extra: tuple[str, ...] = ()) -> None:
        self.endpoint = endpoint
        self.name = name
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
        self.process = subprocess.Popen(
            [sys.executable, "-m", "csl_cli", "learner", "serve", "--name", name, "--db", str(db),
             "--seed-library", str(seed), "--listen", endpoint, *extra],
            cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def ready(self) -> str:
        """The process's one line printed once serving (it fails the test on exit or
        after START_TIMEOUT_S rather than hang)."""
        assert self.process.stdout is not None
        readable, _, _ = select.select([self.process.stdout], [], [], START_TIMEOUT_S)
        line = self.process.stdout.readline() if readable else ""
        if not line:
            self.close()
            pytest.fail(f"learner service did not start: {self.process.stderr.read() if self.process.stderr else ''}")
        return line

    def terminate(self) -> int:
        """SIGTERM, as a service manager would; the exit status. The bound is for a
        hang, not a speed: on the loaded 2-core CI machine a clean shutdown (the zenoh
        session closed, the store committed) once took over 10 s."""
        self.process.send_signal(signal.SIGTERM)
        return self.process.wait(30)

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait(10)
        for stream in (self.process.stdout, self.process.stderr):
            if stream:
                stream.close()


@pytest.fixture
def seed(tmp_path: Path) -> Path:
    path = tmp_path / "seed.json"
    write_library_json(path, four_objects())
    return path


@pytest.fixture
def service(tmp_path: Path, seed: Path) -> Iterator[ServiceProcess]:
    process = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed)
    try:
        process.ready()
        yield process
    finally:
        process.close()


def robot(service: ServiceProcess) -> ZenohLearner:
    return ZenohLearner(service.name, connect=[service.endpoint], timeout_s=3.0)


def test_one_robot_learns_and_the_other_sees_it(service: ServiceProcess) -> None:
    with robot(service) as r1, robot(service) as r2:
        seen = r2.library()
        assert seen.version == 1 and seen.descriptions == tuple(four_objects())
        assert r2.library() is seen  # unchanged version: the cached snapshot, no refetch

        assert r1.learn(MUG) == "mug"
        assert r2.version() == 2
        after = r2.library()
        assert after.version == 2 and after.descriptions == (*four_objects(), MUG)

        assert r2.learn(four_objects()[0]) == "cup#2"  # an id clash is a new encounter
        assert [d.object_id for d in r1.library().descriptions][-2:] == ["mug", "cup#2"]


def test_the_library_outlives_the_service_process(tmp_path: Path, seed: Path) -> None:
    endpoint = free_endpoint()
    first = ServiceProcess(tmp_path / "lib.sqlite", endpoint, seed)
    try:
        assert "4 descriptions, version 1" in first.ready()
        with robot(first) as r1:
            r1.learn(MUG)
        assert first.terminate() == 0  # SIGTERM is a clean shutdown
    finally:
        first.close()
    second = ServiceProcess(tmp_path / "lib.sqlite", endpoint, seed)
    try:
        assert "5 descriptions, version 2" in second.ready()  # the seed is not imported again
        with robot(second) as r1:
            assert r1.library().descriptions[-1] == MUG
    finally:
        second.close()


BAD_REQUESTS = [
    ("version", b"", "empty payload"),
    ("version", b"{not json", "not valid JSON"),
    ("version", b"[1]", "must be a JSON object"),
    ("version", b'{"v": 2}', "unsupported protocol version 2"),
    ("library", b'{"v": 1, "since": 3}', "unknown field 'since'"),
    ("changes", b'{"v": 1}', "missing field 'since'"),
    ("changes", b'{"v": 1, "since": "3"}', "since: must be a non-negative integer"),
    ("learn", b'{"v": 1}', "missing field 'description'"),
    ("learn", b'{"v": 1, "description": {"id": "x", "grasp": "G"}}', "missing field 'grasp_position'"),
    ("learn", json.dumps({"v": 1, "description": {"id": "x", "grasp": "G", "grasp_position": [6, "*"],
                                                  "features": [{"feature": "H", "position": [6, "*"],
                                                                "value": float("nan")}]}}).encode(),
     "'value' must be a finite number"),
    ("learn", b'{"v": 1, "description": ' + b" " * MAX_REQUEST_BYTES + b"{}}",
     f"learn: message: {MAX_REQUEST_BYTES + 27} bytes, more than the {MAX_REQUEST_BYTES} a request may have"),
    ("*", b'{"v": 1}', "verbs must be addressed by their exact key"),
    ("forget", b'{"v": 1}', "'forget' is not a verb"),
]


def test_malformed_requests_get_error_replies_and_the_node_keeps_serving(service: ServiceProcess) -> None:
    session = open_session(connect=[service.endpoint], connect_timeout_s=3.0)
    try:
        for verb, payload, message in BAD_REQUESTS:
            replies = list(session.get(learner_keys(service.name).rpc(verb), payload=payload, timeout=3.0))
            assert len(replies) == 1 and replies[0].err is not None, (verb, payload)
            body = json.loads(replies[0].err.payload.to_bytes())
            assert body["v"] == 1 and body["code"] == "bad_request" and message in body["message"], body
    finally:
        session.close()
    with robot(service) as r1:
        assert r1.version() == 1  # nothing was learned from the bad requests
        assert r1.learn(MUG) == "mug"


def test_a_request_beyond_the_cap_and_its_headers_room_is_dropped_unread(service: ServiceProcess) -> None:
    """zenoh drops it while reassembling (the service's session receives at most the cap
    plus HEADER_ROOM), so it is never held whole: the query only times out, and the
    same session, and everyone else, is served on (BENCHMARKS.md, "Oversized requests")."""
    session = open_session(connect=[service.endpoint], connect_timeout_s=3.0)
    try:
        body = b'{"v": 1, "description": "' + b"x" * (MAX_REQUEST_BYTES + HEADER_ROOM) + b'"}'
        replies = list(session.get(learner_keys(service.name).rpc("learn"), payload=body, timeout=1.0))
        assert [r.ok for r in replies] == [None] and replies[0].err.payload.to_bytes() == b"Timeout"
        [after] = list(session.get(learner_keys(service.name).rpc("version"), payload=b'{"v": 1}', timeout=3.0))
        assert json.loads(after.ok.payload.to_bytes()) == {"v": 1, "version": 1}
    finally:
        session.close()


def test_a_description_the_service_refuses_is_a_one_line_value_error(service: ServiceProcess) -> None:
    with robot(service) as r1:
        with pytest.raises(ValueError) as err:
            r1.learn(desc("", "Front-Wrap"))
        assert "bad_request" in str(err.value) and "'id'" in str(err.value) and "\n" not in str(err.value)
        assert r1.version() == 1


def test_no_service_running_fails_with_one_line() -> None:
    with pytest.raises(ConnectionError) as err:
        ZenohLearner("test", connect=[free_endpoint()], timeout_s=0.5)
    assert "learner 'test'" in str(err.value) and "\n" not in str(err.value)


def test_a_service_under_another_name_is_not_this_one(service: ServiceProcess) -> None:
    with pytest.raises(ConnectionError, match="no learner service 'other'"):
        ZenohLearner("other", connect=[service.endpoint], timeout_s=0.5)


def test_a_call_after_the_service_stopped_fails_without_hanging(service: ServiceProcess) -> None:
    with robot(service) as r1:
        assert service.terminate() == 0
        with pytest.raises(ConnectionError, match="learner 'test'"):
            r1.version()


def test_serve_refuses_bad_arguments_with_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["learner", "serve", "--name", "a/b", "--db", str(tmp_path / "l.sqlite")]) == 2
    assert "learner name 'a/b'" in capsys.readouterr().err
    assert main(["learner", "serve", "--listen", "7448", "--db", str(tmp_path / "l.sqlite")]) == 2
    assert "must look like tcp/HOST:PORT" in capsys.readouterr().err


def test_serve_on_a_taken_port_exits_2_with_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as squatter:
        squatter.bind(("127.0.0.1", int(endpoint.rsplit(":", 1)[1])))
        squatter.listen()
        assert main(["learner", "serve", "--listen", endpoint, "--db", str(tmp_path / "l.sqlite")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("csl: error: zenoh session on ") and err.count("\n") == 1


def test_a_call_to_a_killed_service_fails_in_one_line(service: ServiceProcess) -> None:
    with ZenohLearner(service.name, connect=[service.endpoint], timeout_s=1.0) as r1:
        service.close()  # SIGKILL: nothing is undeclared, the lease has to run out
        with pytest.raises(ConnectionError, match="learner 'test': version: ") as err:
            r1.version()
        assert "\n" not in str(err.value)


def learn_payload(description: ObjectDescription, value: float) -> bytes:
    """A ``learn`` request for ``description`` with its first value replaced, written as
    a careless client would (NaN included, which the protocol's own encoder refuses)."""
    entry = descriptions_to_json([description])["descriptions"][0]  # type: ignore[index]
    entry["features"][0]["value"] = value
    return json.dumps({"v": 1, "description": entry}).encode()


UNUSABLE = [
    (learn_payload(desc("huge", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 0)), 1e308),
     "description 'huge': Width-Degree-1°(24,0) = 1e+308 is outside [0, 180]"),
    (learn_payload(desc("nan", "Front-Wrap", ("Height", P(6, None), 0)), float("nan")),
     "features[0]: 'value' must be a finite number"),
    (learn_payload(desc("colour", "Front-Wrap", ("Colour", P(6, None), 0)), 3),
     "description 'colour': feature 'Colour' is not yielded by any sensing procedure"),
]


def test_a_description_the_robot_cannot_use_is_refused_and_the_service_keeps_serving(service: ServiceProcess) -> None:
    session = open_session(connect=[service.endpoint], connect_timeout_s=3.0)
    try:
        for payload, message in UNUSABLE:
            replies = list(session.get(learner_keys(service.name).rpc("learn"), payload=payload, timeout=3.0))
            assert len(replies) == 1 and replies[0].err is not None, payload
            body = json.loads(replies[0].err.payload.to_bytes())
            assert body["code"] == "bad_request" and message in body["message"], body
            assert "\n" not in body["message"]
    finally:
        session.close()
    with robot(service) as r1:
        assert r1.version() == 1  # nothing was stored
        assert r1.learn(MUG) == "mug"  # a good one after the bad ones
        assert r1.library().descriptions == (*four_objects(), MUG)


def test_a_poisoned_store_is_served_without_its_bad_descriptions(tmp_path: Path, seed: Path) -> None:
    db = tmp_path / "lib.sqlite"
    with LibraryStore(db) as store:  # as a service before admission existed could leave it
        store.add([*four_objects()[:2], desc("huge", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 1e308)),
                   *four_objects()[2:], desc("colour", "Front-Wrap", ("Colour", P(6, None), 3))])
    process = ServiceProcess(db, free_endpoint(), seed)
    try:
        assert "4 descriptions" in process.ready()
        with robot(process) as r1:
            served = r1.library().descriptions
            assert served == tuple(four_objects())
            check_library(served, hero(), "the library")  # what `csl run` checks before moving: passes
            assert r1.learn(MUG) == "mug"
        assert process.terminate() == 0
        assert process.process.stderr is not None
        reports = process.process.stderr.read().splitlines()[:2]  # printed before the ready line
        assert [line.split(": ")[1] for line in reports] == [
            f"quarantined 'huge' (kept in {db}, not served)", f"quarantined 'colour' (kept in {db}, not served)"]
        assert "1e+308 is outside" in reports[0] and "'Colour' is not yielded" in reports[1]
    finally:
        process.close()
    assert [d.object_id for d in load_library(db)] == ["cup", "box", "huge", "tumbler", "closed", "colour", "mug"]


def test_serve_refuses_a_missing_knowledge_file_with_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["learner", "serve", "--db", str(tmp_path / "lib.sqlite"),
                 "--knowledge", str(tmp_path / "nope.toml"), "--listen", free_endpoint()]) == 2
    err = capsys.readouterr().err
    assert "nope.toml" in err and len(err.strip().splitlines()) == 1


def test_the_largest_requests_a_client_sends_are_well_under_the_cap() -> None:
    """The size cap refuses only what no client sends: the largest description of the
    exhaustive-training library as a learn, and a record of the most attempts allowed,
    each with the longest key."""
    from executive.sim_training import train_in_simulator
    from experiments.exhaustive import exhaustive_library
    from learner.service.interface import MAX_GRASP_ATTEMPTS, MAX_KEY_CHARS
    from robot_profile import load_profile

    profile = load_profile()
    knowledge = profile.knowledge()
    trained = train_in_simulator(knowledge, profile)
    log = trained.result.log
    richest, _ = exhaustive_library(list(trained.seen.objects), knowledge, trained.source, log.distances,
                                    log.orientations)
    key = "k" * MAX_KEY_CHARS
    largest = max(len(encode_learn_request(d, key)) for d in richest)
    grasps = len(encode_record_grasps_request([("Top-Vert-Grip", 86_399.999999, False)] * MAX_GRASP_ATTEMPTS, key))
    assert max(largest, grasps) * 2 < MAX_REQUEST_BYTES


def test_the_service_keeps_a_backup_while_it_serves_and_a_last_one_when_it_stops(tmp_path: Path, seed: Path) -> None:
    """``--backup``: taken when serving starts, every ``--backup-every`` seconds (so what a
    robot learned is in it soon after), and once more on SIGTERM."""
    copy = tmp_path / "backup.sqlite"
    process = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed,
                             extra=("--backup", str(copy), "--backup-every", "0.3"))
    try:
        process.ready()
        with robot(process) as r1:
            r1.learn(MUG)
        deadline = time.monotonic() + 10.0
        while "mug" not in _backed_up(copy) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert "mug" in _backed_up(copy)  # a periodic backup, the service still serving
        assert process.terminate() == 0
    finally:
        process.close()
    assert check_file(copy) == [] and "mug" in _backed_up(copy)


def _backed_up(path: Path) -> set[str]:
    if not path.exists():
        return set()
    with LibraryStore(path) as store:
        return {d.object_id for d in store.descriptions()}

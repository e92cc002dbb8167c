"""docs/security.md's router deployment, run as written: TLS with a certificate made
by the page's own openssl commands, a password per process and access control on a
router. Every file comes from the page (``7447`` replaced by a free port),
the router, ``csl driver sim`` and ``csl learner serve`` are real processes on
127.0.0.1, and the test's own sessions play the stranger, the monitor and the
executive. What must hold: a session without credentials, and the read-only monitor,
cannot move the robot or write to the library; the executive can.
"""

from __future__ import annotations

import json
import os
import re
import select
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
import zenoh

from hero_driver.interface import Pose
from hero_driver.zenoh_link.client import ZenohDriver
from learner.service.zenoh_client import ZenohLearner
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import UserConfig, open_session
from zenoh_rpc.router import main as router_main

pytestmark = pytest.mark.zenoh

REPO = Path(__file__).resolve().parents[2]
PAGE = REPO / "docs" / "security.md"
START_TIMEOUT_S = 30.0  # a cold interpreter importing numpy, pymunk and zenoh on a busy box
DENIED_WAIT_S = 2.0  # how long a denied query is given to (not) answer
FILES = ("users.txt", "router.json5", "driver.json5", "learner.json5", "executive.json5", "monitor.json5")


def page_files() -> tuple[str, dict[str, str]]:
    """The certificate commands and every ``File `NAME`:`` block of the page's router section."""
    text = PAGE.read_text(encoding="utf-8")
    section = text[text.index("## Access control, through a router"):]
    [commands] = re.findall(r"```sh\n(.*?)```", section, re.S)
    files = dict(re.findall(r"File `([\w.]+)`[^\n]*\n(?:[^\n]+\n)*?\n```\w*\n(.*?)```", section, re.S))
    return commands, files


def test_the_page_gives_every_file_the_test_needs(tmp_path: Path) -> None:
    commands, files = page_files()
    assert set(files) == set(FILES)
    assert "openssl req -x509" in commands and "router.crt" in commands
    for name in FILES:
        if name.endswith(".json5"):
            (tmp_path / name).write_text(files[name], encoding="utf-8")
            UserConfig(tmp_path / name)  # zenoh parses each one


@pytest.mark.parametrize(("text", "says"), [
    ('{ mode: "peer" }', 'mode is "peer", not "router"'),
    ('{ mode: "router", listen: { endpoints: ["tls/127.0.0.1:1"] }, pasword: 1 }', "unknown field"),
])
def test_the_router_refuses_a_file_it_cannot_route_with_in_one_line(tmp_path: Path, text: str, says: str,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    config = tmp_path / "router.json5"
    config.write_text(text, encoding="utf-8")
    assert router_main([str(config)]) == 2
    [line] = capsys.readouterr().err.splitlines()
    assert line.startswith(f"zenoh_rpc.router: router config {config}: ") and says in line


def _env() -> dict[str, str]:
    """This checkout on the path; no config but the one each command is given."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    env.pop("CSL_ZENOH_CONFIG", None)
    return env


@dataclass
class Deployment:
    folder: Path
    port: int
    processes: list[subprocess.Popen[str]] = field(default_factory=list)

    def config(self, name: str) -> UserConfig:
        return UserConfig(self.folder / name)

    def start(self, argv: list[str], ready: str) -> None:
        process = subprocess.Popen([sys.executable, *argv], cwd=self.folder, env=_env(), stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True)
        self.processes.append(process)
        assert process.stdout is not None
        readable, _, _ = select.select([process.stdout], [], [], START_TIMEOUT_S)
        line = process.stdout.readline() if readable else ""
        if not line.startswith(ready):
            process.kill()
            pytest.fail(f"{' '.join(argv)} did not start: {line}{process.stderr.read() if process.stderr else ''}")

    def stop(self) -> None:
        for process in reversed(self.processes):
            if process.poll() is None:
                process.kill()
            process.wait(10)
            for stream in (process.stdout, process.stderr):
                if stream:
                    stream.close()


@pytest.fixture(scope="module")
def deployment(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Deployment]:
    """The page's router, driver node and learner service, in a folder holding the
    page's files and the certificates its commands made."""
    if shutil.which("openssl") is None:
        pytest.skip("the page makes its certificates with the openssl command, which is not installed")
    folder = tmp_path_factory.mktemp("router")
    commands, files = page_files()
    made = subprocess.run(["bash", "-e", "-c", commands], cwd=folder, capture_output=True, text=True, timeout=60)
    assert made.returncode == 0, made.stderr
    port = int(free_endpoint().rsplit(":", 1)[1])
    for name, text in files.items():
        (folder / name).write_text(text.replace("127.0.0.1:7447", f"127.0.0.1:{port}"), encoding="utf-8")
    (folder / "users.txt").chmod(0o600)
    running = Deployment(folder, port)
    try:
        running.start(["-m", "zenoh_rpc.router", "router.json5"], "routing on")
        running.start(["-m", "csl_cli", "driver", "sim", "--zenoh-config", "driver.json5"], "serving hero/r1")
        running.start(["-m", "csl_cli", "learner", "serve", "--zenoh-config", "learner.json5",
                       "--db", str(folder / "library.sqlite")], "serving learner 'default'")
        yield running
    finally:
        running.stop()


@pytest.fixture
def in_folder(deployment: Deployment, monkeypatch: pytest.MonkeyPatch) -> Deployment:
    """The test's own sessions read the same files, whose paths are relative."""
    monkeypatch.chdir(deployment.folder)
    return deployment


def executive_driver(deployment: Deployment) -> ZenohDriver:
    driver = ZenohDriver("r1", connect=(), discover_s=5.0, zenoh_config=deployment.config("executive.json5"))
    assert driver.wait_ready(10.0)
    return driver


def executive_learner(deployment: Deployment) -> ZenohLearner:
    return ZenohLearner("default", connect=(), zenoh_config=deployment.config("executive.json5"))


def answers(session: zenoh.Session, key: str, payload: bytes) -> list[bool]:
    """For each reply to a query: True for an answer, False for an error reply."""
    return [reply.ok is not None for reply in session.get(key, payload=payload, timeout=DENIED_WAIT_S)]


def move_request(x_in: float, y_in: float) -> bytes:
    return json.dumps({"v": 1, "waypoints": [{"x_in": x_in, "y_in": y_in, "heading_deg": 0.0}]}).encode()


@pytest.mark.parametrize("who", ["no user name", "a wrong password"])
def test_a_session_without_valid_credentials_cannot_even_connect(in_folder: Deployment, who: str) -> None:
    text = (in_folder.folder / "executive.json5").read_text(encoding="utf-8")
    if who == "no user name":
        text = re.sub(r"auth: \{.*?\} \},", "", text, flags=re.S)
    else:
        text = text.replace("correct-horse", "battery-staple")
    stranger = in_folder.folder / "stranger.json5"
    stranger.write_text(text, encoding="utf-8")
    with pytest.raises(ConnectionError, match=r"^zenoh session on .*Unable to connect"):
        open_session(user=UserConfig(stranger)).close()


def test_the_monitor_watches_but_cannot_move_the_robot_or_learn(in_folder: Deployment) -> None:
    driver = executive_driver(in_folder)
    learner = executive_learner(in_folder)
    try:
        before, version = driver.state().pose, learner.version()
        monitor = open_session(user=in_folder.config("monitor.json5"))
        try:
            states: list[bytes] = []
            seen = threading.Event()

            def on_state(sample: zenoh.Sample) -> None:
                states.append(sample.payload.to_bytes())
                seen.set()

            subscriber = monitor.declare_subscriber("hero/r1/state", on_state)
            assert seen.wait(5.0)  # its read path works: what follows is refused, not lost
            assert len(list(monitor.liveliness().get("hero/r1/alive", timeout=DENIED_WAIT_S))) == 1
            assert answers(monitor, "csl/learner/default/rpc/version", b'{"v": 1}') == [True]

            assert answers(monitor, "hero/r1/rpc/noop", b'{"v": 1}') == []
            assert answers(monitor, "hero/r1/rpc/move", move_request(before.x_in + 40.0, before.y_in + 30.0)) == []
            entry = learner.library().descriptions[0]
            learn = json.dumps({"v": 1, "description": _entry_json(entry)}).encode()
            assert answers(monitor, "csl/learner/default/rpc/learn", learn) == []
            subscriber.undeclare()
        finally:
            monitor.close()
        assert driver.state().pose == before  # the robot did not move
        assert learner.version() == version  # nothing was stored
    finally:
        driver.close()
        learner.close()


@pytest.mark.parametrize("forger", ["monitor", "executive"])
def test_a_forged_state_and_token_never_reach_the_executive(in_folder: Deployment, forger: str) -> None:
    """Only the driver speaks for its robot: a monitor, or another session of the
    executive's own user, that publishes a state (a pose far away, the battery nearly
    flat) and declares the robot's liveliness token is dropped by the router, so a
    session of the executive's sees neither (every state it receives meanwhile is the
    driver's; no token appears)."""
    executive = open_session(user=in_folder.config("executive.json5"))
    received: list[dict[str, object]] = []
    appeared: list[str] = []
    states = executive.declare_subscriber("hero/r1/state", lambda sample: received.append(
        json.loads(sample.payload.to_bytes())))
    tokens = executive.liveliness().declare_subscriber("hero/r1/alive", lambda sample: appeared.append(
        str(sample.kind)))
    try:
        time.sleep(0.5)  # the driver's 5 Hz states arrive: the path is open
        assert received
        monitor = open_session(user=in_folder.config(f"{forger}.json5"))
        try:
            forged = {"v": 1, "pose": {"x_in": 999.0, "y_in": 999.0, "heading_deg": 90.0}, "clock_s": 1.0,
                      "battery": 0.02}
            token = monitor.liveliness().declare_token("hero/r1/alive")
            for _ in range(20):
                monitor.put("hero/r1/state", json.dumps(forged).encode())
                time.sleep(0.05)
            time.sleep(0.5)
            token.undeclare()
            time.sleep(0.2)
        finally:
            monitor.close()
    finally:
        states.undeclare()
        tokens.undeclare()
        executive.close()
    assert len(received) > 5 and all(state["pose"] != forged["pose"] for state in received)
    assert appeared == []  # neither the monitor's token nor its going


def test_the_executive_records_grasp_costs_as_its_own_robot_only(in_folder: Deployment) -> None:
    """The router lets the executive's user query ``record_grasps/r1`` and nothing else
    of ``record_grasps``: a record as another robot, or unnamed, gets no reply and adds
    nothing, so one robot's weight in the fleet's grasp prices is what
    ``learner.costs.ROBOT_WEIGHT`` allows r1 (docs/security.md)."""
    learner = executive_learner(in_folder)
    try:
        before = {r.grasp: r.attempts for r in learner.grasp_costs()}
        learner.record_grasp_attempts([("Front-Wrap", 30.0, True)], robot="r1")
        after = {r.grasp: r.attempts for r in learner.grasp_costs()}
        assert after["Front-Wrap"] == before.get("Front-Wrap", 0) + 1
        executive = open_session(user=in_folder.config("executive.json5"))
        try:
            request = json.dumps({"v": 1, "attempts": [["Front-Wrap", 30.0, True]], "key": "as-another"}).encode()
            assert answers(executive, "csl/learner/default/rpc/record_grasps/r2", request) == []
            assert answers(executive, "csl/learner/default/rpc/record_grasps", request) == []
        finally:
            executive.close()
        assert {r.grasp: r.attempts for r in learner.grasp_costs()} == after
    finally:
        learner.close()


def test_the_monitor_reads_the_state_with_csl_driver_state(in_folder: Deployment) -> None:
    watched = subprocess.run([sys.executable, "-m", "csl_cli", "driver", "state", "r1", "--zenoh-config",
                              "monitor.json5", "--count", "1", "--timeout", "10"],
                             cwd=in_folder.folder, env=_env(), capture_output=True, text=True, timeout=60)
    assert watched.returncode == 0, watched.stderr
    [line] = watched.stdout.splitlines()
    assert set(json.loads(line)) >= {"pose", "clock_s", "battery"}


def test_the_executive_moves_the_robot_and_learns(in_folder: Deployment) -> None:
    driver = executive_driver(in_folder)
    learner = executive_learner(in_folder)
    try:
        before = driver.state().pose
        goal = Pose(before.x_in + 30.0, before.y_in + 20.0, 0.0)
        moved = driver.move([goal]).result(timeout=30)
        assert (round(moved.pose.x_in), round(moved.pose.y_in)) == (round(goal.x_in), round(goal.y_in))
        version = learner.version()
        stored = learner.learn(learner.library().descriptions[0])
        assert learner.version() == version + 1
        assert stored in {d.object_id for d in learner.library().descriptions}
    finally:
        driver.close()
        learner.close()


@pytest.mark.slow
def test_a_whole_episode_runs_through_the_router(in_folder: Deployment, tmp_path: Path) -> None:
    learner = executive_learner(in_folder)
    try:
        version = learner.version()
    finally:
        learner.close()
    run = subprocess.run([sys.executable, "-m", "csl_cli", "run", "--driver", "zenoh", "--learner", "zenoh",
                          "--zenoh-config", "executive.json5", "--out", str(tmp_path / "out"), "--no-plots",
                          "--outbox", str(tmp_path / "outbox.sqlite")],
                         cwd=in_folder.folder, env=_env(), capture_output=True, text=True, timeout=180)
    assert run.returncode in (0, 1), run.stderr  # the episode ran to its end: not lost, not refused
    assert "exit status " in run.stdout
    events = [json.loads(line) for line in (tmp_path / "out" / "episode.jsonl").read_text().splitlines()]
    learned = [e for e in events if e["event"] == "learn" and e.get("id")]
    assert learned and not any(str(e["id"]).startswith("queued:") for e in learned)  # stored, not left waiting
    learner = executive_learner(in_folder)
    try:
        assert learner.version() == version + len(learned)
    finally:
        learner.close()


def _entry_json(description: object) -> object:
    """One library entry as the learn request carries it (the protocol's own encoder)."""
    from learner.service.protocol import encode_learn_request

    return json.loads(encode_learn_request(description))["description"]  # type: ignore[arg-type]

"""The wire fuzzer: hostile payloads on the keys of real node processes.

``csl driver sim`` and ``csl learner serve`` run as child processes on 127.0.0.1; a
plain zenoh session sends the driver-verb and learner-request cases of
``surfaces.py`` (and queries on verbs that do not exist) to their keys. Every query is
answered in time, and an error answer is a protocol error other than ``internal``
(unless it is a finding already reduced in ``test_findings.py``). Afterwards each node
still answers a good request and its liveliness token is still up.
"""

from __future__ import annotations

import os
import re
import select
import subprocess
import sys
from collections import Counter
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.keys import robot_keys
from learner.service import protocol
from learner.service.protocol import learner_keys
from tests.fuzz.surfaces import (KNOWN, LIBRARY, REPO, driver_cases, learner_cases, learner_changes_cases,
                                  learner_grasps_cases)
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

pytestmark = [pytest.mark.zenoh, pytest.mark.filterwarnings("ignore::hypothesis.errors.HypothesisWarning")]

NAME = "fuzz"
ANSWER_S = 10.0  # far above any answer's time: a query left unanswered is a hang
START_S = 30.0


class Node:
    """One ``csl`` server as a child process; ends it on :meth:`close`."""

    def __init__(self, argv: list[str]) -> None:
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
        self.process = subprocess.Popen([sys.executable, "-m", "csl_cli", *argv], cwd=REPO, env=env,
                                        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)

    def ready(self) -> None:
        assert self.process.stdout is not None
        readable, _, _ = select.select([self.process.stdout], [], [], START_S)
        line = self.process.stdout.readline() if readable else ""
        if "serving" not in line:
            self.close()
            pytest.fail(f"{self.process.args} did not start: {line!r}")

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait(10)
        if self.process.stdout:
            self.process.stdout.close()


@pytest.fixture(scope="module")
def nodes(tmp_path_factory: pytest.TempPathFactory) -> Iterator[list[str]]:
    folder = Path(tmp_path_factory.mktemp("wire"))
    driver_at, learner_at = free_endpoint(), free_endpoint()
    driver = Node(["driver", "sim", "--robot", NAME, "--listen", driver_at])
    learner = Node(["learner", "serve", "--name", NAME, "--db", str(folder / "lib.sqlite"),
                    "--seed-library", str(LIBRARY), "--listen", learner_at])
    try:
        driver.ready()
        learner.ready()
        yield [driver_at, learner_at]
    finally:
        driver.close()
        learner.close()


def ask(session, key: str, payload: bytes) -> tuple[str, bytes]:
    """("ok" | "err", body) of the one reply, or ("none", b"") when none came in time."""
    for answer in session.get(key, payload=payload, timeout=ANSWER_S):
        if answer.ok is not None:
            return "ok", answer.ok.payload.to_bytes()
        return "err", answer.err.payload.to_bytes()
    return "none", b""


def known(surface: str, message: str) -> bool:
    return any(re.search(pattern, message) for pattern, _ in KNOWN.get(surface, ()))


wire_cases = st.one_of(
    driver_cases.map(lambda c: ("driver", *c)),
    learner_cases.map(lambda c: ("learner", *c)),
    learner_changes_cases.map(lambda c: ("learner", *c)),
    learner_grasps_cases.map(lambda c: ("learner", *c)),
    st.tuples(st.sampled_from(["driver", "learner"]), st.sampled_from(["fly", "x", "move2", "Learn"]),
              st.binary(max_size=32)),
)


def test_nodes_answer_every_hostile_payload_and_stay_up(nodes: list[str]) -> None:
    keys = {"driver": robot_keys(NAME), "learner": learner_keys(NAME)}
    decode_error = {"driver": codec.decode_error, "learner": protocol.decode_error}
    seen: Counter[str] = Counter()
    with open_session(connect=nodes, connect_timeout_s=10.0) as session:

        @settings(max_examples=150, deadline=None, database=None, derandomize=True,
                  suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
        @given(wire_cases)
        def one_case(case: tuple[str, str, bytes]) -> None:
            node, verb, payload = case
            outcome, body = ask(session, keys[node].rpc(verb), payload)
            assert outcome != "none", f"{node} {verb}: no answer in {ANSWER_S} s to {payload[:80]!r}"
            if outcome == "ok":
                seen["ok"] += 1
                return
            error = decode_error[node](body)
            code, message = (error.code, error.message) if node == "driver" else error
            if code == "internal" and known(node, message):
                seen["known"] += 1
                return
            assert code != "internal", f"{node} {verb}: internal for {payload[:80]!r}: {message}"
            assert message.strip() and "\n" not in message.strip(), message
            seen[code] += 1

        one_case()
        print(dict(seen))
        assert seen["bad_request"] > 0 and seen["ok"] > 0, seen

        # Still serving: a good request of each, and both liveliness tokens up.
        outcome, body = ask(session, keys["driver"].rpc("noop"), b'{"v": 1}')
        assert outcome == "ok", body
        outcome, body = ask(session, keys["learner"].rpc("version"), b'{"v": 1}')
        assert outcome == "ok" and protocol.decode_version_reply(body) >= 0
        for node in ("driver", "learner"):
            tokens = [r for r in session.liveliness().get(keys[node].alive, timeout=ANSWER_S) if r.ok is not None]
            assert [str(r.ok.key_expr) for r in tokens] == [keys[node].alive], node

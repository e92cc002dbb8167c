"""The line ``csl driver sim`` prints once serving says where it is really reached: the
endpoint it listens on, or, when the user's zenoh file puts it in client mode (it then
listens on nothing: docs/security.md), the endpoint it connected to."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
from pathlib import Path

import pytest

from tests.zenoh_rpc.support import free_endpoint, wait_until
from zenoh_rpc.config import UserConfig, open_session
from zenoh_rpc.options import CONFIG_ENV, reached_at

REPO = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 30.0  # a cold interpreter importing numpy, pymunk and zenoh on a busy box


def _config(tmp_path: Path, name: str, document: dict[str, object]) -> UserConfig:
    path = tmp_path / f"{name}.json5"
    path.write_text(json.dumps(document))
    return UserConfig(path)


def test_without_a_file_the_node_is_on_its_listen_endpoint() -> None:
    assert reached_at("tcp/127.0.0.1:7447", None) == "on tcp/127.0.0.1:7447"


def test_a_peer_file_that_sets_the_endpoints_is_named(tmp_path: Path) -> None:
    user = _config(tmp_path, "peer", {"listen": {"endpoints": ["tcp/127.0.0.1:7555"]}})
    assert reached_at("tcp/127.0.0.1:7447", user) == f"on the listen/endpoints of {user.path}"


def test_a_client_file_is_reached_through_what_it_connected_to(tmp_path: Path) -> None:
    user = _config(tmp_path, "client", {"mode": "client", "listen": {"endpoints": []},
                                        "connect": {"endpoints": ["tcp/127.0.0.1:7551", "tcp/127.0.0.1:7552"]}})
    assert reached_at("tcp/127.0.0.1:7447", user) == (
        f"as a zenoh client connected to tcp/127.0.0.1:7551 or tcp/127.0.0.1:7552 (client mode, set by {user.path}: "
        "it listens on nothing)")


@pytest.mark.zenoh
def test_a_client_mode_driver_prints_where_it_connected(tmp_path: Path) -> None:
    router = free_endpoint()  # a peer session of this test stands in for the router
    config = tmp_path / "driver.json5"
    config.write_text(json.dumps({"mode": "client", "connect": {"endpoints": [router]}, "listen": {"endpoints": []}}))
    env = {k: v for k, v in os.environ.items() if k != CONFIG_ENV}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    with open_session(listen=[router]) as session:
        process = subprocess.Popen([sys.executable, "-m", "csl_cli", "driver", "sim", "--robot", "r7",
                                    "--zenoh-config", str(config)], cwd=tmp_path, env=env, text=True,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            assert process.stdout is not None
            readable, _, _ = select.select([process.stdout], [], [], START_TIMEOUT_S)
            line = process.stdout.readline() if readable else ""
            assert line == (f"serving hero/r7/rpc/* as a zenoh client connected to {router} (client mode, set by "
                            f"{config}: it listens on nothing) (Ctrl-C to stop)\n")
            # and it is true: the driver's liveliness token reaches us through that connection
            assert wait_until(lambda: any(r.ok is not None for r in session.liveliness().get("hero/r7/alive",
                                                                                                timeout=2.0)), 10.0)
        finally:
            process.terminate()
            process.wait(20)
            for stream in (process.stdout, process.stderr):
                if stream:
                    stream.close()

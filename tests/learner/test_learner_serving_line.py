"""The line ``csl learner serve`` prints once serving says where the service is really
reached: when the user's zenoh file puts it in client mode it listens on nothing
(docs/security.md), so the line names the router it connected to, as ``csl driver
sim``'s does (zenoh_rpc.options.reached_at; tests/hero_driver/test_serving_line.py)."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
from pathlib import Path

import pytest

from executive import defaults
from tests.zenoh_rpc.support import free_endpoint, wait_until
from zenoh_rpc.config import open_session
from zenoh_rpc.options import CONFIG_ENV

REPO = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 30.0  # a cold interpreter importing zenoh and the learner on a busy box


@pytest.mark.zenoh
def test_a_client_mode_learner_prints_where_it_connected(tmp_path: Path) -> None:
    router = free_endpoint()  # a peer session of this test stands in for the router
    config = tmp_path / "learner.json5"
    config.write_text(json.dumps({"mode": "client", "connect": {"endpoints": [router]}, "listen": {"endpoints": []}}))
    db = tmp_path / "library.sqlite"
    env = {k: v for k, v in os.environ.items() if k != CONFIG_ENV}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    with open_session(listen=[router]) as session:
        process = subprocess.Popen([sys.executable, "-m", "csl_cli", "learner", "serve", "--name", "shared",
                                    "--db", str(db), "--zenoh-config", str(config)], cwd=tmp_path, env=env,
                                   text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            assert process.stdout is not None
            readable, _, _ = select.select([process.stdout], [], [], START_TIMEOUT_S)
            line = process.stdout.readline() if readable else ""
            # a new database seeded with the shipped library's 14 descriptions: version 1
            assert line == (f"serving learner 'shared' as a zenoh client connected to {router} (client mode, set by "
                            f"{config}: it listens on nothing): 14 descriptions, version 1, from {db} (a new "
                            f"library, seeded from {defaults.EXAMPLE_LIBRARY}) (Ctrl-C to stop)\n")
            # and it is true: the service's liveliness token reaches us through that connection
            assert wait_until(lambda: any(r.ok is not None for r in session.liveliness().get(
                "csl/learner/shared/alive", timeout=2.0)), 10.0)
        finally:
            process.terminate()
            process.wait(20)
            for stream in (process.stdout, process.stderr):
                if stream:
                    stream.close()

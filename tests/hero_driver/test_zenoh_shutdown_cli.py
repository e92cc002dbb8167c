"""``csl driver check --shutdown-order``: after the suite the command asks for the driver
to be stopped and checks that its liveliness token went before its queryables
(docs/driver-protocol.md, "Shutdown order"), with real processes on 127.0.0.1."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from tests.hero_driver.test_zenoh_support import REPO, DriverProcess

pytestmark = pytest.mark.zenoh


@pytest.mark.slow
def test_the_simulator_stopped_on_request_passes_shutdown_order(endpoint: str) -> None:
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    with DriverProcess.sim(endpoint, robot="sd") as driver:
        driver.ready()
        check = subprocess.Popen([sys.executable, "-m", "csl_cli", "driver", "check", "--robot", "sd",
                                  "--connect", endpoint, "--timeout", "20", "--shutdown-order", "--json"],
                                 cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            asked = check.stderr.readline() if check.stderr else ""
            assert asked == "shutdown-order: stop the driver of robot sd now (within 20 s)\n"
            assert driver.stop() == 0  # SIGTERM, as a service manager stops it
            out, _ = check.communicate(timeout=60)
        finally:
            if check.poll() is None:
                check.kill()
    document = json.loads(out)
    last = document["checks"][-1]
    assert last["name"] == "shutdown-order" and last["passed"], last
    assert last["detail"].startswith("token went first")
    assert document["failed"] == 0 and check.returncode == 0

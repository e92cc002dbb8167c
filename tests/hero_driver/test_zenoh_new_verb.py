"""A verb added to the verb tables reaches the whole zenoh link with no other edit
(docs/conventions.md, "Adding a driver verb", followed here for the link): the node
serves it and lists its feature in ``hello``, ``ZenohDriver`` has its method, the
schemas describe it and ``csl driver check`` asks it of the driver.

The throw-away verb is ``park``, of a new optional feature ``parking``: drive back to
the world's start pose and answer the state there. It sends and answers known message
shapes (an empty request, a RobotState), so its rows are all it needs. The link reads
the tables when it is imported, so the rows are added in a fresh interpreter before
anything of the link is imported, as the recipe's edits would be in the source."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.zenoh

REPO = Path(__file__).resolve().parents[2]

SCRIPT = '''
from __future__ import annotations

import inspect, json
from concurrent.futures import Future
from typing import Protocol, runtime_checkable

from hero_driver import interface
from hero_driver.interface import DriverVerb, Pose, RobotState


# The recipe's step 1, hero_driver/interface.py: the feature's protocol and the verb's row.
@runtime_checkable
class Parker(Protocol):
    def park(self) -> Future[RobotState]:
        """Drive back to the world's start pose and answer the state there."""
        ...


PARK = DriverVerb("park", RobotState, poses_out=("pose",), feature="parking")
interface.PROTOCOLS["parking"] = Parker
interface.DRIVER_VERBS += (PARK,)
interface.VERB_BY_NAME["park"] = PARK

# Step 3, hero_driver/zenoh_link/verbs.py: its row (an empty request, a RobotState).
from hero_driver.zenoh_link import verbs
from hero_driver.zenoh_link.codec import EMPTY, STATE

ROW = verbs.Verb("park", EMPTY, STATE, 900.0, 870.0)
verbs.VERBS += (ROW,)
verbs.BY_NAME["park"] = ROW
verbs.NAMES += ("park",)

# Nothing else is edited: the link, imported now, reads the tables.
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.conformance import run_checks
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.schemas import all_schemas
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session


class ParkingHero(SimulatedHero):
    """Step 2, hero_driver/sim_driver.py: what the simulated HERO does."""

    def park(self):
        def work(sim):
            sim.move([Pose(*sim.spec.robot)], None)
            return sim.state()
        return self._done(work)


def serve(driver):
    endpoint = free_endpoint()
    server = open_session(listen=[endpoint])
    node = DriverNode(driver, server)
    client = ZenohDriver(driver.robot, connect=[endpoint], discover_s=5.0)
    assert client.wait_ready(5.0)
    return endpoint, server, node, client


seen = {"signature": str(inspect.signature(ZenohDriver.park)), "doc": ZenohDriver.park.__doc__}
schemas = all_schemas()
seen["schemas"] = [sorted(schemas["park.request"]["properties"]), sorted(schemas["park.reply"]["properties"])]

endpoint, server, node, client = serve(ParkingHero("parker", world="lab"))
try:
    client.move([Pose(60.0, 30.0, 0.0)]).result(10.0)
    parked = client.park().result(10.0)
    seen["features"] = list(client.hello().result(5.0).served.features)
    seen["agreed"] = sorted(client.agreement.features)
    seen["parked"] = [parked.pose.x_in, parked.pose.y_in, parked.pose.heading_deg]
    checks = {r.name: [r.passed, r.detail] for r in run_checks("parker", [endpoint], timeout_s=5.0)}
    seen["failed"] = sorted(name for name, (passed, _detail) in checks.items() if not passed)
    seen["every_verb"] = checks["every-verb"][1]
finally:
    client.close(); node.close(); server.close()

endpoint, server, node, client = serve(SimulatedHero("plain", world="lab"))
try:
    seen["plain_features"] = list(client.hello().result(5.0).served.features)
    try:
        client.park().result(10.0)
    except Exception as exc:
        seen["plain_park"] = f"{exc.code}: {exc.message}"
finally:
    client.close(); node.close(); server.close()
print(json.dumps(seen))
'''


@pytest.fixture(scope="module")
def seen() -> dict[str, object]:
    run = subprocess.run([sys.executable, "-c", SCRIPT], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.strip().splitlines()[-1])


def test_the_client_has_the_verb_as_the_protocol_declares_it(seen: dict[str, object]) -> None:
    assert seen["signature"] == "(self) -> 'Future[RobotState]'"
    assert seen["doc"] == "Drive back to the world's start pose and answer the state there."


def test_the_schemas_describe_it(seen: dict[str, object]) -> None:
    assert seen["schemas"] == [["v"], ["battery", "clock_s", "pose", "v"]]


def test_a_driver_with_the_verb_serves_it_and_lists_its_feature(seen: dict[str, object]) -> None:
    # the simulated HERO has a dock in the lab, stops for moving obstacles, scans, and now parks
    assert seen["features"] == ["battery", "blocked_moves", "scan", "parking"]
    assert seen["agreed"] == ["battery", "blocked_moves", "parking", "scan"]
    x, y, heading = seen["parked"]  # back from (60, 30) to the lab's start pose (hero_driver/worlds/lab.json),
    # (30, 30) heading 0, within the simulator's motion noise
    assert abs(x - 30.0) < 0.5 and abs(y - 30.0) < 0.5 and abs((heading + 180.0) % 360.0 - 180.0) < 1.0


def test_the_conformance_suite_asks_it_of_the_driver(seen: dict[str, object]) -> None:
    assert seen["failed"] == []
    assert seen["every_verb"].startswith("12 verbs refuse a JSON array bad_request: ")
    assert "park" in seen["every_verb"].split(": ", 1)[1].split(", ")


def test_a_driver_without_it_does_not_list_the_feature_and_refuses_the_verb(seen: dict[str, object]) -> None:
    assert seen["plain_features"] == ["battery", "blocked_moves", "scan"]
    assert seen["plain_park"] == "unknown_verb: park: this driver has no parking feature (see its hello)"

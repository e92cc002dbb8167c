"""Round trip of the driver link's ``noop`` verb between two processes on 127.0.0.1.

    python bench/bench_zenoh.py [--calls 1000] [--warmup 100]

Starts ``csl driver sim`` on a free port in a child process and times, in this
process, ``ZenohDriver.noop().result()`` one call after another (JSON request,
queryable, JSON reply, future completion). For reference it also times a bare
``session.get`` on the same key with zenoh's blocking channel handler: the transport's
floor under the client's futures and codec. Prints a Markdown table of medians and
90th percentiles with the machine and date; BENCHMARKS.md keeps the figures of record.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from importlib.metadata import version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hero_driver.zenoh_link.client import ZenohDriver  # noqa: E402
from hero_driver.zenoh_link.keys import robot_keys  # noqa: E402
from zenoh_rpc.config import open_session  # noqa: E402

ROBOT = "bench"
START_S = 30.0


def free_endpoint() -> str:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


def timed(call: Callable[[], object], calls: int, warmup: int) -> list[float]:
    """Wall seconds of each of ``calls`` sequential calls, after ``warmup`` untimed ones."""
    for _ in range(warmup):
        call()
    samples = []
    for _ in range(calls):
        start = time.perf_counter()
        call()
        samples.append(time.perf_counter() - start)
    return samples


def percentile(samples: list[float], q: float) -> float:
    return statistics.quantiles(samples, n=100, method="inclusive")[int(q) - 1]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--calls", type=int, default=1000, help="timed calls per row (default 1000)")
    parser.add_argument("--warmup", type=int, default=100, help="untimed calls first (default 100)")
    args = parser.parse_args()

    endpoint = free_endpoint()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    driver = subprocess.Popen(
        [sys.executable, "-m", "csl_cli", "driver", "sim", "--robot", ROBOT, "--listen", endpoint],
        cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        driver.stdout.readline()  # the ready line
        with ZenohDriver(ROBOT, connect=[endpoint], discover_s=START_S) as client, \
                open_session(connect=[endpoint]) as bare:
            if not client.wait_ready(START_S):
                raise SystemExit("the driver process did not come up")
            rows = {
                "ZenohDriver.noop().result()": timed(lambda: client.noop().result(5.0),
                                                     args.calls, args.warmup),
                "bare session.get (channel)": timed(
                    lambda: list(bare.get(robot_keys(ROBOT).rpc("noop"), payload=b'{"v":1}')),
                    args.calls, args.warmup),
            }
    finally:
        driver.terminate()
        driver.wait(10)

    today = datetime.datetime.now(datetime.timezone.utc).date().isoformat()
    machine = (f"{os.cpu_count()} vCPU, Python {platform.python_version()}, "
               f"eclipse-zenoh {version('eclipse-zenoh')}")
    print(f"{today}, {machine}, {args.calls} calls after {args.warmup} warm-up\n")
    print("| round trip | median (µs) | p90 (µs) | p99 (µs) |")
    print("|---|---|---|---|")
    for name, samples in rows.items():
        print(f"| {name} | {statistics.median(samples) * 1e6:.0f} | "
              f"{percentile(samples, 90) * 1e6:.0f} | {percentile(samples, 99) * 1e6:.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""How long a zenoh failure takes to surface: the waits the tests only check the outcome of.

    python bench/bench_zenoh_failures.py [--repeat 5]

Each row starts its own child process (``csl driver sim`` or ``csl learner serve``) on a
free port of 127.0.0.1, breaks it, and times in this process the one call that meets
the fault:

- closing a ``ZenohDriver`` whose driver process is frozen (SIGSTOP) after the lease
  dropped it: zenoh retries the frozen peer, and before the handshake was bounded
  (``zenoh_rpc.config.OPEN_TIMEOUT_MS``) every close waited zenoh's ten seconds and
  then raised (tests/hero_driver/test_zenoh_closing.py checks it no longer raises);
- a ``ZenohLearner`` call after its service was killed (SIGKILL), with ``timeout_s`` 1;
- a ``ZenohLearner`` opened with no service there, with ``timeout_s`` 0.5
  (tests/learner/test_service_zenoh.py checks both fail in one line).

Prints a Markdown table of medians and maxima with the machine and date.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from importlib.metadata import version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hero_driver.zenoh_link.client import ZenohDriver  # noqa: E402
from learner.service.zenoh_client import ZenohLearner  # noqa: E402

START_S = 30.0


def free_endpoint() -> str:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


@contextmanager
def child(*argv: str) -> Iterator[subprocess.Popen[str]]:
    """``csl ARGV`` in a child process, after its ready line; continued and killed on exit."""
    process = subprocess.Popen([sys.executable, "-m", "csl_cli", *argv], cwd=ROOT,
                               env={**os.environ, "PYTHONPATH": str(ROOT)},
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        if not (process.stdout and process.stdout.readline()):
            raise SystemExit(f"csl {' '.join(argv)} did not come up")
        yield process
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGCONT)
            process.kill()
        process.wait(10)


def timed(call: Callable[[], object]) -> float:
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


def failing(call: Callable[[], object]) -> Callable[[], None]:
    """``call``, which must raise ConnectionError (the fault under measure)."""
    def run() -> None:
        try:
            call()
        except ConnectionError:
            return
        raise SystemExit("the call did not fail: nothing was measured")
    return run


def close_after_driver_froze() -> float:
    endpoint = free_endpoint()
    with child("driver", "sim", "--robot", "r1", "--listen", endpoint) as driver:
        client = ZenohDriver("r1", connect=[endpoint], discover_s=START_S)
        if not client.wait_ready(START_S):
            raise SystemExit("the driver process did not come up")
        driver.send_signal(signal.SIGSTOP)
        if not client.wait_gone(START_S):
            raise SystemExit("the lease never dropped the frozen driver")
        return timed(client.close)


def call_after_service_killed(folder: Path) -> float:
    endpoint = free_endpoint()
    with child("learner", "serve", "--name", "bench", "--db", str(folder / f"{endpoint[-5:]}.sqlite"),
               "--listen", endpoint) as service:
        with ZenohLearner("bench", connect=[endpoint], timeout_s=1.0) as learner:
            service.kill()
            service.wait(10)
            return timed(failing(learner.version))


def open_with_no_service() -> float:
    return timed(failing(lambda: ZenohLearner("bench", connect=[free_endpoint()], timeout_s=0.5)))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="faults per row (default 5)")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="csl-bench-") as folder:
        rows = {
            "`ZenohDriver.close()`, driver frozen (SIGSTOP)": [close_after_driver_froze() for _ in range(args.repeat)],
            "`ZenohLearner.version()`, service killed, timeout_s 1": [
                call_after_service_killed(Path(folder)) for _ in range(args.repeat)],
            "`ZenohLearner(...)`, no service, timeout_s 0.5": [open_with_no_service() for _ in range(args.repeat)],
        }

    today = datetime.datetime.now(datetime.timezone.utc).date().isoformat()
    machine = (f"{os.cpu_count()} vCPU, Python {platform.python_version()}, "
               f"eclipse-zenoh {version('eclipse-zenoh')}")
    print(f"{today}, {machine}, {args.repeat} faults per row\n")
    print("| the call that meets the fault | median (s) | max (s) |")
    print("|---|---|---|")
    for name, samples in rows.items():
        print(f"| {name} | {statistics.median(samples):.2f} | {max(samples):.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

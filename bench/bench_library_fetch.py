"""Fetching the library over zenoh after a change: deltas against the whole library.

Per size (synthetic libraries perturbed from the shipped one, in a SQLite store in a
temporary folder), ``csl learner serve`` runs as its own process on 127.0.0.1; robot A
(a ``ZenohLearner``) fetches the library once, then, repeatedly, robot B learns one
object and robot A brings its library up to date:

- ``delta``: ``ZenohLearner.library()``: one ``changes`` round trip carrying what B
  learned;
- ``whole``: the path before deltas: a ``version`` round trip, then the whole
  library (the ``library`` verb) decoded again.

Medians of the repeats (the whole library at 100,000 once: it moves ~150 MB). After
each update A's library must equal the whole one fetched afresh, or the bench stops.

    python bench/bench_library_fetch.py [--max 100000] [--repeats 9]
"""

from __future__ import annotations

import argparse
import datetime
import os
import select
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.library.store import LibraryStore  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner.service import protocol  # noqa: E402
from learner.service.protocol import LIBRARY  # noqa: E402
from learner.service.zenoh_client import ZenohLearner  # noqa: E402

SIZES = (1_000, 10_000, 100_000)
WHOLE_ONCE_FROM = 100_000  # sizes from here fetch the whole library once, not per repeat
TIMEOUT_S = 300.0  # the whole library at 100,000 is ~150 MB of JSON each way


def free_endpoint() -> str:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{probe.getsockname()[1]}"


def serve(db: Path, endpoint: str) -> subprocess.Popen[str]:
    """``csl learner serve`` on ``db``; returns once it printed its serving line."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    process = subprocess.Popen([sys.executable, "-m", "csl_cli", "learner", "serve", "--name", "bench",
                                "--db", str(db), "--listen", endpoint], cwd=ROOT, env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout is not None
    readable, _, _ = select.select([process.stdout], [], [], TIMEOUT_S)
    if not readable or not process.stdout.readline():
        process.kill()
        sys.exit(f"the learner service did not start: {process.stderr.read() if process.stderr else ''}")
    return process


def stop(process: subprocess.Popen[str]) -> None:
    """End a service started by :func:`serve` and close its pipes."""
    process.kill()
    process.wait(10)
    for stream in (process.stdout, process.stderr):
        if stream:
            stream.close()


def timed(fn: Callable[[], object]) -> tuple[float, object]:
    began = time.perf_counter()
    out = fn()
    return time.perf_counter() - began, out


def whole(robot: ZenohLearner) -> object:
    """The path before deltas: the version, then the whole library decoded."""
    robot.version()
    return protocol.decode_library_reply(robot._call(LIBRARY, protocol.encode_empty_request()))  # noqa: SLF001


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=SIZES[-1], help=f"largest size (sizes: {SIZES})")
    ap.add_argument("--repeats", type=int, default=9, help="learns per size (median)")
    args = ap.parse_args()
    if args.repeats < 1:
        ap.error(f"--repeats must be at least 1, got {args.repeats}")
    knowledge = load_knowledge(KNOWLEDGE)
    base = read_library_json(EXAMPLE_LIBRARY)
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_library_fetch.py "
          f"--max {args.max} --repeats {args.repeats}")
    print("| descriptions | first fetch (whole) s | after a learn: delta ms | whole s | ratio |")
    print("|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for n in (s for s in SIZES if s <= args.max):
            db = Path(folder) / f"library-{n}.sqlite"
            with LibraryStore(db) as store:
                store.add(synthetic_library(knowledge, n, 0, base=base))
            process = serve(db, endpoint := free_endpoint())
            try:
                with ZenohLearner("bench", [endpoint], TIMEOUT_S) as a, ZenohLearner("bench", [endpoint], 10.0) as b:
                    first, _ = timed(a.library)
                    deltas, wholes = [], []
                    for i in range(args.repeats):
                        b.learn(base[i % len(base)])
                        delta, held = timed(a.library)
                        deltas.append(delta)
                        if n < WHOLE_ONCE_FROM or i == 0:
                            took, fresh = timed(lambda: whole(a))  # noqa: B023
                            wholes.append(took)
                            if tuple(held.descriptions) != tuple(fresh.descriptions):  # type: ignore[attr-defined]
                                sys.exit(f"{n}: the library built from deltas differs from the whole one")
                    d, w = statistics.median(deltas), statistics.median(wholes)
                    print(f"| {n:,} | {first:.2f} | {d * 1e3:.1f} | {w:.2f} | {w / d:,.0f}x |", flush=True)
            finally:
                stop(process)
            db.unlink()


if __name__ == "__main__":
    main()

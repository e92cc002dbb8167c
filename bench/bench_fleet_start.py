"""A fleet starting together: K robots fetch a large library from one learner at once.

``csl learner serve`` runs as its own process on 127.0.0.1 with a synthetic library
(perturbed from the shipped one) in a SQLite store in a temporary folder; K robot
processes each open a ``ZenohLearner`` with the default 5 s bound per request and ask
for the library at the same instant, the way ``csl run --learner zenoh`` starts:

- ``paged``: ``ZenohLearner.library()`` as shipped, page by page;
- ``whole``: the path before pages, the whole library in one reply.

Reported per mode: robots started (their library equal in size to the store's), the
median and slowest start, and the service's peak VmRSS (sampled every 0.2 s).

    python bench/bench_fleet_start.py [--robots 10] [--size 100000] [--modes paged,whole]
"""

from __future__ import annotations

import argparse
import datetime
import json
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.bench_library_fetch import free_endpoint, serve, stop  # noqa: E402
from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.library.store import LibraryStore  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402

MODES = ("paged", "whole")


def robot(endpoint: str, mode: str, at: float) -> None:
    """One robot: connect, wait for the common start instant, fetch, print one JSON line."""
    from learner.service.zenoh_client import ZenohLearner

    try:
        with ZenohLearner("bench", [endpoint]) as learner:
            learner._paged = mode == "paged"  # noqa: SLF001 - the path before pages, for the comparison
            time.sleep(max(0.0, at - time.time()))
            began = time.perf_counter()
            got = learner.library()
            print(json.dumps({"ok": True, "s": time.perf_counter() - began, "n": len(got.descriptions)}))
    except Exception as exc:  # noqa: BLE001 - the bench reports every failure as its line
        print(json.dumps({"ok": False, "error": str(exc).splitlines()[0]}))


def rss_mb(pid: int) -> float:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


class PeakRss:
    """The peak VmRSS of process ``pid`` while the ``with`` block runs, sampled every
    ``period_s`` from a thread (``first``: before the block)."""

    def __init__(self, pid: int, period_s: float = 0.2) -> None:
        self.pid, self.period_s = pid, period_s
        self.first = rss_mb(pid)
        self.samples = [self.first]
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._sample, daemon=True)

    def _sample(self) -> None:
        while not self._done.wait(self.period_s):
            self.samples.append(rss_mb(self.pid))

    @property
    def peak(self) -> float:
        return max(self.samples)

    def __enter__(self) -> PeakRss:
        self._thread.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self._done.set()
        self._thread.join()


def run(db: Path, n: int, robots: int, mode: str) -> str:
    process = serve(db, endpoint := free_endpoint())
    try:
        with PeakRss(process.pid) as sampler:
            at = time.time() + 3.0 + 0.3 * robots  # every robot connected before the common instant
            children = [subprocess.Popen([sys.executable, __file__, "--robot", endpoint, mode, str(at)],
                                         cwd=ROOT, stdout=subprocess.PIPE, text=True) for _ in range(robots)]
            lines = [c.communicate(timeout=1800)[0].strip().splitlines() for c in children]
    finally:
        stop(process)
    results = [json.loads(out[-1]) if out else {"ok": False, "error": "no output"} for out in lines]
    started = [r for r in results if r["ok"] and r["n"] == n]
    times = [r["s"] for r in started]
    errors = sorted({r["error"] for r in results if not r["ok"]})
    return (f"| {mode} | {len(started)} of {robots} | "
            f"{statistics.median(times):.1f} s | {max(times):.1f} s | " if times else f"| {mode} | 0 of {robots} | - | - | "
            ) + f"{sampler.peak:.0f} MB | {errors[0][:90] if errors else '-'} |"


def main() -> None:
    if len(sys.argv) == 5 and sys.argv[1] == "--robot":
        robot(sys.argv[2], sys.argv[3], float(sys.argv[4]))
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=10, help="robots starting together (default 10)")
    ap.add_argument("--size", type=int, default=100_000, help="descriptions in the library (default 100000)")
    ap.add_argument("--modes", default=",".join(MODES), help=f"comma-separated, of {', '.join(MODES)}")
    args = ap.parse_args()
    modes = args.modes.split(",")
    if args.robots < 1 or args.size < 1 or not set(modes) <= set(MODES):
        ap.error("--robots and --size must be at least 1; --modes of " + ", ".join(MODES))
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_fleet_start.py "
          f"--robots {args.robots} --size {args.size} --modes {args.modes}")
    print("| mode | started | median start | slowest | service peak RSS | first error |")
    print("|---|---:|---:|---:|---:|---|")
    knowledge, base = load_knowledge(KNOWLEDGE), read_library_json(EXAMPLE_LIBRARY)
    with tempfile.TemporaryDirectory() as folder:
        db = Path(folder) / "library.sqlite"
        with LibraryStore(db) as store:
            store.add(synthetic_library(knowledge, args.size, 0, base=base))
        for mode in modes:
            print(run(db, args.size, args.robots, mode), flush=True)


if __name__ == "__main__":
    main()

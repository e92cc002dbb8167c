"""A fleet through one zenoh router: K simulated robots learning into one library.

    python bench/bench_fleet.py [--robots 3] [--minutes 2] [--episodes N] [--out DIR]
                                [--kill-every S [--chaos-seed N]]

Starts, as real processes on 127.0.0.1 only, one zenoh router (``zenoh_rpc.router`` in router
mode), one learner service (``csl learner serve``), K simulated drivers (``csl driver
sim --robot rK``) and, for each robot, executives run back to back (``csl run --driver
zenoh --learner zenoh``) until the time is up: each episode first resets its robot's
world under a seed of its own (``csl driver call rK reset``), so no two episodes see the
same noise. Every node is a zenoh *client* of the router, listening nowhere itself, so
all traffic crosses the router.

It measures and prints:

- objects located, handled and failed per robot, from each episode's ``--json`` report
  and its log (every object located must come out handled or failed);
- learned descriptions per second, and the library's new rows against the episodes'
  ``learn`` events: none lost (a learned id missing from the library), none duplicated
  (a row no learn event names, as a retried learn stored twice would leave, or an id
  two learn events name); rows alike but for their ids are counted, for information;
- latency: of a decision as the executive paid it (its computing time per choice,
  learner calls included; the episode log carries no wall-clock times) and of a learner
  query measured client side (a probe in this process asks ``rpc/version``, the query a
  robot makes before each decision, and ``rpc/library`` through the router); of a learn
  as the service handled it (its ``-v`` log, SQLite commit included);
- the learner service's resident memory, sampled from ``/proc``.

With ``--kill-every S`` it is a soak: at random moments (S seconds apart on average,
repeatable from ``--chaos-seed``) the learner or one of the drivers is killed
(SIGKILL) and started again, while the episodes go on. Every description must still be
in the library exactly once, and every run's exit status honest: 0 only when every
object on its floor was handled, anything else with its reason on standard error
(a run killed by the bench for hanging is never honest).

Everything goes under ``--out`` (default: a new temporary folder): the episodes'
reports and logs, every node's output, the library, and ``fleet.json`` with every
figure. Exit status 0 when every object and every description is accounted for, 1
otherwise. BENCHMARKS.md ("Fleet load") keeps the figures of record.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import json
import math
import os
import platform
import random
import sqlite3
import re
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from importlib.metadata import version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

CSL = (sys.executable, "-m", "csl_cli")
LEARNER = "default"
START_S = 60.0  # a node that has not said it serves by then is a failed start
RESET_S = 60.0
EPISODE_S = 300.0  # an episode still running after this is a hang: killed and reported
STOP_S = 10.0
HANDLED = ("grasped", "left")
WORLD = "lab"  # every driver serves it, and every episode resets to it


def placed_objects(world: str) -> int:
    """How many objects the shipped world ``world`` puts on the floor: the truth every
    episode's report is counted against (a camera that misses one must not hide it)."""
    from hero_driver.sim.worldfile import resolve

    return len(json.loads(resolve(world).read_text(encoding="utf-8"))["objects"])


PLACED = placed_objects(WORLD)
LATENCY_LABELS = {
    "decision_executive": "decision, executive computing per choice (learner queries and planning included)",
    "version_query_client": "learner rpc/version, client round trip through the router",
    "library_query_client": "learner rpc/library, client round trip through the router",
    "learn_served": "learn, as the service handled it (SQLite commit included)",
    "version_served": "rpc/version, as the service handled it",
    "library_served": "rpc/library, as the service handled it",
}
SERVED = re.compile(r"csl/learner/[^/]+/rpc/(\w+): (\S+) in ([\d.]+) ms")


# --- the router -------------------------------------------------------------------

def router_config(path: Path, endpoint: str) -> Path:
    """The router's zenoh config file: router mode, listening on ``endpoint`` only; it
    runs as ``python -m zenoh_rpc.router FILE`` (a ``zenohd`` of our own, so the bench
    needs nothing beyond the Python package)."""
    path.write_text(json.dumps({"mode": "router", "listen": {"endpoints": [endpoint]}}, indent=2) + "\n",
                    encoding="utf-8")
    return path


def client_config(path: Path, router: str) -> Path:
    """The zenoh config file every node is given: a client of ``router`` that listens
    nowhere (so K drivers need no ports of their own and nothing bypasses the router)."""
    path.write_text(json.dumps({"mode": "client", "connect": {"endpoints": [router]},
                                "listen": {"endpoints": []}}, indent=2) + "\n", encoding="utf-8")
    return path


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


# --- processes --------------------------------------------------------------------

class Node:
    """A long-running process of the fleet, its output in files under ``folder``."""

    def __init__(self, name: str, argv: Sequence[str], folder: Path, env: dict[str, str]) -> None:
        self.name, self.argv, self.folder, self.env = name, tuple(argv), folder, env
        self.stdout = folder / f"{name}.out"
        self.stderr = folder / f"{name}.err"
        self.starts = 0
        self._start()

    def _start(self) -> None:
        """Start the process; a restart appends to the same output files (a new start
        line marks it), so the logs read after the run hold every life of the node."""
        mode = "wb" if self.starts == 0 else "ab"
        with self.stdout.open(mode) as out, self.stderr.open(mode) as err:
            self.process = subprocess.Popen(self.argv, stdout=out, stderr=err, env=self.env, cwd=self.folder)
        self.starts += 1

    def kill_and_restart(self, says: str) -> None:
        """SIGKILL the node (no clean stop: the token vanishes with the lease), start it
        again and wait for its serving line, counted from the new start."""
        self.process.kill()
        self.process.wait()
        said_before = len(self.stdout.read_text(encoding="utf-8", errors="replace"))
        self._start()
        self.wait_ready(says, after=said_before)

    def wait_ready(self, says: str, timeout_s: float = START_S, after: int = 0) -> None:
        """Wait for ``says`` on the node's standard output (its serving line), written
        after its first ``after`` characters."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if says in self.stdout.read_text(encoding="utf-8", errors="replace")[after:]:
                return
            if self.process.poll() is not None:
                break
            time.sleep(0.1)
        self.stop()
        raise RuntimeError(f"{self.name} did not start: {self.stderr.read_text(errors='replace').strip()[-500:]}")

    def stop(self) -> int | None:
        """SIGTERM (a clean stop: the node undeclares its token), SIGKILL if it hangs."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(STOP_S)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        return self.process.returncode


def rss_kib(pid: int) -> int | None:
    """Resident memory of ``pid`` in KiB (VmRSS), None once it has gone."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        return None
    return None


# --- one episode ------------------------------------------------------------------

@dataclass(frozen=True)
class Episode:
    """What one ``csl run`` did, read from its JSON report and its episode log."""

    robot: str
    index: int
    seed: int
    exit_status: int | None  # None: hung and killed
    wall_s: float
    placed: int  # objects the world puts on the floor
    located: int | None  # regions the camera found (None: no log)
    outcomes: tuple[str, ...]  # one per object reported
    learned_ids: tuple[str, ...]  # ids the learn events carry (a row each)
    nothing_measured: int  # learn events with no description: the grasp needed no test
    grasped_unlearned: int  # objects grasped with no learn event at all
    decision_ms: tuple[float, ...]  # per object: computing ms per choice
    error: str = ""
    said: str = ""  # the last line the run wrote on standard error

    @property
    def honest(self) -> bool:
        """The exit status tells the truth: 0 only when every object on the floor was
        handled, anything else with a reason said (or an object not handled); a run
        the bench had to kill for hanging never is."""
        if self.exit_status is None:
            return False
        all_handled = bool(self.outcomes) and self.unaccounted == 0 and all(o in HANDLED for o in self.outcomes)
        if self.exit_status == 0:
            return all_handled
        return not all_handled or self.said not in ("", "(nothing said)")

    @property
    def unaccounted(self) -> int:
        """Objects on the floor not reported handled or failed: missed by the camera,
        or all of them when the episode left no report."""
        return max(0, self.placed - len(self.outcomes))


def run_episode(robot: str, index: int, seed: int, folder: Path, config: Path, env: dict[str, str]) -> Episode:
    """Reset ``robot``'s world (the lab) under ``seed``, then run one executive against it."""
    folder.mkdir(parents=True)
    started = time.monotonic()
    try:
        reset = subprocess.run([*CSL, "driver", "call", robot, "reset", json.dumps({"world": WORLD, "seed": seed}),
                                "--zenoh-config", str(config)],
                               capture_output=True, text=True, env=env, timeout=RESET_S, check=False)
    except subprocess.TimeoutExpired as hung:
        said = hung.stderr.decode(errors="replace") if isinstance(hung.stderr, bytes) else hung.stderr or ""
        return Episode(robot, index, seed, None, time.monotonic() - started, PLACED, None, (), (), 0, 0, (),
                       f"reset: no answer in {RESET_S:g} s, killed; it said: {last_line(said)}")
    if reset.returncode != 0:
        return Episode(robot, index, seed, reset.returncode, time.monotonic() - started, PLACED, None, (), (),
                       0, 0, (), f"reset: {last_line(reset.stderr or reset.stdout)}")
    argv = [*CSL, "run", "--driver", "zenoh", "--robot", robot, "--learner", "zenoh",
            "--learner-name", LEARNER, "--zenoh-config", str(config),
            "--outbox", str(folder.parent / "outbox.sqlite"), "--out", str(folder), "--json", "--no-plots"]
    try:
        run = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=EPISODE_S, check=False)
    except subprocess.TimeoutExpired:
        return _read_episode(robot, index, seed, folder, None, time.monotonic() - started, "", "hung: killed")
    (folder / "run.json").write_text(run.stdout, encoding="utf-8")
    (folder / "run.err").write_text(run.stderr, encoding="utf-8")
    return _read_episode(robot, index, seed, folder, run.returncode, time.monotonic() - started,
                         run.stdout, last_line(run.stderr) if run.returncode not in (0, 1) else "",
                         last_line(run.stderr))


def last_line(text: str) -> str:
    lines = text.strip().splitlines()
    return lines[-1][-300:] if lines else "(nothing said)"


def _read_episode(robot: str, index: int, seed: int, folder: Path, status: int | None, wall_s: float,
                  report: str, error: str, said: str = "") -> Episode:
    events = read_events(folder / "episode.jsonl")
    located = next((len(e["regions"]) for e in events if e["event"] == "located"), None)
    learns = [e for e in events if e["event"] == "learn"]
    learned = tuple(e["id"] for e in learns if e.get("id") is not None)
    choices = Counter(e["object"] for e in events if e["event"] in ("choose", "choose_grasp"))
    try:
        objects = json.loads(report)["objects"]
    except (json.JSONDecodeError, KeyError, TypeError):
        objects, error = [], error or f"no JSON report: {said or 'none written'}"
    decision = tuple(o["computing_ms"] / choices[o["index"]] for o in objects if choices[o["index"]])
    taught = {e["object"] for e in learns}
    unlearned = sum(1 for o in objects if o["outcome"] == "grasped" and o["index"] not in taught)
    return Episode(robot, index, seed, status, wall_s, PLACED, located, tuple(str(o["outcome"]) for o in objects),
                   learned, len(learns) - len(learned), unlearned, decision, error, said)


def read_events(path: Path) -> list[dict]:
    """An episode log's events (none when the run left no log); a torn last line, from
    a killed run, is skipped."""
    if not path.exists():
        return []
    events = []
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            events.append(json.loads(line))
        except json.JSONDecodeError:
            continue
    return events


# --- samplers -----------------------------------------------------------------------

@dataclass
class Samples:
    """What the background threads collect while the fleet runs."""

    rss_kib: list[int] = field(default_factory=list)
    load_1min: list[float] = field(default_factory=list)  # the machine's load average, others' work included
    version_ms: list[float] = field(default_factory=list)
    library_ms: list[float] = field(default_factory=list)
    probe_failures: int = 0


def sample_memory(pid: Callable[[], int], samples: Samples, stop: threading.Event, period_s: float = 0.5) -> None:
    """Sample the resident memory of the process ``pid()`` names now (a restarted
    learner is a new process)."""
    while not stop.is_set():
        kib = rss_kib(pid())
        if kib is not None:
            samples.rss_kib.append(kib)
        samples.load_1min.append(os.getloadavg()[0])
        stop.wait(period_s)


def probe_learner(router: str, samples: Samples, stop: threading.Event, period_s: float = 0.25) -> None:
    """Time learner queries from a client of the router, as a robot sees them:
    ``rpc/version`` every ``period_s``, ``rpc/library`` every eighth time."""
    import zenoh

    from zenoh_rpc.config import close_session, make_config

    config = make_config(connect=[router])
    config.insert_json5("mode", '"client"')
    session = zenoh.open(config)
    request = json.dumps({"v": 1}).encode()
    try:
        n = 0
        while not stop.is_set():
            verb, into = ("library", samples.library_ms) if n % 8 == 7 else ("version", samples.version_ms)
            started = time.perf_counter()
            ok = any(r.ok is not None for r in session.get(f"csl/learner/{LEARNER}/rpc/{verb}",
                                                           payload=request, timeout=5.0))
            if ok:
                into.append((time.perf_counter() - started) * 1000)
            else:
                samples.probe_failures += 1
            n += 1
            stop.wait(period_s)
    finally:
        close_session(session)


def served_ms(log: Path) -> dict[str, list[float]]:
    """Milliseconds the service took per verb, from its ``-v`` log (answered ``ok``)."""
    times: dict[str, list[float]] = {}
    for match in SERVED.finditer(log.read_text(encoding="utf-8", errors="replace")):
        if match[2] == "ok":
            times.setdefault(match[1], []).append(float(match[3]))
    return times


# --- accounting -------------------------------------------------------------------

def export_library(db: Path, into: Path, env: dict[str, str]) -> list[dict]:
    """The library's descriptions as JSON entries, through ``csl library export``."""
    subprocess.run([*CSL, "library", "--db", str(db), "export", str(into)], env=env, check=True,
                   capture_output=True, timeout=120)
    return json.loads(into.read_text(encoding="utf-8"))["descriptions"]


@dataclass(frozen=True)
class Accounting:
    """Descriptions the episodes learned against the rows the library gained."""

    learned: int  # learn events naming a stored id
    queued: int  # learn events answered 'queued:' (undelivered when the episode ended), their key never stored
    stored: int  # new rows in the library
    lost: tuple[str, ...]  # learned ids not in the library
    unclaimed: tuple[str, ...]  # new rows no learn event names
    claimed_twice: tuple[str, ...]  # ids two learn events name
    identical: int  # new rows identical to another but for the id, each claimed by its own learn

    @property
    def holds(self) -> bool:
        """Each learned id is one new row and each new row one learned id. Rows alike
        but for their ids are not duplicates when each has its own learn event: the same
        object met again and measured alike (quantised features make that common)."""
        return not (self.lost or self.unclaimed or self.claimed_twice or self.queued)


def learn_keys(db: Path) -> dict[str, str]:
    """Each stored row's idempotency key, by its id (rows learned without one left out)."""
    with contextlib.closing(sqlite3.connect(f"file:{db}?mode=ro", uri=True)) as store:
        return dict(store.execute("SELECT learn_key, id FROM descriptions WHERE learn_key IS NOT NULL").fetchall())


def account(episodes: Sequence[Episode], seed_rows: Sequence[dict], final_rows: Sequence[dict],
            keys: dict[str, str] | None = None) -> Accounting:
    """``keys``: each stored row's id by its learn key, so a learn the episode queued
    (``queued:<key>``: the service was down) and a later run's outbox delivered claims
    the row stored under that key."""
    keys = keys or {}
    before = {row["id"] for row in seed_rows}
    new = [row for row in final_rows if row["id"] not in before]
    new_ids = {row["id"] for row in new}
    ids = [keys.get(i.removeprefix("queued:"), i) if i.startswith("queued:") else i
           for e in episodes for i in e.learned_ids]
    claims = Counter(i for i in ids if not i.startswith("queued:"))
    queued = sum(1 for i in ids if i.startswith("queued:"))
    contents = Counter(json.dumps({k: v for k, v in row.items() if k != "id"}, sort_keys=True) for row in new)
    return Accounting(learned=sum(claims.values()), queued=queued, stored=len(new),
                      lost=tuple(sorted(set(claims) - new_ids)),
                      unclaimed=tuple(sorted(new_ids - set(claims))),
                      claimed_twice=tuple(sorted(i for i, n in claims.items() if n > 1)),
                      identical=sum(n - 1 for n in contents.values() if n > 1))


def percentile(values: Sequence[float], q: float) -> float | None:
    """Nearest-rank percentile (None for no values)."""
    if not values:
        return None
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, math.ceil(len(ordered) * q / 100) - 1))]


def spread(values: Sequence[float]) -> dict[str, float | int | None]:
    return {"n": len(values), "p50": percentile(values, 50), "p99": percentile(values, 99),
            "max": max(values) if values else None}


# --- the fleet --------------------------------------------------------------------

def chaos(victims: Sequence[Node], kill_every: float, seed: int, until: float, stop: threading.Event,
          kills: list[dict]) -> None:
    """Kill one of ``victims`` at random moments (``kill_every`` s apart on average) and
    start it again, until ``until`` (monotonic) or ``stop``; each kill is one entry of
    ``kills`` (a restart that failed ends the chaos, said in its entry)."""
    rng = random.Random(seed)
    began = time.monotonic()
    while True:
        wait = rng.expovariate(1.0 / kill_every)
        if stop.wait(wait) or time.monotonic() >= until:
            return
        node = rng.choice(list(victims))
        entry = {"t_s": round(time.monotonic() - began, 1), "node": node.name}
        kills.append(entry)
        try:
            node.kill_and_restart("serving")
        except RuntimeError as exc:
            entry["restart_failed"] = str(exc)[:300]
            return


def run_fleet(robots: int, minutes: float, episodes: int | None, out: Path,
              kill_every: float | None = None, chaos_seed: int = 0) -> dict:
    """Start the fleet, run episodes until ``minutes`` pass (or each robot has run
    ``episodes``), killing and restarting the learner or a driver now and then with
    ``kill_every``, stop it, and return every figure."""
    out.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "CSL_HOME": str(out / "home"), "CSL_ZENOH_CONFIG": "", "PYTHONUNBUFFERED": "1"}
    router = f"tcp/127.0.0.1:{free_port()}"
    config = client_config(out / "client.json5", router)
    db = out / "library.sqlite"
    nodes: list[Node] = []
    stop = threading.Event()
    samples = Samples()
    try:
        routing = router_config(out / "router.json5", router)
        nodes.append(Node("router", [sys.executable, "-m", "zenoh_rpc.router", str(routing)], out, env))
        nodes[-1].wait_ready("routing on")
        learner = Node("learner", [*CSL, "learner", "serve", "--name", LEARNER, "--db", str(db),
                                   "--zenoh-config", str(config), "-v"], out, env)
        nodes.append(learner)
        drivers = [Node(f"driver-r{k}", [*CSL, "driver", "sim", "--robot", f"r{k}", "--world", WORLD, "--seed", str(k),
                                         "--zenoh-config", str(config)], out, env) for k in range(1, robots + 1)]
        nodes.extend(drivers)
        for node in (learner, *drivers):
            node.wait_ready("serving")
        seed_rows = export_library(db, out / "seed-library.json", env)
        threads = [threading.Thread(target=sample_memory, args=(lambda: learner.process.pid, samples, stop),
                                    daemon=True),
                   threading.Thread(target=probe_learner, args=(router, samples, stop), daemon=True)]
        done: list[Episode] = []
        lock = threading.Lock()
        started = time.monotonic()
        deadline = started + minutes * 60
        kills: list[dict] = []
        if kill_every is not None:
            threads.append(threading.Thread(target=chaos, args=((learner, *drivers), kill_every, chaos_seed,
                                                                deadline, stop, kills), daemon=True))
        for t in threads:
            t.start()

        def drive(k: int) -> None:
            n = 0
            while time.monotonic() < deadline and (episodes is None or n < episodes):
                episode = run_episode(f"r{k}", n, k * 100_000 + n, out / f"r{k}" / f"ep{n:04d}", config, env)
                with lock:
                    done.append(episode)
                n += 1

        executives = [threading.Thread(target=drive, args=(k,)) for k in range(1, robots + 1)]
        for t in executives:
            t.start()
        for t in executives:
            t.join()
        elapsed = time.monotonic() - started
        stop.set()
        for t in threads:
            t.join(10)
    finally:
        stop.set()
        statuses = {node.name: node.stop() for node in reversed(nodes)}
    final_rows = export_library(db, out / "final-library.json", env)
    figures = report(robots, minutes, elapsed, sorted(done, key=lambda e: (e.robot, e.index)), seed_rows,
                     final_rows, samples, served_ms(learner.stderr), statuses, learn_keys(db))
    return {**figures, "kills": kills}


def report(robots: int, minutes: float, elapsed: float, episodes: Sequence[Episode], seed_rows: Sequence[dict],
           final_rows: Sequence[dict], samples: Samples, served: dict[str, list[float]],
           statuses: dict[str, int | None], keys: dict[str, str] | None = None) -> dict:
    per_robot = {}
    for k in range(1, robots + 1):
        mine = [e for e in episodes if e.robot == f"r{k}"]
        outcomes = Counter(o for e in mine for o in e.outcomes)
        per_robot[f"r{k}"] = {
            "episodes": len(mine),
            "placed": sum(e.placed for e in mine),
            "located": sum(e.located or 0 for e in mine),
            "handled": sum(outcomes[o] for o in HANDLED),
            "grasped": outcomes["grasped"],
            "failed": sum(n for o, n in outcomes.items() if o not in HANDLED),
            "unaccounted": sum(e.unaccounted for e in mine),
            "learned": sum(len(e.learned_ids) for e in mine),
            "nothing_measured": sum(e.nothing_measured for e in mine),
            "grasped_unlearned": sum(e.grasped_unlearned for e in mine),
            "exit_statuses": dict(Counter(str(e.exit_status) for e in mine)),
            "dishonest": sum(not e.honest for e in mine),
            "errors": [f"ep{e.index}: {e.error}" for e in mine if e.error],
        }
    books = account(episodes, seed_rows, final_rows, keys)
    rss = samples.rss_kib
    return {
        "robots": robots, "minutes": minutes, "elapsed_s": round(elapsed, 1),
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}, "
                   f"eclipse-zenoh {version('eclipse-zenoh')}, {platform.system()}",
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "per_robot": per_robot,
        "accounting": {**asdict(books), "holds": books.holds,
                       "seed_rows": len(seed_rows), "final_rows": len(final_rows)},
        "learned_per_s": round(books.stored / elapsed, 3) if elapsed else None,
        "episode_wall_s": spread([e.wall_s for e in episodes]),  # reset + csl run, start-up included
        "latency_ms": {
            "decision_executive": spread([d for e in episodes for d in e.decision_ms]),
            "version_query_client": spread(samples.version_ms),
            "library_query_client": spread(samples.library_ms),
            "learn_served": spread(served.get("learn", [])),
            "version_served": spread(served.get("version", [])),
            "library_served": spread(served.get("library", [])),
        },
        "learner_busy": busy(served, elapsed, robots),
        "probe_failures": samples.probe_failures,
        "load_1min": {"mean": round(sum(samples.load_1min) / len(samples.load_1min), 1) if samples.load_1min else None,
                      "max": max(samples.load_1min, default=None)},
        "learner_rss_mib": {"first": round(rss[0] / 1024, 1) if rss else None,
                            "max": round(max(rss) / 1024, 1) if rss else None,
                            "last": round(rss[-1] / 1024, 1) if rss else None, "samples": len(rss)},
        "node_exit_statuses": statuses,
    }


def busy(served: dict[str, list[float]], elapsed: float, robots: int) -> dict[str, object]:
    """How long the learner service spent answering, in all and per verb, and what share
    of the run's wall time that is: the load one robot puts on it is that share over the
    robots, so about ``1 / (share / robots)`` robots would keep it always busy."""
    total_s = sum(sum(ms) for ms in served.values()) / 1000
    share = total_s / elapsed if elapsed else None
    return {"total_s": round(total_s, 1), "share": None if share is None else round(share, 4),
            "robots_to_saturate": round(robots / share) if share else None,
            "by_verb": {verb: {"n": len(ms), "total_s": round(sum(ms) / 1000, 1)} for verb, ms in sorted(served.items())}}


def accounted(figures: dict) -> bool:
    """Every object located came out handled or failed, every episode ended on its own,
    and every description is in the library exactly once."""
    robots = figures["per_robot"].values()
    if figures.get("kills"):  # a soak: runs may end lost while a node is down, but never dishonestly
        return figures["accounting"]["holds"] and all(r["dishonest"] == 0 for r in robots)
    return (figures["accounting"]["holds"]
            and all(r["unaccounted"] == 0 and r["grasped_unlearned"] == 0 and r["dishonest"] == 0 for r in robots)
            and all(s in ("0", "1") for r in robots for s in r["exit_statuses"]))


def print_figures(figures: dict, out: Path) -> None:
    def ms(s: dict) -> str:
        return "n/a" if s["p50"] is None else f"{s['p50']:.1f} / {s['p99']:.1f} ms (n={s['n']})"

    print(f"# Fleet load: {figures['robots']} robots, {figures['elapsed_s']} s, {figures['date']}")
    print(f"machine: {figures['machine']}; output in {out}\n")
    print("| robot | episodes | placed | located | handled | grasped | failed | unaccounted | learned "
          "| nothing to learn | grasped, no learn event | exit statuses |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for name, r in figures["per_robot"].items():
        print(f"| {name} | {r['episodes']} | {r['placed']} | {r['located']} | {r['handled']} | {r['grasped']} | "
              f"{r['failed']} | "
              f"{r['unaccounted']} | {r['learned']} | {r['nothing_measured']} | {r['grasped_unlearned']} | "
              f"{r['exit_statuses']} |")
    a = figures["accounting"]
    print(f"\nlibrary: {a['seed_rows']} seed rows -> {a['final_rows']}; learned {a['learned']}, stored {a['stored']}, "
          f"queued {a['queued']}, lost {len(a['lost'])}, unclaimed {len(a['unclaimed'])}, "
          f"claimed twice {len(a['claimed_twice'])}; {a['identical']} rows alike but for their ids, "
          f"each from its own learn event")
    print(f"learned descriptions per second: {figures['learned_per_s']}")
    wall = figures["episode_wall_s"]
    if wall["p50"] is not None:
        print(f"an episode (reset + csl run, process start included): p50 {wall['p50']:.1f} s, "
              f"p99 {wall['p99']:.1f} s (n={wall['n']})")
    for name, s in figures["latency_ms"].items():
        print(f"p50 / p99 {LATENCY_LABELS[name]}: {ms(s)}")
    b = figures["learner_busy"]
    print(f"learner busy answering: {b['total_s']} s of {figures['elapsed_s']} s ({b['share']}); "
          f"at this load per robot, about {b['robots_to_saturate']} robots would keep it always busy; "
          + ", ".join(f"{verb} {v['n']} x, {v['total_s']} s" for verb, v in b["by_verb"].items()))
    m = figures["learner_rss_mib"]
    print(f"learner RSS: {m['first']} MiB at start, {m['max']} MiB max, {m['last']} MiB at end "
          f"({m['samples']} samples); probe failures {figures['probe_failures']}; machine load (1 min) "
          f"{figures['load_1min']['mean']} mean, {figures['load_1min']['max']} max")
    for name, r in figures["per_robot"].items():
        for error in r["errors"][:5]:
            print(f"{name} {error}")
    kills = figures.get("kills") or []
    if kills:
        print(f"kills: {len(kills)} ({dict(Counter(k['node'].split('-')[0] for k in kills))}); "
              f"restarts failed: {sum('restart_failed' in k for k in kills)}; dishonest exit statuses: "
              f"{sum(r['dishonest'] for r in figures['per_robot'].values())}")
    print("every object and description accounted for" if accounted(figures) else "ACCOUNTING FAILED")


def positive(kind: Callable[[str], float]) -> Callable[[str], float]:
    """An argparse type: a number of ``kind`` above zero, else a one-line error."""

    def parse(text: str) -> float:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
        if not value > 0:
            raise argparse.ArgumentTypeError(f"{text!r} must be > 0")
        return value
    return parse


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=positive(int), default=3, help="simulated robots, each with its executive")
    parser.add_argument("--minutes", type=positive(float), default=2.0, help="start no episode after this")
    parser.add_argument("--episodes", type=positive(int), default=None, help="at most this many episodes per robot")
    parser.add_argument("--out", type=Path, default=None, help="output folder (default: a new temporary folder)")
    parser.add_argument("--kill-every", type=positive(float), default=None, metavar="S",
                        help="a soak: kill (SIGKILL) and restart the learner or a driver S seconds apart on average")
    parser.add_argument("--chaos-seed", type=int, default=0, help="seed of the kills' moments and victims (default 0)")
    args = parser.parse_args(argv)
    out = args.out or Path(tempfile.mkdtemp(prefix="csl-fleet-"))
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        parser.error(f"--out {out}: not an empty folder; give a new one")
    try:
        figures = run_fleet(args.robots, args.minutes, args.episodes, out, args.kill_every, args.chaos_seed)
    except (RuntimeError, OSError, subprocess.SubprocessError) as exc:
        print(f"bench_fleet: {exc}", file=sys.stderr)
        return 1
    (out / "fleet.json").write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")
    print_figures(figures, out)
    return 0 if accounted(figures) else 1


if __name__ == "__main__":
    sys.exit(main())

"""Several oversized requests at once: the learner service's memory stays bounded.

``csl learner serve`` runs as its own process on 127.0.0.1 with the shipped library;
K clients (each its own zenoh session, in this process) send one ``learn`` of M MB at
the same instant, then a well-formed client asks ``version``. Reported: what each
oversized request got, whether the service still answered, and its peak VmRSS (sampled
every 0.1 s) against its RSS before.

    python bench/bench_oversized.py [--clients 4] [--mb 400]
"""

from __future__ import annotations

import argparse
import datetime
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.bench_fleet_start import PeakRss, rss_mb  # noqa: E402
from bench.bench_library_fetch import free_endpoint, serve, stop  # noqa: E402
from learner.service.protocol import LEARN, learner_keys  # noqa: E402
from learner.service.zenoh_client import ZenohLearner  # noqa: E402
from zenoh_rpc.client import RpcClient  # noqa: E402
from zenoh_rpc.config import open_session  # noqa: E402


def oversized(endpoint: str, mb: int, at: float, outcomes: Counter[str]) -> None:
    body = b'{"v": 1, "description": "' + b"x" * (mb * 1_000_000) + b'"}'
    try:
        with open_session(connect=[endpoint], connect_timeout_s=5.0) as session:
            rpc = RpcClient(session, learner_keys("bench"))
            time.sleep(max(0.0, at - time.time()))
            answer = rpc.ask(LEARN, body, 60.0)
            reply = answer.first
            outcomes["ok (accepted!)" if reply is not None and reply.ok is not None else
                     "no reply" if reply is None or reply.err == b"Timeout" else "refused"] += 1
    except Exception as exc:  # noqa: BLE001 - every outcome is counted
        outcomes[f"error: {str(exc).splitlines()[0][:60]}"] += 1


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--clients", type=int, default=4, help="oversized requests at once (default 4)")
    ap.add_argument("--mb", type=int, default=400, help="size of each, MB (default 400)")
    args = ap.parse_args()
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_oversized.py "
          f"--clients {args.clients} --mb {args.mb}")
    with tempfile.TemporaryDirectory() as folder:
        process = serve(Path(folder) / "library.sqlite", endpoint := free_endpoint())
        outcomes: Counter[str] = Counter()
        try:
            with PeakRss(process.pid, 0.1) as sampler:
                at = time.time() + 2.0 + 0.5 * args.clients
                senders = [threading.Thread(target=oversized, args=(endpoint, args.mb, at, outcomes))
                           for _ in range(args.clients)]
                for s in senders:
                    s.start()
                for s in senders:
                    s.join()
                with ZenohLearner("bench", [endpoint], 10.0) as robot:
                    answered = f"yes (version {robot.version()})"
                time.sleep(1.0)
        except Exception as exc:  # noqa: BLE001
            answered = f"no: {str(exc).splitlines()[0]}"
        finally:
            after = rss_mb(process.pid)
            stop(process)
    print("| clients x MB | outcomes | service answered after | RSS before | peak | after |")
    print("|---|---|---|---:|---:|---:|")
    print(f"| {args.clients} x {args.mb} | {', '.join(f'{k}: {v}' for k, v in sorted(outcomes.items()))} | "
          f"{answered} | {sampler.first:.0f} MB | {sampler.peak:.0f} MB | {after:.0f} MB |")


if __name__ == "__main__":
    main()

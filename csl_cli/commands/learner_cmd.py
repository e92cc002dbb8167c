"""``csl learner serve``: the learner service as a zenoh node, so several robots share
one library (docs/learner-protocol.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from typing import TYPE_CHECKING

from executive import defaults
from csl_cli.args import library_path, writable_file
from zenoh_rpc.argtypes import positive_seconds
from zenoh_rpc.endpoints import LEARNER_ENDPOINT, LISTEN_KEY, check_endpoint
from zenoh_rpc.options import add_zenoh_config_option, endpoint_of, open_listen_warning, reached_at, user_config

if TYPE_CHECKING:  # the learner's store and formats (numpy) are imported when the service starts, not for --help
    from learner.service.local import LocalLearner


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``learner`` group and its ``serve`` command."""
    group = sub.add_parser(
        "learner",
        help="serve the shared library over zenoh so several robots learn into it",
        description=(
            "The learner service owns the library of object descriptions and adds what "
            "robots learn after each grasp. Robots use it in-process by default; "
            "'serve' runs it as a zenoh node on keys csl/learner/<name>/... "
            "(docs/learner-protocol.md) so that every robot started with '--learner "
            "zenoh' shares one library."
        ),
    )
    actions = group.add_subparsers(dest="learner_command", metavar="ACTION", required=True)
    serve = actions.add_parser(
        "serve",
        help="serve a library database until interrupted",
        description=(
            "Serve the library in a SQLite database: declares the liveliness token "
            "csl/learner/<name>/alive and answers csl/learner/<name>/rpc/library, "
            "rpc/learn and rpc/version. A store with no description yet is first seeded "
            "from --seed-library; a store in use is never overwritten. Prints one line "
            "once serving; stops cleanly on Ctrl-C or SIGTERM."
        ),
    )
    serve.add_argument("--name", default="default",
                       help="service name, one key chunk of letters, digits, '_', '-', '.' "
                            "(default: default)")
    serve.add_argument("--db", type=Path, default=None, metavar="PATH",
                       help="the library database (default: $CSL_HOME/library.sqlite, "
                            "CSL_HOME defaulting to ~/.local/share/csl)")
    serve.add_argument("--seed-library", type=Path, default=defaults.EXAMPLE_LIBRARY, metavar="JSON",
                       help="library JSON imported only into an empty database "
                            "(default: the shipped HERO 2000 example library)")
    serve.add_argument("--knowledge", type=Path, default=defaults.KNOWLEDGE, metavar="FILE",
                       help="the robot profile every learned description must fit; stored ones that "
                            "do not are quarantined, kept but not served (default: the HERO 2000 profile)")
    serve.add_argument("--listen", default=None, metavar="ENDPOINT",
                       help=f"zenoh endpoint to listen on (default {LEARNER_ENDPOINT})")
    serve.add_argument("--backup", type=Path, default=None, metavar="FILE",
                       help="keep a backup of the library in FILE: taken when serving starts, every "
                            "--backup-every seconds and when it stops, through SQLite's online backup API "
                            "(csl library restore brings it back; docs/reliability.md; default: none)")
    serve.add_argument("--backup-every", type=positive_seconds, default=3600.0, metavar="S",
                       help="seconds between backups with --backup (default 3600)")
    add_zenoh_config_option(serve)
    serve.set_defaults(handler=run_serve)


def run_serve(args: argparse.Namespace) -> int:
    """Serve until SIGINT or SIGTERM; exit status 0 after a clean shutdown."""
    from learner.library.backup import keep_backed_up
    from learner.library.format import read_library_json
    from learner.service.local import LocalLearner
    from learner.service.protocol import learner_keys
    from robot_profile import load_knowledge

    learner_keys(args.name)
    if args.listen is not None:
        check_endpoint(args.listen)
    zenoh_config = user_config(args.zenoh_config)
    listen = endpoint_of("--listen", args.listen, LEARNER_ENDPOINT, LISTEN_KEY, zenoh_config)
    warning = open_listen_warning(listen, zenoh_config)
    if warning:
        print(warning, file=sys.stderr, flush=True)
    # Imported here: zenoh costs `csl --help` and every other command its start-up time.
    from learner.service.zenoh_node import serve_learner
    from zenoh_rpc.serving import stop_on_signals

    db = library_path(args.db, "--db")  # the database is opened and checked before the port is bound
    backup_to = None if args.backup is None else writable_file(args.backup, "--backup")
    created = "" if db.exists() else f" (a new library, seeded from {args.seed_library})"
    service = LocalLearner(db, seed_library=read_library_json(args.seed_library),
                           knowledge=load_knowledge(args.knowledge))
    report_quarantined(service, args.name)

    def on_ready() -> None:
        snapshot = service.library()
        print(f"serving learner {args.name!r} {reached_at(listen, zenoh_config)}: "
              f"{len(snapshot.descriptions)} "
              f"descriptions, version {snapshot.version}, from {db}{created} (Ctrl-C to stop)", flush=True)

    backups = None
    try:
        with stop_on_signals() as stop:
            if backup_to is not None:
                backups = keep_backed_up(db, backup_to, args.backup_every, stop,
                                         lambda line: print(f"learner {args.name!r}: {line}", file=sys.stderr))
            serve_learner(service, args.name, [listen], stop, on_ready=on_ready, zenoh_config=zenoh_config)
            stop.set()
            if backups is not None:
                backups.join()  # the last backup, with everything learned, before the store closes
    finally:
        service.close()
    print(f"learner {args.name!r} stopped", file=sys.stderr)
    return 0


QUARANTINE_LINES = 10
"""Quarantined descriptions named one per line at start; the rest are counted."""


def report_quarantined(service: LocalLearner, name: str) -> None:
    """Say on stderr which stored descriptions are not served, and why."""
    for q in service.quarantined[:QUARANTINE_LINES]:
        print(f"learner {name!r}: quarantined {q.object_id!r} (kept in {service.path}, not served): {q.reason}",
              file=sys.stderr)
    if len(service.quarantined) > QUARANTINE_LINES:
        print(f"learner {name!r}: and {len(service.quarantined) - QUARANTINE_LINES} more quarantined descriptions",
              file=sys.stderr)

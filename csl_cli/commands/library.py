"""``csl library``: the persistent library of object descriptions (SQLite), and the
history of the runs that learned into it (``reporting/history.py``).

The library's formats, its store and the history (numpy, through the descriptions and
the exit statuses) are imported by the handlers that use them, so that ``csl library
--help`` and the shell's completion stay light (docs/conventions.md).
"""

from __future__ import annotations

import argparse
from collections import Counter
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING

from executive import defaults
from csl_cli.args import library_path, writable_file
from csl_cli.completion import complete_library_id
from reporting.tables import Column, print_json, print_table

if TYPE_CHECKING:
    from learner.library.store import LibraryStore
    from reporting.history import Run


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "library",
        help="show, import, export or summarise the persistent library; the learning history",
        description=(
            "The library of learned object descriptions, kept in a SQLite file: the robot's, "
            "$CSL_HOME/library.sqlite (CSL_HOME defaulting to ~/.local/share/csl), which csl run "
            "learns into. csl demo keeps its own in its --out folder, made anew each time; while "
            "the robot's does not exist, show, export, stats, check and backup read the last "
            "demo's and say so. import and restore always write the robot's (or --db). Every "
            "write is one transaction: a crash loses nothing committed."
        ),
    )
    db_help = ("the library database (default: $CSL_HOME/library.sqlite; to read, while it does not exist, the "
               "last csl demo's)")
    p.add_argument("--db", type=Path, default=None, help=db_help)
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)

    def action(name: str, **kwargs: str) -> argparse.ArgumentParser:
        a = actions.add_parser(name, **kwargs)
        a.add_argument("--db", type=Path, default=argparse.SUPPRESS, help=db_help)  # before or after the action
        return a

    show = action("show", help="list every description with its features",
                  description="List every description: id, grasp(position) and features.")
    show.add_argument("id", nargs="?", help="show only this description"
                      ).completer = complete_library_id  # type: ignore[attr-defined]  # argcomplete's hook
    show.add_argument("--json", action="store_true",
                      help="print the descriptions as one library JSON document (docs/library-format.md)")
    show.set_defaults(handler=run_show)
    imp = action("import", help="add descriptions from a JSON file",
                 description=("Add the descriptions of a library JSON file (docs/library-format.md), checked "
                              "against the robot's knowledge file, in one transaction: all or nothing."))
    imp.add_argument("file", type=Path, help="library JSON file")
    imp.add_argument("--replace", action="store_true", help="overwrite descriptions whose id already exists")
    imp.add_argument("--knowledge", type=Path, default=defaults.KNOWLEDGE,
                     help="the robot knowledge TOML the descriptions must fit (default: the HERO 2000 profile)")
    imp.set_defaults(handler=run_import)
    exp = action("export", help="write every description to a JSON file",
                 description="Write the whole library as library JSON (docs/library-format.md).")
    exp.add_argument("file", type=Path, help="output JSON file")
    exp.add_argument("--columnar", action="store_true",
                     help=("write the columnar layout (version 3) for big libraries: faster to load and smaller "
                           "(BENCHMARKS.md, 'Loading a library'); the default is the readable version 2"))
    exp.set_defaults(handler=run_export)
    stats = action("stats", help="counts by grasp, feature and position",
                   description="Summarise the library: descriptions per grasp, features per position.")
    stats.add_argument("--json", action="store_true", help="print the counts as one JSON document")
    stats.set_defaults(handler=run_stats)
    history = action("history", help="the runs so far and the learning curve (cost and errors per object)",
                     description=("List the runs csl demo and csl run appended to the history file, one row each "
                                  "(docs/recording.md, The learning history), and with --out draw the learning "
                                  "curve: robot minutes, errors and failures per object over the runs. With --db, "
                                  "only the runs that learned into that library."))
    history.add_argument("--history", type=Path, default=None, metavar="FILE",
                         help="the history file (default: $CSL_HOME/history.jsonl)")
    history.add_argument("--out", type=Path, default=None, metavar="PNG",
                         help="draw the learning curve to this PNG file")
    history.add_argument("--json", action="store_true", help="print the runs as one JSON document")
    history.set_defaults(handler=run_history)
    check = action("check", help="SQLite's full integrity check of the library",
                   description=("Run SQLite's full integrity check (every page, every index against its table) on "
                                "the library. Prints 'ok' and the number of descriptions, or what is damaged; exits "
                                "0 when sound, 1 when damaged. Every opening of the library already runs the quick "
                                "check (the b-trees, not the indexes) and refuses a damaged store in one line."))
    check.set_defaults(handler=run_check)
    backup = action("backup", help="copy the library to a file while it may be serving",
                    description=("Copy a consistent snapshot of the library through SQLite's online backup API "
                                 "(a learner service may go on writing), check it, and only then put it at FILE: "
                                 "a failed or damaged copy never replaces a good backup."))
    backup.add_argument("file", type=Path, help="the backup file to write (replaced when the copy checks out)")
    backup.set_defaults(handler=run_backup)
    restore = action("restore", help="make the library a backup's copy",
                     description=("Check the backup and copy it into the library through SQLite's backup API; a "
                                  "library too damaged to be written is moved aside first (named on the output). "
                                  "Stop the learner service that serves the library before restoring it."))
    restore.add_argument("file", type=Path, help="a backup written by 'csl library backup'")
    restore.set_defaults(handler=run_restore)


def _existing(args: argparse.Namespace) -> Path:
    """The library database to read (csl_cli/library_choice.py: --db, else the robot's,
    else the last demo's); one that does not exist is an error, not a new file."""
    from csl_cli.library_choice import library_to_read, no_library

    path = library_to_read(args.db, "--db", f"csl library {args.action}")
    if path is None:
        raise no_library("--db")
    if not path.exists():
        raise ValueError(f"{path}: no library database there (import into it first, or pass --db)")
    return path


def _store(args: argparse.Namespace) -> LibraryStore:
    """The library store to read (it must exist)."""
    from learner.library.store import LibraryStore

    return LibraryStore(_existing(args))


SHOW_COLUMNS = (Column("id"), Column("grasp"), Column("features", fold=True))
"""Ids and grasps whole (an id is what ``show ID`` takes); the features fold."""


def run_show(args: argparse.Namespace) -> int:
    from learner.library.format import descriptions_to_json

    with _store(args) as store:
        descriptions = store.descriptions()
    if args.id is not None:
        descriptions = [d for d in descriptions if d.object_id == args.id]
        if not descriptions:
            raise ValueError(f"library: no description with id {args.id!r}")
    if args.json:
        print_json(descriptions_to_json(descriptions))
        return 0
    print_table(SHOW_COLUMNS,
                [[d.object_id, f"{d.grasp}{d.grasp_position}", " ".join(str(o) for o in d.observations)]
                 for d in descriptions], title=_count(len(descriptions), "description"), row_lines=True)
    return 0


def run_import(args: argparse.Namespace) -> int:
    from learner.library.checks import check_library
    from learner.library.format import read_library_json
    from learner.library.store import LibraryStore
    from robot_profile import load_knowledge

    descriptions = read_library_json(args.file)
    check_library(descriptions, load_knowledge(args.knowledge), str(args.file))
    path = library_path(args.db, "--db")
    created = not path.exists()
    with LibraryStore(path) as store:
        n = store.add(descriptions, replace=args.replace)
        print(f"imported {_count(n, 'description')} into {store.path}{' (a new library)' if created else ''}")
    return 0


def run_export(args: argparse.Namespace) -> int:
    from learner.library.format import write_library_json

    with _store(args) as store:
        descriptions = store.descriptions()
    write_library_json(args.file, descriptions, columnar=args.columnar)
    print(f"exported {_count(len(descriptions), 'description')} to {args.file}")
    return 0


def run_stats(args: argparse.Namespace) -> int:
    with _store(args) as store:
        descriptions = store.descriptions()
    grasps = Counter(d.grasp for d in descriptions)
    features = Counter(f"{o.feature}{o.position}" for d in descriptions for o in d.observations)
    if args.json:
        print_json({"descriptions": len(descriptions), "feature_values": sum(features.values()),
                    "by_grasp": dict(sorted(grasps.items())), "by_feature": dict(sorted(features.items()))})
        return 0
    print(f"{_count(len(descriptions), 'description')}, {_count(sum(features.values()), 'feature value')}, "
          f"{_count(len(features), 'distinct feature-position')}")
    count = Column("descriptions", numeric=True)
    print_table([Column("grasp"), count], [[g, str(n)] for g, n in sorted(grasps.items())], title="by grasp")
    print_table([Column("feature(position)"), count], [[f, str(n)] for f, n in sorted(features.items())],
                title="by feature")
    return 0


HISTORY_COLUMNS = (Column("#", numeric=True), Column("date", fold=True), Column("cmd"), Column("world", fold=True),
                   Column("seed", numeric=True), Column("criterion", fold=True), Column("obj", numeric=True),
                   Column("done", numeric=True), Column("fail", numeric=True), Column("err", numeric=True),
                   Column("min", numeric=True), Column("lib", numeric=True))
"""Fits 80 columns: the date (UTC), world and criterion wrap; the rest keep whole."""
HISTORY_CAPTION = ("obj: objects seen, done: handled (grasped or left), fail: not handled; err: grasps at a leaf "
                   "that did not hold; min: robot minutes per object; lib: descriptions in the library after the run")


def run_history(args: argparse.Namespace) -> int:
    from reporting.history import default_history, learning_curve, read_history

    if args.out is not None:
        if args.out.suffix.lower() != ".png":
            raise ValueError(f"--out: {args.out} is not a .png file")
        writable_file(args.out, "--out")  # before reading anything
    path = args.history or default_history()
    runs = read_history(path)
    if args.db is not None:
        library = str(library_path(args.db, "--db").resolve())
        runs = [r for r in runs if r.library == library]
    if not runs:
        raise ValueError(f"{path}: no runs recorded{' on ' + str(args.db) if args.db is not None else ''} yet")
    if args.out is not None:
        from reporting.plots import plot_learning_curve  # matplotlib: only to draw

        plot_learning_curve(args.out, learning_curve(runs), str(path))
    if args.json:
        print_json({"history": str(path), "runs": [asdict(r) for r in runs],
                    "plot": None if args.out is None else str(args.out)})
        return 0
    print_table(HISTORY_COLUMNS, [_history_cells(n, r) for n, r in enumerate(runs, 1)],
                title=f"{_count(len(runs), 'run')} in {path}", caption=HISTORY_CAPTION)
    if args.out is not None:
        print(f"learning curve: {args.out}")
    return 0


def _history_cells(n: int, run: Run) -> list[str]:
    minutes = "-" if run.robot_min_per_object is None else f"{run.robot_min_per_object:.1f}"
    return [str(n), run.date.replace("T", " ")[:16], run.command, run.world or f"({run.robot})",
            "-" if run.seed is None else str(run.seed), run.criterion, str(run.objects), str(run.handled),
            str(run.failed), str(run.errors), minutes, str(run.library_size)]


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def run_check(args: argparse.Namespace) -> int:
    from learner.library.backup import RESTORE_HINT, check_file
    from learner.library.store import LibraryStore

    path = _existing(args)
    found = check_file(path)
    if found:
        print(f"{path}: damaged: {len(found)} problem(s) found by SQLite's integrity check")
        for line in found[:20]:
            print(f"  {line}")
        print(RESTORE_HINT.format(path=path))
        return 1
    with LibraryStore(path) as store:
        count = len(store.descriptions())
    print(f"{path}: ok ({_count(count, 'description')})")
    return 0


def run_backup(args: argparse.Namespace) -> int:
    from learner.library.backup import backup

    path = _existing(args)
    target = writable_file(args.file, "backup FILE")
    backup(path, target)
    print(f"backed up {path} to {target}")
    return 0


def run_restore(args: argparse.Namespace) -> int:
    from learner.library.backup import restore
    from learner.library.store import LibraryStore

    if not args.file.is_file():
        raise ValueError(f"restore FILE {args.file}: no such file")
    path = library_path(args.db, "--db")
    aside = restore(args.file, path)
    if aside is not None:
        print(f"the damaged library was moved aside to {aside}")
    with LibraryStore(path) as store:
        count = len(store.descriptions())
    print(f"restored {path} from {args.file} ({_count(count, 'description')})")
    return 0

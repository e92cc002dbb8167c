"""``csl library``: the persistent library of object descriptions (SQLite)."""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

from executive import defaults
from executive.profile import load_knowledge
from executive.tables import print_table
from learner.library import LibraryStore, check_library, read_library_json, write_library_json


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "library",
        help="show, import, export or summarise the persistent library",
        description=(
            "The library of learned object descriptions, kept in a SQLite file (default "
            "$CSL_HOME/library.sqlite, CSL_HOME defaulting to ~/.local/share/csl). Every "
            "write is one transaction: a crash loses nothing committed."
        ),
    )
    db_help = "the library database (default: $CSL_HOME/library.sqlite)"
    p.add_argument("--db", type=Path, default=None, help=db_help)
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)

    def action(name: str, **kwargs: str) -> argparse.ArgumentParser:
        a = actions.add_parser(name, **kwargs)
        a.add_argument("--db", type=Path, default=argparse.SUPPRESS, help=db_help)  # before or after the action
        return a

    show = action("show", help="list every description with its features",
                  description="List every description: id, grasp(position) and features.")
    show.add_argument("id", nargs="?", help="show only this description")
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
    exp.set_defaults(handler=run_export)
    stats = action("stats", help="counts by grasp, feature and position",
                   description="Summarise the library: descriptions per grasp, features per position.")
    stats.set_defaults(handler=run_stats)


def _store(args: argparse.Namespace, *, create: bool = False) -> LibraryStore:
    """The library store; reading one that does not exist is an error, not a new file."""
    path = args.db or defaults.library_db()
    if not create and not path.exists():
        raise ValueError(f"{path}: no library database there (import into it first, or pass --db)")
    return LibraryStore(path)


def run_show(args: argparse.Namespace) -> int:
    with _store(args) as store:
        descriptions = store.descriptions()
    if args.id is not None:
        descriptions = [d for d in descriptions if d.object_id == args.id]
        if not descriptions:
            raise ValueError(f"library: no description with id {args.id!r}")
    print_table(["id", "grasp", "features"],
                [[d.object_id, f"{d.grasp}{d.grasp_position}", " ".join(str(o) for o in d.observations)]
                 for d in descriptions], title=_count(len(descriptions), "description"))
    return 0


def run_import(args: argparse.Namespace) -> int:
    descriptions = read_library_json(args.file)
    check_library(descriptions, load_knowledge(args.knowledge), str(args.file))
    with _store(args, create=True) as store:
        n = store.add(descriptions, replace=args.replace)
        print(f"imported {_count(n, 'description')} into {store.path}")
    return 0


def run_export(args: argparse.Namespace) -> int:
    with _store(args) as store:
        descriptions = store.descriptions()
    write_library_json(args.file, descriptions)
    print(f"exported {_count(len(descriptions), 'description')} to {args.file}")
    return 0


def run_stats(args: argparse.Namespace) -> int:
    with _store(args) as store:
        descriptions = store.descriptions()
    grasps = Counter(d.grasp for d in descriptions)
    features = Counter(f"{o.feature}{o.position}" for d in descriptions for o in d.observations)
    print(f"{_count(len(descriptions), 'description')}, {_count(sum(features.values()), 'feature value')}, "
          f"{_count(len(features), 'distinct feature-position')}")
    print_table(["grasp", "descriptions"], [[g, str(n)] for g, n in sorted(grasps.items())], title="by grasp")
    print_table(["feature(position)", "descriptions"], [[f, str(n)] for f, n in sorted(features.items())],
                title="by feature")
    return 0


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"

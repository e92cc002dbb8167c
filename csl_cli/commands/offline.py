"""``csl tree`` and ``csl train``: the learner on its own, without a robot."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from executive import defaults
from csl_cli.args import add_criterion_options, criterion_from_args, non_negative_int, writable_file
from reporting.tables import Column, print_paragraph, print_table

if TYPE_CHECKING:  # the learner (numpy) when a command runs, not for --help; the simulator stack only for --sim
    from executive.sim_training import SimTraining
    from learner.training.grasps import GraspSearch
    from learner.training.inputs import TrainingObject
    from learner.training.stage import TrainingResult
    from learner.training.summary import TrainingSummary


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "tree",
        help="print the decision tree the learner grows from a pose",
        description=(
            "Print the whole run-time tree the learner would grow for an unknown object, "
            "standing at POSE, every branch expanded, in the paper's style: a test is "
            "'move-to-(d,θ) (Ns)' then 'Feature(d,θ) (Ns)', a branch '[lo, hi]', a leaf "
            "'Grasp(d,θ) (Ns)'."
        ),
    )
    p.add_argument("--knowledge", type=Path, default=defaults.KNOWLEDGE,
                   help="robot knowledge TOML (default: the shipped HERO 2000 profile)")
    p.add_argument("--library", type=Path, default=None,
                   help="object descriptions, .json or a .sqlite store (default: the robot's, "
                        "$CSL_HOME/library.sqlite; while it does not exist, the last csl demo's; with neither, the "
                        "shipped example library)")
    p.add_argument("--pose", default="60,0", metavar="D,THETA",
                   help="the robot's position relative to the object, inches and degrees (default: 60,0)")
    add_criterion_options(p)
    p.add_argument("--no-grasp-features", action="store_true",
                   help="never try a grasp as a binary feature before sensing")
    p.add_argument("--json", action="store_true", help="print the tree as JSON")
    p.set_defaults(handler=run_tree)

    t = sub.add_parser(
        "train",
        help="run the training stage, in the simulator (--sim) or on recorded measurements",
        description=(
            "The training stage of CSL (Tan & Schlimmer 1991; docs/training-format.md): choose "
            "training positions from the objects' footprints and sizes, then measure at each only "
            "what classifies every object. Prints the positions, what was measured for each object "
            "and the robot time, and writes the learned descriptions. Measurements come from a "
            "replay file (--objects and --measurements) or from the simulator (--sim)."
        ),
    )
    t.add_argument("--knowledge", type=Path, default=defaults.KNOWLEDGE, help="robot knowledge TOML")
    t.add_argument("--objects", type=Path, help="training objects JSON (docs/training-format.md)")
    t.add_argument("--measurements", type=Path,
                   help="replay file of recorded measurements (docs/training-format.md)")
    t.add_argument("--sim", action="store_true",
                   help="measure in the simulator instead: the catalogue's Table 3 training objects, each "
                        "alone, its footprint as the overhead camera sees it (or the robot's scans: --perception), "
                        "with the robot staged at every training position; also checks the library against the "
                        "simulator's exact values")
    t.add_argument("--no-teacher", action="store_true",
                   help="with --sim: find each object's grasp by trying grasps on it (most likely to hold per "
                        "expected second first, learning from each outcome) instead of taking the catalogue's; "
                        "the attempts count in the training cost")
    t.add_argument("--perception", choices=("camera", "onboard"), default=None,
                   help="with --sim: see the training objects with the overhead camera (camera, the default) or "
                        "outline each from the robot's own lidar scans, four views round it (onboard: no ceiling "
                        "camera, no appearance)")
    t.add_argument("--seed", type=non_negative_int, default=0, help="simulator seed (with --sim)")
    t.add_argument("--noise", action="store_true", help="simulated sonar noise on (with --sim; default: exact)")
    t.add_argument("--record", type=Path, metavar="FILE",
                   help="with --sim: also write what was measured as a replay file, and the objects next to it")
    t.add_argument("--out", type=Path, required=True,
                   help="where to write the library: .json, or .sqlite to add to a store (same ids replaced)")
    t.set_defaults(handler=run_train)


MAX_POSE_DISTANCE_IN = 10_000.0
"""The farthest ``--pose``: 833 ft, more than any room one overhead camera sees. A tree
priced from farther is the first move's cost and nothing else, and from 1e308 in every
cost overflows to inf."""


def run_tree(args: argparse.Namespace) -> int:
    from learner.choosing.matrix import DescriptionMatrix
    from learner.choosing.node import Context, Node
    from learner.costs import ModelMoveCost
    from learner.decision_tree import grow
    from csl_cli.library_choice import library_to_read  # the history, and with it numpy
    from learner.library.checks import check_library
    from learner.library.store import load_library
    from learner.position import parse_position
    from learner.render import tree_json, tree_text
    from robot_profile import load_knowledge

    knowledge = load_knowledge(args.knowledge)
    path = args.library or library_to_read(None, "--library", "csl tree") or defaults.EXAMPLE_LIBRARY
    library = load_library(path)
    if not library:
        raise ValueError(f"{path}: the library is empty")
    check_library(library, knowledge, str(path))
    start = parse_position(args.pose, "--pose")
    if start.distance_in is None or start.orientation_deg is None:
        raise ValueError("--pose: the robot's pose must be concrete (no '*')")
    if start.distance_in > MAX_POSE_DISTANCE_IN:
        raise ValueError(f"--pose: a distance of {start.distance_in:g} in is farther than any room "
                         f"(at most {MAX_POSE_DISTANCE_IN:g} in)")
    matrix = DescriptionMatrix(library, knowledge, grasps_as_features=not args.no_grasp_features)
    ctx = Context(matrix, criterion_from_args(args), ModelMoveCost(knowledge.move))
    tree = grow(Node.root(len(library)), start, ctx)
    if args.json:
        json.dump(tree_json(tree), sys.stdout, indent=2, ensure_ascii=False)
        print()
    else:
        print(tree_text(tree))
    return 0


def run_train(args: argparse.Namespace) -> int:
    from learner.costs import ModelMoveCost
    from learner.library.format import write_json_atomically, write_library_json
    from learner.library.store import LibraryStore
    from learner.training.inputs import objects_document, read_objects, read_replay, replay_document
    from learner.training.stage import train
    from learner.training.summary import summarise
    from robot_profile import load_knowledge, load_profile

    # The simulator drives a robot body, so --sim needs the whole profile; replayed
    # measurements need only the learner's part ([robot] may be absent).
    profile = load_profile(args.knowledge) if args.sim else None
    knowledge = load_knowledge(args.knowledge) if profile is None else profile.knowledge()
    if args.out.suffix.lower() not in (".json", ".sqlite", ".db"):
        raise ValueError(f"--out: {args.out} must end in .json or .sqlite")
    writable_file(args.out, "--out")  # before hours of (simulated) training, not after
    if args.record:
        writable_file(args.record, "--record")
    sim: SimTraining | None = None
    if args.sim:
        if args.objects or args.measurements:
            raise ValueError("--sim measures in the simulator: leave out --objects and --measurements")
        from executive.sim_training import train_in_simulator

        sim = train_in_simulator(knowledge, profile, args.seed, args.noise, teacher=not args.no_teacher,
                                 perception=args.perception or "camera")
        objects = list(sim.seen.objects if sim.grasp_search is None else sim.grasp_search.objects)
        result, summary = sim.result, sim.summary
    else:
        if args.no_teacher:
            raise ValueError("--no-teacher tries grasps in the simulator: it goes with --sim")
        if args.perception:
            raise ValueError("--perception chooses how the simulator sees the training objects: it goes with --sim")
        if not (args.objects and args.measurements):
            raise ValueError("train needs --objects and --measurements (or --sim)")
        if args.record:
            raise ValueError("--record goes with --sim")
        objects = read_objects(args.objects)
        for o in objects:
            if not knowledge.has_grasp(o.grasp):
                raise ValueError(f"{args.objects}: object {o.object_id!r}: grasp {o.grasp!r} is not in the knowledge file")
        result = train(objects, knowledge, read_replay(args.measurements), ModelMoveCost(knowledge.move))
        summary = summarise(result, objects, knowledge)
    if sim is not None and sim.grasp_search is not None:
        _print_grasp_search(sim.grasp_search, list(sim.seen.objects))
    _print_training(objects, result, summary)
    if sim is not None and sim.grasp_search is not None:
        print_paragraph(f"with finding the grasps: {sim.robot_s:.0f} s of robot time ({sim.robot_s / 3600:.1f} h)")
    if sim is not None:
        from executive.sim_training import ground_truth

        truth = ground_truth(result.descriptions, sim.seen, knowledge, summary, profile)
        print_paragraph(f"against the simulator's exact values: {len(truth.misfits)} of {truth.checked} library "
                        "values (each at every training position it stands for) off by more than the expected error")
        for misfit in truth.misfits:
            print(f"  {misfit}")
    if args.out.suffix.lower() == ".json":
        write_library_json(args.out, result.descriptions)
    else:
        with LibraryStore(args.out) as store:
            store.add(result.descriptions, replace=True)
    print(f"wrote {len(result.descriptions)} descriptions to {args.out}")
    if args.record and sim is not None:
        write_json_atomically(args.record, replay_document(sim.source.records))
        objects_path = args.record.with_name(args.record.stem + "-objects.json")
        write_json_atomically(objects_path, objects_document(objects))
        print(f"recorded {len(sim.source.records)} measurements to {args.record}, objects to {objects_path}")
    return 0


MEASURED_COLUMNS = (Column("object"), Column("n", numeric=True), Column("procedures applied", fold=True))
"""Whole ids, and every procedure applied, folded onto as many lines as it takes."""


SEARCH_COLUMNS = (Column("object"), Column("found"), Column("catalogue's"), Column("tries", numeric=True),
                  Column("s", numeric=True))


def _print_grasp_search(search: GraspSearch, taught: list[TrainingObject]) -> None:
    """Each object's grasp as found, next to the catalogue's label it was not given."""
    print_table(SEARCH_COLUMNS, [
        [o.object_id, f"{o.grasp}{o.grasp_position}", f"{t.grasp}{t.grasp_position}",
         str(sum(1 for x in search.trials if x.object_id == o.object_id)),
         f"{sum(x.seconds + x.move_s for x in search.trials if x.object_id == o.object_id):.0f}"]
        for o, t in zip(search.objects, taught)], title="grasps found by trying them")
    print_paragraph(f"finding the grasps: {len(search.trials)} attempts, {search.grasping_s:.0f} s grasping and "
                    f"{search.moving_s:.0f} s moving")


def _print_training(objects: list[TrainingObject], result: TrainingResult, summary: TrainingSummary) -> None:
    """Positions found, what was measured per object, and the robot time (the paper's
    training figures: 0/90/181/272°, 6/16/24 in, about 7 h; exhaustive over 5 years)."""
    log = result.log
    print(f"training orientations (deg): {', '.join(f'{o:g}' for o in summary.orientations_deg)}")
    print(f"training distances (in):     {', '.join(f'{d:g}' for d in summary.distances_in)}")
    print_paragraph(f"  from {len(log.distance_reasons)} candidate distances (a sweep still separating two "
                    "similar-sized objects of different grasps); for example:", indent=2)
    for d in summary.distances_in:
        near = [r for r in log.distance_reasons if abs(r.distance_in - d) < 1.0]
        if near:
            r = min(near, key=lambda r: r.distance_in)
            print_paragraph(f"  {d:g} in: {r.feature} separates {r.object_a} from {r.object_b} up to "
                            f"{r.distance_in:.1f} in", indent=4)
    per_object: dict[str, list[str]] = {}
    for oid, proc, pos, _why in log.applied:
        per_object.setdefault(oid, []).append(f"{proc}{pos}")
    print_table(MEASURED_COLUMNS,
                [[o.object_id, str(len(per_object.get(o.object_id, []))), ", ".join(per_object.get(o.object_id, []))]
                 for o in objects], title="measured per object", row_lines=True)
    if log.unresolved:
        where = sorted({str(pos) for _, pos in log.unresolved})
        objects_left = len({oid for oid, _ in log.unresolved})
        print_paragraph(f"note: at {len(where)} far position(s) ({', '.join(where)}) {objects_left} object(s) "
                        "could not all be told apart with the procedures usable there; nearer positions resolve them")
    print_paragraph(f"training cost: {summary.total_s:.0f} s of robot time ({summary.sensing_s:.0f} s sensing, "
                    f"{summary.moving_s:.0f} s moving; {summary.robot_hours:.1f} h); {summary.applications} "
                    f"procedure applications, {summary.observations} values in {summary.descriptions} descriptions")
    print_paragraph(f"every procedure at every training position: {summary.every_procedure_at_positions_s / 3600:.1f} "
                    f"h of sensing; at every whole inch and degree (exhaustive): {summary.exhaustive_years:.1f} years")

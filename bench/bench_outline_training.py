"""Training from outlines against training from the camera (``csl train --sim`` with
``--perception onboard`` and ``camera``): what each sees of the Table 3 objects, and
whether the libraries and decision trees they train are the same.

    python bench/bench_outline_training.py [--seeds 5]

First, per object: the reference axis each perception finds, as degrees from the
catalogue's (the object lies at yaw 0), the camera's (noise makes no difference to
it here), the outline's from exact scans and the worst over ``--seeds`` seeds of noisy
ones (the simulator's default scan noise), and the outline's difference from the
camera's; axes are undirected (the camera's points into the half with more pixels),
so differences are taken modulo 180°; and what each calls round.

Then both trainings, without and with noise (seed 0): their training positions,
procedure applications, values kept, robot time, misfits against the simulator's
exact values; how many values at the positions both libraries hold are equal (each
position's orientation taken as the face it stands for, the nearest multiple of
90°); and whether the decision tree grown from each library is the same from four
start poses, read the same way (a move between two positions at the same face, which
costs nothing, left out).
"""

from __future__ import annotations

import argparse
import datetime
import platform
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.outline_objects import outline_objects  # noqa: E402
from executive.sim_training import SimTraining, ground_truth, train_in_simulator  # noqa: E402
from executive.training_sources import camera_objects  # noqa: E402
from learner.choosing.criteria import DEFAULT_CRITERION, criterion  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.choosing.node import Context, Node  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.decision_tree import grow  # noqa: E402
from learner.description import ObjectDescription  # noqa: E402
from learner.knowledge import Knowledge  # noqa: E402
from learner.position import Position  # noqa: E402
from learner.render import tree_text  # noqa: E402
from robot_profile import load_profile  # noqa: E402

START_POSES = (Position(60.0, 0.0), Position(30.0, 90.0), Position(100.0, 180.0), Position(45.0, 270.0))


def undirected(a: float) -> float:
    """An axis's angle in (-90, 90]."""
    a = (a + 90.0) % 180.0 - 90.0
    return 90.0 if a == -90.0 else a


def face(orientation: float | None) -> str:
    return "*" if orientation is None else str(round(orientation / 90.0) % 4 * 90)


def by_face(description: ObjectDescription) -> dict[tuple[str, float | None, str], float]:
    return {(o.feature, o.position.distance_in, face(o.position.orientation_deg)): o.value
            for o in description.observations}


def tree_by_face(library: tuple[ObjectDescription, ...], knowledge: Knowledge, start: Position) -> str:
    """The tree's text with every orientation read as its face, free moves left out."""
    matrix = DescriptionMatrix(list(library), knowledge)
    tree = grow(Node.root(len(library)), start, Context(matrix, criterion(DEFAULT_CRITERION),
                                                        ModelMoveCost(knowledge.move)))
    text = re.sub(r"\((\d+(?:\.\d+)?),(\d+(?:\.\d+)?)\)", lambda m: f"({m[1]},{face(float(m[2]))})", tree_text(tree))
    return "\n".join(line for line in text.splitlines() if not re.match(r"\s*move-to-\(.*\) \(0s\)$", line))


def axes(seeds: int) -> None:
    camera = camera_objects()
    exact = outline_objects()
    noisy = [outline_objects(noise=True, seed=s) for s in range(seeds)]
    print(f"| object | camera ° | outline ° (exact) | outline ° (noise, worst of {seeds}) | outline − camera ° "
          "| round: camera / outline |")
    print("|---|---:|---:|---:|---:|---|")
    for cam, out in zip(camera.objects, exact.objects):
        oid = cam.object_id
        cam_axis = undirected(camera.axis_offsets_deg[oid])
        worst = max((undirected(n.axis_offsets_deg[oid]) for n in noisy), key=abs)
        difference = max((undirected(n.axis_offsets_deg[oid] - camera.axis_offsets_deg[oid]) for n in noisy), key=abs)
        rounds = f"{'yes' if cam.round else 'no'} / {'yes' if out.round else 'no'}"
        print(f"| {oid} | {cam_axis:.2f} | {undirected(exact.axis_offsets_deg[oid]):.2f} | {worst:.2f} | "
              f"{difference:.2f} | {rounds} |")


def compare(noise: bool) -> None:
    profile = load_profile()
    knowledge = profile.knowledge()
    runs: dict[str, SimTraining] = {p: train_in_simulator(knowledge, profile, 0, noise, perception=p)
                                    for p in ("camera", "onboard")}
    print(f"| noise {'on' if noise else 'off'}, seed 0 | camera | onboard (outlines) |")
    print("|---|---|---|")
    rows: dict[str, list[str]] = {"training orientations (°)": [], "training distances (in)": [],
                                  "procedure applications": [], "values kept (14 descriptions)": [],
                                  "robot time (h)": [], "misfits against the exact values": []}
    for run in runs.values():
        s = run.summary
        truth = ground_truth(run.result.descriptions, run.seen, knowledge, s, profile)
        rows["training orientations (°)"].append(", ".join(f"{o:g}" for o in s.orientations_deg))
        rows["training distances (in)"].append(", ".join(f"{d:g}" for d in s.distances_in))
        rows["procedure applications"].append(str(s.applications))
        rows["values kept (14 descriptions)"].append(str(s.observations))
        rows["robot time (h)"].append(f"{s.robot_hours:.1f}")
        rows["misfits against the exact values"].append(f"{len(truth.misfits)} of {truth.checked}")
    for name, cells in rows.items():
        print(f"| {name} | {' | '.join(cells)} |")
    camera, onboard = (runs[p].result.descriptions for p in ("camera", "onboard"))
    shared = equal = 0
    for a, b in zip(camera, onboard):
        va, vb = by_face(a), by_face(b)
        for key in va.keys() & vb.keys():
            shared += 1
            equal += va[key] == vb[key]
    print(f"| values at positions both hold: equal | {equal} of {shared} | |")
    same = [tree_by_face(camera, knowledge, start) == tree_by_face(onboard, knowledge, start) for start in START_POSES]
    print(f"| decision tree the same, by face, from {', '.join(map(str, START_POSES))} | "
          f"{', '.join('yes' if s else 'no' for s in same)} | |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=5, help="seeds of noisy outlines per object (default 5)")
    args = parser.parse_args()
    print(f"date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}")
    print(f"command: python bench/bench_outline_training.py --seeds {args.seeds}")
    print()
    axes(args.seeds)
    for noise in (False, True):
        print()
        compare(noise)


if __name__ == "__main__":
    main()

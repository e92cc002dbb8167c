"""Small hand-made libraries whose gains and costs the tests work out by hand."""

from __future__ import annotations

from pathlib import Path

from robot_profile import load_knowledge
from learner.choosing.criteria import CriterionSpec, criterion
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Context
from learner.costs import ModelMoveCost
from learner.description import ObjectDescription, Observation
from learner.knowledge import Knowledge, MoveModel
from learner.position import Position

HERO = Path(__file__).resolve().parents[2] / "hero_driver" / "profiles" / "hero2000.toml"
ANY = None


def hero() -> Knowledge:
    return load_knowledge(HERO)


def P(d: float | None, o: float | None) -> Position:  # noqa: N802 - reads like the paper
    return Position(d, o)


def desc(oid: str, grasp: str, *obs: tuple[str, Position, float], at: Position = Position(6, None)) -> ObjectDescription:
    return ObjectDescription(oid, grasp, at, tuple(sorted(Observation(f, p, v) for f, p, v in obs)))


def three_wraps_and_a_tumbler() -> list[ObjectDescription]:
    """Three Front-Wrap objects and one Top-Pinch one; a 5° vertical sweep tells all four
    apart (heights 30, 40, 70, 60, each its own range with the 5° error)."""
    return [
        desc("cup", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 30)),
        desc("soda-can", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 40)),
        desc("tennis-can", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 70)),
        desc("tumbler", "Top-Pinch", ("Height-Degree-5°", P(6, ANY), 60)),
    ]


def four_objects() -> list[ObjectDescription]:
    """Cup, open box, tumbler, closed box: four grasps, H(C) = 2 bits.

    Width-Degree-1°(24,0): 8, 18, 9, 30 -> ranges [8,9] [18] [30]: I = 2 - 2/4*1 = 1.5.
    Height(6,*): 3.5, 9, 6, missing -> 3 ranges + unknown subset, the closed box spread
    1/4 into each: I = 2 - 3 * (1.25/4) * H(0.8, 0.2) = 1.3233.
    """
    return [
        desc("cup", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8), ("Height", P(6, ANY), 3.5)),
        desc("box", "Front-Pinch", ("Width-Degree-1°", P(24, 0), 18), ("Height", P(6, ANY), 9)),
        desc("tumbler", "Top-Pinch", ("Width-Degree-1°", P(24, 0), 9), ("Height", P(6, ANY), 6),
             ("Top-Hole?", P(6, ANY), 1)),
        desc("closed", "No-Grab", ("Width-Degree-1°", P(24, 0), 30), at=P(ANY, ANY)),
    ]


def context(library: list[ObjectDescription], knowledge: Knowledge | None = None, name: str | CriterionSpec = "cs-id3",
            grasps: bool = True, move: MoveModel | None = None) -> Context:
    """``name``: a product criterion's name, or a spec composed with the learner's
    builders (``with_joint_gain`` ...) for a form the product does not offer."""
    k = knowledge or hero()
    rule = name.build() if isinstance(name, CriterionSpec) else criterion(name)
    return Context(DescriptionMatrix(library, k, grasps), rule, ModelMoveCost(move or k.move))

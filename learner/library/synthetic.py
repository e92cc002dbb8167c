"""Synthetic libraries: plausible object descriptions made by perturbing real ones.

Two needs call for more libraries than the robot has learned: the distance to the
optimum on a library that is not the one the rules were tuned on, and the scaling of
test choice from 100 to 100,000 descriptions. Values drawn uniformly from a feature's
span would make every pair of objects trivially separable by one test; real libraries
are not like that (objects of one family share sizes, descriptions are incomplete in
patterns that training left). So each synthetic description starts from a real one and
keeps its structure: the same features at the same positions (``*`` slots included),
each value moved by up to twice its feature's expected error and kept in the span, a
few observations dropped (incomplete on purpose, as learned ones are), a hole feature
flipped now and then, and the grasp, now and then, swapped for another grasp of the
base library, so the classes stay the few the robot has.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from learner.description import ObjectDescription, Observation
from learner.knowledge import FeatureSpec, Knowledge

_SHIFT_ERRORS = 2.0  # a value moves by up to this many expected errors
_DROP = 0.1  # chance an observation is left out
_FLIP = 0.1  # chance a binary (hole) value flips
_OTHER_GRASP = 0.15  # chance the grasp is another of the base library's grasps


def synthetic_library(knowledge: Knowledge, n_objects: int, seed: int, *,
                      base: Sequence[ObjectDescription]) -> list[ObjectDescription]:
    """``n_objects`` descriptions perturbed from ``base`` (e.g. the shipped library),
    repeatable from ``seed``; ids are ``synthetic-NNNNNN/<base id>``.

    Only features the knowledge has are kept (a value must have an error and a span to
    be perturbed within).
    """
    if n_objects < 0:
        raise ValueError(f"n_objects must not be negative, got {n_objects}")
    templates = [d for d in base if any(knowledge.has_feature(o.feature) for o in d.observations)]
    if not templates:
        raise ValueError("synthetic_library needs base descriptions with features the knowledge has")
    grasps = sorted({d.grasp for d in templates})
    rng = np.random.default_rng(seed)
    width = max(6, len(str(n_objects)))
    return [_perturbed(templates[int(rng.integers(len(templates)))], f"synthetic-{i:0{width}d}", grasps,
                       knowledge, rng) for i in range(n_objects)]


def _perturbed(template: ObjectDescription, prefix: str, grasps: Sequence[str], knowledge: Knowledge,
               rng: np.random.Generator) -> ObjectDescription:
    observations = [o for o in template.observations if knowledge.has_feature(o.feature)]
    keep = rng.random(len(observations)) >= _DROP
    if not keep.any():
        keep[int(rng.integers(len(observations)))] = True
    shifts = rng.uniform(-_SHIFT_ERRORS, _SHIFT_ERRORS, len(observations))
    flips = rng.random(len(observations)) < _FLIP
    grasp = template.grasp
    if len(grasps) > 1 and rng.random() < _OTHER_GRASP:
        grasp = grasps[int(rng.integers(len(grasps)))]
    # (feature, position) is unique in a description, so the template's order still sorts
    moved = tuple(Observation(o.feature, o.position, _moved(o.value, knowledge.feature(o.feature), shift, flip))
                  for o, k, shift, flip in zip(observations, keep.tolist(), shifts.tolist(), flips.tolist()) if k)
    return ObjectDescription(f"{prefix}/{template.object_id}", grasp, template.grasp_position, moved)


def _moved(value: float, spec: FeatureSpec, shift: float, flip: bool) -> float:
    """``value`` moved by ``shift`` errors (to 0.1, within the span); a binary value
    flipped instead, when ``flip``."""
    if spec.binary:
        return 1.0 - value if flip else value
    return round(min(max(value + shift * spec.error, spec.span[0]), spec.span[1]), 1)

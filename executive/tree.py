"""The behaviour tree: Table 7 of the paper and its control strategies as composites.

Every recovery is a branch you can see in ``csl bt``: reselection, backtracking and
nearest neighbour under "choose a test" / "step"; the ambiguous leaf inside
ChooseGrasp; side effects and dropping a failed grasp under "recover".
"""

from __future__ import annotations

import py_trees
from py_trees.composites import Selector, Sequence

from behaviours.acting import ApplyTest, Grasp, MoveTo
from behaviours.choosing import Backtrack, BestTest, ChooseGrasp, NearestNeighbour, Reselect
from behaviours.context import Services
from behaviours.learning import Discriminate, DropFailedGrasp, FollowBranch, Learn, StartOver
from behaviours.loops import ForEachObject, UntilHandled
from behaviours.perception import CheckSideEffects, LocateObjects, RememberAppearance


def build_tree(services: Services) -> py_trees.behaviour.Behaviour:
    """The executive's tree for one episode: locate, then approach and recognize each."""
    choose = Selector("choose a test", memory=True, children=[
        BestTest(services), Reselect(services), Backtrack(services)])
    follow = Sequence("follow the tree", memory=True, children=[
        choose, MoveTo(services, "test"), ApplyTest(services), FollowBranch(services)])
    grasp = Sequence("grasp", memory=True, children=[
        ChooseGrasp(services), MoveTo(services, "grasp"), Grasp(services)])
    recover = Selector("recover", memory=True, children=[
        Sequence("side effects", memory=True, children=[CheckSideEffects(services), StartOver(services)]),
        Sequence("wrong grasp", memory=True, children=[DropFailedGrasp(services), Discriminate(services)]),
    ])
    step = Selector("step", memory=True, children=[follow, NearestNeighbour(services), grasp, recover])
    per_object = Sequence("approach and recognize", memory=True, children=[
        RememberAppearance(services),
        UntilHandled(step, services, name="recognize and grasp"),
        Learn(services),
    ])
    return Sequence("retrieve objects", memory=True, children=[
        LocateObjects(services),
        ForEachObject(per_object, services, name="each object"),
    ])

"""The behaviour tree: Table 7 of the paper and its control strategies as composites.

Built without resources: the services arrive in ``setup(services=...)``, so ``csl bt``
and the shape snapshot build the tree alone. Every recovery is a branch you can see:
reselection (gated by ``Unreliable?``), backtracking and nearest neighbour under
"choose a test" / "step"; the ambiguous leaf under "choose a grasp"; the other end
under "reach the grasp"; and, gated by ``GraspFailed?``, side effects or dropping a
failed grasp under "recover". Before each sensing and each grasp, ``Disturbed?`` looks
with the camera and, when the object moved, changed or is gone, relocates it, starts
afresh or reports it gone (``behaviours.disturbance``). Above it all, the low-battery
guard ("battery check", ``behaviours.battery``) sends the robot to its dock and lets the
work resume where it was; above that, gated by ``DriverLost?``, the lost-driver guard
("driver check", ``behaviours.reconnect``) waits for a driver that went away to come
back and has the objects located again. Without a ceiling camera, "explore the home"
comes first: look, go to the next view, until the home is mapped
(``behaviours.exploration``); every look is then a scan. Each move to a test or grasp position can be
blocked by a moving obstacle: "until past" looks again, re-plans around it or waits,
and gives the object up after a bound (``behaviours.blocked``). Between a test's choice
and the move to it, ``BeamClear?`` makes a test whose sonar beam another object would
meet unusable there (``behaviours.clutter``). A sensing or grasp the driver refuses as
out of range is re-approached, gated by ``RefusedForRange?`` (``behaviours.reapproach``).
What the robot says is checked where it can be: ``Plausible?`` makes a sensing whose
value its feature cannot take unusable there (``behaviours.plausible``), and
``GraspVerified?`` fails an object reported grasped that the camera still sees on the
floor, and ``LetGo`` opens the hand (``behaviours.verified_grasp``).
"""

from __future__ import annotations

import py_trees
from py_trees.composites import Selector, Sequence

from behaviours.actions import ApplyTest, Grasp, Learn, LocateObjects, MoveTo
from behaviours.battery import guarded
from behaviours.blocked import around_movers
from behaviours.choosing import BestTest, ChooseGrasp, FollowBranch
from behaviours.clutter import BeamClear, LookForTheRest
from behaviours.disturbance import look_before
from behaviours.exploration import explore as explore_home
from behaviours.loop import ForEachObject, StartObject, UntilHandled
from behaviours.plausible import Plausible
from behaviours.reapproach import reapproached
from behaviours.reconnect import reconnecting
from behaviours.verified_grasp import grasp_verified
from behaviours.recovery import (AmbiguousGrasp, Backtrack, CheckSideEffects, Discriminate, DropFailedGrasp,
                                 GraspFailed, NearestNeighbour, OtherEnd, Reselect, StartOver, ValueUnreliable)


def build_tree(robot: str = "r1", explore: bool = False) -> py_trees.behaviour.Behaviour:
    """The executive's tree for one episode of robot ``robot``: locate, then approach and
    recognize each object; with ``explore`` (a robot without a ceiling camera), explore
    the home first (``behaviours.exploration``)."""
    choose = Selector("choose a test", memory=True, children=[
        BestTest(robot),
        Sequence("reselect", memory=True, children=[ValueUnreliable(robot), Reselect(robot)]),
        Backtrack(robot)])
    follow = Sequence("follow the tree", memory=True, children=[
        choose, BeamClear(robot), _move(robot, "test"),
        look_before(robot, "test", Sequence("measure", memory=True, children=[
            reapproached(robot, ApplyTest(robot)), Plausible(robot), FollowBranch(robot)]))])
    grasp = Sequence("grasp", memory=True, children=[
        Selector("choose a grasp", memory=True, children=[ChooseGrasp(robot), AmbiguousGrasp(robot)]),
        Selector("reach the grasp", memory=True, children=[_move(robot, "grasp"), OtherEnd(robot)]),
        look_before(robot, "grasp", reapproached(robot, Grasp(robot)))])
    recover = Sequence("recover", memory=True, children=[
        GraspFailed(robot),
        Selector("how it failed", memory=True, children=[
            Sequence("side effects", memory=True, children=[CheckSideEffects(robot), StartOver(robot)]),
            Sequence("wrong grasp", memory=True, children=[DropFailedGrasp(robot), Discriminate(robot)]),
        ])])
    step = Selector("step", memory=True, children=[follow, NearestNeighbour(robot), grasp, recover])
    per_object = Sequence("approach and recognize", memory=True, children=[
        StartObject(robot),
        UntilHandled(step, robot, name="recognize and grasp"),
        grasp_verified(robot),
        Learn(robot),
        LookForTheRest(robot),
    ])
    return reconnecting(guarded(Sequence("retrieve objects", memory=True, children=[
        *([explore_home(robot)] if explore else []),
        LocateObjects(robot),
        ForEachObject(per_object, robot, name="each object"),
    ]), robot), robot)


def _move(robot: str, target: str) -> py_trees.behaviour.Behaviour:
    """A move to the step's ``target`` position with the blocked-move branch."""
    return around_movers(robot, MoveTo(robot, target),
                         MoveTo(robot, target, f"MoveTo {target} around it", role="around"),
                         MoveTo(robot, target, f"MoveTo {target} again", role="retry"))

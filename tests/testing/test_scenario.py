"""Running a scenario: the same inputs give the same transcript, the driver and store
are the scenario's own, and every input reaches the episode."""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest

from behaviours.services import Params
from csl_testing import Scenario, ScenarioFactory, one_object, simulated_hero, tree_display
from executive.defaults import EXAMPLE_LIBRARY
from hero_driver.interface import DriverError
from hero_driver.sim.worldfile import Placement
from learner.library.format import read_library_json


def test_the_same_scenario_gives_the_same_transcript(tmp_path: Path) -> None:
    scenario = one_object("cup-8oz/upright", seed=0, workdir=tmp_path)
    first, again = scenario.run(), scenario.run()
    assert first.transcript() == again.transcript()
    assert first.store != again.store and first.store.parent.parent == tmp_path  # a new store each run
    moves = [line for line in first.transcript().splitlines() if " move: " in line]
    assert moves and not any("seconds=" in m or "path=" in m for m in moves)
    assert (first.status, first.object.outcome, first.object.grasp) == ("SUCCESS", "grasped", "Front-Wrap")


def test_every_input_reaches_the_episode(tmp_path: Path) -> None:
    """The driver factory is called with the robot, world, seed and noise; the driver is
    closed afterwards; the store given is the one written; the library given is what a
    new store starts from; max_ticks stops the tree."""
    calls, drivers = [], []

    def recording_driver(robot, world, seed, noise):  # noqa: ANN001, ANN202
        calls.append((robot, world.objects, seed, noise))
        drivers.append(simulated_hero(robot, world, seed, noise))
        return drivers[-1]

    store = tmp_path / "mine.sqlite"
    known = read_library_json(EXAMPLE_LIBRARY)
    result = Scenario(objects=[("cup-8oz/upright", 110, 80, 20)], seed=5, noise="clean", library=known,
                      driver=recording_driver, robot="r7", max_ticks=2, store=store,
                      params=Params(use_appearance=False)).run()  # arm only: three ticks, so two stop it
    assert [(r, o, s, n.outlier_p) for r, o, s, n in calls] == [
        ("r7", (Placement("cup-8oz/upright", 110.0, 80.0, 20.0),), 5, 0.0)]
    with pytest.raises(DriverError, match="closed"):
        drivers[0].state()
    assert result.store == store and store.is_file()
    assert result.ticks == 2 and result.status == "INVALID"  # stopped while running (it learns at tick 3)
    assert result.library == tuple(known)  # what the store started from; nothing learned yet
    assert [line[:5] for line in result.trace] == ["   1 ", "   2 "]


def test_the_object_of_a_two_object_episode_is_refused(tmp_path: Path) -> None:
    result = Scenario(objects=[("cup-8oz/upright", 60, 90), ("soda-can-12oz/lying", 150, 60)],
                      workdir=tmp_path).run()
    assert [o.index for o in result.objects] == [0, 1]
    with pytest.raises(ValueError, match=r"^the episode handled 2 objects, not one$"):
        result.object  # noqa: B018


@pytest.mark.parametrize(("inputs", "message"), [
    ({"seed": -1}, "seed: expected a whole number >= 0, got -1"),
    ({"seed": True}, "seed: expected a whole number >= 0, got True"),
    ({"max_ticks": 2.5}, "max_ticks: expected a whole number >= 0, got 2.5"),
    ({"params": {"max_alternatives": 1}}, "params: expected behaviours.services.Params, got dict"),
])
def test_bad_inputs_are_one_line(inputs: dict, message: str) -> None:
    with pytest.raises(ValueError) as caught:
        Scenario(**inputs)
    assert str(caught.value) == message


def test_objects_are_checked_when_the_scenario_is_made() -> None:
    scenario = Scenario(objects=[("cup-8oz/upright", 110, 80)])
    assert scenario.objects == (Placement("cup-8oz/upright", 110.0, 80.0, 0.0),)
    with pytest.raises(ValueError, match=r"^objects\[0\]: expected a Placement"):
        Scenario(objects=["cup-8oz/upright"])


def test_but_changes_only_what_it_names(tmp_path: Path) -> None:
    base = ScenarioFactory(tmp_path).one_object("cup-8oz/upright", seed=2)
    changed = base.but(seed=3)
    assert (changed.seed, changed.objects, changed.workdir) == (3, base.objects, tmp_path)


def test_tree_display_is_py_trees_unicode_tree_without_colours(monkeypatch: pytest.MonkeyPatch) -> None:
    root = py_trees.composites.Sequence("s", memory=True, children=[
        py_trees.behaviours.Success("a"),
        py_trees.composites.Selector("b", memory=False, children=[py_trees.behaviours.Failure("c")])])
    assert tree_display(root) == "{-} s\n    --> a\n    [o] b\n        --> c\n"
    assert tree_display().splitlines()[0] == "[o] driver check"  # the executive's own tree
    monkeypatch.setattr(py_trees.display, "unicode_tree", lambda _root: "\x1b[1m{-} s\x1b[0m\n    \x1b[32m--> a\n")
    assert tree_display(root) == "{-} s\n    --> a\n"

"""``csl demo`` reuses the library it trained while the inputs are the same."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import executive.sim_training
from csl_cli.demo_library import DemoLibrary, trained_folder, trained_library, training_key
from executive.sim_training import SimTraining
from learner.library.format import read_library_json
from robot_profile import load_profile
from tests.executive.floors import sim_training
from tests.learner.fixtures import HERO

WORLDS = Path(executive.sim_training.__file__).resolve().parents[1] / "hero_driver" / "worlds"


@pytest.fixture(scope="module")
def trained_once() -> SimTraining:
    return sim_training()  # the shipped profile's (HERO's), shared with the other training tests


class Trainings:
    """Stands in for training in the simulator, counting the runs (and their seeds)."""

    def __init__(self, result: SimTraining) -> None:
        self.result, self.seeds = result, []

    def __call__(self, knowledge, profile, seed=0, noise=False) -> SimTraining:  # noqa: ANN001
        self.seeds.append((seed, noise))
        return self.result


@pytest.fixture
def trainings(trained_once: SimTraining, monkeypatch: pytest.MonkeyPatch) -> Trainings:
    counter = Trainings(trained_once)
    monkeypatch.setattr(executive.sim_training, "train_in_simulator", counter)
    return counter


def _demo(folder: Path, world: str | Path = "lab", seed: int = 0, retrain: bool = False,
          profile_path: Path = HERO) -> tuple[DemoLibrary, list[str]]:
    said: list[str] = []
    profile = load_profile(profile_path)
    library = trained_library(profile.knowledge(), profile, world, seed, retrain=retrain, folder=folder,
                              say=said.append)
    return library, said


def test_a_second_demo_reuses_the_library_the_first_trained(tmp_path: Path, trainings: Trainings) -> None:
    first, said = _demo(tmp_path)
    assert not first.reused and said[0].startswith("training on the Table 3 objects") and first.key[:12] in said[0]
    second, said = _demo(tmp_path)
    assert second.reused and said == [f"reusing trained library {first.key[:12]} ({tmp_path / first.key}.json)"]
    assert trainings.seeds == [(0, False)]  # trained once, without noise
    assert second.descriptions == first.descriptions == trainings.result.result.descriptions
    assert second.summary == first.summary == trainings.result.summary
    assert (second.key, first.key) == (first.key, training_key(load_profile(HERO), "lab", 0))


def test_a_changed_input_or_retrain_trains_again(tmp_path: Path, trainings: Trainings) -> None:
    base, _ = _demo(tmp_path)
    other_seed, _ = _demo(tmp_path, seed=1)
    world = tmp_path / "lab-copy.json"
    world.write_text((WORLDS / "lab.json").read_text(encoding="utf-8") + "\n", encoding="utf-8")
    other_world, _ = _demo(tmp_path, world=world)
    profile = tmp_path / "hero-copy.toml"
    profile.write_text(HERO.read_text(encoding="utf-8") + "\n# a comment is a change too\n", encoding="utf-8")
    other_profile, _ = _demo(tmp_path, profile_path=profile)
    forced, said = _demo(tmp_path, retrain=True)
    assert [d.reused for d in (base, other_seed, other_world, other_profile, forced)] == [False] * 5
    assert len({base.key, other_seed.key, other_world.key, other_profile.key}) == 4 and forced.key == base.key
    assert trainings.seeds == [(0, False), (1, False), (0, False), (0, False), (0, False)]
    assert _demo(tmp_path, world=WORLDS / "lab.json")[0].reused  # the same file, named by path
    assert len(list(tmp_path.glob("*.json"))) == 4 + 1  # four libraries and the world copy


def test_the_training_code_is_part_of_the_key(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    profile = load_profile(HERO)
    before = training_key(profile, "lab", 0)
    repository = tmp_path / "repo"
    for source in ("learner/training/stage.py", "executive/sim_training.py"):
        (repository / source).parent.mkdir(parents=True, exist_ok=True)
        (repository / source).write_text("# version 1\n", encoding="utf-8")
    monkeypatch.setattr("csl_cli.demo_library.REPOSITORY", repository)
    one = training_key(profile, "lab", 0)
    (repository / "learner" / "training.py").write_text("# version 2\n", encoding="utf-8")
    assert len({before, one, training_key(profile, "lab", 0)}) == 3


def test_a_damaged_stored_library_is_trained_again(tmp_path: Path, trainings: Trainings) -> None:
    first, _ = _demo(tmp_path)
    (tmp_path / f"{first.key}.json").write_text("{not json", encoding="utf-8")
    again, said = _demo(tmp_path)
    assert not again.reused and said[0].startswith("ignoring the stored trained library: ")
    assert len(trainings.seeds) == 2 and _demo(tmp_path)[0].reused  # stored again, whole


@pytest.mark.slow
def test_the_stored_library_is_the_shipped_one_and_lives_in_the_user_data_folder(trained_once: SimTraining) -> None:
    """The default folder is under ``$CSL_HOME``; seed 0 trains the shipped library
    (tests/executive/test_train_sim.py), and that is what comes back from the store."""
    assert trained_folder() == Path(os.environ["CSL_HOME"]) / "trained"
    _demo(trained_folder())
    second, _ = _demo(trained_folder())
    assert second.reused and tuple(read_library_json(HERO.parent / "hero2000-library.json")) == second.descriptions


def test_a_folder_that_cannot_be_written_still_gives_the_demo_its_library(tmp_path: Path,
                                                                          trainings: Trainings) -> None:
    blocked = tmp_path / "a-file"
    blocked.write_text("not a folder", encoding="utf-8")
    library, said = _demo(blocked / "trained")
    assert not library.reused and library.descriptions == trainings.result.result.descriptions
    assert said[-1].startswith(f"could not keep the trained library in {blocked / 'trained'}: ")

"""``reset`` loads only named worlds: a name from the driver's worlds
folder or the start world's stem; paths, '..', FIFOs and unknown names are one
``bad_request`` line that says nothing about the driver's file system."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from hero_driver.interface import BAD_REQUEST, DriverError
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.worldfile import WORLDS_DIR, WorldRefused, shelf_for
from hero_driver.sim_driver import SimulatedHero

SECRET = {"api_key": "hunter2", "about": "not a world"}


def small_world(name: str, objects: int = 1) -> dict[str, object]:
    placed = [{"id": "closed-box-2x2x2/upright", "x_in": 60 + 20 * i, "y_in": 60} for i in range(objects)]
    return {"name": name, "room": {"width_in": 120, "depth_in": 120},
            "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0}, "objects": placed}


def refusal(hero: SimulatedHero, world: str) -> str:
    error = hero.reset(world=world).exception()
    assert isinstance(error, DriverError) and error.code == BAD_REQUEST
    assert "\n" not in error.message
    return error.message


@pytest.fixture
def hero(tmp_path: Path) -> SimulatedHero:
    folder = tmp_path / "worlds"
    folder.mkdir()
    (folder / "two.json").write_text(json.dumps(small_world("two", 2)))
    (folder / "broken.json").write_text("{not json")
    (tmp_path / "secret.json").write_text(json.dumps(SECRET))
    return SimulatedHero(noise=NoiseConfig.off(), worlds_dir=folder)


def test_a_name_in_the_worlds_folder_loads(hero: SimulatedHero) -> None:
    hero.reset(world="two").result()
    assert len(hero.truth()) == 2


def test_the_start_world_stays_served_under_its_name(hero: SimulatedHero) -> None:
    # started on the shipped lab (not in the custom folder): still 'lab'
    hero.reset(world="two").result()
    hero.reset(world="lab").result()
    assert len(hero.truth()) == 7


def test_a_start_world_file_is_served_under_its_stem(tmp_path: Path) -> None:
    own = tmp_path / "my-room.json"
    own.write_text(json.dumps(small_world("whatever", 3)))
    hero = SimulatedHero(world=own, noise=NoiseConfig.off())
    hero.reset(world="training").result()
    assert len(hero.truth()) == 14  # the shipped folder is the default
    hero.reset(world="my-room").result()
    assert len(hero.truth()) == 3


@pytest.mark.parametrize("world", ["../secret", "/etc/passwd", "secret.json", "two.json", ".", "..",
                                   "a/b", "~root", "x" * 65, "two\n", "C:\\x"])
def test_paths_and_non_names_are_refused_without_echo(hero: SimulatedHero, world: str) -> None:
    message = refusal(hero, world)
    assert message == "world: expected a world name (up to 64 letters, digits, '_' or '-'), not a path"


def test_an_absolute_path_to_a_json_file_is_refused_and_its_keys_not_echoed(hero: SimulatedHero,
                                                                            tmp_path: Path) -> None:
    message = refusal(hero, str(tmp_path / "secret.json"))
    assert "api_key" not in message and "hunter2" not in message and str(tmp_path) not in message


def test_unknown_and_unloadable_names_say_only_that(hero: SimulatedHero, tmp_path: Path) -> None:
    assert refusal(hero, "nope") == "world: no world named 'nope' on this driver"
    broken = refusal(hero, "broken")
    assert broken == "world: 'broken' cannot be loaded on this driver (see the driver's log)"
    assert str(tmp_path) not in broken
    assert len(hero.truth()) == 7  # still the lab: a refused reset changes nothing


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_fifo_in_the_worlds_folder_is_refused_at_once(hero: SimulatedHero, tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "worlds" / "pipe.json")
    assert refusal(hero, "pipe") == "world: no world named 'pipe' on this driver"  # did not block


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=80))
def test_any_text_is_a_name_on_the_shelf_or_refused(text: str) -> None:
    shelf = shelf_for(None)
    try:
        path = shelf.path_of(text)
    except WorldRefused as exc:
        assert "\n" not in str(exc)
        return
    assert path.parent == WORLDS_DIR  # never anywhere else


@pytest.mark.zenoh
def test_a_driver_process_serves_its_folder_and_its_start_world_by_name(tmp_path: Path) -> None:
    from hero_driver.zenoh_link.client import ZenohDriver
    from tests.hero_driver.test_zenoh_support import DriverProcess
    from tests.zenoh_rpc.support import free_endpoint

    folder = tmp_path / "worlds"
    folder.mkdir()
    (folder / "two.json").write_text(json.dumps(small_world("two", 2)))
    own = tmp_path / "kitchen.json"
    own.write_text(json.dumps(small_world("kitchen", 3)))
    (tmp_path / "secret.json").write_text(json.dumps(SECRET))
    endpoint = free_endpoint()
    argv = ["-m", "csl_cli", "driver", "sim", "--listen", endpoint, "--world", str(own),
            "--worlds-dir", str(folder)]
    with DriverProcess(argv) as driver, ZenohDriver("r1", connect=[endpoint], discover_s=20.0) as client:
        driver.ready()
        assert client.wait_ready(20.0)
        assert client.reset(world="two").result(5.0).pose.x_in == 20.0
        assert client.reset(world="kitchen").result(5.0).clock_s == 0
        for world in ("lab", "../secret", str(tmp_path / "secret.json")):  # lab: not in this folder
            error = client.reset(world=world).exception(5.0)
            assert isinstance(error, DriverError) and error.code == BAD_REQUEST
            assert str(tmp_path) not in error.message and "api_key" not in error.message


def test_a_worlds_dir_that_is_not_a_folder_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from csl_cli.main import main

    assert main(["driver", "sim", "--worlds-dir", str(tmp_path / "nowhere")]) == 2
    assert capsys.readouterr().err.strip() == f"csl: error: --worlds-dir {tmp_path / 'nowhere'}: not a folder"


@pytest.mark.parametrize("field", ["furniture", "objects"])
@pytest.mark.parametrize("value", [None, {"id": "x"}, "table", 3])
def test_a_list_field_that_is_not_an_array_is_one_line(field: str, value: object) -> None:
    from hero_driver.sim.worldfile import parse_world

    catalogue = SimulatedHero(noise=NoiseConfig.off()).world.catalogue
    data = {**small_world("w"), field: value}
    with pytest.raises(ValueError, match=f"{field}.*must be an array") as refused:
        parse_world(data, "w.json", catalogue)
    assert "\n" not in str(refused.value)

"""A battery that runs low during the first object, with the dock detour priced into
the learner's moves (executive.battery_cost): every object is still handled, and the
test records what the pricing changed on this floor (the world of
test_battery_episode: the robot at (20, 20), the dock at (20, 75) facing 180°)."""

from __future__ import annotations

from pathlib import Path

import pytest

from behaviours.services import Params
from executive import defaults
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from tests.executive.test_battery_episode import small_world


def episode(tmp_path: Path, price: bool) -> tuple[EpisodeResult, EpisodeLog, float]:
    folder = tmp_path / ("priced" if price else "plain")
    folder.mkdir()
    driver = SimulatedHero("r1", world=small_world(folder, 0.2005), seed=0)
    learner = LocalLearner(folder / "library.sqlite", seed_library=read_library_json(defaults.EXAMPLE_LIBRARY))
    log = EpisodeLog()
    executive = Executive(driver, learner, log=log, params=Params(battery_low=0.2, price_detours=price))
    try:
        return executive.run(), log, driver.state().clock_s
    finally:
        executive.shutdown()
        learner.close()


def test_a_priced_detour_still_handles_every_object_and_here_changes_no_choice(tmp_path: Path) -> None:
    plain, plain_log, plain_clock = episode(tmp_path, price=False)
    priced, priced_log, priced_clock = episode(tmp_path, price=True)
    for result, log in ((plain, plain_log), (priced, priced_log)):
        assert [r.outcome for r in result.objects] == ["grasped", "left"]
        assert [e["object"] for e in log.events if e["event"] == "charge"] == [0]
    chosen = [[(e["object"], e["test"]) for e in log.events if e["event"] == "choose"]
              for log in (plain_log, priced_log)]
    # What the pricing changed: nothing chosen. The first test, Front-Wrap from
    # (52.1, 25.4) heading 14.4, is 88 s of moving from where the robot stands, (20, 20)
    # heading 0: 32.55 in straight (65.1 s at 2 s/in), 14.4° of turning (2.9 s at 5°/s),
    # 5 + 15 s of vision and centring; 0.2005 - 88/18000
    # - 105/36000 (the longest sensing) = 0.1927 < 0.2, so it will not last, and neither
    # will any other first test (every one needs a move at least as long). Its detour by
    # hand: to the dock 59.1 in (118.2 s) turning 108.5° + 57.1° (33.1 s), 5 + 15 s of
    # vision and centring: 171.3 s; back, 122.9° onto the bearing and 71.5° to heading
    # 14.4 (38.9 s): 177.1 s; with the recharge of that trip, 1.1 x 348.4 = 383.2 s (the
    # grid's lengths a little over the straight line's).
    [first_plain] = [e for e in plain_log.events if e["event"] == "choose"][:1]
    [first_priced] = [e for e in priced_log.events if e["event"] == "choose"][:1]
    assert first_plain["move_s"] == pytest.approx(88.0, abs=0.5)
    assert first_priced["move_s"] - first_plain["move_s"] == pytest.approx(383.2, abs=5.0)
    # the surcharge falls on every candidate alike: the same tests, the same robot time
    assert chosen[0] == chosen[1] and chosen[0][0] == (0, "Front-Wrap(6,*)")
    assert priced_clock == pytest.approx(plain_clock)

"""Scripted episodes for tests: a scenario is every input of one episode (world,
objects, seed, noise, library, driver, criterion, control parameters) as keyword
arguments, and running it gives back what the robot did in a form a test can assert
on and a snapshot can pin.

The same scenario run twice gives the same transcript: the simulator is seeded, and
:mod:`csl_testing.transcript` leaves out what a sampling planner or the host changes.
"""

from __future__ import annotations

import dataclasses
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from behaviours.records import ObjectRecord
from behaviours.services import Params
from executive.executive import Executive
from hero_driver.interface import Driver
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.worldfile import Placement, WorldSpec
from hero_driver.sim_driver import SimulatedHero
from learner.choosing.criteria import Criterion
from learner.description import ObjectDescription
from learner.service.local import LocalLearner

from csl_testing.inputs import (STEADY_NOISE, ObjectEntry, criterion_of, noise_config, placements, seed_library,
                                world_spec)
from csl_testing.transcript import transcript_text

DriverFactory = Callable[[str, WorldSpec, int, NoiseConfig | None], Driver]
"""Builds the robot an episode drives: ``(robot, world, seed, noise) -> Driver``."""


def simulated_hero(robot: str, world: WorldSpec, seed: int, noise: NoiseConfig | None) -> Driver:
    """The default driver: the in-process simulated HERO 2000, seeded, so an episode is
    the same on every run."""
    return SimulatedHero(robot, world=world, seed=seed, noise=noise)


@dataclass(frozen=True)
class ScenarioResult:
    """What one episode did. ``events`` are the episode log's entries in order,
    ``trace`` one line per tick (every behaviour ticked, with S/F/R), ``library`` the
    learner's descriptions after the episode, ``store`` the SQLite file they live in
    (give it to the next scenario's ``store`` to learn across encounters)."""

    scenario: Scenario
    status: str
    ticks: int
    objects: tuple[ObjectRecord, ...]
    trace: tuple[str, ...]
    events: tuple[Mapping[str, object], ...]
    library: tuple[ObjectDescription, ...]
    store: Path

    @property
    def object(self) -> ObjectRecord:
        """The only object of a one-object scenario."""
        if len(self.objects) != 1:
            raise ValueError(f"the episode handled {len(self.objects)} objects, not one")
        return self.objects[0]

    def events_of(self, kind: str) -> list[Mapping[str, object]]:
        """The events of one kind (``choose``, ``grasp``, ``learn``...: docs/executive.md)."""
        return [e for e in self.events if e["event"] == kind]

    def transcript(self) -> str:
        """Ticks and decisions as text, the same on every run of this scenario."""
        return transcript_text(self.trace, self.events)


@dataclass(frozen=True)
class Scenario:
    """One episode's inputs. Every field has a default, so a test names only what it is
    about.

    ``world``: None (an empty 200 x 140 in room), a shipped world's name (``"lab"``),
    a world file, or a :class:`WorldSpec`. ``objects``: replace the world's objects
    with these (:class:`Placement` or ``(entry, x_in, y_in[, yaw_deg])``). ``noise``: a
    preset's name, a :class:`NoiseConfig`, or None for the world's own (default
    :data:`~csl_testing.inputs.STEADY_NOISE`). ``library``: None (the shipped example
    library), a ``.json`` or SQLite library file, or descriptions; a store that already
    holds descriptions keeps them. ``store``: the learner's SQLite file (None: a new
    one under ``workdir``, itself None for the system's temporary folder). ``driver``
    builds the robot (default: :func:`simulated_hero`). ``criterion``: a name or a
    built criterion (None: the executive's default).
    """

    world: str | Path | WorldSpec | None = None
    objects: Sequence[ObjectEntry] | None = None
    seed: int = 0
    noise: str | NoiseConfig | None = STEADY_NOISE
    library: str | Path | Sequence[ObjectDescription] | None = None
    driver: DriverFactory = simulated_hero
    criterion: str | Criterion | None = None
    params: Params = field(default_factory=Params)
    robot: str = "r1"
    max_ticks: int | None = None
    store: Path | None = None
    workdir: Path | None = None

    def __post_init__(self) -> None:
        if self.objects is not None:  # checked now, so a mistake points at the line that made it
            object.__setattr__(self, "objects", placements(self.objects))
        for name in ("seed", "max_ticks"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
                raise ValueError(f"{name}: expected a whole number >= 0, got {value!r}")
        if not isinstance(self.params, Params):
            raise ValueError(f"params: expected behaviours.services.Params, got {type(self.params).__name__}")

    def but(self, **changes: object) -> Scenario:
        """This scenario with some inputs changed (another seed, the same store...)."""
        return dataclasses.replace(self, **changes)  # type: ignore[arg-type]

    def world_spec(self) -> WorldSpec:
        """The world the driver is given, objects placed and checked."""
        return world_spec(self.world, self.objects, profile_and_catalogue()[1])

    def run(self) -> ScenarioResult:
        """Run the episode to its end (or ``max_ticks``) and close what it opened."""
        spec, noise = self.world_spec(), noise_config(self.noise)
        descriptions, chosen = seed_library(self.library), criterion_of(self.criterion)
        store = self.store or Path(tempfile.mkdtemp(prefix="csl-scenario-", dir=self.workdir)) / "library.sqlite"
        learner = LocalLearner(store, seed_library=descriptions)
        try:
            driver = self.driver(self.robot, spec, self.seed, noise)
            try:
                executive = Executive(driver, learner, params=self.params, criterion=chosen)
                try:
                    episode = executive.run(trace=True, max_ticks=self.max_ticks)
                finally:
                    executive.shutdown()
            finally:
                driver.close()
            library = tuple(learner.library().descriptions)
        finally:
            learner.close()
        return ScenarioResult(self, episode.status, episode.ticks, tuple(episode.objects), tuple(episode.trace),
                              tuple(executive.log.events), library, store)


def one_object(entry: str, *, x_in: float = 110.0, y_in: float = 80.0, yaw_deg: float = 20.0,
               **inputs: object) -> Scenario:
    """A scenario with one catalogue entry (``"tumbler-20oz/upright"``) on the floor,
    by default in the middle of the empty room turned 20 degrees (where the project's
    own snapshot tests put it); ``inputs`` are :class:`Scenario`'s other fields."""
    return Scenario(objects=(Placement(entry, x_in, y_in, yaw_deg),), **inputs)  # type: ignore[arg-type]


@dataclass(frozen=True)
class ScenarioFactory:
    """:class:`Scenario` and :func:`one_object` with every new learner store under
    ``workdir`` (what the ``csl_scenario`` fixture gives a test: its ``tmp_path``)."""

    workdir: Path

    def __call__(self, **inputs: object) -> Scenario:
        return Scenario(**{"workdir": self.workdir, **inputs})  # type: ignore[arg-type]

    def one_object(self, entry: str, **inputs: object) -> Scenario:
        return one_object(entry, **{"workdir": self.workdir, **inputs})

"""``csl demo``'s trained library, kept between runs while what it was trained from is
unchanged.

Training on the Table 3 objects in the simulator is deterministic: the same robot
profile, catalogue, seed, noise setting and training code give the same library. So a
demo run stores what it trained under a content hash of those inputs (in the user data
folder, ``$CSL_HOME/trained/``) and a later run with the same hash reuses it instead of
training again. Any changed input, the code included, is a new hash and trains anew;
``--retrain`` trains even when the hash is known. The world the demo runs in is part of
the hash too: training does not read it today, but a demo is described by its world,
and retraining when it changes costs a second, while a stale library would cost a
wrong demo.

``csl run`` with another robot's profile than the HERO 2000's starts a new library
from the lab's trained library here too: the shipped example serves only the HERO, and
one hash store means a robot's demo and its first run train once between them.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass
from pathlib import Path

from executive import defaults
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.library.format import descriptions_from_json, descriptions_to_json, write_json_atomically
from learner.training.summary import TrainingSummary
from robot_profile import RobotProfile

FORMAT = "csl-trained-library"
VERSION = 1
REPOSITORY = Path(__file__).resolve().parents[1]
# The code a trained library depends on: the learner, the simulated robot and its
# camera, the camera's published model and the vision that makes training objects of
# what the camera sees, the profile reader (which builds the learner's knowledge), and
# the executive modules that drive training.
TRAINING_CODE = ("learner/**/*.py", "hero_driver/sim/**/*.py", "hero_driver/interface.py", "camera_model/*.py",
                 "planner/*.py", "robot_profile/*.py", "behaviours/appearance.py", "behaviours/bridge.py",
                 "executive/sim_training.py", "executive/training_sources.py")
ONBOARD_TRAINING_CODE = ("executive/outline_objects.py", "mapping/*.py")
"""The code that also makes the training objects when the robot sees them with its own
scans (``--perception onboard``: their outlines as the scans see them)."""
TRAINING_NOISE = False  # demo training measures the objects exactly, as the shipped library was made
PERCEPTION_OF_TRAINING = {"ceiling": "camera", "onboard": "onboard"}
"""How a demo's training objects are seen, by the demo's perception: the overhead
camera's polygon, or the outline of the robot's own scans (``executive.sim_training``)."""


@dataclass(frozen=True)
class DemoLibrary:
    """The library a demo runs with, its training figures, and whether it was reused."""

    descriptions: tuple[ObjectDescription, ...]
    summary: TrainingSummary
    key: str  # the inputs' content hash (sha256, hex)
    reused: bool


def trained_folder() -> Path:
    """Where trained libraries are kept: ``trained/`` beside the user's library store."""
    return defaults.library_db().parent / "trained"


def training_key(profile: RobotProfile, world: str | Path, seed: int, noise: bool = TRAINING_NOISE,
                 perception: str = "ceiling") -> str:
    """The content hash of everything a demo's training depends on: the knowledge file,
    the simulator's catalogue (the training objects), the world file, seed, noise and the
    training code's source; with onboard perception, that perception and its code too
    (a ceiling demo's hash is what it was before there were two)."""
    from hero_driver.sim.catalogue import DEFAULT_CATALOGUE
    from hero_driver.sim.worldfile import resolve

    digest = hashlib.sha256()
    _add(digest, "format", f"{FORMAT} {VERSION}".encode())
    _add(digest, "knowledge", Path(profile.source).read_bytes())
    _add(digest, "catalogue", DEFAULT_CATALOGUE.read_bytes())
    _add(digest, "world", resolve(world).read_bytes())
    _add(digest, "seed noise", f"{seed} {noise}".encode())
    if perception != "ceiling":
        _add(digest, "perception", perception.encode())
    for path in _training_sources(perception):
        _add(digest, path.relative_to(REPOSITORY).as_posix(), path.read_bytes())
    return digest.hexdigest()


def trained_library(knowledge: Knowledge, profile: RobotProfile, world: str | Path, seed: int, *,
                    retrain: bool = False, folder: Path | None = None,
                    say: Callable[[str], None] = print, perception: str = "ceiling") -> DemoLibrary:
    """The demo's library: reused from ``folder`` (default :func:`trained_folder`) when
    one was stored under the same inputs' hash and ``retrain`` is not set, else trained
    in the simulator and stored, the training objects seen as ``perception`` sees
    (``ceiling`` or ``onboard``). ``say`` reports which, naming the hash."""
    if perception not in PERCEPTION_OF_TRAINING:
        raise ValueError(f"perception must be one of {', '.join(PERCEPTION_OF_TRAINING)}, got {perception!r}")
    key = training_key(profile, world, seed, perception=perception)
    path = (folder or trained_folder()) / f"{key}.json"
    if not retrain and path.exists():
        try:
            descriptions, summary = _read(path, key)
        except ValueError as exc:
            say(f"ignoring the stored trained library: {exc}")
        else:
            say(f"reusing trained library {key[:12]} ({path})")
            return DemoLibrary(descriptions, summary, key, reused=True)
    say(f"training on the Table 3 objects in the simulator (library {key[:12]})...")
    from executive.sim_training import train_in_simulator  # the simulator: only when training

    seen_by = {} if perception == "ceiling" else {"perception": PERCEPTION_OF_TRAINING[perception]}
    trained = train_in_simulator(knowledge, profile, seed, TRAINING_NOISE, **seen_by)
    try:  # a store that cannot be written costs the next run a training, not this one its demo
        path.parent.mkdir(parents=True, exist_ok=True)
        write_json_atomically(path, {"format": FORMAT, "version": VERSION, "key": key,
                                     "summary": asdict(trained.summary),
                                     "library": descriptions_to_json(trained.result.descriptions)})
    except (OSError, ValueError) as exc:
        say(f"could not keep the trained library in {path.parent}: {exc}")
    return DemoLibrary(trained.result.descriptions, trained.summary, key, reused=False)


def _read(path: Path, key: str) -> tuple[tuple[ObjectDescription, ...], TrainingSummary]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: not readable JSON ({exc})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT or data.get("version") != VERSION:
        raise ValueError(f"{path}: not a {FORMAT} version {VERSION} file")
    if data.get("key") != key:
        raise ValueError(f"{path}: 'key' does not match its file name")
    summary = data.get("summary")
    try:
        fields = dict(summary)  # type: ignore[call-overload]
        fields["orientations_deg"] = tuple(fields["orientations_deg"])
        fields["distances_in"] = tuple(fields["distances_in"])
        figures = TrainingSummary(**fields)
    except (TypeError, KeyError, ValueError):
        raise ValueError(f"{path}: 'summary' is not a training summary") from None
    return tuple(descriptions_from_json(data.get("library"), f"{path}: library")), figures


def _training_sources(perception: str = "ceiling") -> Iterable[Path]:
    patterns = TRAINING_CODE + (ONBOARD_TRAINING_CODE if perception != "ceiling" else ())
    return sorted({p for pattern in patterns for p in REPOSITORY.glob(pattern)})


def _add(digest: "hashlib._Hash", label: str, content: bytes) -> None:
    """Each part labelled and length-prefixed: no two sets of inputs hash alike by
    shifting bytes from one part to the next."""
    digest.update(f"{label}\0{len(content)}\0".encode())
    digest.update(content)

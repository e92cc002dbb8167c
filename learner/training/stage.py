"""The training stage (docs/method.md §4): choose training positions, then learn descriptions.

Phase 1 picks a few positions worth sensing from: orientations perpendicular to the
objects' faces (sonar works best there), and distances as far as a sweep still tells
apart objects of similar size but different grasp. Phase 2 at each position measures
only what is needed to classify every object (familiarize, discriminate, reorganize);
the descriptions of all positions are then merged, generalising to ``*`` a value that
agrees at every training orientation (or distance), i.e. does not depend on it.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from learner.costs import MoveCostEstimator
from learner.description import ObjectDescription, Observation
from learner.knowledge import Knowledge, SensingProcedure
from learner.position import Position
from learner.training.inputs import MeasurementSource, TrainingObject
from learner.training.trees import PhaseTree, TrainingTrees, predicted_grasp

ORIENTATION_TOLERANCE_DEG = 20.0  # face normals closer than this are one training orientation
DISTANCE_TOLERANCE = 0.3  # candidate distances within 30% of a cluster's nearest are one
MAX_DISTANCES = 3  # "a few" training distances (the paper's Table 3 run: 6, 16, 24 in)


# -- Phase 1 ----------------------------------------------------------------------------
def face_normals(polygon: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """``(direction in degrees, edge length)`` of each edge's outward normal.

    The robot senses a face from outside, looking back along its normal; the direction
    is relative to the object's reference axis (the polygon's +x).
    """
    area2 = sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(polygon, [*polygon[1:], polygon[0]]))
    sign = 1.0 if area2 >= 0 else -1.0  # counter-clockwise: outward normal is the edge turned right
    out = []
    for (x0, y0), (x1, y1) in zip(polygon, [*polygon[1:], polygon[0]]):
        dx, dy = x1 - x0, y1 - y0
        length = math.hypot(dx, dy)
        if length > 1e-9:
            out.append((math.degrees(math.atan2(-dx * sign, dy * sign)) % 360.0, length))
    return out


def training_orientations(objects: Sequence[TrainingObject], tolerance_deg: float = ORIENTATION_TOLERANCE_DEG) -> list[float]:
    """All objects' face normals, clustered (length-weighted circular means), sorted.

    Round footprints have no faces: alone they give just 0°.
    """
    normals = [n for o in objects if not o.round for n in face_normals(o.polygon)]
    if not normals:
        return [0.0]
    clusters: list[list[tuple[float, float]]] = []
    for direction, length in sorted(normals):
        for cluster in clusters:
            if abs(_wrap(direction - _circular_mean(cluster))) <= tolerance_deg:
                cluster.append((direction, length))
                break
        else:
            clusters.append([(direction, length)])
    total = sum(length for _, length in normals)
    kept = [c for c in clusters if sum(l for _, l in c) >= 0.05 * total]
    return sorted(round(_circular_mean(c)) % 360 for c in kept)


def separation_distance(size_a: float, size_b: float, error_deg: float, range_in: tuple[float, float]) -> float | None:
    """The greatest distance at which a sweep's angular sizes of two objects differ by more
    than twice its expected error (angular size ``2 atan(w / 2d)``); None if never."""
    def apart(d: float) -> bool:
        return abs(_angular(size_a, d) - _angular(size_b, d)) > 2.0 * error_deg

    lo, hi = range_in
    if not apart(lo):
        return None
    if apart(hi):
        return hi
    for _ in range(60):  # bisection: separation shrinks monotonically with distance
        mid = (lo + hi) / 2.0
        lo, hi = (mid, hi) if apart(mid) else (lo, mid)
    return lo


def _angular(size: float, distance: float) -> float:
    return math.degrees(2.0 * math.atan(size / (2.0 * distance)))


@dataclass(frozen=True)
class DistanceReason:
    """Why a candidate distance was proposed: which sweep separates which two objects."""

    feature: str
    object_a: str
    object_b: str
    distance_in: float


def candidate_distances(
    objects: Sequence[TrainingObject],
    sizes: Mapping[tuple[str, str], float],
    knowledge: Knowledge,
) -> list[DistanceReason]:
    """For each angular feature and object, the distance that still separates it from the
    most similar-sized object of a different grasp. ``sizes[(object, linear feature)]``."""
    reasons = []
    for proc in knowledge.sensing:
        for feat in proc.features:
            if feat.angular_of is None:
                continue
            measured = [(o, sizes[(o.object_id, feat.angular_of)]) for o in objects
                        if (o.object_id, feat.angular_of) in sizes]
            for obj, size in measured:
                rivals = [(abs(size - s), other) for other, s in measured
                          if other.grasp != obj.grasp and abs(size - s) > 0]
                for _, other in sorted(rivals, key=lambda r: (r[0], r[1].object_id)):
                    d = separation_distance(size, sizes[(other.object_id, feat.angular_of)], feat.error, proc.range_in)
                    if d is not None:
                        reasons.append(DistanceReason(feat.name, obj.object_id, other.object_id, d))
                        break
    return reasons


def cluster_distances(candidates: Iterable[float], tolerance: float = DISTANCE_TOLERANCE,
                      most: int = MAX_DISTANCES) -> list[float]:
    """Cluster candidate distances into at most ``most`` training distances.

    Neighbours within ``tolerance`` (relative) share a cluster; while there are too
    many, the two adjacent clusters closest in ratio merge (the paper keeps "a few":
    each distance multiplies the positions to train at). A cluster is represented by its
    nearest distance, in whole inches: every pair it stands for still separates there.
    """
    clusters: list[list[float]] = []
    for d in sorted(candidates):
        if clusters and d <= clusters[-1][0] * (1.0 + tolerance):
            clusters[-1].append(d)
        else:
            clusters.append([d])
    while len(clusters) > max(most, 1):
        i = min(range(len(clusters) - 1), key=lambda j: clusters[j + 1][-1] / clusters[j][0])
        clusters[i:i + 2] = [clusters[i] + clusters[i + 1]]
    return sorted({float(math.floor(c[0])) for c in clusters})


# -- Phase 2 ----------------------------------------------------------------------------
@dataclass
class TrainingLog:
    """What training did: positions, every procedure applied, and the robot time spent."""

    orientations: list[float] = field(default_factory=list)
    distances: list[float] = field(default_factory=list)
    distance_reasons: list[DistanceReason] = field(default_factory=list)
    applied: list[tuple[str, str, Position, str]] = field(default_factory=list)  # object, procedure, position, why
    sensing_s: float = 0.0
    moving_s: float = 0.0
    unresolved: list[tuple[str, Position]] = field(default_factory=list)
    trees_asked: int = 0  # trees phase 2 classified with (one per object per pass)
    trees_grown: int = 0  # of them, grown rather than reused: the distinct ones

    @property
    def total_s(self) -> float:
        return self.sensing_s + self.moving_s


class _Recorder:
    """Measures through the source once per (object, procedure, position), and keeps
    in the descriptions only what phase 2 asked for.

    Phase 1's size scans are paid for once and reused if phase 2 wants the same
    procedure there, but they are not features of a description until it does: a
    description holds only what was needed to classify the object (docs/method.md §4).
    """

    def __init__(self, source: MeasurementSource, knowledge: Knowledge, log: TrainingLog, reuse: bool = True) -> None:
        self.source, self.knowledge, self.log, self.reuse = source, knowledge, log, reuse
        self.applied: dict[tuple[str, Position], set[str]] = defaultdict(set)
        self.values: dict[str, dict[tuple[str, Position], float]] = defaultdict(dict)
        self._measured: dict[tuple[str, str, Position], Mapping[str, float | None]] = {}
        self._at: dict[tuple[str, Position], ObjectDescription] = {}  # description at a position, until it grows

    def measure(self, obj: TrainingObject, proc: SensingProcedure, at: Position, why: str,
                record_at: Position) -> Mapping[str, float | None]:
        key = (obj.object_id, proc.name, at)
        if key not in self._measured:
            self._measured[key] = self.source.measure(obj.object_id, proc.name, at)
            self.log.applied.append((obj.object_id, proc.name, record_at, why))
            self.log.sensing_s += proc.time_s
        return self._measured[key]

    def apply(self, obj: TrainingObject, proc: SensingProcedure, at: Position, record_at: Position, why: str) -> None:
        """Phase 2: the procedure's values become part of the object's description."""
        if proc.name in self.applied[(obj.object_id, record_at)]:
            return
        self.applied[(obj.object_id, record_at)].add(proc.name)
        self._at.pop((obj.object_id, record_at), None)
        values = self.measure(obj, proc, at, why, record_at)
        for feat in proc.features:
            v = values.get(feat.name)
            if v is not None:
                self.values[obj.object_id][(feat.name, record_at)] = float(v)

    @property
    def count(self) -> int:
        return sum(len(p) for p in self.applied.values())

    def description(self, obj: TrainingObject, at: Position | None = None) -> ObjectDescription:
        """What was recorded of ``obj`` at ``at`` (everywhere: None).

        Phase 2 asks for every object's description at a position before each
        prediction, yet only :meth:`apply` changes one: it is kept until then (unless
        ``reuse`` is off: the simple path rebuilds it every time).
        """
        if at is not None and (obj.object_id, at) in self._at:
            return self._at[(obj.object_id, at)]
        obs = tuple(sorted(Observation(f, p, v) for (f, p), v in self.values[obj.object_id].items()
                           if at is None or p == at))
        description = ObjectDescription(obj.object_id, obj.grasp, obj.grasp_position, obs)
        if at is not None and self.reuse:
            self._at[(obj.object_id, at)] = description
        return description


def _predict(tree: PhaseTree, obj: TrainingObject, at: Position, recorder: _Recorder) -> str | None:
    """Familiarize: classify ``obj`` with ``tree``, measuring any tested feature it lacks."""
    def value_of(feature: str) -> float | None:
        proc = recorder.knowledge.procedure_for(feature)
        recorder.apply(obj, proc, sensed_at(obj, at), at, f"familiarize: tree tests {feature}")
        return recorder.values[obj.object_id].get((feature, at))

    return predicted_grasp(tree, value_of)


def sensed_at(obj: TrainingObject, at: Position) -> Position:
    """Where the robot is staged to measure ``obj`` for training position ``at``.

    Round objects have no orientation: they are sensed at 0° and recorded at ``*``.
    """
    return Position(at.distance_in, 0.0) if obj.round else at


def _record_at(obj: TrainingObject, at: Position) -> Position:
    return Position(at.distance_in, None) if obj.round else at


def train_position(
    objects: Sequence[TrainingObject],
    at: Position,
    knowledge: Knowledge,
    recorder: _Recorder,
    progress: Callable[[str], None] | None = None,
    trees: TrainingTrees | None = None,
) -> None:
    """Phase 2 at one training position (Table 6): familiarize every object with the
    current tree, discriminate a misclassified one with the cheapest procedure not yet
    applied to it, reorganize; repeat until a whole pass changes nothing (every object
    classified, or every usable procedure applied to those that are not)."""
    assert at.distance_in is not None
    procs = sorted((p for p in knowledge.sensing if p.applicable_at(at.distance_in)), key=lambda p: (p.time_s, p.name))
    if not procs:
        return
    trees = trees or TrainingTrees(knowledge)
    while True:
        before = recorder.count
        wrong = []
        for obj in objects:
            where = _record_at(obj, at)
            tree = trees.tree([recorder.description(o, _record_at(o, at)) for o in objects])
            if _predict(tree, obj, where, recorder) == obj.grasp:
                continue
            wrong.append(obj)
            remaining = [p for p in procs if p.name not in recorder.applied[(obj.object_id, where)]]
            if remaining:  # reorganize: the next object's tree is built from all descriptions
                recorder.apply(obj, remaining[0], sensed_at(obj, at), where, "discriminate: cheapest not yet applied")
        if progress:
            progress(f"position {at}: {len(objects) - len(wrong)}/{len(objects)} classified")
        if recorder.count == before:  # a pass that measured nothing new: done
            recorder.log.unresolved.extend((o.object_id, _record_at(o, at)) for o in wrong)
            return


# -- Merging ------------------------------------------------------------------------------
def generalise(observations: Iterable[Observation], knowledge: Knowledge,
               orientations: Sequence[float], distances: Sequence[float]) -> list[Observation]:
    """Replace a feature's values that agree within its error at *every* training
    orientation (at one distance) by one value at ``(d,*)``, then at every training
    distance its procedure reaches by ``(*,θ)``.

    Agreement at the orientations that happened to be measured is not enough: a lying
    tumbler's width agrees at 0° and 180° and differs at 90°, and ``(d,*)`` would claim
    it holds there too. The paper generalises only when all training positions of the
    slot agree, so a value missing at one of them keeps its concrete positions.
    """
    obs = list(observations)
    obs = _generalise_slot(obs, knowledge, keep="distance", required=lambda _feature: set(orientations))
    return _generalise_slot(obs, knowledge, keep="orientation",
                            required=lambda feature: reachable_distances(feature, distances, knowledge))


def reachable_distances(feature: str, distances: Sequence[float], knowledge: Knowledge) -> set[float]:
    """The training distances at which the feature's procedure can be applied."""
    if not knowledge.has_feature(feature):
        return set(distances)
    proc = knowledge.procedure_for(feature)
    return {d for d in distances if proc.applicable_at(d)}


def _generalise_slot(obs: list[Observation], knowledge: Knowledge, keep: str,
                     required: Callable[[str], set[float]]) -> list[Observation]:
    out: list[Observation] = []
    groups: dict[tuple[str, float], list[Observation]] = defaultdict(list)
    for o in obs:
        p = o.position
        fixed, varying = (p.distance_in, p.orientation_deg) if keep == "distance" else (p.orientation_deg, p.distance_in)
        if fixed is None or varying is None:
            out.append(o)
        else:
            groups[(o.feature, fixed)].append(o)
    for (feature, fixed), members in groups.items():
        values = [m.value for m in members]
        measured_at = {m.position.orientation_deg if keep == "distance" else m.position.distance_in for m in members}
        spec = knowledge.feature(feature) if knowledge.has_feature(feature) else None
        error = spec.error if spec else 0.0
        # an angular size shrinks with distance: agreeing values at two distances are a
        # coincidence of quantisation, not a value that holds at any distance
        angular_over_distance = keep == "orientation" and spec is not None and spec.angular_of is not None
        if (len(members) >= 2 and measured_at >= required(feature) and not angular_over_distance
                and max(values) - min(values) <= error + 1e-9):
            position = Position(fixed, None) if keep == "distance" else Position(None, fixed)
            out.append(Observation(feature, position, round(sum(values) / len(values), 3)))
        else:
            out.extend(members)
    return sorted(out)


@dataclass(frozen=True)
class TrainingResult:
    descriptions: tuple[ObjectDescription, ...]
    log: TrainingLog


def train(
    objects: Sequence[TrainingObject],
    knowledge: Knowledge,
    source: MeasurementSource,
    estimator: MoveCostEstimator,
    progress: Callable[[str], None] | None = None,
    reuse: bool = True,
    distances: Sequence[float] | None = None,
) -> TrainingResult:
    """Both phases: positions, per-position descriptions, then merged descriptions.

    ``distances`` replaces the training distances phase 1 would choose (phase 1 still
    runs and still logs its candidates): a what-if, e.g. what training costs at the
    paper's distances.

    ``reuse=False`` is the method as written: every phase-2 prediction rebuilds the
    descriptions at its position and grows its whole tree anew
    (:mod:`learner.training.trees`). The same result, slower; kept as the reference for
    tests and the benchmark.
    """
    log = TrainingLog()
    recorder = _Recorder(source, knowledge, log, reuse)
    trees = TrainingTrees(knowledge, reuse)
    log.orientations = training_orientations(objects)
    scan_distances = sorted({p.range_in[0] for p in knowledge.sensing if p.range_in[0] == p.range_in[1]})
    linear = {f.angular_of for p in knowledge.sensing for f in p.features if f.angular_of}
    for orientation in log.orientations:
        # Phase 1: each object's sizes as seen from this orientation (round: any)
        sizes: dict[tuple[str, str], float] = {}
        for obj in objects:
            for proc in knowledge.sensing:
                yielded = {f.name for f in proc.features} & linear
                if yielded and proc.range_in[0] == proc.range_in[1]:
                    at = Position(proc.range_in[0], orientation)
                    values = recorder.measure(obj, proc, sensed_at(obj, at), "phase 1: size for distances",
                                              _record_at(obj, at))
                    sizes.update({(obj.object_id, n): float(values[n]) for n in yielded if values.get(n) is not None})
        log.distance_reasons += candidate_distances(objects, sizes, knowledge)
    log.distances = (sorted(float(d) for d in distances) if distances is not None else
                     cluster_distances([*scan_distances, *(r.distance_in for r in log.distance_reasons)]))
    for at in (Position(d, o) for d in sorted(log.distances, reverse=True) for o in log.orientations):
        train_position(objects, at, knowledge, recorder, progress, trees)
    log.moving_s = _moving_cost(objects, recorder, estimator)
    log.trees_asked, log.trees_grown = trees.asked, trees.grown
    merged = []
    for obj in objects:
        d = recorder.description(obj)
        merged.append(ObjectDescription(d.object_id, d.grasp, d.grasp_position,
                                        tuple(generalise(d.observations, knowledge, log.orientations,
                                                         log.distances)), obj.appearance))
    return TrainingResult(tuple(merged), log)


def _moving_cost(objects: Sequence[TrainingObject], recorder: _Recorder, estimator: MoveCostEstimator) -> float:
    """Robot time to visit, per object, the positions it was sensed at, far to near."""
    total = 0.0
    for obj in objects:
        visited = sorted({sensed_at(obj, p) for (oid, p) in recorder.applied if oid == obj.object_id
                          and p.distance_in is not None},
                         key=lambda p: (-(p.distance_in or 0.0), p.orientation_deg or 0.0))
        for a, b in zip(visited, visited[1:]):
            total += estimator.move_cost(a, b)
    return total


def _circular_mean(items: Sequence[tuple[float, float]]) -> float:
    x = sum(l * math.cos(math.radians(d)) for d, l in items)
    y = sum(l * math.sin(math.radians(d)) for d, l in items)
    return math.degrees(math.atan2(y, x)) % 360.0


def _wrap(deg: float) -> float:
    return (deg + 180.0) % 360.0 - 180.0

"""Object candidates beside the home's structure: an object against a wall is one, a piece
of wall or furniture seen short is not.

The settings are the executive's for a home (``range_sigma_in`` 1 in: a 3 in band round
each structure line) or wider, so that the object lies inside a wall's band and only the
proud rule can find it; the scans are the synthetic ray caster's.
"""

from __future__ import annotations

import math

import numpy as np

from mapping import OccupancyGrid, PlanarScan
from mapping.candidates import Candidate, CandidateFinder, CandidateSettings, continues_structure
from mapping.faces import run_along, straight_face
from tests.mapping.synthetic import Lidar, box, circle

ONBOARD = CandidateSettings(range_sigma_in=1.0)


def explore(walls: np.ndarray, poses: list[tuple[float, float]], settings: CandidateSettings, lidar: Lidar,
            seed: int = 0) -> tuple[CandidateFinder, OccupancyGrid]:
    """Scans at true poses (heading 0.3 rad) into a finder and a 1 in grid."""
    rng = np.random.default_rng(seed)
    finder, grid = CandidateFinder(settings), OccupancyGrid(-10.0, -10.0, 210.0, 160.0, 1.0)
    for k, (x, y) in enumerate(poses):
        scan = PlanarScan(lidar.angles_rad, lidar.scan(walls, (x, y, 0.3), rng), x, y, math.degrees(0.3), float(k),
                          lidar.max_range_in)
        grid.integrate(scan)
        finder.update(scan)
    return finder, grid


def near(candidates: tuple[Candidate, ...], x: float, y: float, tolerance: float) -> list[int]:
    return [c.id for c in candidates if math.dist((c.x_in, c.y_in), (x, y)) <= tolerance]


def test_a_can_against_a_wall_stands_proud_of_the_scans_own_line() -> None:
    """A soda can (1.3 in radius) 0.7 in from the wall y = 0: its front stands 3.3 in off
    the wall. With a 4.5 in band (``range_sigma_in`` 1.5) every return of it lies in the
    wall's band. The scans are exact, so the wall's own returns lie on its line (noise
    0) and the can's, 0.7 to 3.3 in off it, stand proud by more than ``front_min_in``
    (1 in): one candidate, on the can's near side (its centroid between the can's centre
    and its front, 2 to 3.3 in from the wall). Without the rule (no run of returns is
    ever long enough) the can is wall."""
    walls = np.array(box(0.0, 0.0, 200.0, 150.0) + circle(100.0, 2.0, 1.3), dtype=float)
    exact = Lidar(sigma_in=0.0, dropout=0.0)
    poses = [(80.0, 40.0), (120.0, 40.0), (100.0, 60.0)]
    settings = CandidateSettings(range_sigma_in=1.5)
    finder, grid = explore(walls, poses, settings, exact)
    (can,) = finder.candidates(grid)
    assert abs(can.x_in - 100.0) <= 1.3 and 2.0 <= can.y_in <= 3.3
    off, _ = explore(walls, poses, CandidateSettings(range_sigma_in=1.5, proud_min_returns=10 ** 6), exact)
    assert off.candidates(grid) == ()


def test_a_cup_3_in_from_a_wall_is_a_candidate() -> None:
    """The apartment's cup: 1.65 in radius, its centre 3 in from the wall y = 0 (1.35 in
    gap), the range finder's noise 0.5 in and 10 % of beams lost, the home's 3 in band.
    It is one candidate, within 3 in of its centre (the centroid of its near side), and
    the walls none."""
    walls = np.array(box(0.0, 0.0, 200.0, 150.0) + circle(100.0, 3.0, 1.65), dtype=float)
    poses = [(60.0, 40.0), (100.0, 50.0), (140.0, 40.0), (100.0, 25.0)]
    finder, grid = explore(walls, poses, ONBOARD, Lidar(sigma_in=0.5, dropout=0.1))
    found = finder.candidates(grid)
    assert len(found) == 1 and near(found, 100.0, 3.0, 3.0) == [found[0].id]


def test_corners_are_not_proud_and_a_can_near_one_is() -> None:
    """Where two walls meet, the returns of one near the corner lie in the other's band,
    in front of it: they are not proud of it, for they lie on a wall at 45° or more to
    it. An empty room with its corners seen from inside gives no candidate; a can 0.7 in
    from the bottom wall, 18.7 in from the left one, is one."""
    lidar = Lidar(sigma_in=0.5, dropout=0.1)
    poses = [(30.0, 30.0), (60.0, 20.0), (20.0, 60.0), (170.0, 120.0)]
    empty, grid = explore(np.array(box(0.0, 0.0, 200.0, 150.0), dtype=float), poses, ONBOARD, lidar)
    assert empty.candidates(grid) == ()
    walls = np.array(box(0.0, 0.0, 200.0, 150.0) + circle(20.0, 2.0, 1.3), dtype=float)
    finder, grid = explore(walls, poses, ONBOARD, lidar)
    found = finder.candidates(grid)
    assert len(found) == 1 and near(found, 20.0, 2.0, 3.0) == [found[0].id]


# A wall with a nook: a 4 in partition (x 58-62) from the top wall down to y = 90, a
# wardrobe (x 76-124, y 126-150) against the top wall; between them a 14 in nook whose
# back is the top wall, seen from the room as a 14 in face: object-sized.
NOOK = box(0.0, 0.0, 200.0, 150.0) + box(58.0, 90.0, 62.0, 150.0) + box(76.0, 126.0, 124.0, 150.0)


def test_a_wall_with_a_nook_is_not_a_candidate() -> None:
    """Scans into the nook and along the wardrobe from six places: its back, its two
    concave corners and the wardrobe's corners give no candidate (the map's face rule
    by hand: :func:`test_the_nook_back_in_the_map_by_hand`)."""
    lidar = Lidar(sigma_in=0.5, dropout=0.1)
    poses = [(30.0, 100.0), (30.0, 60.0), (90.0, 80.0), (69.0, 100.0), (110.0, 100.0), (150.0, 110.0)]
    finder, grid = explore(np.array(NOOK, dtype=float), poses, ONBOARD, lidar)
    assert finder.candidates(grid) == ()


def occupied(cells: list[tuple[float, float]]) -> OccupancyGrid:
    """A 1 in grid over (-10, -10)-(210, 160) with the cells holding ``cells`` occupied."""
    grid = OccupancyGrid(-10.0, -10.0, 210.0, 160.0, 1.0)
    for x, y in cells:
        row, col = grid.cell_of(x, y)
        grid.log_odds[row, col] = 3.0
    return grid


def line(x0: float, y0: float, x1: float, y1: float) -> list[tuple[float, float]]:
    """Points every half inch from (x0, y0) to (x1, y1)."""
    n = max(1, math.ceil(2 * math.dist((x0, y0), (x1, y1))))
    return [(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n) for k in range(n + 1)]


def face(x0: float, y0: float, x1: float, y1: float) -> Candidate:
    """A candidate whose outline is the straight piece from (x0, y0) to (x1, y1)."""
    outline = tuple(line(x0, y0, x1, y1))
    return Candidate(1, (x0 + x1) / 2, (y0 + y1) / 2, outline, math.dist((x0, y0), (x1, y1)), 5, 0.0, 1.0)


def test_a_counter_end_face_is_not_a_candidate() -> None:
    """A counter (x 120-200, y 0-24) against the bottom wall: its end face x = 120 is
    24 in long. Seen 8 in of it (y 14.5-22.5, points every half inch), the outline's core
    (the 15 of 17 points nearest its median) is straight and 7 in long (y 15-22); in the
    map the face runs on 2 in up to the counter's front row (whose cells turn off to one
    side) and 13.5 in down to the wall's row, which crosses the line (cells on both
    sides, not counted): 22.5 in in all, more than the 14 in of any object's face."""
    grid = occupied(line(0.5, 0.5, 199.5, 0.5) + line(120.5, 0.5, 120.5, 23.5) + line(120.5, 23.5, 199.5, 23.5))
    end = face(120.5, 14.5, 120.5, 22.5)
    found = straight_face(end.core(), 5.0, 2.0)
    assert found is not None and np.allclose([found.a, found.b], [(120.5, 15.0), (120.5, 22.0)])
    assert run_along(grid, found, 2.0, 5.0, 14.0, 3.0) == 22.5
    assert continues_structure(grid, end, ONBOARD)


def test_a_box_face_square_to_a_wall_is_not_structure() -> None:
    """A 9 x 4 in box standing square against the bottom wall, its side face seen (cells
    y 1.5-9.5): the core of its outline is 7 in (y 2-9); beyond its top end only the
    box's back corner cell (1 in), beyond its bottom end half an inch of face and then
    the wall, which crosses the line (cells on both sides) and does not continue it:
    8.5 in, less than 14. The box is a candidate."""
    grid = occupied(line(0.5, 0.5, 199.5, 0.5) + line(120.5, 1.5, 120.5, 9.5) + line(120.5, 9.5, 124.5, 9.5))
    side = face(120.5, 1.5, 120.5, 9.5)
    found = straight_face(side.core(), 5.0, 2.0)
    assert found is not None and run_along(grid, found, 2.0, 5.0, 14.0, 3.0) == 8.5
    assert not continues_structure(grid, side, ONBOARD)


def test_the_nook_back_in_the_map_by_hand() -> None:
    """The nook's back (y = 149.5, x 62.5-75.5) seen 8 in (x 66-74; its core 7 in, x
    66.5-73.5): to the right it runs 2 in to the wardrobe's side (which turns down, one
    side only); to the left 4 in to the partition's face (one side), over the
    partition's inside no beam reaches (a gap of 4 in, under the 5 allowed) and on
    along the top wall of the left room, as far as it is followed (14 in): 23 in, where
    14 is structure. A can's arc has no direction to follow (its points span under 5 in)."""
    cells = (line(0.5, 149.5, 57.5, 149.5) + line(57.5, 90.5, 57.5, 149.5) + line(62.5, 90.5, 62.5, 149.5)
             + line(62.5, 149.5, 75.5, 149.5) + line(75.5, 126.5, 75.5, 149.5) + line(75.5, 126.5, 124.5, 126.5))
    grid = occupied(cells)
    back = face(66.0, 149.5, 74.0, 149.5)
    found = straight_face(back.core(), 5.0, 2.0)
    assert found is not None and run_along(grid, found, 2.0, 5.0, 14.0, 3.0) == 23.0
    assert continues_structure(grid, back, ONBOARD)
    arc = [(100.0 + 1.3 * math.cos(a), 3.3 + 1.3 * math.sin(a)) for a in np.linspace(math.pi, 2 * math.pi, 9)]
    assert straight_face(np.array(arc), ONBOARD.face_min_in, ONBOARD.face_straight_in) is None


def test_returns_behind_a_wall_are_its_noise() -> None:
    """A far wall's returns measured long lie behind its line: a run of them 8 in beyond
    the wall x = 200 (past its 3 in band), in a scan whose other returns fit that wall,
    is no observation, for nothing seen through a wall is there."""
    lidar = Lidar(sigma_in=0.0, dropout=0.0)
    walls = np.array(box(0.0, 0.0, 200.0, 150.0), dtype=float)
    ranges = lidar.scan(walls, (100.0, 75.0, 0.0), np.random.default_rng(0))
    angles = lidar.angles_rad
    bump = (np.abs(np.remainder(angles + math.pi, 2 * math.pi) - math.pi) <= math.radians(2.0))  # 5 beams dead ahead
    ranges = np.where(bump, ranges + 8.0, ranges)
    scan = PlanarScan(angles, ranges, 100.0, 75.0, 0.0, 0.0, lidar.max_range_in)
    finder = CandidateFinder(ONBOARD)
    assert finder.update(scan) == []
    ahead = np.where(bump, ranges - 16.0, ranges)  # the same run 8 in in front of the wall: an object
    (seen,) = CandidateFinder(ONBOARD).update(PlanarScan(angles, ahead, 100.0, 75.0, 0.0, 0.0, lidar.max_range_in))
    assert abs(seen.centroid[0] - 192.0) <= 0.1

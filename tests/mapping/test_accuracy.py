"""Map and localisation accuracy, by hand."""

from __future__ import annotations

import numpy as np
import pytest

from mapping import localisation_error, occupied_iou
from planner.geometry import Pose


def test_iou_of_overlapping_walls() -> None:
    """Built: cells (0,0), (0,1), (0,2); truth: (0,1), (0,2), (1,2). Shared 2, either 4: 0.5."""
    built = np.zeros((3, 3), bool)
    truth = np.zeros((3, 3), bool)
    built[0, :] = True
    truth[0, 1:] = True
    truth[1, 2] = True
    assert occupied_iou(built, truth) == pytest.approx(0.5)


def test_iou_extremes() -> None:
    a = np.eye(4, dtype=bool)
    assert occupied_iou(a, a) == 1.0
    assert occupied_iou(a, ~a) == 0.0
    assert occupied_iou(np.zeros((2, 2), bool), np.zeros((2, 2), bool)) == 1.0


def test_iou_refuses_grids_of_different_shapes() -> None:
    with pytest.raises(ValueError, match=r"\(2, 2\) and \(3, 3\)"):
        occupied_iou(np.zeros((2, 2), bool), np.zeros((3, 3), bool))


def test_localisation_error_over_time() -> None:
    """A 3-4-5 position error and headings 350° against 10° (20° apart) at the end."""
    truth = [Pose(0, 0, 0), Pose(10, 0, 10)]
    estimated = [Pose(0, 0, 0), Pose(13, 4, 350)]
    error = localisation_error(estimated, truth, [0.0, 1.5])
    assert error.position_in == (0.0, 5.0)
    assert error.heading_deg == pytest.approx((0.0, 20.0))
    assert (error.final_in, error.mean_in, error.max_in) == (5.0, 2.5, 5.0)
    assert (error.final_deg, error.mean_deg) == pytest.approx((20.0, 10.0))
    assert error.stamps_s == (0.0, 1.5)


def test_localisation_error_refuses_sequences_of_different_lengths() -> None:
    with pytest.raises(ValueError, match="1, 0 and 1"):
        localisation_error([Pose(0, 0, 0)], [], [0.0])

"""The marker board file: which ArUco markers are printed where on the floor
(docs/camera.md, "The marker board file").

The simulator prints the board into its realistic images and the executive calibrates
the camera from it; both read the file here, so the two ends agree on where the
markers are without the planner importing the simulator. OpenCV is not needed to read
it: the dictionaries OpenCV predefines are listed with their markers' bit size.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

# OpenCV's predefined ArUco dictionaries (cv2.aruco.DICT_*) and their markers' bits
# across (the black border adds one module each side).
DICTIONARY_BITS: dict[str, int] = {
    **{f"DICT_{n}X{n}_{count}": n for n in (4, 5, 6, 7) for count in (50, 100, 250, 1000)},
    "DICT_ARUCO_ORIGINAL": 5,
    "DICT_APRILTAG_16h5": 4, "DICT_APRILTAG_16H5": 4,
    "DICT_APRILTAG_25h9": 5, "DICT_APRILTAG_25H9": 5,
    "DICT_APRILTAG_36h10": 6, "DICT_APRILTAG_36H10": 6,
    "DICT_APRILTAG_36h11": 6, "DICT_APRILTAG_36H11": 6,
    "DICT_ARUCO_MIP_36h12": 6, "DICT_ARUCO_MIP_36H12": 6,
}
QUIET_MODULES = 1  # white paper around each marker, in marker modules


@dataclass(frozen=True)
class BoardMarker:
    """One printed marker: its id and its centre on the floor, top edge towards +y."""

    marker_id: int
    x_in: float
    y_in: float


@dataclass(frozen=True)
class MarkerBoard:
    """ArUco markers of one OpenCV dictionary, each ``marker_in`` wide (black border
    included), axis-aligned on the floor."""

    dictionary: str
    marker_in: float
    markers: tuple[BoardMarker, ...]

    def corners(self, marker_id: int) -> list[tuple[float, float]]:
        """The marker's floor corners in ArUco's order: top-left, top-right,
        bottom-right, bottom-left of the printed image (the top edge faces +y)."""
        m = next(m for m in self.markers if m.marker_id == marker_id)
        h = self.marker_in / 2
        return [(m.x_in - h, m.y_in + h), (m.x_in + h, m.y_in + h), (m.x_in + h, m.y_in - h),
                (m.x_in - h, m.y_in - h)]

    def modules(self) -> int:
        """Cells across one marker, its black border included."""
        return DICTIONARY_BITS[self.dictionary] + 2

    def paper_in(self) -> float:
        """Side of the white square a marker is printed on (QUIET_MODULES all round)."""
        return self.marker_in * (1 + 2 * QUIET_MODULES / self.modules())


def load_board(path: Path) -> MarkerBoard:
    """Read a board file; a bad one raises ValueError naming the file and the field."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the marker board: {exc}") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path}: a marker board is a JSON object")
    dictionary = data.get("dictionary")
    if not (isinstance(dictionary, str) and dictionary in DICTIONARY_BITS):
        raise ValueError(f"{path}: dictionary: expected an OpenCV ArUco dictionary name such as DICT_4X4_50")
    marker_in = _number(path, "marker_in", data.get("marker_in"))
    if marker_in <= 0:
        raise ValueError(f"{path}: marker_in: must be positive")
    raw = data.get("markers")
    if not isinstance(raw, list) or not raw:
        raise ValueError(f"{path}: markers: expected a non-empty list")
    markers = []
    for i, m in enumerate(raw):
        if not isinstance(m, dict) or not isinstance(m.get("id"), int) or isinstance(m.get("id"), bool):
            raise ValueError(f"{path}: markers[{i}].id: expected an integer")
        markers.append(BoardMarker(m["id"], _number(path, f"markers[{i}].x_in", m.get("x_in")),
                                   _number(path, f"markers[{i}].y_in", m.get("y_in"))))
    if len({m.marker_id for m in markers}) != len(markers):
        raise ValueError(f"{path}: markers: ids must be distinct")
    return MarkerBoard(dictionary, marker_in, tuple(markers))


def _number(path: Path, name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{path}: {name}: expected a finite number, got {value!r}")
    return float(value)

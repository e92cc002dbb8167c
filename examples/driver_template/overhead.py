"""The overhead image as docs/driver-protocol.md ("camera") requires it: the grey band
of each kind of thing, the pixel-to-world mapping, and the reply's PNG encoding.

The executive's vision tells floor, furniture, robot and objects apart by grey level
alone, so whatever the camera sees must reach the executive drawn in these levels;
a hardware driver segments its picture into them, the toy backend draws them.
"""

from __future__ import annotations

import base64
import struct
import zlib

import numpy as np

from robot import Image

FLOOR = 30  # band 0-69
FURNITURE = 110  # walls and anything to drive around: band 70-139
BASE = 170  # the robot's base disc: band 140-194
OBJECT = 220  # anything to recognise and grasp: band 195-234
MARKER = 250  # the heading marker, a disc of base_radius / 4 at 2/3 base_radius ahead: 235-255


def pixel_centres(height: int, width: int, inches_per_pixel: float, origin_x_in: float,
                  origin_y_in: float) -> tuple[np.ndarray, np.ndarray]:
    """World x and y of every pixel centre: columns along +x, rows *down* the y axis
    (row 0 is the room's high-y edge)."""
    cols = origin_x_in + (np.arange(width) + 0.5) * inches_per_pixel
    rows = origin_y_in - (np.arange(height) + 0.5) * inches_per_pixel
    return np.meshgrid(cols, rows)


def disc(x: np.ndarray, y: np.ndarray, cx: float, cy: float, radius: float) -> np.ndarray:
    """Pixels whose centre lies in a disc."""
    return (x - cx) ** 2 + (y - cy) ** 2 <= radius**2


def rectangle(x: np.ndarray, y: np.ndarray, cx: float, cy: float, length: float, width: float,
              angle_deg: float) -> np.ndarray:
    """Pixels whose centre lies in a rectangle of ``length`` along ``angle_deg`` and
    ``width`` across it, centred at (cx, cy)."""
    a = np.radians(angle_deg)
    along = (x - cx) * np.cos(a) + (y - cy) * np.sin(a)
    across = -(x - cx) * np.sin(a) + (y - cy) * np.cos(a)
    return (np.abs(along) <= length / 2) & (np.abs(across) <= width / 2)


def png(pixels: np.ndarray) -> bytes:
    """An 8-bit greyscale PNG of ``pixels`` (standard library only: zlib and struct)."""
    height, width = pixels.shape

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    rows = np.hstack([np.zeros((height, 1), np.uint8), pixels.astype(np.uint8)])  # filter 0 per row
    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)  # 8 bit, greyscale, no interlace
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
            + chunk(b"IEND", b""))


def image_body(image: Image) -> dict:
    """The camera reply's fields. camera_matrix and fisheye are null: the image is
    already undistorted (send OpenCV fisheye K and D instead to let the executive
    undistort it)."""
    height, width = image.pixels.shape
    return {"image": {"format": "png", "height": height, "width": width,
                      "data": base64.b64encode(png(image.pixels)).decode("ascii")},
            "inches_per_pixel": image.inches_per_pixel,
            "origin_x_in": image.origin_x_in, "origin_y_in": image.origin_y_in,
            "camera_matrix": None, "fisheye": None, "clock_s": image.clock_s, "meta": dict(image.meta)}

"""The grey bands of a band image (docs/driver-protocol.md, "The overhead image").

A band image draws each kind of thing at one grey level; a reader classifies a pixel
by the band it falls in. Band limits sit halfway between neighbouring levels, so the
protocol's pixel noise (at most PIXEL_NOISE_MAX levels either way) never moves a pixel
into the wrong band.

A real camera's image has no bands, and nothing in a reply says which kind an image
is: :func:`looks_like_bands` tells them apart by whether the pixels cluster at the
documented levels, as a band image's do however much noise the protocol allows.
"""

from __future__ import annotations

import numpy as np

FLOOR, WALL, BASE, OBJECT, MARKER = 30, 110, 170, 220, 250  # the levels drawn
FLOOR_BAND = (0, 69)
WALL_BAND = (70, 139)  # walls and furniture
ROBOT_BAND = (140, 194)  # the robot's base
OBJECT_BAND = (195, 234)  # an object's footprint
MARKER_BAND = (235, 255)  # the heading marker on the base
PIXEL_NOISE_MAX = 12  # levels either way

UNSEEN = 0  # outside a fish-eye lens's view, once undistorted
LEVELS = (UNSEEN, FLOOR, WALL, BASE, OBJECT, MARKER)
# Share of pixels within the noise of a level above which an image is a band image: a
# band image has all of them there (a fish-eye one ~0.8, its rim of blended edges
# aside); the simulator's realistic preset ~0.26; a continuous-tone image by chance
# about half (the levels' neighbourhoods cover 131 of the 256 grey levels).
BAND_SHARE = 0.6


def in_band(pixels: np.ndarray, band: tuple[int, int]) -> np.ndarray:
    """Whether each pixel falls in ``band`` (inclusive), as a bool array."""
    pixels = np.asarray(pixels)
    return (pixels >= band[0]) & (pixels <= band[1])


def band_share(pixels: np.ndarray) -> float:
    """The share of pixels within PIXEL_NOISE_MAX of one of the drawn LEVELS."""
    pixels = np.asarray(pixels, dtype=np.int16)
    if pixels.size == 0:
        return 0.0
    near = np.zeros(pixels.shape, dtype=bool)
    for level in LEVELS:
        near |= np.abs(pixels - level) <= PIXEL_NOISE_MAX
    return float(near.mean())


def looks_like_bands(pixels: np.ndarray) -> bool:
    """Whether an image is drawn in the grey bands (else it is a real camera's, or
    drawn like one, and needs a calibration to be read; docs/camera.md)."""
    return band_share(pixels) >= BAND_SHARE

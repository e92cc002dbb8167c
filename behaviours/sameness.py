"""When the overhead camera's view of an object counts as the same object, pushed,
changed, moved or gone.

These are properties of the camera and the catalogue (the pixel noise of a region's
outline, how far a failed grasp can push an object), not settings a run would change,
so they are named constants rather than ``Params`` fields: no caller ever set them.
"""

from __future__ import annotations

PUSHED_IN = 1.0
"""A region's centroid this far from where the object was means it was pushed (nearer:
the same object seen anew)."""

CHANGED_RATIO = 0.25
"""A pixel count this much bigger or smaller than before (as a share) means the object
changed (knocked over, or another object)."""

SEARCH_IN = 24.0
"""How far from its place a moved object is looked for before it counts as gone."""

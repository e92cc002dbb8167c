"""The overhead camera's published model, shared by both ends of the driver protocol.

What a driver's image must mean (docs/driver-protocol.md, docs/camera.md) is stated
once here and read by the simulator that draws images, the conformance suite that
checks a driver's images and the planner's vision that reads them: the image itself,
one type from the driver to the vision (:mod:`camera_model.image`), the grey bands of
a band image (:mod:`camera_model.bands`), the pixel-to-floor mapping
(:mod:`camera_model.floor_grid`) with the fish-eye undistortion it holds after
(:mod:`camera_model.fisheye`), and the marker board file (:mod:`camera_model.board`).
A leaf: numpy and the standard library only, nothing of ours, so the driver side and
the executive side may both import it without either importing the other.
"""

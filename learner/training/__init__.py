"""The training stage (docs/method.md §4): from labelled training objects to a library.

``inputs`` are the training objects and where measurements come from; ``stage`` picks
the training positions (Phase 1) and learns descriptions at them (Phase 2), growing
Phase 2's trees through ``trees``; ``grasps`` finds an object's grasp by trying grasps
when no teacher gave it; ``fidelity`` checks a trained library against exact values and
``summary`` gives the stage's numbers as the paper reports them.
"""

"""A guard's pause: the work under a guard keeps its place while the guard acts.

py_trees' guard idiom is a Selector without memory whose first branch, gated by a
condition, pre-empts the work when the condition holds (the low-battery guard,
``behaviours.battery``; the lost-driver guard, ``behaviours.reconnect``). Pre-empted,
the work would be reset and start over; :class:`KeepPlace` pauses it instead, so the
object in hand resumes where it was when the guard is done.
"""

from __future__ import annotations

from typing import Protocol

import py_trees
from py_trees.common import Status


class Guard(Protocol):
    """The condition of a guard: whether it fired at its last tick."""

    fired: bool


class KeepPlace(py_trees.decorators.Decorator):
    """The work under a guard: when ``guard`` pre-empts it, the work is paused with its
    place kept (its composites remember their running child) instead of being reset, so
    the next tick after the guard is done continues the same step of the same object.
    Any other stop (the episode ending) stops the work as usual."""

    def __init__(self, child: py_trees.behaviour.Behaviour, guard: Guard, name: str = "keep place") -> None:
        super().__init__(name=name, child=child)
        self.guard = guard

    def update(self) -> Status:
        return self.decorated.status

    def stop(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.guard.fired and self.decorated.status == Status.RUNNING:
            self.terminate(new_status)  # paused: the child keeps its status and memory
            self.status = new_status
            return
        super().stop(new_status)

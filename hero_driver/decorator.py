"""One way to wrap a driver: every verb of the verb table through one hook.

The executive drives its robot through wrappers that each change one thing about every
verb: sending a verb again while the robot finishes an overdue one
(``behaviours.overdue``), shifting poses into the overhead camera's frame
(``behaviours.localisation``), recording what the robot answered
(``recording.driver``). Each used to list the verbs by hand, so a verb it
did not list slipped past it. A :class:`DriverDecorator` lists none: every name in
:data:`~hero_driver.interface.VERB_BY_NAME` goes through :meth:`DriverDecorator.call`
with its row of the table, which says which arguments and result fields carry poses,
and whether the verb takes the robot's time. A verb added to the table reaches every
wrapper without editing any of them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Future
from dataclasses import replace
from typing import Any, TypeVar

from hero_driver.interface import VERB_BY_NAME, Driver, DriverVerb, Obstacle, Pose

A = TypeVar("A")
B = TypeVar("B")


class DriverDecorator:
    """``inner`` with each verb of the table passed through :meth:`call`; what a driver
    offers beyond the table (the simulator's ``truth``, the zenoh client's ``alive``
    and ``profile``) is ``inner``'s as it is. A verb ``inner`` lacks (an optional
    feature it does not have) is missing here too, so ``isinstance(d, Charger)`` tells
    the truth through any number of decorators."""

    def __init__(self, inner: Driver) -> None:
        self.inner = inner
        self.robot = inner.robot

    def __getattr__(self, name: str) -> Any:
        if name == "inner":  # not set yet (copying, unpickling): no recursion through inner
            raise AttributeError(name)
        method = getattr(self.inner, name)
        verb = VERB_BY_NAME.get(name)
        if verb is None or not callable(method):
            return method
        return lambda *args, **kwargs: self.call(verb, method, args, kwargs)

    def call(self, verb: DriverVerb, method: Callable[..., Any], args: tuple[Any, ...],
             kwargs: dict[str, Any]) -> Any:
        """Carry out ``verb`` with ``method`` (``inner``'s); by default unchanged."""
        return method(*args, **kwargs)


def argument(verb: DriverVerb, args: Sequence[Any], kwargs: Mapping[str, Any], name: str) -> Any:
    """The argument ``name`` of a call of ``verb`` (None when not given)."""
    at = verb.args.index(name)
    return args[at] if at < len(args) else kwargs.get(name)


def poses_in(verb: DriverVerb, args: tuple[Any, ...], kwargs: dict[str, Any],
             dx: float, dy: float, turn_deg: float = 0.0) -> tuple[tuple[Any, ...], dict[str, Any]]:
    """The call's arguments with every pose the table names moved (:func:`translated`)."""
    named = verb.args
    moved = tuple(translated(a, dx, dy, turn_deg) if i < len(named) and named[i] in verb.poses_in else a
                  for i, a in enumerate(args))
    return moved, {k: translated(v, dx, dy, turn_deg) if k in verb.poses_in else v for k, v in kwargs.items()}


def poses_out(verb: DriverVerb, result: Any, dx: float, dy: float, turn_deg: float = 0.0) -> Any:
    """``result`` with every pose the table names moved (:func:`translated`)."""
    if result is None:
        return None
    if "" in verb.poses_out:
        return translated(result, dx, dy, turn_deg)
    fields = {f: translated(getattr(result, f), dx, dy, turn_deg) for f in verb.poses_out}
    return replace(result, **fields) if fields else result


def translated(value: Any, dx: float, dy: float, turn_deg: float = 0.0) -> Any:
    """A world position turned by ``turn_deg`` about the origin, then moved by (``dx``,
    ``dy``): a :class:`Pose` (its heading turned too), an :class:`Obstacle` (reach kept),
    an ``(x, y)`` point, a sequence of them, or None. With no turn, a shift alone (the
    overhead camera's correction: it leaves the heading to the driver)."""
    if value is None:
        return None
    if turn_deg:
        c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))

        def moved(x: float, y: float) -> tuple[float, float]:
            return c * x - s * y + dx, s * x + c * y + dy
    else:
        def moved(x: float, y: float) -> tuple[float, float]:
            return x + dx, y + dy
    if isinstance(value, Pose):
        return Pose(*moved(value.x_in, value.y_in), (value.heading_deg + turn_deg) % 360.0 if turn_deg else value.heading_deg)
    if isinstance(value, Obstacle):
        return Obstacle(*moved(value.x_in, value.y_in), value.radius_in)
    if isinstance(value, tuple) and len(value) == 2 and all(isinstance(v, (int, float)) for v in value):
        return moved(value[0], value[1])
    if isinstance(value, (list, tuple)):
        return type(value)(translated(v, dx, dy, turn_deg) for v in value)
    raise TypeError(f"not a world position: {value!r}")


def mapped(future: Future[A], fn: Callable[[A], B]) -> Future[B]:
    """A future settled with ``fn`` of ``future``'s result, or with its exception."""
    out: Future[B] = Future()

    def done(f: Future[A]) -> None:
        try:
            out.set_result(fn(f.result()))
        except BaseException as exc:  # noqa: BLE001 (the driver's error, handed on as it came)
            out.set_exception(exc)

    future.add_done_callback(done)
    return out

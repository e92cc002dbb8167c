"""A driver for docs/driver-protocol.md, standalone: eclipse-zenoh, numpy and the
Python standard library, nothing of the executive. Copy this directory, fill in the
``# VENDOR:`` stubs of robot.py's HardwareRobot, put your robot's knowledge profile in
place of hero2000.toml, and check it with ``csl driver check --robot NAME --connect
ENDPOINT --profile YOUR.toml`` (docs/vendor-guide.md).

    python driver.py --robot r1 --listen tcp/0.0.0.0:7447            # the toy backend
    python driver.py --robot r1 --backend hardware --profile myrobot.toml --zenoh-config zenoh.json5

This file is the protocol plumbing, in the order the protocol page asks for it: a
state publisher (5 Hz and after every verb), one queryable per verb answering only
its exact key, a catch-all on ``rpc/**`` for unknown verbs and wildcards, one robot
verb at a time (``busy`` otherwise, never queued), ``hello`` naming the robot profile
served (knowledge.py), and the liveliness token declared last and undeclared first.
"""

from __future__ import annotations

import argparse
import re
import signal
import sys
import threading
from collections.abc import Callable

import zenoh

import knowledge
import messages
from robot import BAD_REQUEST, BUSY, INTERNAL, UNKNOWN_VERB, HardwareRobot, Robot, RobotError
from toy_robot import ToyRobot

DEFAULT_LISTEN = "tcp/127.0.0.1:7447"
STATE_PERIOD_S = 0.2
ROBOT_NAME = re.compile(r"[A-Za-z0-9_.-]+")
ROBOT_VERBS = ("move", "sense", "grasp", "release", "camera", "reset")
LINK_VERBS = ("noop", "hello")  # answered by the driver itself, even while a verb runs
JSON = zenoh.Encoding.APPLICATION_JSON

# docs/driver-protocol.md "Transport": the settings every driver runs with.
# --zenoh-config FILE replaces them with your own file (start from these and add the
# security settings); --listen, if given, sets the endpoint over either.
DEFAULT_CONFIG = """{
  mode: "peer",
  listen: { endpoints: [] },
  connect: { endpoints: [] },
  scouting: { multicast: { enabled: false }, delay: 0 },
  transport: { link: { tx: { lease: 1000 } } },
}"""


class Driver:
    """Serves ``robot`` as ``hero/<name>/...`` on ``session`` until :meth:`close`."""

    def __init__(self, session: zenoh.Session, name: str, robot: Robot, profile: knowledge.Knowledge) -> None:
        self.robot = robot
        self.profile = profile
        self.root = f"hero/{name}"
        self._busy_lock = threading.Lock()
        self._busy: str | None = None
        self._stop = threading.Event()
        self._publisher = session.declare_publisher(f"{self.root}/state", encoding=JSON)
        self._publish_state()
        self._ticker = threading.Thread(target=self._tick, daemon=True)
        self._ticker.start()
        self._queryables = [session.declare_queryable(f"{self.root}/rpc/{verb}", self._exact(verb), complete=True)
                            for verb in (*ROBOT_VERBS, *LINK_VERBS)]
        self._queryables.append(session.declare_queryable(f"{self.root}/rpc/**", self._other_key))
        # Last: a client that sees the token finds every queryable and the state in place.
        self._token = session.liveliness().declare_token(f"{self.root}/alive")

    def close(self) -> None:
        """Token first (clients stop sending), then the queryables and the publisher."""
        self._token.undeclare()
        for queryable in self._queryables:
            queryable.undeclare()
        self._stop.set()
        self._ticker.join()
        self._publisher.undeclare()

    # ------------------------------------------------------------------- queries

    def _exact(self, verb: str) -> Callable[[zenoh.Query], None]:
        key = f"{self.root}/rpc/{verb}"

        def on_query(query: zenoh.Query) -> None:
            if str(query.key_expr) != key:  # a wildcard such as rpc/*: the catch-all answers it
                query.drop()
                return
            self._serve(verb, query)

        return on_query

    def _other_key(self, query: zenoh.Query) -> None:
        key = str(query.key_expr)
        name = key.removeprefix(f"{self.root}/rpc/")
        if name in ROBOT_VERBS or name in LINK_VERBS:
            query.drop()  # its own queryable answers
        elif "*" in key or "$" in key:
            _reply_err(query, BAD_REQUEST, f"{key}: verbs must be addressed by their exact key")
        else:
            _reply_err(query, UNKNOWN_VERB, f"{name!r} is not a verb (known: "
                       f"{', '.join((*ROBOT_VERBS, *LINK_VERBS))})")

    def _serve(self, verb: str, query: zenoh.Query) -> None:
        payload = b"" if query.payload is None else query.payload.to_bytes()
        try:
            request = messages.parse_request(verb, payload)
        except messages.BadRequest as exc:
            _reply_err(query, BAD_REQUEST, str(exc))
            return
        if verb == "noop":
            _reply(query, {})
        elif verb == "hello":
            _reply(query, messages.hello_body(self.profile))
        else:
            with self._busy_lock:
                if self._busy is not None:
                    _reply_err(query, BUSY, f"{verb}: the robot is still executing {self._busy}")
                    return
                self._busy = verb
            # Off zenoh's thread: a move takes seconds, and other queries must be answered meanwhile.
            threading.Thread(target=self._run, args=(verb, request, query), daemon=True).start()

    def _run(self, verb: str, request: dict, query: zenoh.Query) -> None:
        try:
            result = getattr(self.robot, verb)(**request)
            body = messages.result_body(result)
        except RobotError as exc:
            body, error = None, (exc.code, exc.message)
        except Exception as exc:  # a backend bug or a VENDOR stub: answer, keep serving
            body, error = None, (INTERNAL, f"{verb}: {type(exc).__name__}: {exc}")
        with self._busy_lock:
            self._busy = None
        self._publish_state()  # ahead of the reply, as the protocol asks
        if body is None:
            _reply_err(query, *error)
            return
        try:
            _reply(query, body)
        except ValueError as exc:  # NaN or Infinity in the result: not JSON
            _reply_err(query, INTERNAL, f"{verb}: the robot produced a malformed result: {exc}")

    # --------------------------------------------------------------------- state

    def _tick(self) -> None:
        while not self._stop.wait(STATE_PERIOD_S):
            self._publish_state()

    def _publish_state(self) -> None:
        try:
            body = messages.encode(messages.state_body(self.robot.state()))
        except Exception as exc:  # no valid state: publish none rather than a bad one
            print(f"driver: cannot publish the state: {type(exc).__name__}: {exc}", file=sys.stderr)
            return
        if not self._stop.is_set():
            self._publisher.put(body)


def _reply(query: zenoh.Query, fields: dict) -> None:
    body = messages.encode(fields)  # before replying: a ValueError leaves the query open
    query.reply(query.key_expr, body, encoding=JSON)
    query.drop()


def _reply_err(query: zenoh.Query, code: str, message: str) -> None:
    query.reply_err(messages.error(code, message), encoding=JSON)
    query.drop()


# ---------------------------------------------------------------------- the command


def _arguments(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description="Serve one robot on zenoh (docs/driver-protocol.md).")
    parser.add_argument("--robot", default="r1", help="robot name, the <robot> key chunk (default r1)")
    parser.add_argument("--listen", default=None, metavar="ENDPOINT",
                        help=f"zenoh endpoint to listen on (default {DEFAULT_LISTEN}, or the config file's)")
    parser.add_argument("--zenoh-config", default=None, metavar="FILE",
                        help="zenoh JSON5 config file (security settings: docs/vendor-guide.md)")
    parser.add_argument("--backend", choices=("toy", "hardware"), default="toy",
                        help="toy: an in-memory robot and box; hardware: robot.py's VENDOR stubs")
    parser.add_argument("--profile", default=str(knowledge.DEFAULT_PROFILE), metavar="FILE",
                        help="the robot's knowledge profile (TOML): the procedures it runs, and the name and "
                             "fingerprint hello sends (default: hero2000.toml next to this file)")
    parser.add_argument("--time-scale", type=float, default=0.1, metavar="X",
                        help="toy backend: real seconds per robot second of motion (default 0.1)")
    return parser.parse_args(argv)


def _config(args: argparse.Namespace) -> zenoh.Config:
    if args.zenoh_config is None:
        config = zenoh.Config.from_json5(DEFAULT_CONFIG)
    else:
        try:
            config = zenoh.Config.from_file(args.zenoh_config)
        except (zenoh.ZError, OSError) as exc:
            raise SystemExit(f"--zenoh-config {args.zenoh_config}: {str(exc).splitlines()[0]}") from None
    listen = args.listen if args.listen is not None else (DEFAULT_LISTEN if args.zenoh_config is None else None)
    if listen is not None:
        try:
            config.insert_json5("listen/endpoints", f'["{listen}"]')
        except zenoh.ZError as exc:
            raise SystemExit(f"--listen {listen}: {str(exc).splitlines()[0]}") from None
    return config


def main(argv: list[str] | None = None) -> int:
    args = _arguments(argv)
    if not ROBOT_NAME.fullmatch(args.robot):
        raise SystemExit(f"--robot {args.robot!r}: one key chunk of letters, digits, '_', '-', '.'")
    if not args.time_scale >= 0:
        raise SystemExit(f"--time-scale {args.time_scale}: expected a number >= 0")
    try:
        profile = knowledge.load(args.profile)
    except ValueError as exc:
        raise SystemExit(f"--profile {exc}") from None
    robot: Robot = ToyRobot(profile, args.time_scale) if args.backend == "toy" else HardwareRobot()
    try:
        session = zenoh.open(_config(args))
    except zenoh.ZError as exc:
        raise SystemExit(f"zenoh: {str(exc).split(' at /')[0]}") from None
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    driver = Driver(session, args.robot, robot, profile)
    print(f"serving robot {args.robot} ({args.backend} backend); Ctrl-C stops", flush=True)
    try:
        while not stop.wait(0.5):  # a timed wait lets the signal handler run promptly
            pass
    finally:
        driver.close()
        session.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

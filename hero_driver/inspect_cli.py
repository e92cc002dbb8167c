"""``csl driver state`` and ``csl driver call``: looking at a running robot by hand,
as ``ros2 topic echo`` and ``ros2 service call`` do.

``state`` prints the robot's state publications (``hero/<robot>/state``) as they
arrive, one JSON message a line, exactly as the driver sent them. ``call`` sends one
request through :class:`~hero_driver.zenoh_link.client.ZenohDriver` (so it greets the
driver and agrees on a version first, like ``csl run``) and prints the reply as the
protocol writes it. Both import zenoh only when they run.

Exit status: 0 a reply (or the messages asked for), 1 the driver answered with an error
reply, 2 bad input (an unknown verb, JSON that does not parse or does not fit the verb's
request), 3 no driver reachable or no state in time.
"""

from __future__ import annotations

import argparse
import json
import queue
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from hero_driver.zenoh_link.keys import robot_keys
from zenoh_rpc.argtypes import positive_int, positive_seconds
from zenoh_rpc.endpoints import CONNECT_KEY, DRIVER_ENDPOINT, check_endpoint
from zenoh_rpc.options import add_zenoh_config_option, endpoint_of, user_config, where

if TYPE_CHECKING:  # zenoh, and the interface (numpy), are imported only when a command runs
    from hero_driver.interface import DriverError
    from zenoh_rpc.config import UserConfig

DEFAULT_STATE_TIMEOUT_S = 5.0
"""A driver publishes its state at least every second (docs/driver-protocol.md); five
seconds of silence means nobody is serving the robot."""

REFUSED = 1
"""The driver answered, with an error reply."""


def register_inspect(actions: argparse._SubParsersAction) -> None:
    """Add ``state`` and ``call`` to the ``csl driver`` actions."""
    state = actions.add_parser(
        "state",
        help="print the robot's state messages as they arrive (like 'ros2 topic echo')",
        description=(
            "Subscribe to hero/ROBOT/state and print each state message the driver publishes "
            "(5 Hz from 'csl driver sim', and after every verb) as one line of JSON, as sent. "
            "Stops after --count messages, on Ctrl-C, or with exit status 3 when no message "
            "comes for --timeout seconds."
        ),
    )
    state.add_argument("robot", metavar="ROBOT", help="robot name (zenoh keys hero/ROBOT/...)")
    state.add_argument("--count", type=positive_int, default=None, metavar="N",
                       help="stop after N messages (default: until Ctrl-C)")
    state.add_argument("--timeout", type=positive_seconds, default=DEFAULT_STATE_TIMEOUT_S, metavar="S",
                       help=f"give up when no message arrives for S seconds (default {DEFAULT_STATE_TIMEOUT_S:g})")
    connect_options(state)
    state.set_defaults(handler=run_state)

    call = actions.add_parser(
        "call",
        help="send one request to the robot and print the reply (like 'ros2 service call')",
        description=(
            "Send one request on hero/ROBOT/rpc/VERB and print the reply body as JSON. "
            "REQUEST is the request's fields as a JSON object (docs/driver-protocol.md; the "
            "'v' field is added when left out), e.g. csl driver call r1 sense "
            "'{\"procedure\": \"H-Scan-0.3\"}'. An error reply is printed as sent and exits 1."
        ),
    )
    call.add_argument("robot", metavar="ROBOT", help="robot name (zenoh keys hero/ROBOT/...)")
    verb = call.add_argument("verb", metavar="VERB", help="the verb: %(verbs)s (docs/driver-protocol.md, Verbs)")
    verb.verbs = VerbNames()  # type: ignore[attr-defined]  # argparse fills %(verbs)s from the action's attributes
    verb.completer = complete_verb  # type: ignore[attr-defined]  # argcomplete's hook
    call.add_argument("request", metavar="REQUEST", nargs="?", default="{}",
                      help="the request as a JSON object (default {}, for verbs without arguments)")
    call.add_argument("--timeout", type=positive_seconds, default=None, metavar="S",
                      help="seconds to wait for the driver and for the reply (default: the verb's own "
                           "timeout, e.g. 5 for noop, 900 for move)")
    connect_options(call)
    call.set_defaults(handler=run_call)


class VerbNames:
    """The protocol's verbs, from the verb table, as text when a help is printed: the
    table brings the codec and OpenCV, which building the parser (``csl --help``)
    need not wait for."""

    def __str__(self) -> str:
        from hero_driver.zenoh_link.verbs import NAMES

        return ", ".join(NAMES)


def complete_verb(prefix: str, **_kwargs: object) -> list[str]:
    """The protocol's verbs that start with ``prefix`` (the verb table is imported only
    while completing: it brings the codec and OpenCV)."""
    from hero_driver.zenoh_link.verbs import BY_NAME

    return [name for name in BY_NAME if name.startswith(prefix)]


def connect_options(parser: argparse.ArgumentParser) -> None:
    """Add ``--connect ENDPOINT`` and ``--zenoh-config FILE`` (read by :func:`connect_endpoint`)."""
    parser.add_argument("--connect", default=None, metavar="ENDPOINT",
                        help=f"zenoh endpoint of the driver process (default {DRIVER_ENDPOINT})")
    add_zenoh_config_option(parser)


def connect_endpoint(args: argparse.Namespace) -> tuple[str, str, UserConfig | None]:
    """The endpoint to connect to, where it came from (for messages), and the user's
    zenoh file."""
    zenoh_config = user_config(args.zenoh_config)
    connect = endpoint_of("--connect", args.connect, DRIVER_ENDPOINT, CONNECT_KEY, zenoh_config)
    check_endpoint(connect)
    return connect, where(connect, CONNECT_KEY, zenoh_config), zenoh_config


def _not_served(robot: str, at: str, why: str) -> DriverError:
    from hero_driver.interface import UNAVAILABLE, DriverError

    return DriverError(UNAVAILABLE, f"{why} robot {robot!r} at {at}; start one with 'csl driver sim --robot {robot}'")


def run_state(args: argparse.Namespace) -> int:
    """Print state messages until --count, Ctrl-C or --timeout seconds of silence."""
    keys = robot_keys(args.robot)
    connect, at, zenoh_config = connect_endpoint(args)
    from hero_driver.zenoh_link.codec import CodecError, decode_state
    from zenoh_rpc.config import close_session, open_session

    messages: queue.Queue[bytes] = queue.Queue()
    session = open_session(connect=[connect], user=zenoh_config)
    try:
        subscriber = session.declare_subscriber(keys.state, lambda sample: messages.put(sample.payload.to_bytes()))
        printed = 0
        try:
            while args.count is None or printed < args.count:
                try:
                    payload = messages.get(timeout=args.timeout)
                except queue.Empty:
                    raise _not_served(args.robot, at, f"no state message for {args.timeout:g} s from") from None
                try:
                    decode_state(payload)
                except CodecError as exc:  # shown all the same: this is a tool for finding such things
                    print(f"csl: not a valid state message: {exc}", file=sys.stderr)
                print(_one_line_json(payload), flush=True)
                printed += 1
        except KeyboardInterrupt:  # the usual way to stop an echo
            pass
        subscriber.undeclare()
    finally:
        close_session(session)
    return 0


def run_call(args: argparse.Namespace) -> int:
    """Send one request, print the reply; an error reply exits 1."""
    robot_keys(args.robot)
    from hero_driver.interface import PROTOCOL_VERSION, TIMEOUT, UNAVAILABLE, DriverError
    from hero_driver.zenoh_link.client import VerbTimeouts, ZenohDriver
    from hero_driver.zenoh_link.codec import CodecError, encode_error
    from hero_driver.zenoh_link.verbs import BY_NAME

    verb = BY_NAME.get(args.verb)
    if verb is None:
        raise ValueError(f"VERB: unknown verb {args.verb!r} (verbs: {', '.join(BY_NAME)})")
    try:
        fields = json.loads(args.request)
    except json.JSONDecodeError as exc:
        raise ValueError(f"REQUEST: not JSON: {exc.msg} at column {exc.colno}") from None
    if not isinstance(fields, dict):
        raise ValueError(f"REQUEST: expected a JSON object such as {{}}, got {args.request!r}")
    try:  # checked as the driver node checks it: a bad field is named before anything is sent
        request = verb.decode_request(json.dumps({"v": PROTOCOL_VERSION, **fields}).encode())
    except CodecError as exc:
        raise ValueError(f"REQUEST: {exc}") from None
    connect, at, zenoh_config = connect_endpoint(args)
    timeout_s = args.timeout if args.timeout is not None else verb.timeout_s
    driver = ZenohDriver(args.robot, connect=[connect], timeouts=VerbTimeouts(**{f"{verb.name}_s": timeout_s}),
                         discover_s=min(timeout_s, 3.0), zenoh_config=zenoh_config)
    try:
        if not driver.wait_ready(timeout_s):
            raise _not_served(args.robot, at, "no driver is serving")
        start: Callable[[], object] = (lambda: verb.call(driver, request)) if verb.touches_robot else \
            getattr(driver, verb.name)
        try:
            result = start().result()
        except DriverError as exc:
            if exc.code in (UNAVAILABLE, TIMEOUT):  # nobody answered: not the driver's answer
                raise
            print(_one_line_json(encode_error(exc.code, exc.message)))
            return REFUSED
    finally:
        driver.close()
    print(_one_line_json(verb.encode_result(result)))
    return 0


def _one_line_json(payload: bytes) -> str:
    """A message as one line of JSON (its text as sent when it is not JSON at all)."""
    try:
        return json.dumps(json.loads(payload), ensure_ascii=False)
    except (json.JSONDecodeError, UnicodeDecodeError):
        return payload.decode("utf-8", errors="replace")

"""A zenoh router in a Python process, for machines without ``zenohd``.

``python -m zenoh_rpc.router ROUTER.json5`` opens one session in router mode from the
file (its listen endpoints, TLS, password dictionary and access-control rules: the
router is where a fleet's security is enforced, docs/security.md) and routes until
SIGINT or SIGTERM. The file must say ``mode: "router"``; our own settings fill only
what it leaves unset (:func:`zenoh_rpc.config.make_config`), so it listens nowhere it
does not name and never scouts by multicast. ``zenohd -c ROUTER.json5`` does the same
where it is installed.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from zenoh_rpc.config import UserConfig, close_session, open_session
from zenoh_rpc.serving import stop_on_signals, wait_for_stop


def main(argv: Sequence[str] | None = None) -> int:
    """Route until stopped; 0 then, 2 with one line on stderr for a file zenoh cannot
    use or one that is not a router's."""
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1 or args[0].startswith("-"):
        print("usage: python -m zenoh_rpc.router ROUTER.json5", file=sys.stderr)
        return 2
    try:
        config = UserConfig(Path(args[0]), "router config")
        mode = config.load().get_json("mode")
        if mode != '"router"':
            raise ValueError(f"router config {args[0]}: mode is {mode}, not \"router\"")
        with stop_on_signals() as stop:
            session = open_session(user=config)
            try:
                print(f"routing on {config.load().get_json('listen/endpoints')}", flush=True)
                wait_for_stop(stop)
            finally:
                close_session(session)
    except (ValueError, OSError) as exc:
        print(f"zenoh_rpc.router: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())

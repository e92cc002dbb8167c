"""``--record``, ``--live`` and their companions, checked and turned into a recording.
Foxglove is imported only when one of them is given."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from csl_cli.args import writable_file
from robot_profile import RobotProfile

if TYPE_CHECKING:
    from recording.session import Recording

DEFAULT_LIVE_PORT = 8765  # Foxglove's own default
DEFAULT_LIVE_PACE_S = 0.2


def check_recording_options(args: argparse.Namespace) -> None:
    """Refuse a companion option without ``--live`` and an unwritable ``--record`` at
    once, before any robot time."""
    for option in ("--live-port", "--live-pace"):
        if getattr(args, option[2:].replace("-", "_")) is not None and not args.live:
            raise ValueError(f"{option} goes with --live")
    if args.record is not None:
        writable_file(args.record, "--record")


def open_recording(args: argparse.Namespace, profile: RobotProfile) -> Recording | None:
    """The recording the options ask for (None: neither ``--record`` nor ``--live``);
    with ``--live``, its address is printed and the episode waits for a client."""
    record, live = args.record, args.live
    if record is None and not live:
        return None
    from recording.session import Recording

    port = DEFAULT_LIVE_PORT if args.live_port is None else args.live_port
    pace = 0.0 if not live else DEFAULT_LIVE_PACE_S if args.live_pace is None else args.live_pace  # a file: flat out
    try:
        recording = Recording(profile.robot.geometry, mcap=record, live_port=port if live else None, live_pace_s=pace)
    except RuntimeError as exc:  # the live server's error for a port in use (recording.live_server)
        raise ValueError(f"--live-port {port}: cannot serve the live view: {exc}") from None
    except OSError as exc:  # the file could not be made after all; the SDK's own line names neither flag nor file
        if record is None:
            raise
        raise ValueError(f"--record: cannot create {record}: {str(exc).lower()}") from None
    if live:
        print(f"csl: live view at ws://127.0.0.1:{recording.live_port} (Foxglove: Open connection, Foxglove "
              "WebSocket); waiting for a client to subscribe...", file=sys.stderr)
        try:
            recording.wait_for_viewer()
        except KeyboardInterrupt:
            recording.close()
            raise
    return recording

"""A serving process: signals stop it, and the session goes with it."""

from __future__ import annotations

import os
import signal
import threading
from contextlib import nullcontext

import pytest
import zenoh

from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session
from zenoh_rpc.serving import serve_until, stop_on_signals


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_sets_the_event_and_the_old_handler_comes_back(signum: int) -> None:
    before = signal.getsignal(signum)
    with stop_on_signals() as stop:
        assert not stop.is_set()
        os.kill(os.getpid(), signum)
        assert stop.wait(2.0)
    assert signal.getsignal(signum) is before


@pytest.mark.zenoh
def test_serve_until_declares_after_ready_and_closes_the_session_when_stopped() -> None:
    endpoint = free_endpoint()
    stop = threading.Event()
    seen: list[str] = []

    def declare(session: zenoh.Session) -> nullcontext[None]:
        seen.append("declared")
        return nullcontext()

    def on_ready() -> None:
        seen.append("ready")
        stop.set()

    serve_until(stop, [endpoint], declare, on_ready)
    assert seen == ["declared", "ready"]
    with open_session(listen=[endpoint]):  # the port is free again: the session closed
        pass

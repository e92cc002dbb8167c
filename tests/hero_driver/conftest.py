"""Fixtures shared by the zenoh-link tests: a free loopback endpoint and a session
listening on it (the driver node's side)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
import zenoh

from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session


@pytest.fixture
def endpoint() -> str:
    return free_endpoint()


@pytest.fixture
def server(endpoint: str) -> Iterator[zenoh.Session]:
    with open_session(listen=[endpoint]) as session:
        yield session

"""A serving command that listens beyond this computer with no password and no TLS says so
in one warning line (docs/security.md, "Listening beyond this computer")."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from csl_cli.main import main
from zenoh_rpc.config import UserConfig
from zenoh_rpc.options import open_listen_warning


def _user(tmp_path: Path, settings: dict[str, object]) -> UserConfig:
    path = tmp_path / "zenoh.json5"
    path.write_text(json.dumps(settings))
    return UserConfig(path)


@pytest.mark.parametrize("listen", ["tcp/127.0.0.1:7447", "tcp/127.5.0.1:7447", "tcp/localhost:7447",
                                    "tcp/[::1]:7447", "tls/0.0.0.0:7447", "quic/10.0.0.5:7447"])
def test_loopback_or_tls_is_quiet(listen: str) -> None:
    assert open_listen_warning(listen, None) is None


@pytest.mark.parametrize("listen", ["tcp/0.0.0.0:7447", "tcp/192.168.1.20:7448", "tcp/[::]:7447", "udp/10.0.0.5:7447"])
def test_any_other_address_without_a_password_warns(listen: str) -> None:
    assert open_listen_warning(listen, None) == (
        f"warning: listening on {listen} with no password and no TLS: anyone who can reach this address can use "
        "this service; see docs/security.md")


def test_a_password_in_the_users_file_is_quiet(tmp_path: Path) -> None:
    secured = _user(tmp_path, {"transport": {"auth": {"usrpwd": {"user": "r1", "password": "pw"}}}})
    assert open_listen_warning("tcp/0.0.0.0:7447", secured) is None
    assert open_listen_warning("tcp/0.0.0.0:7447", _user(tmp_path, {})) is not None


@pytest.mark.zenoh
def test_csl_learner_serve_warns_before_it_opens_anything(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """192.0.2.1 (TEST-NET-1) is no address of this computer: the command warns, then
    cannot listen there and stops in one line; nothing beyond loopback is ever bound."""
    code = main(["learner", "serve", "--listen", "tcp/192.0.2.1:7448", "--db", str(tmp_path / "lib.sqlite")])
    err = capsys.readouterr().err.splitlines()
    assert code != 0
    assert err[0].startswith("warning: listening on tcp/192.0.2.1:7448 with no password and no TLS")
    assert len(err) == 2 and "192.0.2.1" in err[1]

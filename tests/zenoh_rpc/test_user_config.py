"""A user's zenoh config file under our settings: what it sets wins, what it leaves
out gets ours, and zenoh's own user/password authentication works through it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import zenoh

from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import LEASE_MS, OUR_SETTINGS, UserConfig, make_config, open_session
from zenoh_rpc.options import CONFIG_ENV, endpoint_of, user_config, where


def _file(tmp_path: Path, settings: dict[str, object], name: str = "zenoh.json5") -> UserConfig:
    path = tmp_path / name
    path.write_text(json.dumps(settings))  # JSON is JSON5
    return UserConfig(path)


def _value(config: zenoh.Config, key: str) -> object:
    return json.loads(config.get_json(key))


def test_an_empty_file_gets_every_one_of_our_settings(tmp_path: Path) -> None:
    mine = make_config(listen=["tcp/127.0.0.1:7000"], connect=["tcp/127.0.0.1:7001"], connect_timeout_s=0.5,
                       user=_file(tmp_path, {}))
    ours = make_config(listen=["tcp/127.0.0.1:7000"], connect=["tcp/127.0.0.1:7001"], connect_timeout_s=0.5)
    assert {key: _value(mine, key) for key in OUR_SETTINGS} == {key: _value(ours, key) for key in OUR_SETTINGS}
    assert _value(mine, "transport/link/tx/lease") == LEASE_MS


# One non-default value for each of our keys, as a user's file would write it.
THEIRS = {
    "mode": "client",
    "scouting/multicast/enabled": True,
    "scouting/delay": 250,
    "listen/endpoints": ["tls/127.0.0.1:7447"],
    "connect/endpoints": ["tls/10.0.0.2:7447"],
    "connect/retry": {"period_init_ms": 2000, "period_max_ms": 8000, "period_increase_factor": 3.0},
    "connect/timeout_ms": 7000,
    "connect/exit_on_failure": False,
    "transport/link/tx/lease": 3000,
    "transport/unicast/open_timeout": 5000,
    "transport/link/rx/max_message_size": 4194304,
}


def _nested(key: str, value: object) -> dict[str, object]:
    for chunk in reversed(key.split("/")):
        value = {chunk: value}
    return value  # type: ignore[return-value]


@pytest.mark.parametrize("key", OUR_SETTINGS)
def test_a_key_the_file_sets_keeps_the_files_value(tmp_path: Path, key: str) -> None:
    user = _file(tmp_path, _nested(key, THEIRS[key]))
    assert user.sets(key)
    config = make_config(listen=["tcp/127.0.0.1:7000"], connect=["tcp/127.0.0.1:7001"], connect_timeout_s=0.5,
                         user=user)
    assert _value(config, key) == THEIRS[key]
    others = [k for k in OUR_SETTINGS if k != key]
    assert not any(user.sets(k) for k in others)


def test_the_files_own_security_settings_reach_the_session_config(tmp_path: Path) -> None:
    usrpwd = {"user": "exec", "password": "pw", "dictionary_file": str(tmp_path / "users.txt")}
    config = make_config(connect=["tcp/127.0.0.1:7001"],
                         user=_file(tmp_path, {"transport": {"auth": {"usrpwd": usrpwd}}}))
    assert _value(config, "transport/auth/usrpwd") == usrpwd
    assert _value(config, "connect/endpoints") == ["tcp/127.0.0.1:7001"]


@pytest.mark.parametrize(("text", "reason"), [
    ("{ transport: { auth: ", "line 1, column 22: expected array, boolean, null, number, object, or string"),
    ("{ transportx: 1 }", "line 1, column 3: unknown field `transportx`"),
    ('{ transport: { link: { tx: { lease: "soon" } } } }', "line 1, column 37: error parsing number"),
])
def test_a_bad_file_is_one_line_naming_it(tmp_path: Path, text: str, reason: str) -> None:
    path = tmp_path / "bad.json5"
    path.write_text(text)
    with pytest.raises(ValueError) as caught:
        UserConfig(path)
    message = str(caught.value)
    assert message.startswith(f"--zenoh-config {path}: {reason}")
    assert "\n" not in message and " at /" not in message


def test_a_missing_file_or_a_folder_is_one_line_naming_it(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=rf"^--zenoh-config {tmp_path}/none.json5: No such file or directory"):
        UserConfig(tmp_path / "none.json5")
    with pytest.raises(ValueError, match=rf"^--zenoh-config {tmp_path}: Is a directory"):
        UserConfig(tmp_path)


def test_the_environment_names_the_file_when_no_flag_does(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    given = _file(tmp_path, {}, "given.json5").path
    named = _file(tmp_path, {}, "named.json5").path
    monkeypatch.setenv(CONFIG_ENV, str(named))
    assert user_config(None) == UserConfig(named, CONFIG_ENV)
    assert user_config(given) == UserConfig(given, "--zenoh-config")
    monkeypatch.setenv(CONFIG_ENV, "")
    assert user_config(None) is None
    monkeypatch.setenv(CONFIG_ENV, str(tmp_path / "gone.json5"))
    with pytest.raises(ValueError, match=rf"^{CONFIG_ENV} {tmp_path}/gone.json5: "):
        user_config(None)


def test_a_flag_the_file_would_override_is_refused(tmp_path: Path) -> None:
    user = _file(tmp_path, {"connect": {"endpoints": ["tcp/127.0.0.1:9"]}})
    key = "connect/endpoints"
    with pytest.raises(ValueError, match=r"^--connect tcp/127.0.0.1:8: --zenoh-config .* sets connect/endpoints"):
        endpoint_of("--connect", "tcp/127.0.0.1:8", "tcp/127.0.0.1:7", key, user)
    assert endpoint_of("--connect", None, "tcp/127.0.0.1:7", key, user) == "tcp/127.0.0.1:7"
    assert endpoint_of("--connect", "tcp/127.0.0.1:8", "tcp/127.0.0.1:7", key, None) == "tcp/127.0.0.1:8"
    assert where("tcp/127.0.0.1:7", key, user) == f"the connect/endpoints of {user.path}"
    assert where("tcp/127.0.0.1:7", key, _file(tmp_path, {}, "empty.json5")) == "tcp/127.0.0.1:7"


def _auth(tmp_path: Path) -> tuple[UserConfig, UserConfig, UserConfig]:
    """A server checking a password dictionary; a client that knows the password; one that does not."""
    users = tmp_path / "users.txt"
    users.write_text("exec:right-pw\n")
    server = _file(tmp_path, {"transport": {"auth": {"usrpwd": {
        "user": "exec", "password": "right-pw", "dictionary_file": str(users)}}}}, "server.json5")
    right = _file(tmp_path, {"transport": {"auth": {"usrpwd": {"user": "exec", "password": "right-pw"}}}},
                  "right.json5")
    wrong = _file(tmp_path, {"transport": {"auth": {"usrpwd": {"user": "exec", "password": "guess"}}}},
                  "wrong.json5")
    return server, right, wrong


@pytest.mark.zenoh
def test_a_password_server_admits_only_the_matching_credentials(tmp_path: Path) -> None:
    server, right, wrong = _auth(tmp_path)
    endpoint = free_endpoint()
    with open_session(listen=[endpoint], user=server) as session:
        queryable = session.declare_queryable("t/echo", lambda query: query.reply("t/echo", b"moved"))
        for stranger in (None, wrong):
            with pytest.raises(ConnectionError, match=f"^zenoh session on {endpoint}.*: Unable to connect"):
                open_session(connect=[endpoint], connect_timeout_s=0.5, user=stranger)
        with open_session(connect=[endpoint], connect_timeout_s=2.0, user=right) as client:
            replies = list(client.get("t/echo", timeout=2.0))
        queryable.undeclare()
    assert [r.ok.payload.to_bytes() for r in replies if r.ok is not None] == [b"moved"]


@pytest.mark.zenoh
def test_a_missing_password_dictionary_is_a_one_line_connection_error(tmp_path: Path) -> None:
    user = _file(tmp_path, {"transport": {"auth": {"usrpwd": {
        "user": "a", "password": "b", "dictionary_file": str(tmp_path / "none.txt")}}}})
    with pytest.raises(ConnectionError) as caught:
        open_session(listen=[free_endpoint()], user=user)
    text = str(caught.value)
    assert f"({user.path})" in text and "dictionary file" in text and "\n" not in text and " at /" not in text

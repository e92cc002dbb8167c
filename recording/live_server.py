"""The live view's server: the Foxglove SDK's WebSocket server on a private loopback
port, and in front of it, on the port a viewer is given, a relay that reads each
client's opening handshake (:mod:`recording.handshake`) so that clients offering either
name of the protocol connect, and that ends every connection with a close frame saying
why when the episode ends.

After the handshake the relay copies bytes unchanged both ways, but for one frame: the
SDK closes each client with an empty close frame when it stops; when the episode is
over the relay sends a close frame with code 1001 and a reason in its place, so a
viewer can tell the end of an episode from a lost connection.
"""

from __future__ import annotations

import logging
import selectors
import socket
import struct
import threading
import time

import foxglove

from recording import handshake

log = logging.getLogger(__name__)

HANDSHAKE_TIMEOUT_S = 10.0
"""Seconds a client has to send its opening handshake: one that never does holds no
thread for longer."""
CLOSE_WAIT_S = 5.0
"""Seconds :meth:`LiveServer.stop` waits for the connections to pass on their close frames
and end, before it cuts what is left (a viewer that never answers a close)."""
_CHUNK = 65536


class _Reader:
    """A socket read in exact amounts, with what was read past the last one kept."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = sock
        self.pending = b""

    def _more(self) -> bool:
        data = self.sock.recv(_CHUNK)
        self.pending += data
        return bool(data)

    def head(self) -> bytes:
        """An HTTP head, up to and with its blank line; at most a little more than
        :data:`handshake.HEAD_LIMIT` bytes (what there is then, or at the end of input)."""
        while b"\r\n\r\n" not in self.pending and len(self.pending) <= handshake.HEAD_LIMIT and self._more():
            pass
        end = self.pending.find(b"\r\n\r\n")
        cut = len(self.pending) if end < 0 else end + 4
        head, self.pending = self.pending[:cut], self.pending[cut:]
        return head

    def exactly(self, n: int) -> bytes | None:
        """``n`` bytes, or None when the input ends first."""
        while len(self.pending) < n:
            if not self._more():
                return None
        data, self.pending = self.pending[:n], self.pending[n:]
        return data

    def some(self) -> bytes:
        """What is pending, else the next bytes from the socket (b"": the input ended)."""
        if self.pending:
            data, self.pending = self.pending, b""
            return data
        return self.sock.recv(_CHUNK)


class _Connection:
    """One viewer's connection through the relay."""

    def __init__(self, client: socket.socket, address: str, upstream: tuple[str, int],
                 episode_over: threading.Event) -> None:
        self.client = client
        self.address = address
        self.upstream_address = upstream
        self.upstream: socket.socket | None = None
        self.episode_over = episode_over
        self.thread = threading.Thread(target=self._serve, name=f"live view {address}", daemon=True)

    def _serve(self) -> None:
        try:
            self._relay()
        except OSError as exc:  # a viewer gone mid-way, or the connection cut at stop
            log.debug("live view: connection from %s ended: %s", self.address, exc)
        finally:
            self.cut()

    def _relay(self) -> None:
        self.client.settimeout(HANDSHAKE_TIMEOUT_S)
        from_client = _Reader(self.client)
        try:
            head = from_client.head()
        except TimeoutError:
            log.warning("live view: refused a client at %s: no opening handshake within %.0f s", self.address,
                        HANDSHAKE_TIMEOUT_S)
            return
        if not head:
            log.debug("live view: a client at %s closed before its opening handshake", self.address)
            return
        opened = handshake.opening(head)
        if opened.request is None:
            log.warning("live view: refused a client at %s: %s", self.address, opened.reason)
            self.client.sendall(handshake.refusal(opened.reason))
            return
        self.upstream = socket.create_connection(self.upstream_address, timeout=HANDSHAKE_TIMEOUT_S)
        self.upstream.sendall(opened.request + from_client.pending)
        from_client.pending = b""
        from_server = _Reader(self.upstream)
        response = from_server.head()
        self.client.sendall(handshake.answer(response, opened.renamed))
        if not handshake.accepted(response):
            status = response.split(b"\r\n", 1)[0].decode("latin-1")
            log.warning("live view: the Foxglove SDK refused a client at %s offering %s: %s %s", self.address,
                        ", ".join(opened.offered), status, from_server.pending.decode("utf-8", "replace").strip())
            self._copy(from_server, self.client)
            return
        log.info("live view: a client at %s connected (%s)", self.address,
                 handshake.SPEC if opened.renamed else ", ".join(opened.offered))
        self.client.settimeout(None)
        self.upstream.settimeout(None)
        towards_server = threading.Thread(target=self._copy, args=(from_client, self.upstream), daemon=True,
                                          name=f"live view {self.address} in")
        towards_server.start()
        self._frames(from_server)
        _shut_write(self.client)  # the SDK has closed: so does the relay, after the close frame
        towards_server.join(CLOSE_WAIT_S)

    def _frames(self, source: _Reader) -> None:
        """The server's frames on to the client, each as it came but the SDK's empty close
        frame once the episode is over (server frames are unmasked: RFC 6455 5.1)."""
        while (header := source.exactly(2)) is not None:
            size = header[1] & 0x7F
            extended = b""
            if size >= 126:
                extended = source.exactly(2 if size == 126 else 8) or b""
                if len(extended) not in (2, 8):
                    return
                size = struct.unpack(">H" if size == 126 else ">Q", extended)[0]
            mask = b"" if not header[1] & 0x80 else source.exactly(4)
            if mask is None:
                return
            if header[0] & 0x0F == 0x8 and size == 0 and self.episode_over.is_set():
                self.client.sendall(handshake.close_frame())
                continue
            self.client.sendall(header + extended + mask)
            while size > 0:
                chunk = source.exactly(min(size, _CHUNK))
                if chunk is None:
                    return
                self.client.sendall(chunk)
                size -= len(chunk)

    @staticmethod
    def _copy(source: _Reader, target: socket.socket) -> None:
        try:
            while data := source.some():
                target.sendall(data)
        except OSError:
            pass
        _shut_write(target)

    def cut(self) -> None:
        """Close both sockets (the threads reading them end)."""
        for sock in (self.client, self.upstream):
            if sock is not None:
                try:
                    sock.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass
                sock.close()


def _shut_write(sock: socket.socket) -> None:
    try:
        sock.shutdown(socket.SHUT_WR)
    except OSError:
        pass


class LiveServer:
    """The Foxglove SDK's server for ``context`` behind the relay on ``host``:``port``
    (0: any free port, read back from :attr:`port`). Raises RuntimeError, as the SDK's
    own server does, when the port cannot be bound (one in use): an OSError would pass
    for the MCAP file's."""

    def __init__(self, context: foxglove.Context, *, host: str, port: int, name: str,
                 server_listener: object | None = None) -> None:
        self._sdk = foxglove.start_server(name=name, host="127.0.0.1", port=0, context=context,
                                          server_listener=server_listener)  # type: ignore[arg-type]
        try:
            self._listener = socket.create_server((host, port))
        except OSError as exc:
            self._sdk.stop()
            raise RuntimeError(exc.strerror or str(exc)) from None
        self._episode_over = threading.Event()
        self._connections: list[_Connection] = []
        self._lock = threading.Lock()
        self._wake, self._woken = socket.socketpair()
        self._accepting = threading.Thread(target=self._accept, name="live view relay", daemon=True)
        self._accepting.start()

    @property
    def port(self) -> int:
        """The port viewers connect to."""
        return int(self._listener.getsockname()[1])

    def _accept(self) -> None:
        with selectors.DefaultSelector() as selector:
            selector.register(self._listener, selectors.EVENT_READ)
            selector.register(self._woken, selectors.EVENT_READ)
            while not self._episode_over.is_set():
                for key, _ in selector.select():
                    if key.fileobj is self._woken:
                        return
                    try:
                        client, (host, port, *_) = self._listener.accept()
                    except OSError as exc:  # out of descriptors, or a client gone before it was taken
                        log.warning("live view: could not take a client: %s", exc)
                        continue
                    connection = _Connection(client, f"{host}:{port}", ("127.0.0.1", self._sdk.port),
                                             self._episode_over)
                    with self._lock:
                        self._connections = [c for c in self._connections if c.thread.is_alive()] + [connection]
                    connection.thread.start()

    def stop(self) -> None:
        """Take no more viewers, stop the SDK's server (each viewer is sent a close frame
        with code 1001, "the episode is over"), and wait for the connections to end."""
        self._episode_over.set()
        self._wake.send(b"x")
        self._accepting.join()
        self._listener.close()
        self._sdk.stop()
        with self._lock:
            connections = list(self._connections)
        deadline = time.monotonic() + CLOSE_WAIT_S
        for connection in connections:
            connection.thread.join(max(0.0, deadline - time.monotonic()))
            connection.cut()
        self._wake.close()
        self._woken.close()

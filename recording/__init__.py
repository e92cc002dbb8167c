"""Recording episodes the way roboticists watch them: Foxglove's well-known schemas,
written to an MCAP file (``--record``) or served live over the Foxglove SDK's WebSocket
server (``--live``); docs/recording.md lists the channels.

Importing this package imports no Foxglove code: :mod:`recording.topics`
names the channels for everyone (docs, ``csl log``, tests), and only
:func:`recording.session.open_recording` loads the SDK, when a run asks for
a recording.
"""

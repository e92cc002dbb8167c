"""The zenoh link: a driver node serving any Driver, and a client that is a Driver.

``node.serve`` / ``node.DriverNode`` put a driver on the keys of
``docs/driver-protocol.md``; ``client.ZenohDriver`` drives whatever serves them;
``verbs`` is the table of verbs both sides (and ``conformance``, which checks a
driver process against the protocol) read; ``versions`` is the ``hello`` policy,
``schemas`` the JSON Schemas published in docs/schemas/, ``camera_check`` the
conformance check that the image shows the robot where its pose says, ``motion_check``
the checks that it turns, takes the time and is free as its replies say, ``scan_check``
the checks that its range scans say what the robot can verify. Sessions, keys, queryables and the
liveliness token come from the shared :mod:`zenoh_rpc` kit.
"""

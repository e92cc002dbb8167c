"""The zenoh link: a driver node serving any Driver, and a client that is a Driver.

``node.serve`` / ``node.DriverNode`` put a driver on the keys of
``docs/driver-protocol.md``; ``client.ZenohDriver`` drives whatever serves them;
``config.make_config`` builds the peer-mode configuration both sides use;
``conformance`` checks a driver process against the protocol.
"""

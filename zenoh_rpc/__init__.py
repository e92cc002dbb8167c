"""A small kit for JSON request/reply services on zenoh 1.x.

The driver link (``hero_driver.zenoh_link``) and the learner service
(``learner.service``) speak the same transport dialect: peer sessions on explicit
endpoints, keys ``<prefix>/<name>/rpc/<verb>`` answered by exactly one queryable
each, a liveliness token ``<prefix>/<name>/alive`` present while a server serves,
and error replies carrying a code and a message. Keeping that dialect here means the
two protocols differ only in what they say, never in how they say it.

This is a leaf package: it imports zenoh and the standard library only, so either
protocol (and a robot's own tools) can depend on it without pulling in the other.

- :mod:`zenoh_rpc.endpoints`: what an endpoint looks like and the default ports;
- :mod:`zenoh_rpc.config`: the session configuration (lease, retry) and opening one;
- :mod:`zenoh_rpc.keys`: one service's key space, with name validation;
- :mod:`zenoh_rpc.server`: queryables with exact-key filtering, refusals, the token;
- :mod:`zenoh_rpc.client`: queries with timeouts and the liveliness watch;
- :mod:`zenoh_rpc.serving`: a process serving until a signal stops it.
"""

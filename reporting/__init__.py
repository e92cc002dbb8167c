"""What a person reads after a run: per-object tables, the learning history, the map
and each object's run-time tree as pictures. Reads the executive's results; the
executive never imports it."""

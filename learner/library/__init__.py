"""The library of object descriptions at rest (docs/library-format.md): the JSON format,
the SQLite store a running robot appends to, and whether a robot can use them.

``format`` (with its ``columnar`` layout) is for people and version control, ``store``
for a robot learning after every grasp (``backup``: its integrity checks, online backup
and restore), ``checks`` for refusing what this robot cannot use. ``input_file`` and ``json_text`` read what a person or a peer hands in, as one
error line whatever is wrong (the executive's logs read through them too), and
``synthetic`` perturbs a real library into larger ones for studies and benches.
"""

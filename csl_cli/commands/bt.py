"""``csl bt``: the executive's behaviour tree as text, Graphviz DOT or a PNG picture;
``--perception onboard`` shows the tree of a robot without a ceiling camera, with the
exploration branch.

Apart from ``csl_cli/commands/episode.py`` (the demo's and run's handlers) so that
printing the tree imports the tree alone: not the simulator, the recording, the
learner's services, nor matplotlib unless ``--render`` asks for a picture.
"""

from __future__ import annotations

import argparse
import sys

from csl_cli.args import ONBOARD


def run_bt(args: argparse.Namespace) -> int:
    import py_trees

    from executive.behaviour_tree import build_tree

    root = build_tree(explore=args.perception == ONBOARD)
    if args.dot:
        graph = py_trees.display.dot_tree(root)
        graph.set_name("csl_executive")
        text = graph.to_string()
        if str(args.dot) == "-":
            sys.stdout.write(text)
        else:
            args.dot.write_text(text, encoding="utf-8")
            print(f"wrote {args.dot}")
        return 0
    if args.render:
        from reporting.plots import plot_behaviour_tree

        plot_behaviour_tree(args.render, root)
        print(f"wrote {args.render}")
        return 0
    text = py_trees.display.unicode_tree(root) if args.unicode else py_trees.display.ascii_tree(root)
    sys.stdout.write(text + ("\n" if not text.endswith("\n") else ""))
    return 0

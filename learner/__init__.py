"""CSL's learner (Tan & Schlimmer 1991): object descriptions, choosing tests, run-time
trees, training, and the library robots share. It imports nothing of ours but numpy
(the zenoh half of ``service`` uses the shared ``zenoh_rpc`` kit), and it reads no
robot files: the executive hands it a :class:`~learner.knowledge.Knowledge`.

Layout, by concern; each layer imports only those above it in this list:

- top level, the domain values: ``knowledge`` (procedures, costs, moving),
  ``position``, ``appearance``, ``description`` (object descriptions), ``costs``
  (move estimators, what grasps have cost);
- ``choosing/``, what chooses a test at a node: the evaluation functions
  (``criteria``), the library as a matrix (``matrix``), noise-tolerant partitions and
  information gain (``partition``, ``gain``), a node and a test priced at it
  (``node``), the leaf rule (``leaf``), the ranking by score with its lookahead
  (``scoring``), the rollouts (``rollout``, ``rollout_walk``) and the ranking that
  ends with them (``selection``);
- top level again, what choosing builds: the run-time tree (``decision_tree``, shown
  by ``render``), the recognition session the executive steps through (``runtime``),
  and the optimum, the least expected cost any policy could reach (``optimum``);
- ``training/``, the training stage: its inputs (``inputs``), the stage itself
  (``stage``), Phase 2's trees (``trees``), finding grasps by trying them
  (``grasps``), its fidelity and its numbers (``fidelity``, ``summary``);
- ``library/``, the descriptions at rest, beside choosing and training: the JSON
  format (``format``, ``columnar``), the SQLite store (``store``, checked and backed up
  by ``backup``), whether a robot can
  use them (``checks``), the readers of outside input (``input_file``, ``json_text``)
  and synthetic libraries (``synthetic``);
- ``service/``, the library shared by robots, in process or over zenoh.
"""

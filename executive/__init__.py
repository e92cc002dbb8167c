"""The executive: it orchestrates and nothing else.

It composes the behaviour tree (:mod:`executive.behaviour_tree`), runs an episode
around a driver and a learner service (:mod:`executive.executive`), logs what happened
(:mod:`executive.episode_log`), tells a script how it ended
(:mod:`executive.exit_status`), and drives the training stage through a driver
(:mod:`executive.sim_training`, :mod:`executive.training_sources`,
:mod:`executive.outline_objects`). What uses it sits
above it in packages of its own and is never imported here: the command line
(``csl_cli``), the paper's experiments (``experiments``), reports and figures
(``reporting``) and the recording (``recording``). docs/conventions.md draws the map.
"""

"""``csl experiment paper``: the paper's experiment, its baselines and the distance to
the optimum, measured in the simulator in one run.

One module, one idea:

- :mod:`~experiments.figures`: the paper's numbers we compare against;
- :mod:`~experiments.ablations`: the criteria measured besides the product's;
- :mod:`~experiments.worlds`: floors with objects at random poses;
- :mod:`~experiments.floor`: one floor played to its end in the simulator,
  with the ground truth before and after (what every study's job does);
- :mod:`~experiments.episodes`: one episode (or a chain of them) in a worker
  process, and the per-object rows it yields;
- :mod:`~experiments.runner`: independent jobs in parallel processes, with
  progress bars;
- :mod:`~experiments.table`: result rows (paper, ours, ratio) and the markdown;
- :mod:`~experiments.csvfile`: the raw per-episode CSV;
- :mod:`~experiments.plots`: the PNG figures;
- ``study_*``: one study each (training, execution and baselines, cost trends,
  incremental learning, noise, optimum);
- :mod:`~experiments.paper`: the whole run, end to end.
"""

"""Choosing a test at a node (docs/method.md §3): the evaluation functions, gain and cost,
the ranking, the leaf rule, the rollouts that look further, and the exact search.

Bottom up: ``criteria`` and ``partition`` need nothing here; ``matrix`` holds the
library as arrays; ``gain`` scores its columns; ``node`` is what every chooser passes
on; ``leaf`` says when a node is a leaf; ``scoring`` ranks by the criterion's score;
``rollout`` and ``rollout_walk`` finish candidates with that ranking and the leaf rule;
``exact`` is the optimal policy's search from a node, and ``exact_choice`` chooses by it
where few descriptions remain; ``selection.rank`` is the choice, rollouts and search
included. Only the domain values at the
top of ``learner`` are imported from outside this package.
"""

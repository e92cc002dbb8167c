"""The criteria the experiments measure besides the product's: ablations, each a
product rule with one trait of the learner's added or taken apart, built from the
learner's public builders (``learner.choosing.criteria.with_...``).

None is the best on any measure of docs/results.md ("Baselines in the same run",
"Distance to the optimum"), so the product does not offer them (docs/optimum.md, "Which criteria
the product offers"); the paper's experiment keeps measuring them beside the product's
rules so the finding stays checked: the ``-joint`` and ``-lookahead`` forms of every
cost-sensitive baseline, and the default's walk rollout and walk search without the
leaf rule of ``cs-id3-failure-search-every-row``.

:data:`MEASURED` is what the studies and benches iterate: the product's criteria and
these, in the order the results page lists them.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from learner.choosing.criteria import (CRITERIA, DEFAULT_CRITERION, Criterion, CriterionSpec, criterion_in,
                                       with_joint_gain, with_lookahead, with_walk_rollout, with_walk_search)

_REFINED = tuple(form(CRITERIA[base]) for base in ("cs-id3", "idx", "eg2")
                 for form in (with_joint_gain, with_lookahead))
_WALKED = (with_walk_rollout(CRITERIA[DEFAULT_CRITERION]), with_walk_search(CRITERIA[DEFAULT_CRITERION]))

ABLATIONS: Mapping[str, CriterionSpec] = MappingProxyType({spec.name: spec for spec in (*_REFINED, *_WALKED)})
"""The experiments' own criteria by name; none of them is a product criterion."""

_ORDER = ("cs-id3", "id3", "id3-cost-ties", "idx", "eg2", *(s.name for s in _REFINED), "cs-id3-rollout",
          "idx-rollout", DEFAULT_CRITERION, *(s.name for s in _WALKED), "cs-id3-failure-search-every-row")

_EVERY = {**CRITERIA, **ABLATIONS}
MEASURED: Mapping[str, CriterionSpec] = MappingProxyType({**{name: _EVERY[name] for name in _ORDER}, **CRITERIA})
"""Every criterion the experiments measure: the product's and the ablations, in the
order the results page lists them (a product criterion not named above comes last)."""


def criterion(name: str, *values: float, **given: float) -> Criterion:
    """The measured criterion called ``name`` (a product criterion or an ablation) with
    its parameters; unknown names are rejected with the valid ones."""
    return criterion_in(MEASURED, name, *values, **given)

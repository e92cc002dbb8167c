"""Evaluation functions: how a test's information gain trades against its cost.

``cs-id3`` is CSL's ``I^2 / C``. The others are the usual baselines, so runs can be
compared side by side: ``id3`` is truly cost-blind (gain only; ties and ``*`` positions
left to chance), ``id3-cost-ties`` is gain with ties settled by cost, ``idx`` is
``I / C`` (Norton 1989), and ``eg2`` is Nunez's ``(2^I - 1) / (C + 1)^w``.

A rule is refined by traits (:class:`Traits`), each added by a public builder
(``with_...``) so that forms can be composed wherever they are needed:
``cs-id3-rollout`` and ``idx-rollout`` rank their rule's best few tests by the expected
cost of taking the test and then finishing the object with the rule itself
(learner/choosing/rollout.py). ``cs-id3-failure`` prices a grasp tried as a feature by its
chance of failing (it is paid only then); ``cs-id3-failure-search-every-row`` rolls that
rule out with an estimate that follows the session's walk, also rolls out every grasp
test and every ``*`` fill the library uses, searches the best few a few nodes deep
(learner/choosing/rollout_walk.py, docs/optimum.md), and makes a node a leaf only when
every description at it, carried ones included, shares one grasp (``leaf_every_row``);
``cs-id3-failure-exact`` chooses by the exact search where few descriptions remain
(learner/choosing/exact_choice.py) and by the walk rollout elsewhere.
The builders also make the forms only the experiments measure, as ablations (joint
gain, a one-step lookahead, the walk rollout and search on their own; docs/optimum.md,
"Which criteria the product offers").

:data:`CRITERIA` is the product's registry: command-line help, ``--criterion`` and the
tests iterate it, so a criterion added here reaches all of them, with its formula,
its help line and its parameters, without anyone re-typing them. How a criterion
chooses besides its formula (ties, ``*`` slots, joint gain, lookahead) is part of the
entry too, so the learner asks the criterion, never its name.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType


@dataclass(frozen=True, kw_only=True)
class Traits:
    """How a criterion ranks besides its formula, declared once: a registry entry
    (:class:`CriterionSpec`) and the criterion it builds (:class:`Criterion`) both carry
    them, as keyword-only fields after their own.

    ``cost_blind_choices``: what the score leaves open is left to chance, not to cost:
    equal scores are ordered at random and a ``*`` slot of a test's position is filled
    at random within the procedure's range (any orientation). Without it, ties go to the
    nearer, then the cheaper test, and a ``*`` slot stays where the robot is.
    ``joint_gain``: a test is scored with the gain of all the features its procedure
    yields at that position (one application, one cost, several values).
    ``lookahead``: a test is scored on the gain and cost expected over two steps, itself
    and the best test after it in each branch.
    ``rollout``: the best few tests by this formula are ranked by expected cost: the
    test's, plus finishing the object with the formula alone (learner/choosing/rollout.py).
    ``grasp_paid_on_failure``: a grasp tried as a feature is priced at what it is
    expected to cost, its failure share of the node times its move and feature cost: when
    it holds, the object's own grasp has been executed and nothing more is paid.
    ``rollout_follows_walk``: the rollout's estimate follows the session's walk (rows
    weighted by how likely they reached a node, a wrong grasp rebuilding from the root:
    learner/choosing/rollout_walk.py) rather than the learner's view of a node.
    ``rollout_searches``: the rollout's finishing rule searches the next few nodes (the
    least expected cost over the best few tests at each, as the session walks them)
    before the one-step rule takes over, within a budget of searched nodes per decision
    (learner/choosing/rollout_walk.py).
    ``leaf_every_row``: a node is a leaf only when every description at it, carried ones
    included, shares one grasp (``leaf.leaf_at``). Without it the descriptions
    carried down a test they lack do not decide a leaf, and the leaf's grasp is executed
    blind where a carried description of another grasp is still as likely as a measured
    one; with it the session tests on while a test still tells them apart
    (docs/optimum.md, "Carried rows decide the leaf").
    ``exact_search``: at a node of few descriptions (``exact_choice.EXACT_ROWS``) every
    test is priced exactly, its cost plus the optimal expected cost below each branch
    (learner/choosing/exact.py); above it the walk rollout chooses at a node of tens of
    descriptions, the one-step ranking at larger ones (learner/choosing/exact_choice.py,
    docs/optimum.md, "Exact below, rollout above" and "A rule above the exact search").
    """

    cost_blind_choices: bool = False
    joint_gain: bool = False
    lookahead: bool = False
    rollout: bool = False
    grasp_paid_on_failure: bool = False
    rollout_follows_walk: bool = False
    rollout_searches: bool = False
    leaf_every_row: bool = False
    exact_search: bool = False


@dataclass(frozen=True)
class Criterion(Traits):
    """A named evaluation function of (gain in bits, cost in seconds); higher is better,
    with how it ranks besides (:class:`Traits`)."""

    name: str
    score: Callable[[float, float], float]
    cost_sensitive: bool


@dataclass(frozen=True)
class Parameter:
    """A numeric knob of a criterion (eg2's ``w``). Values must be finite and at least
    ``minimum``: a NaN or infinite weight would make every score NaN or 0 and the tree
    would silently test at random."""

    name: str
    default: float
    help: str
    minimum: float = 0.0

    def check(self, value: float) -> float:
        """``value`` as a float, or ValueError naming the parameter and the bound."""
        value = float(value)
        if not (math.isfinite(value) and value >= self.minimum):
            raise ValueError(f"{self.name} must be a finite number >= {self.minimum:g}, got {value:g}")
        return value


@dataclass(frozen=True)
class CriterionSpec(Traits):
    """One registry entry: what a user reads (formula, help), what it takes
    (parameters), and how to build the :class:`Criterion` from given parameter values.

    ``score(gain, cost, **parameters)`` is the formula itself; :meth:`build` binds the
    parameters so the learner only ever sees ``score(gain, cost)``."""

    name: str
    formula: str
    help: str
    cost_sensitive: bool
    score: Callable[..., float]
    parameters: tuple[Parameter, ...] = ()

    def build(self, *values: float, **given: float) -> Criterion:
        """The criterion with parameters given by position (in declared order) or by
        name, the rest at their defaults; unknown or invalid ones raise ValueError."""
        names = [p.name for p in self.parameters]
        if len(values) > len(names):
            raise ValueError(f"{self.name} takes {len(names)} parameter(s), got {len(values)}")
        for name, value in zip(names, values):
            if name in given:
                raise ValueError(f"{self.name}: parameter {name} given twice")
            given[name] = value
        unknown = sorted(set(given) - set(names))
        if unknown:
            raise ValueError(f"{self.name} has no parameter {', '.join(unknown)} "
                             f"(its parameters: {', '.join(names) or 'none'})")
        bound = {p.name: p.check(given.get(p.name, p.default)) for p in self.parameters}
        traits = {name: getattr(self, name) for name in _TRAITS}
        return Criterion(self.name, functools.partial(self.score, **bound), **traits)


_TRAITS = ("cost_sensitive", *(f.name for f in dataclasses.fields(Traits)))
"""What a criterion takes from its registry entry besides the name and the bound formula."""


def _ratio(numerator: float, cost: float) -> float:
    """A free test (its value already known) beats every paid one."""
    if cost <= 0:
        return math.inf if numerator > 0 else 0.0
    return numerator / cost


def _cs_id3(gain: float, cost: float) -> float:
    return _ratio(gain * gain, cost)


def _id3(gain: float, cost: float) -> float:
    return gain


def _idx(gain: float, cost: float) -> float:
    return _ratio(gain, cost)


def _eg2(gain: float, cost: float, *, w: float) -> float:
    return (2.0**gain - 1.0) / (cost + 1.0) ** w


def with_joint_gain(base: CriterionSpec) -> CriterionSpec:
    """``base`` scoring a procedure application by the joint gain of every feature it
    yields (``joint_gain``). (Help lines stay short: ``--help`` lists every entry on one
    line.)"""
    return dataclasses.replace(base, name=f"{base.name}-joint", formula=f"{base.formula}, joint I",
                               help="I of every feature one procedure run yields", joint_gain=True)


def with_lookahead(base: CriterionSpec) -> CriterionSpec:
    """``base`` by joint gain with a one-step lookahead (``lookahead``): the formula is
    given the gain and cost expected over the test and the best test after it."""
    return dataclasses.replace(with_joint_gain(base), name=f"{base.name}-lookahead",
                               formula=f"{base.formula}, joint I, 2 steps", help="I and C with the best next test",
                               lookahead=True)


def with_rollout(base: CriterionSpec) -> CriterionSpec:
    """``base`` rolled out, on its own gain: the rule it finishes with is ``base`` itself."""
    return dataclasses.replace(base, name=f"{base.name}-rollout", formula=f"{base.formula}, rollout",
                               help="least expected cost", rollout=True)


def with_grasp_paid_on_failure(base: CriterionSpec) -> CriterionSpec:
    """``base`` with a grasp test priced at its chance of failing (docs/method.md §3.7)."""
    return dataclasses.replace(base, name=f"{base.name}-failure", formula=f"{base.formula}, grasp C x P(fail)",
                               help="a grasp test costs only when it fails", grasp_paid_on_failure=True)


def with_walk_rollout(priced: CriterionSpec) -> CriterionSpec:
    """``priced`` (a failure-priced rule) rolled out with an estimate that follows the
    session's walk (``rollout_follows_walk``, learner/choosing/rollout_walk.py)."""
    return dataclasses.replace(priced, name=f"{priced.name}-rollout", formula=f"{priced.formula}, walk rollout",
                               help="least expected cost, as walked", rollout=True, rollout_follows_walk=True)


def with_walk_search(priced: CriterionSpec) -> CriterionSpec:
    """``priced``'s walk rollout with that walk searched a few nodes deep before the
    one-step rule takes over (``rollout_searches``, docs/optimum.md)."""
    return dataclasses.replace(with_walk_rollout(priced), name=f"{priced.name}-search",
                               formula=f"{priced.formula}, walk search", help="least expected cost, walk searched",
                               rollout_searches=True)


def with_leaf_every_row(searched: CriterionSpec) -> CriterionSpec:
    """``searched`` (a walk search) with a node a leaf only when every row at it, carried
    ones included, shares a grasp (``leaf_every_row``)."""
    return dataclasses.replace(searched, name=f"{searched.name}-every-row",
                               formula=f"{searched.formula}, leaf when every row agrees",
                               help="walk searched, carried rows decide leaves too", leaf_every_row=True)


def with_exact_search(priced: CriterionSpec) -> CriterionSpec:
    """``priced`` (a failure-priced rule) choosing by the exact search at nodes of few
    descriptions, by its walk rollout above at nodes of tens and by itself beyond
    (``exact_search``), a node a leaf only when every row at it shares a grasp
    (``leaf_every_row``: where the search stops)."""
    return dataclasses.replace(with_walk_rollout(priced), name=f"{priced.name}-exact",
                               formula=f"{priced.formula}, exact search at small nodes",
                               help="exact below a few descriptions, walk rollout above", leaf_every_row=True,
                               exact_search=True)


_CS_ID3 = CriterionSpec("cs-id3", "I^2 / C", "CSL's, Tan & Schlimmer 1991", True, _cs_id3)
_IDX = CriterionSpec("idx", "I / C", "Norton 1989", True, _idx)
_FAILURE_PRICED = with_grasp_paid_on_failure(_CS_ID3)

DEFAULT_CRITERION = "cs-id3-failure"
"""The executive's rule. Cheaper under noise than ``cs-id3`` (docs/optimum.md, "Under
noise"); ``cs-id3-failure-search-every-row`` is cheaper still but takes seconds where
this takes milliseconds per object, beyond the learner's decision-time goals, so it is
opt-in (docs/optimum.md, "The default stays"); so is ``cs-id3-failure-exact``, which walks
the optimum noise-free and is no dearer than this rule on noisy floors, but whose first
decision over a fresh library and later decisions under noise are still past the
learner's decision-time goals (docs/optimum.md, "A rule above the exact search")."""

CRITERIA: Mapping[str, CriterionSpec] = MappingProxyType({
    spec.name: spec for spec in (
        _CS_ID3,
        CriterionSpec("id3", "I", "cost-blind ID3, Quinlan 1986: ties and * slots at random", False, _id3,
                      cost_blind_choices=True),
        CriterionSpec("id3-cost-ties", "I", "ID3, ties to the nearer test, * slots where the robot is", False, _id3),
        _IDX,
        CriterionSpec("eg2", "(2^I - 1) / (C + 1)^w", "Nunez 1991, w weighs the cost", True, _eg2,
                      (Parameter("w", 1.0, "how much cost counts: 0 ignores it, 1 counts it fully"),)),
        with_rollout(_CS_ID3),
        with_rollout(_IDX),
        _FAILURE_PRICED,
        with_leaf_every_row(with_walk_search(_FAILURE_PRICED)),
        with_exact_search(_FAILURE_PRICED),
    )
})
"""The criteria the product offers, by name, in the order help lists them: the paper's
baselines, the rollouts of CSL's rule and Norton's, the default, the default's walk
search with carried rows deciding leaves, and its exact search where few descriptions
remain (docs/optimum.md, "Which criteria the product offers", says why these).
Iterating it gives the names, so it also serves as argparse ``choices``. The other forms
the builders above make are the experiments' to measure."""


def criterion(name: str, *values: float, **given: float) -> Criterion:
    """The product's criterion called ``name`` with its parameters (see
    :meth:`CriterionSpec.build`); unknown names are rejected with the valid ones."""
    return criterion_in(CRITERIA, name, *values, **given)


def criterion_in(registry: Mapping[str, CriterionSpec], name: str, *values: float, **given: float) -> Criterion:
    """:func:`criterion` in another registry of specs (the experiments' own)."""
    spec = registry.get(name)
    if spec is None:
        raise ValueError(f"unknown criterion {name!r} (choose from: {', '.join(registry)})")
    return spec.build(*values, **given)

"""One copy of the count and seed checks (``zenoh_rpc/argtypes.py``) for ``csl driver``
and the executive's commands: the same mistake reads the same on either."""

from __future__ import annotations

import argparse
import ast
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

import csl_cli.args
import zenoh_rpc.argtypes
from csl_cli.main import main
from zenoh_rpc.argtypes import non_negative_int, positive_int


def test_the_executive_uses_the_one_copy() -> None:
    assert csl_cli.args.non_negative_int is non_negative_int
    assert not hasattr(csl_cli.args, "positive_int") or csl_cli.args.positive_int is positive_int


def test_argtypes_imports_nothing_of_ours() -> None:
    """The driver side imports it on a robot's own computer: standard library only."""
    tree = ast.parse(Path(zenoh_rpc.argtypes.__file__).read_text(encoding="utf-8"))
    imported = {alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import)
                for alias in node.names}
    imported |= {node.module.split(".")[0] for node in ast.walk(tree)
                 if isinstance(node, ast.ImportFrom) and node.module}
    assert imported <= {"__future__", "argparse"}


@given(st.integers(min_value=-(10**6), max_value=10**6))
def test_the_bounds(value: int) -> None:
    for check, least in ((positive_int, 1), (non_negative_int, 0)):
        if value >= least:
            assert check(str(value)) == value
        else:
            with pytest.raises(argparse.ArgumentTypeError) as refused:
                check(str(value))
            expected = "must be at least 1" if least == 1 else "must not be negative"
            assert str(refused.value) == f"{expected}, got {value}"


@pytest.mark.parametrize(("text", "reason"), [("-3", "must be at least 1, got -3"), ("0", "must be at least 1, got 0"),
                                              ("2.5", "expected a whole number, got '2.5'")])
def test_one_mistake_reads_the_same_on_either_side(text: str, reason: str,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """A count on an executive command (``csl run --alternatives``) and on a driver
    command (``csl driver state --count``) is refused in the same words."""
    assert main(["run", "--alternatives", text]) == 2
    executive_line = capsys.readouterr().err.strip()
    assert main(["driver", "state", "--count", text]) == 2
    driver_line = capsys.readouterr().err.strip()
    assert executive_line == f"csl run: error: argument --alternatives: {reason} (see 'csl run --help')"
    assert driver_line == f"csl driver state: error: argument --count: {reason} (see 'csl driver state --help')"


def test_a_negative_seed_for_the_simulated_driver_names_the_flag(capsys: pytest.CaptureFixture[str]) -> None:
    """``csl driver sim --seed -1`` used to reach numpy: 'expected non-negative integer'."""
    assert main(["driver", "sim", "--seed", "-1"]) == 2
    assert capsys.readouterr().err.strip() == ("csl driver sim: error: argument --seed: must not be negative, got -1 "
                                               "(see 'csl driver sim --help')")

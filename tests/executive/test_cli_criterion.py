"""The criterion and its parameters on the command line: one registry behind every
command's ``--criterion``, and a bad parameter refused in one line before any work."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from csl_cli.args import add_criterion_options, criterion_from_args
from csl_cli.main import main
from experiments.ablations import ABLATIONS
from learner.choosing.criteria import CRITERIA


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["run", "--eg2-w", "nan"], "argument --eg2-w: w must be a finite number >= 0, got nan"),
        (["demo", "--eg2-w", "nan"], "argument --eg2-w: w must be a finite number >= 0, got nan"),
        (["demo", "--criterion", "eg2", "--eg2-w", "-1"], "argument --eg2-w: w must be a finite number >= 0"),
        (["run", "--eg2-w", "inf"], "argument --eg2-w: w must be a finite number >= 0, got inf"),
        (["tree", "--eg2-w", "heavy"], "argument --eg2-w: expected a number, got 'heavy'"),
        (["tree", "--eg2-w", "0.5"], "--eg2-w goes with --criterion eg2"),
    ],
)
def test_bad_criterion_parameters_are_one_line(tmp_path: Path, capsys, argv, message) -> None:  # noqa: ANN001
    out = ["--out", str(tmp_path)] if argv[0] != "tree" else []
    assert main([*argv, *out]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("csl") and "error: " in err[0] and message in err[0]


@pytest.mark.parametrize("command", ["run", "demo", "tree"])
def test_help_lists_every_criterion_with_its_formula(command: str, capsys, monkeypatch) -> None:  # noqa: ANN001
    monkeypatch.setenv("COLUMNS", "100000")  # no wrapping inside a formula (the listing is over 1000)
    assert main([command, "--help"]) == 0
    text = capsys.readouterr().out
    for name, spec in CRITERIA.items():
        assert f"{name} = {spec.formula} ({spec.help})" in text
        for parameter in spec.parameters:
            assert f"--{name}-{parameter.name}" in text and parameter.help in text
    for name in ABLATIONS:  # the experiments' criteria are not the product's
        assert f"{name} = " not in text and f"--{name}-" not in text


@pytest.mark.parametrize("command", ["run", "tree"])
@pytest.mark.parametrize("name", sorted(ABLATIONS))
def test_an_ablation_is_not_a_choice(tmp_path: Path, capsys, command: str, name: str) -> None:  # noqa: ANN001
    out = ["--out", str(tmp_path)] if command != "tree" else []
    assert main([command, "--criterion", name, *out]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"csl {command}: error: argument --criterion: invalid choice: '{name}'")
    offered = err[0].partition("(choose from ")[2].partition(")")[0]
    assert offered == ", ".join(f"'{n}'" for n in CRITERIA)


def test_parsed_options_build_the_criterion() -> None:
    parser = argparse.ArgumentParser()
    add_criterion_options(parser)
    default = criterion_from_args(parser.parse_args([]))
    assert default.name == "cs-id3-failure" and default.score(1.0, 10.0) == pytest.approx(0.1)  # 1^2 / 10
    assert criterion_from_args(parser.parse_args(["--criterion", "eg2"])).score(1.0, 10.0) == pytest.approx(1 / 11)
    w0 = criterion_from_args(parser.parse_args(["--criterion", "eg2", "--eg2-w", "0"]))
    assert w0.name == "eg2" and w0.score(1.0, 10.0) == pytest.approx(1.0)

"""``csl driver check --timeout`` is a positive, finite number of seconds
(zenoh_rpc.argtypes.positive_seconds): NaN, infinities, zero and negatives used to
be taken as they came (a NaN or infinite wait never ends), now argparse refuses
each in one line naming the flag, before any session opens."""

from __future__ import annotations

import argparse
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from csl_cli.main import main
from zenoh_rpc.argtypes import positive_seconds


@pytest.mark.parametrize(("text", "reason"), [
    ("nan", "must be a positive number of seconds, got nan"),
    ("NaN", "must be a positive number of seconds, got NaN"),
    ("inf", "must be a positive number of seconds, got inf"),
    ("-inf", "must be a positive number of seconds, got -inf"),
    ("1e400", "must be a positive number of seconds, got 1e400"),  # overflows to inf
    ("0", "must be a positive number of seconds, got 0"),
    ("-0.0", "must be a positive number of seconds, got -0.0"),
    ("-2.5", "must be a positive number of seconds, got -2.5"),
    ("soon", "expected a number of seconds, got 'soon'"),
])
def test_each_bad_timeout_is_one_line_naming_the_flag(text: str, reason: str,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["driver", "check", f"--timeout={text}"]) == 2
    assert capsys.readouterr().err == (f"csl driver check: error: argument --timeout: {reason} "
                                       "(see 'csl driver check --help')\n")


@given(st.floats(allow_nan=True, allow_infinity=True))
def test_positive_seconds_takes_exactly_the_positive_finite_numbers(value: float) -> None:
    text = repr(value)
    if value > 0 and math.isfinite(value):
        assert positive_seconds(text) == value
    else:
        with pytest.raises(argparse.ArgumentTypeError, match=r"^must be a positive number of seconds, got "):
            positive_seconds(text)

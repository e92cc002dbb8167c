"""JSON text from outside (a file, a request), parsed with every way it can fail as one
:class:`NotJson`.

``json.loads`` refuses bad text in more ways than ``JSONDecodeError``: a nest deeper
than Python's recursion limit raises ``RecursionError``, an integer of more than 4,300
digits a plain ``ValueError`` with advice for programmers, broken UTF-8 in bytes a
``UnicodeDecodeError``. Each reader catching its own subset let the rest through as a
traceback (or a service's ``internal``), so the readers of the learner's inputs and
the executive's episode logs parse here. The driver's side keeps its own guards: it
knows nothing of the learner.
"""

from __future__ import annotations

import json
import sys


class NotJson(ValueError):
    """Text that is not one JSON value. The message is the reason alone, one line,
    for the caller to put after the file or field it names."""


def parse_json(text: str | bytes) -> object:
    """The value ``text`` holds; :class:`NotJson` for anything ``json.loads`` refuses."""
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise NotJson(str(exc)) from None
    except UnicodeDecodeError as exc:
        raise NotJson(f"not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except RecursionError:
        raise NotJson("nested too deeply (arrays or objects inside each other)") from None
    except ValueError:  # the only other: int() refusing a very long literal
        raise NotJson(f"holds an integer of more than {sys.get_int_max_str_digits()} digits") from None

"""How refusal messages quote the input they refuse: briefly, and in JSON's vocabulary.

Hostile input may be megabytes long, and the person reading a quarantine thinks in JSON types
(number, array), not Python ones (float, list).
"""

from __future__ import annotations

from typing import Any

SHOWN = 60  # characters of a bad value quoted in a message


def show(value: Any) -> str:
    """repr(value), cut to SHOWN characters."""
    text = repr(value)
    return text if len(text) <= SHOWN else text[: SHOWN - 1] + "…"


def json_type(value: Any) -> str:
    """The JSON type name of a decoded value (bool before int: True is an int in Python)."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, (int, float)):
        return "number"
    if isinstance(value, str):
        return "string"
    if isinstance(value, (list, tuple)):
        return "array"
    if isinstance(value, dict):
        return "object"
    return type(value).__name__

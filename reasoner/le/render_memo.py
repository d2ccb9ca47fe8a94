"""Sentences rendered once per shape: the English of Prolog data whose whole numbers differ.

A judgement renders every node of every proof ("it is not the case that 217 can exceed the speed
limit", then the same for 218, ...): tens of thousands of sentences an hour of traffic, nearly
all alike but for a vehicle's number. So a sentence is rendered once per *shape* (its data with
each whole number replaced by a placeholder number) and the numbers are put back into the text.

That gives what rendering the sentence gives only where each number reads as itself, once: a
shape is kept only if the text of its placeholders holds each of them exactly once and nothing
else that looks like one. The placeholders are instants a date slot reads as a date (2009-02-13
and after), so a shape with a number in a date slot is rendered afresh every time, as is data
holding text that looks like a placeholder.
"""
from __future__ import annotations

from typing import Any, Callable

PLACEHOLDER = 1_234_560_000             # the first placeholder: 10 digits, an instant in 2009
MAX_NUMBERS = 10_000                    # placeholders there are (all 10 digits, all starting alike)
_PREFIX = str(PLACEHOLDER)[:6]          # what every placeholder's text starts with
LIMIT = 1 << 16                         # shapes kept (then it starts again)

_LIST, _DICT, _FLOAT, _INT, _TRUE, _FALSE, _NONE = (object() for _ in range(7))
Recipe = tuple                          # text pieces and number indexes, in order


class ShapeMemo:
    """The texts of one rulebook's shapes (a recipe each, or None: rendered afresh)."""

    def __init__(self) -> None:
        self._recipes: dict[Any, Recipe | None] = {}

    def text(self, data: list, render: Callable[[Any], str]) -> str:
        numbers: list[int] = []
        key = _shape(data, numbers)
        if key is None or len(numbers) > MAX_NUMBERS:
            return render(data)
        try:
            recipe = self._recipes[key]
        except KeyError:
            if len(self._recipes) >= LIMIT:
                self._recipes.clear()
            recipe = self._recipes[key] = _recipe(render(_placed(data, iter(range(len(numbers))))), len(numbers))
        if recipe is None:
            return render(data)
        return "".join([part if type(part) is str else str(numbers[part]) for part in recipe])


def _shape(value: Any, numbers: list[int]) -> Any:
    """A hashable key for the value with its whole numbers taken out (into `numbers`, in order);
    None where the value holds something else than plain JSON data, or text like a placeholder."""
    kind = type(value)
    if kind is str:
        return None if _PREFIX in value else value
    if kind is int:
        numbers.append(value)
        return _INT
    if kind is list:
        parts: list[Any] = [_LIST]
        for item in value:
            part = _shape(item, numbers)
            if part is None:
                return None
            parts.append(part)
        return tuple(parts)
    if kind is dict:
        parts = [_DICT]
        for name, item in value.items():
            part = _shape(item, numbers)
            if part is None or type(name) is not str:
                return None
            parts += (name, part)
        return tuple(parts)
    if kind is float:
        return (_FLOAT, repr(value))
    if kind is bool:
        return _TRUE if value else _FALSE
    if value is None:
        return _NONE
    return None


def _placed(value: Any, places) -> Any:
    """The value with its whole numbers replaced by placeholders, in order."""
    kind = type(value)
    if kind is int:
        return PLACEHOLDER + next(places)
    if kind is list:
        return [_placed(item, places) for item in value]
    if kind is dict:
        return {name: _placed(item, places) for name, item in value.items()}
    return value


def _recipe(text: str, count: int) -> Recipe | None:
    """The text cut at its placeholders; None unless it holds each of them exactly once and no
    other text that starts like one."""
    if text.count(_PREFIX) != count:
        return None
    found = []
    for index in range(count):
        mark = str(PLACEHOLDER + index)
        at = text.find(mark)
        if at < 0 or text.find(mark, at + 1) >= 0:
            return None
        found.append((at, index, len(mark)))
    pieces: list[Any] = []
    last = 0
    for at, index, length in sorted(found):
        if at < last:
            return None
        pieces += (text[last:at], index)
        last = at + length
    pieces.append(text[last:])
    return tuple(piece for piece in pieces if piece != "")

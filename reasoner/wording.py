"""The rulebooks' English, for the room that words what the reasoner found.

An explanation is written in the words the rules were written in: a proof node's sentence through
its rulebook's templates, a value as the rulebook writes it, and, for what might have been ("had
173 been stopped"), a template as its words and slots so that grammar can put it in another tense
(explain/phrases.py). This is all explain needs of the LE compiler (reasoner/le), given here so that
explain reads the reasoner's face and never the compiler's parts (tests/architecture/test_walls.py):
the compiler can change its insides without explain knowing.
"""
from __future__ import annotations

from typing import Any

from .engine import Rulebook
from .le.render import arg_text as _arg_text
from .le.render import sentence_text as _sentence_text
from .le.sentences import constant
from .le.templates import Slot, parse_template

# Rulebook: the rulebook whose English it is (explain/text.py names the type of what it words with)
__all__ = ["Rulebook", "Shape", "arg_text", "sentence_text", "shape", "term"]

Shape = list[str | int]   # a template's words in order, and for each slot the index of its argument


def arg_text(arg: Any) -> str:
    """A value of a proof node as the rulebook writes it: `fire_engine` -> "fire_engine", a
    variable as "a vehicle"."""
    return _arg_text(arg)


def sentence_text(data: Any, rb: Rulebook) -> str:
    """The English of one proof node's sentence (`['has_light', 173, 'red']` -> "173 has red
    light"), through the templates of the rulebook that proved it."""
    return _sentence_text(data, rb.document)


def term(name: str) -> Any:
    """A name as proof trees hold it: "173" -> 173, "car_1" -> "car_1" (the vehicle of an incident
    is a number to the rulebooks where it reads as one)."""
    return constant([name])


def shape(template: str) -> Shape:
    """A template as declared, as its words and its slots numbered in order:
    "*a vehicle* has a *a colour* light" -> [0, "has", "a", 1, "light"]."""
    out: Shape = []
    for part in parse_template(template).parts:
        out.append(sum(isinstance(x, int) for x in out) if isinstance(part, Slot) else part)
    return out

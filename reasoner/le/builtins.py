"""The sentences every LE document understands without declaring them.

Comparisons and arithmetic in words and symbols, dates (`is before`, `is after`, ...), types
(`X is a T`, `X is of type T`, with transitivity at query time), lists, `X is known`.  A
document's own templates are tried first; among built-ins the one with the most words wins,
so `is before or equal to` beats `is before`, and `X is Y` is only a last resort.

Each built-in names the Prolog predicate of `prolog/engine.pl` that evaluates it.
"""
from __future__ import annotations

from .templates import Template, parse_template

# (template, prolog functor).  The first template of a functor/arity is how it is rendered.
_SPECS = [
    ("*a thing* is a *a type*", "is_a"),
    ("*a thing* is an *a type*", "is_a"),
    ("*a thing* is of type *a type*", "is_a"),
    ("*a thing* is of *a type*", "is_a"),
    ("*a thing* is known", "le_known"),
    ("*a thing* is unknown", "le_unknown"),
    ("*a first time* is before *a second time*", "le_before"),
    ("*a first time* is after *a second time*", "le_after"),
    ("*a first time* is before or equal to *a second time*", "le_before_or_equal"),
    ("*a first time* is on or before *a second time*", "le_before_or_equal"),
    ("*a first time* is after or equal to *a second time*", "le_after_or_equal"),
    ("*a first time* is on or after *a second time*", "le_after_or_equal"),
    ("*a first time* is not before *a second time*", "le_after_or_equal"),
    ("*a first time* is not after *a second time*", "le_before_or_equal"),
    ("*a first time* is immediately before *a second time*", "le_immediately_before"),
    ("*a first date* is *a number* days after *a second date*", "le_days_after"),
    ("*a first number* < *a second number*", "<"),
    ("*a first number* is less than *a second number*", "<"),
    ("*a first number* =< *a second number*", "=<"),
    ("*a first number* <= *a second number*", "=<"),
    ("*a first number* is less than or equal to *a second number*", "=<"),
    ("*a first number* is at most *a second number*", "=<"),
    ("*a first number* > *a second number*", ">"),
    ("*a first number* is greater than *a second number*", ">"),
    ("*a first number* >= *a second number*", ">="),
    ("*a first number* is greater than or equal to *a second number*", ">="),
    ("*a first number* is at least *a second number*", ">="),
    ("*a first thing* = *a second thing*", "le_eq"),
    ("*a first thing* is equal to *a second thing*", "le_eq"),
    ("*a first thing* == *a second thing*", "le_eq"),
    ("*a first thing* =:= *a second thing*", "le_eq"),
    ("*a first thing* \\= *a second thing*", "le_neq"),
    ("*a first thing* != *a second thing*", "le_neq"),
    ("*a first thing* is different from *a second thing*", "le_neq"),
    ("*a first thing* is not equal to *a second thing*", "le_neq"),
    ("*a thing* is in *a list*", "le_member"),
    ("*a thing* is not in *a list*", "le_not_member"),
    ("the length of *a list* is *a number*", "le_length"),
    ("*a number* is the sum of *a list*", "le_sum_list"),
    ("*a number* is the maximum of *a list*", "le_max_list"),
    ("*a number* is the minimum of *a list*", "le_min_list"),
    ("*a first thing* is *a second thing*", "le_eq"),
]

BUILTINS: list[Template] = []
BUILTIN_BY_KEY: dict = {}
for _text, _functor in _SPECS:
    _t = parse_template(_text)
    _t = Template(_t.parts, _t.glue, builtin=_functor)
    BUILTINS.append(_t)
    BUILTIN_BY_KEY.setdefault((_functor, _t.arity), _t)

GENERIC_IS = BUILTINS[-1]                      # `X is Y`: only for a value or a symbolic variable
BUILTIN_FUNCTORS = {t.builtin for t in BUILTINS} - {"is_a"}
PREDEFINED_TYPES = {"thing", "time", "type", "object", "date", "day", "person", "list", "number"}

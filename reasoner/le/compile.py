"""From parsed LE to the data `prolog/engine.pl` builds clauses from (never Prolog text).

Arguments become atoms, numbers or tagged tuples (janus turns a tuple into a `-` term):
`("v", name)` a variable, `("l", [...])` a list, `("e", op, [...])` arithmetic, `("s", [...])`
a sentence in a `that` slot.  Conditions are `("pos", atom)`, `("not", [...])`,
`("or", [[...], ...])`, `("forall", [...], [...])` and `("agg", kind, result, each, [...])`.
"""
from __future__ import annotations

from functools import lru_cache

from .terms import Aggregate, Atom, Cond, Expr, ListTerm, Rule, Var


def arg_data(a):
    if isinstance(a, Var):
        return ("v", a.name)
    if isinstance(a, bool):
        return str(a).lower()
    if isinstance(a, (int, float)):
        return a
    if isinstance(a, str):
        return a
    if isinstance(a, ListTerm):
        return ("l", [arg_data(x) for x in a.items])
    if isinstance(a, Expr):
        return ("e", a.op, [arg_data(x) for x in a.args])
    if isinstance(a, Atom):
        return ("s", atom_data(a))
    raise TypeError(f"not an LE argument: {a!r}")


def atom_data(atom: Atom) -> list:
    """The data of a sentence (cached: the same facts are asked about again and again)."""
    try:
        return _cached_atom_data(atom)
    except TypeError:            # unhashable arguments (a caller's own objects)
        return _atom_data(atom)


def _atom_data(atom: Atom) -> list:
    args = atom.args
    if all(type(a) is str or type(a) is int or type(a) is float for a in args):
        return [atom.functor, *args]
    return [atom.functor, *(arg_data(a) for a in args)]


@lru_cache(maxsize=65_536)
def _cached_atom_data(atom: Atom) -> list:
    return _atom_data(atom)


def cond_data(cond: Cond):
    if cond.atom is not None:
        return ("pos", atom_data(cond.atom))
    if cond.negated is not None:
        return ("not", [cond_data(c) for c in cond.negated])
    if cond.any_of is not None:
        return ("or", [[cond_data(c) for c in alt] for alt in cond.any_of])
    if cond.forall is not None:
        cases, then = cond.forall
        return ("forall", [cond_data(c) for c in cases], [cond_data(c) for c in then])
    if cond.aggregate is not None:
        a: Aggregate = cond.aggregate
        return ("agg", a.kind, arg_data(a.result), arg_data(a.each), [cond_data(c) for c in a.body])
    raise TypeError(f"not an LE condition: {cond!r}")


def body_data(body) -> list:
    return [cond_data(c) for c in body]


def fact_data(rule: Rule, rule_id=None):
    """A scenario statement: a fact as its atom's data, a rule as ("rule", id, head, body)."""
    if not rule.body:
        return atom_data(rule.head)
    return ("rule", rule_id if rule_id is not None else rule.line, atom_data(rule.head),
            body_data(rule.body))


def predicates(document) -> list[tuple[str, int]]:
    """Every functor/arity the document's templates compile to (the built-ins excluded)."""
    seen: dict[tuple[str, int], None] = {}
    for t in document.templates.values():
        seen.setdefault((t.functor, t.arity), None)
    return list(seen)

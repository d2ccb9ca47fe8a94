"""Prolog back to LE: any compiled goal, answer or proof node as an English sentence.

The data comes from `prolog/engine.pl` (`[functor, args...]`, with `{"var": name}`,
`{"list": [...]}`, `{"expr": [op, ...]}` and `{"sentence": [...]}` arguments, and `$not`,
`$or`, `$and`, `$forall`, `$agg` for the other conditions) or from the compiler's Atoms.  A
sentence reads through the rulebook's own template (or the built-in one): words joined by
single spaces, multi-word constants as written, integers plain, floats as Python prints them
(`6250.0`, `0.43200000000000005`), `X is a B` with `a`/`an`, dates in ISO 8601 in a date slot.
"""
from __future__ import annotations

from .dates import format_date
from .templates import Slot, article, render
from .terms import Atom, Expr, ListTerm, Var

DATE_TYPES = {"date", "day", "instant"}


def arg_text(arg, slot: Slot | None = None, document=None) -> str:
    if isinstance(arg, dict):
        if "var" in arg:
            name = str(arg["var"])
            if name == "_" and slot is not None:
                return slot.phrase
            return f"{article(name)} {name}"
        if "list" in arg:
            return "[" + ", ".join(arg_text(a, None, document) for a in arg["list"]) + "]"
        if "expr" in arg:
            op, *args = arg["expr"]
            return expr_text(op, [arg_text(a, None, document) for a in args])
        if "sentence" in arg:
            return sentence_text(arg["sentence"], document)
    if isinstance(arg, Var):
        return f"{article(arg.name)} {arg.name}"
    if isinstance(arg, ListTerm):
        return "[" + ", ".join(arg_text(a, None, document) for a in arg.items) + "]"
    if isinstance(arg, Expr):
        return expr_text(arg.op, [arg_text(a, None, document) for a in arg.args])
    if isinstance(arg, Atom):
        return sentence_text(atom_list(arg), document)
    if isinstance(arg, bool):
        return str(arg).lower()
    if isinstance(arg, (int, float)):
        if slot is not None and slot.type.split("_")[-1].lower() in DATE_TYPES:
            return format_date(arg)
        return repr(arg) if isinstance(arg, float) else str(arg)
    return str(arg)


def expr_text(op: str, args: list[str]) -> str:
    if op == "neg":
        return f"-{args[0]}"
    return f"({args[0]} {op} {args[1]})" if len(args) == 2 else f"{op}({', '.join(args)})"


def atom_list(atom: Atom) -> list:
    return [atom.functor, *atom.args]


def sentence_text(data, document=None) -> str:
    """The English of one sentence or condition (a list from Prolog, or an Atom)."""
    if isinstance(data, Atom):
        data = atom_list(data)
    head = data[0]
    if head == "$not":
        return "it is not the case that " + conj_text(data[1], document)
    if head == "$and":
        return conj_text(data[1], document)
    if head == "$or":
        return " or ".join(f"({conj_text(alt, document)})" if len(alt) > 1 else conj_text(alt, document)
                           for alt in data[1])
    if head == "$forall":
        return (f"for all cases in which {conj_text(data[1], document)} "
                f"it is the case that {conj_text(data[2], document)}")
    if head == "$agg":
        kind, result, each, body = data[1:]
        what = {"sum": "the sum of each", "max": "the maximum of each", "min": "the minimum of each",
                "count": "the number of each"}.get(kind)
        r, e = arg_text(result, None, document), _bare(arg_text(each, None, document))
        if what:
            return f"{r} is {what} {e} such that {conj_text(body, document)}"
        noun = "a set" if kind == "set" else "a collection"
        return f"{r} is {noun} of {e} where {conj_text(body, document)}"
    args = data[1:]
    template = document.template_for(head, len(args)) if document is not None else None
    if template is None:
        from .builtins import BUILTIN_BY_KEY
        template = BUILTIN_BY_KEY.get((head, len(args)))
    if template is None:
        return f"{head}({', '.join(arg_text(a, None, document) for a in args)})"
    slots = template.slots
    texts = [arg_text(a, slots[i] if i < len(slots) else None, document) for i, a in enumerate(args)]
    if head == "is_a" and len(args) == 2:
        return f"{texts[0]} is {article(texts[1])} {texts[1]}"
    return render(template, texts)


def _bare(text: str) -> str:
    for det in ("a ", "an "):
        if text.startswith(det):
            return text[len(det):]
    return text


def conj_text(conds, document=None) -> str:
    return " and ".join(sentence_text(c, document) for c in conds)

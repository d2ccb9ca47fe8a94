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
from .templates import Slot, Template, article, render
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
    return render(template, _any_before_its_plural(template, args, texts))


def _any_before_its_plural(template: Template, args: list, texts: list[str]) -> list[str]:
    """An unknown named by a slot the template follows with the slot's own noun in the plural
    reads "any": "126 is being used for any purposes", not "for a purpose purposes" (issue 39),
    the template being "*a vehicle* is being used for *a purpose* purposes"."""
    out = list(texts)
    parts = template.parts
    slot_at = [i for i, p in enumerate(parts) if not isinstance(p, str)]
    for n, i in enumerate(slot_at[:len(args)]):
        arg = args[n]
        name = str(arg["var"]) if isinstance(arg, dict) and "var" in arg else arg.name if isinstance(arg, Var) else None
        following = parts[i + 1] if i + 1 < len(parts) and isinstance(parts[i + 1], str) else ""
        if name and name != "_" and following.split(" ", 1)[0] in (name + "s", name + "es"):
            out[n] = "any"
    return out


def _bare(text: str) -> str:
    for det in ("a ", "an "):
        if text.startswith(det):
            return text[len(det):]
    return text


def conj_text(conds, document=None) -> str:
    return " and ".join(sentence_text(c, document) for c in conds)


# -- rules back to LE ------------------------------------------------------------------------

def rule_text(rule, document) -> str:
    """A compiled rule (or fact) as LE text that compiles back to the same rule: variables read
    `a X` where they first occur and `the X` after, and the nesting of `and`/`or`, negations,
    `for all cases in which` and aggregates is given by indentation."""
    seen: set = set()

    def arg(a, slot=None):
        if isinstance(a, Var):
            if a.name in seen:
                return a.name if _symbolic(a.name) else f"the {a.name}"
            seen.add(a.name)
            label = a.label or a.name
            return f"{article(label)} {label}"
        if isinstance(a, ListTerm):
            return "[" + ", ".join(arg(x) for x in a.items) + "]"
        if isinstance(a, Expr):
            return expr_text(a.op, [arg(x) for x in a.args])
        if isinstance(a, Atom):
            return sentence(a)
        return arg_text(a, slot, document)

    def sentence(atom: Atom) -> str:
        template = document.template_for(atom.functor, len(atom.args))
        slots = template.slots if template is not None else []
        texts = [arg(x, slots[i] if i < len(slots) else None) for i, x in enumerate(atom.args)]
        if atom.functor == "is_a" and len(texts) == 2:
            return f"{texts[0]} is {article(texts[1])} {texts[1]}"
        if template is None:
            return f"{atom.functor}({', '.join(texts)})"
        return render(template, texts)

    def conj(conds, conn, lead):
        out = []
        for i, c in enumerate(conds):
            out += cond(c, conn, lead if i == 0 else " " * conn + "and ")
        return out

    def cond(c, conn, lead):
        block = " " * (conn + 4)
        if c.atom is not None:
            return [lead + sentence(c.atom)]
        if c.negated is not None:
            return [lead + "it is not the case that"] + conj(c.negated, conn + 4, block)
        if c.any_of is not None:
            out, ind_or = [], conn + 4
            for j, alt in enumerate(c.any_of):
                out += conj(alt, ind_or + 4, lead if j == 0 else " " * ind_or + "or ")
            return out
        if c.forall is not None:
            cases, then = c.forall
            return ([lead + "for all cases in which"] + conj(cases, conn + 4, block) +
                    [" " * (conn + 2) + "it is the case that"] + conj(then, conn + 4, block))
        a = c.aggregate
        result, each = arg(a.result), _bare(arg(a.each))
        if a.kind in ("bag", "set"):
            noun = "a set" if a.kind == "set" else "a collection"
            return [lead + f"{result} is {noun} of {each} where"] + conj(a.body, conn + 4, block)
        what = {"sum": "the sum", "max": "the maximum", "min": "the minimum", "count": "the number"}[a.kind]
        return [lead + f"{result} is {what} of each {each} such that"] + conj(a.body, conn + 4, block)

    head = sentence(rule.head)
    if not rule.body:
        return head + "."
    return "\n".join([head + " if"] + conj(rule.body, 4, "    ")) + "."


def _symbolic(name: str) -> bool:
    return " " not in name and not name.islower()

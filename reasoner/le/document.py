"""Reading an LE document: templates, then a knowledge base of rules with nested conditions.

This is the walking skeleton's subset (templates; facts; rules whose conditions are joined by
`and`, with `it is not the case that` blocks nested by indentation).  The full language is
issue 4's compiler; anything outside the subset is refused with a located error rather than
misread.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from .errors import LEError
from .sentences import parse_rule_sentence
from .templates import parse_template
from .terms import Cond, Document, Rule

LABEL = re.compile(r"^%\s*(HC\s+\d+)\s*(?::\s*(.*))?$")
KB_HEADER = re.compile(r"^the knowledge base( \S.*)? includes:$", re.I)
NOT_YET = ("for all cases in which", "is the sum of each", "is a collection of", "is a set of",
           "scenario ", "query ")


@dataclass
class Line:
    number: int
    indent: int
    text: str


def parse_document(source: str, file: str = "<le>") -> Document:
    doc = Document(file)
    section = None
    label: tuple[str, str | None] | None = None
    pending: list[Line] = []
    for number, raw in enumerate(source.splitlines(), 1):
        stripped = raw.strip()
        if stripped.startswith("%"):
            if m := LABEL.match(stripped):
                label = (re.sub(r"\s+", " ", m.group(1)), m.group(2))
            continue
        if not stripped:
            continue
        low = stripped.lower()
        if low.startswith("the target language is"):
            continue
        if low in ("the templates are:", "the predicates are:"):
            section = "templates"
            continue
        if KB_HEADER.match(stripped):
            section = "kb"
            continue
        if any(low.startswith(k) for k in NOT_YET):
            raise LEError(f"not supported by the skeleton compiler: {stripped!r}", file, number, 1,
                          "the full LE compiler is issue 4")
        if section == "templates":
            for piece in filter(None, (p.strip() for p in re.split(r"(?<=[.,])\s*$", stripped))):
                t = parse_template(piece.rstrip(",."))
                doc.templates[t.functor] = t
        elif section == "kb":
            indent = len(raw.expandtabs(4)) - len(raw.expandtabs(4).lstrip())
            pending.append(Line(number, indent, stripped))
            if stripped.endswith("."):
                doc.rules.append(_statement(pending, doc, label))
                pending, label = [], None
        else:
            raise LEError(f"text outside any section: {stripped!r}", file, number, 1,
                          "start with `the templates are:` or `the knowledge base ... includes:`")
    if pending:
        raise LEError("unfinished statement: no full stop", file, pending[0].number, 1,
                      "end every rule and fact with `.`")
    return doc


def _statement(lines: list[Line], doc: Document, label) -> Rule:
    first = lines[0]
    head_text = first.text.rstrip(".")
    has_body = head_text.endswith(" if") or len(lines) > 1
    if has_body and not head_text.endswith(" if"):
        raise LEError("a rule's first line must end with `if`", doc.file, first.number, 1)
    head_text = head_text[:-3] if head_text.endswith(" if") else head_text
    scope: set[str] = set()
    head = parse_rule_sentence(head_text, doc.templates, scope, doc.file, first.number, first.indent + 1)
    body, rest = _block(lines[1:], 0, scope, doc) if has_body else ([], [])
    if rest:
        raise LEError("bad indentation", doc.file, rest[0].number, rest[0].indent + 1)
    text = "\n".join(l.text for l in lines)
    return Rule(head, body, first.number, label[0] if label else None, label[1] if label else None, text)


def _block(lines: list[Line], min_indent: int, scope: set[str], doc: Document):
    """Conditions at one depth; an `it is not the case that` line owns the deeper lines after it."""
    conds: list[Cond] = []
    while lines and lines[0].indent >= min_indent:
        line, lines = lines[0], lines[1:]
        text = line.text.rstrip(".")
        if text.lower().startswith("or ") or text.lower() == "or":
            raise LEError("`or` is not supported by the skeleton compiler", doc.file, line.number,
                          line.indent + 1, "the full LE compiler is issue 4")
        if text.lower().startswith("and "):
            text = text[4:]
        if text.lower() == "it is not the case that":
            if not lines or lines[0].indent <= line.indent:
                raise LEError("`it is not the case that` needs an indented block below it",
                              doc.file, line.number, line.indent + 1)
            inner, lines = _block(lines, lines[0].indent, scope, doc)
            conds.append(Cond(negated=tuple(inner)))
        else:
            atom = parse_rule_sentence(text, doc.templates, scope, doc.file, line.number, line.indent + 1)
            conds.append(Cond(atom=atom))
    return conds, lines
